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
from typing import NoReturn

from pix2pockets import __version__

# Sub-command modules, imported lazily so `pix2pockets --help` stays fast.


def discover_commands() -> tuple[str, ...]:
    """Sub-command modules: every ``pix2pockets.cli.*_cmd`` module, sorted by name."""
    package = importlib.import_module("pix2pockets.cli")
    names = (m.name for m in pkgutil.iter_modules(package.__path__) if m.name.endswith("_cmd"))
    return tuple(f"pix2pockets.cli.{name}" for name in sorted(names))


COMMANDS: tuple[str, ...] = discover_commands()


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line (``pix2pockets suggest: error: ...``), exit code 2.

    Sub-command parsers are made by the same class, so every command answers a bad option this way.
    """

    def error(self, message: str, prog: str | None = None) -> NoReturn:
        prog = prog or self.prog
        line = " ".join(message.split())
        self.exit(2, f"{prog}: error: {line} (see '{prog} --help')\n")

    def parse_args(self, args=None, namespace=None):  # type: ignore[override]
        """As argparse's, but options no parser knows are named with the command they were given to."""
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            command = getattr(parsed, "command", None)
            self.error(f"unrecognized arguments: {' '.join(extras)}", f"{self.prog} {command}" if command else None)
        return parsed


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``pix2pockets`` parser with every sub-command, or only ``command`` when its own module registers it
    (``serve`` -> ``serve_cmd``): a command then imports only what it uses (the web server stays light)."""
    if command is not None:
        own = f"pix2pockets.cli.{command.replace('-', '_')}_cmd"
        if own in COMMANDS:
            parser, sub = _empty_parser()
            importlib.import_module(own).register(sub)
            if command in sub.choices:
                return parser
    parser, sub = _empty_parser()
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    return parser


def _empty_parser() -> tuple[argparse.ArgumentParser, argparse._SubParsersAction]:
    parser = OneLineParser(
        prog="pix2pockets",
        description="Shot suggestions for 8-ball pool from one photo of the table.",
    )
    parser.add_argument("--version", action="version", version=f"pix2pockets {__version__}")
    return parser, parser.add_subparsers(dest="command", metavar="COMMAND")


def main(argv: Sequence[str] | None = None) -> int:
    words = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(next((w for w in words if not w.startswith("-")), None))
    args = parser.parse_args(words)
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
