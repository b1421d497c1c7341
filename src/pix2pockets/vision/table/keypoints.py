"""The table model run through onnxruntime: the playing surface, its corners and its side pockets in a photo.

A small network (the detector's MobileNetV2 trunk and neck with its own head, ``pix2pockets train-table``) reads
the whole photo at a low resolution and returns, at stride 4 of its input:

- the chance that each cell lies on the playing surface (the cloth within the cushion noses, balls and players
  over it included), whose outline gives the four cushion lines;
- peaks at the four playing-surface corners (where two cushion noses meet);
- peaks at the two side-pocket mouths, which tell the long rails from the short ones.

It needs no diamonds and no particular cloth colour, so it finds pub and home tables that carry no sights.

Example:
    >>> model = TableModel.from_option(None)  # doctest: +SKIP
    >>> cues = model.read(image_rgb)  # doctest: +SKIP
    >>> cues.corners_px, cues.surface_mask().shape  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Self

import cv2
import numpy as np

from pix2pockets.vision.detect.letterbox import Letterbox, network_input
from pix2pockets.vision.detect.onnx_session import open_session

DEFAULT_TABLE_MODEL = "table.onnx"
INPUT_LONG_SIDE = 384
"""Long side of the network input [px]: the table is large in any photo of it."""
INPUT_MULTIPLE = 32
STRIDE = 4
"""Output cells per input pixel: one cell covers 4 x 4 input pixels."""
N_TABLE_CHANNELS = 3
SURFACE_CHANNEL, CORNER_CHANNEL, SIDE_CHANNEL = range(N_TABLE_CHANNELS)
OUTPUT_NAME = "table"
PEAK_MIN_SCORE = 0.25
"""Corner and side-pocket peaks below this are no cue."""
MAX_PEAKS = 8


def cell_of_pixel(xy: np.ndarray) -> np.ndarray:
    """Output-cell coordinates (..., 2) of network-input pixels (..., 2): cell ``j`` covers pixels ``4j .. 4j+3``."""
    return (np.asarray(xy, dtype=float) - (STRIDE - 1) / 2) / STRIDE


def pixel_of_cell(cell: np.ndarray) -> np.ndarray:
    """Network-input pixels (..., 2) of output-cell coordinates (..., 2); the inverse of :func:`cell_of_pixel`."""
    return np.asarray(cell, dtype=float) * STRIDE + (STRIDE - 1) / 2


@dataclass(frozen=True, slots=True, eq=False)
class TableCues:
    """What the table model saw in one photo.

    Attributes:
        surface: (h, w) chance per output cell that it lies on the playing surface.
        corners_px: (k, 2) playing-surface corner peaks in image pixels, best first; ``corner_scores`` (k,).
        sides_px: (m, 2) side-pocket mouth peaks in image pixels, best first; ``side_scores`` (m,).
        letterbox: how the photo was scaled into the network input.
        image_size: (width, height) of the photo [px].
    """

    surface: np.ndarray
    corners_px: np.ndarray
    corner_scores: np.ndarray
    sides_px: np.ndarray
    side_scores: np.ndarray
    letterbox: Letterbox
    image_size: tuple[int, int]

    def scaled(self, sx: float, sy: float, image_size: tuple[int, int]) -> TableCues:
        """The same reading of the photo resized by ``sx`` across and ``sy`` down to ``image_size`` [px] (the
        network input is scaled by the mean of the two)."""
        grow = np.array([sx, sy])
        scale = self.letterbox.scale / ((sx + sy) / 2)
        return replace(
            self,
            corners_px=self.corners_px * grow,
            sides_px=self.sides_px * grow,
            letterbox=Letterbox(scale, self.letterbox.size),
            image_size=(int(image_size[0]), int(image_size[1])),
        )

    def surface_mask(self, threshold: float = 0.5) -> np.ndarray:
        """(H, W) uint8 mask of the playing surface in the photo's pixels (1 on the surface)."""
        w, h = self.image_size
        grid = self.surface.astype(np.float32)
        # cell centres sit at 4j + 1.5 network px: resize the grid onto the padded input, then undo the scale
        net = cv2.resize(grid, (grid.shape[1] * STRIDE, grid.shape[0] * STRIDE), interpolation=cv2.INTER_LINEAR)
        M = np.array([[1 / self.letterbox.scale, 0, 0], [0, 1 / self.letterbox.scale, 0]], dtype=np.float64)
        full = cv2.warpAffine(net, M, (w, h), flags=cv2.INTER_LINEAR, borderValue=0.0)
        return (full >= threshold).astype(np.uint8)


def peaks(heat: np.ndarray, min_score: float = PEAK_MIN_SCORE, max_peaks: int = MAX_PEAKS) -> np.ndarray:
    """Local maxima (k, 3) of a heatmap: sub-cell x, y (3 x 3 weighted centre) and score, best first."""
    h, w = heat.shape
    padded = np.pad(heat, 1, constant_values=0.0)
    neighbours = np.stack([padded[dy : dy + h, dx : dx + w] for dy in range(3) for dx in range(3)])
    is_peak = (heat >= neighbours.max(axis=0)) & (heat >= min_score)
    ys, xs = np.nonzero(is_peak)
    order = np.argsort(-heat[ys, xs])[:max_peaks]
    out = []
    for y, x in zip(ys[order], xs[order], strict=True):
        window = padded[y : y + 3, x : x + 3]
        weight = window.sum()
        dy, dx = np.mgrid[-1:2, -1:2]
        out.append((x + (window * dx).sum() / weight, y + (window * dy).sum() / weight, heat[y, x]))
    return np.array(out, dtype=float).reshape(-1, 3)


class TableModel:
    """The table model (``table.onnx``).

    Args:
        model_path: the ``.onnx`` file written by ``pix2pockets train-table``.
        threads: onnxruntime intra-op threads (0 lets onnxruntime choose).

    Raises:
        ValueError: if the file does not exist, cannot be loaded or is not a table model.
    """

    def __init__(self, model_path: str | Path, threads: int = 1) -> None:
        self.model_path = Path(model_path)
        self.session = open_session(self.model_path, threads, "table model")
        out = self.session.get_outputs()[0]
        if out.name != OUTPUT_NAME or len(out.shape) != 4 or out.shape[1] != N_TABLE_CHANNELS:
            raise ValueError(
                f"{self.model_path} is not a table model: output {out.name!r} {out.shape} (expected {OUTPUT_NAME!r} "
                f"[n, {N_TABLE_CHANNELS}, h, w])"
            )
        self.input_name = self.session.get_inputs()[0].name

    @staticmethod
    def default_path() -> Path:
        """Path of the model shipped with the package (may not exist in a checkout without weights)."""
        from pix2pockets.vision.stages.base import shipped_model_path

        return shipped_model_path(DEFAULT_TABLE_MODEL)

    @classmethod
    def from_option(cls, option: str | Path | None, threads: int = 1) -> Self | None:
        """None -> the shipped model when this build has it (else None), ``"none"`` -> None, else that file."""
        if option is None:
            shipped = cls.default_path()
            return cls(shipped, threads) if shipped.is_file() else None
        if str(option).lower() == "none":
            return None
        return cls(option, threads)

    def read(self, image_rgb: np.ndarray) -> TableCues:
        """The table cues of an RGB uint8 photo (H, W, 3)."""
        image = np.asarray(image_rgb)
        if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 3:
            raise ValueError(f"expected an RGB uint8 image (H, W, 3), got {image.dtype} {image.shape}")
        x, box = network_input(image, INPUT_LONG_SIDE, INPUT_MULTIPLE)
        out = self.session.run(None, {self.input_name: x})[0][0]
        return cues_from_output(out, box, (image.shape[1], image.shape[0]))


def cues_from_output(out: np.ndarray, box: Letterbox, image_size: tuple[int, int]) -> TableCues:
    """:class:`TableCues` from the model's output (C, h, w) for a photo letterboxed by ``box``."""
    corners = peaks(out[CORNER_CHANNEL])
    sides = peaks(out[SIDE_CHANNEL])
    return TableCues(
        surface=out[SURFACE_CHANNEL],
        corners_px=box.to_image(pixel_of_cell(corners[:, :2])),
        corner_scores=corners[:, 2],
        sides_px=box.to_image(pixel_of_cell(sides[:, :2])),
        side_scores=sides[:, 2],
        letterbox=box,
        image_size=image_size,
    )
