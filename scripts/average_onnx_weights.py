"""Average the weights of two ONNX detectors with the same graph (needs the ``train`` extra's onnx).

Usage:
    python scripts/average_onnx_weights.py FIRST.onnx SECOND.onnx OUT.onnx [--weight 0.5] [--force]
"""

from __future__ import annotations

import argparse
import sys

from pix2pockets.files import check_output
from pix2pockets.vision.train.weight_average import average_onnx_weights


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("first")
    ap.add_argument("second")
    ap.add_argument("out")
    ap.add_argument("--weight", type=float, default=0.5, help="share of SECOND in [0, 1] (default 0.5)")
    ap.add_argument("--force", action="store_true", help="overwrite OUT")
    args = ap.parse_args()
    try:
        check_output(args.out, args.force, (".onnx",))
        print(f"wrote {average_onnx_weights(args.first, args.second, args.out, args.weight)}")
    except ImportError as err:
        print(f"error: averaging needs the onnx package (pip install 'pix2pockets[train]'): {err}", file=sys.stderr)
        return 2
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
