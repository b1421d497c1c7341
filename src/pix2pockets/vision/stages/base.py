"""The second-stage crop models' base: an ONNX network that reads square uint8 crops of the full-resolution photo.

Each crop model (ball classifier, ball refiner, diamond refiner, ball-number reader) is a small subclass that
names its model file, its ONNX output and its output width, and turns photo regions into crops and outputs into
answers. Loading, shape checks, the shipped file and the command-line option (`None` -> the shipped model when the
build has it, ``"none"`` -> no stage, a path -> that file) live here once.

Example:
    >>> from pix2pockets.vision.stages.ball_classifier import BallClassifier
    >>> clf = BallClassifier.from_option(None)  # doctest: +SKIP
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import ClassVar, Self

import numpy as np

from pix2pockets.vision.detect.onnx_session import open_crop_model


def shipped_model_path(file_name: str) -> Path:
    """Path of a model shipped as package data (``pix2pockets/data/models``; may not exist in a checkout)."""
    return Path(str(resources.files("pix2pockets.data").joinpath("models", file_name)))


class CropModel:
    """An ONNX crop network: input (n, S, S, 3) uint8 crops, output (n, :attr:`n_outputs`) named :attr:`output_name`.

    Args:
        model_path: the ``.onnx`` file written by the stage's ``pix2pockets train-*`` command.
        threads: onnxruntime intra-op threads (0 lets onnxruntime choose).

    Attributes:
        crop_size: side of the model's square crops [px]: the subclass's fixed :attr:`fixed_crop_size`, or the
            model's own input side when that is None.

    Raises:
        ValueError: if the file does not exist, cannot be loaded, or is another kind of model.
    """

    what: ClassVar[str] = "crop model"
    """What the model is, for error messages."""
    file_name: ClassVar[str]
    """The shipped model's file name in ``pix2pockets/data/models``."""
    output_name: ClassVar[str]
    """Name of the model's ONNX output (tells crop models with the same input apart)."""
    n_outputs: ClassVar[int]
    """Outputs per crop."""
    fixed_crop_size: ClassVar[int | None] = None
    """Crop side the model must take [px], or None for any square side."""

    def __init__(self, model_path: str | Path, threads: int = 1) -> None:
        path = Path(model_path)
        self.session = open_crop_model(path, threads, self.what, self.fixed_crop_size, self.output_name, self.n_outputs)
        self.input_name: str = self.session.get_inputs()[0].name
        self.crop_size: int = int(self.session.get_inputs()[0].shape[1])
        self.model_path = path

    @classmethod
    def default_path(cls) -> Path:
        """Path of the model shipped with the package (may not exist in a checkout without weights)."""
        return shipped_model_path(cls.file_name)

    @classmethod
    def from_default(cls, threads: int = 1) -> Self:
        """The model shipped with the package."""
        return cls(cls.default_path(), threads)

    @classmethod
    def from_option(cls, option: str | Path | None, threads: int = 1) -> Self | None:
        """The model a command-line option names: None -> the shipped one when this build has it (else None),
        ``"none"`` -> None (no such stage), anything else -> that ONNX file."""
        if option is None:
            shipped = cls.default_path()
            return cls(shipped, threads) if shipped.is_file() else None
        if str(option).lower() == "none":
            return None
        return cls(option, threads)

    def run(self, crops: np.ndarray) -> np.ndarray:
        """Model outputs (n, :attr:`n_outputs`) float32 for crops (n, S, S, 3) uint8 (none for no crops)."""
        if len(crops) == 0:
            return np.zeros((0, self.n_outputs), dtype=np.float32)
        return self.session.run(None, {self.input_name: crops})[0]
