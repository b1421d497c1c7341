"""The ``pix2pockets`` command: one sub-command per module.

Sub-commands are discovered: every ``cli/<name>_cmd.py`` module exposes ``register(subparsers)``, which adds
its parser and sets ``func`` (a callable taking the parsed args and returning an exit code). Errors the user
can fix are raised as ``ValueError`` (or ``OSError``) and printed as one line on stderr with exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
from collections.abc import Sequence

from pix2pockets import __version__

# Sub-command modules, imported lazily so `pix2pockets --help` stays fast.


def discover_commands() -> tuple[str, ...]:
    """Sub-command modules: every ``pix2pockets.cli.*_cmd`` module, sorted by name."""
    package = importlib.import_module("pix2pockets.cli")
    names = (m.name for m in pkgutil.iter_modules(package.__path__) if m.name.endswith("_cmd"))
    return tuple(f"pix2pockets.cli.{name}" for name in sorted(names))


COMMANDS: tuple[str, ...] = discover_commands()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="pix2pockets",
        description="Shot suggestions for 8-ball pool from one photo of the table.",
    )
    parser.add_argument("--version", action="version", version=f"pix2pockets {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "func", None) is None:
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except (ValueError, OSError) as err:
        print(f"pix2pockets {args.command}: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
