"""Command-line options shared by the commands that train a crop network (ball classifier, diamond refiner)."""

from __future__ import annotations

import argparse


def add_crop_training_options(
    parser: argparse.ArgumentParser,
    *,
    data_help: str,
    epochs: int,
    copies: int,
    centre_jitter: float,
    thing: str,
    size_unit: str,
) -> None:
    """--data, --out, --epochs, --seed, --batch, --lr, --threads, --widths, --copies, --centre-jitter, --quiet.

    Args:
        parser: the sub-command's parser.
        data_help: what a --data dataset must hold.
        epochs, copies, centre_jitter: the command's defaults.
        thing: one labelled object ("ball"), for the --copies help.
        size_unit: the unit of --centre-jitter ("ball diameters").
    """
    parser.add_argument("--data", action="append", default=[], help=f"{data_help} (repeatable)")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--epochs", type=int, default=epochs, help=f"passes over the crops (default {epochs})")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--batch", type=int, default=256, help="crops per step (default 256)")
    parser.add_argument("--lr", type=float, default=3e-3, help="peak learning rate (default 3e-3)")
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads (default 1)")
    parser.add_argument("--widths", default="16,32,64", help="channels of the three network stages (default 16,32,64)")
    parser.add_argument(
        "--copies", type=int, default=copies, help=f"shifted crops per labelled {thing} (default {copies})"
    )
    parser.add_argument(
        "--centre-jitter",
        type=float,
        default=centre_jitter,
        help=f"largest crop centre shift in {size_unit} (default {centre_jitter})",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def crop_training_settings(args: argparse.Namespace) -> dict:
    """The shared options as keyword arguments of the training configs."""
    return {
        "data": tuple(args.data),
        "out": args.out,
        "epochs": args.epochs,
        "seed": args.seed,
        "batch": args.batch,
        "lr": args.lr,
        "threads": args.threads,
        "widths": parse_widths(args.widths),
        "copies": args.copies,
        "centre_jitter": args.centre_jitter,
    }


def parse_widths(text: str) -> tuple[int, ...]:
    """Channel counts from ``24,48,96``; their number and range are checked by the training config."""
    try:
        return tuple(int(v) for v in text.split(","))
    except ValueError as err:
        raise ValueError(f"--widths needs three comma-separated channel counts like 24,48,96, got {text!r}") from err
