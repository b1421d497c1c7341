"""The torch device of a training command's ``--device`` option."""

import pytest

from pix2pockets.torch_device import resolve_device


def test_resolve_device_names_checks_and_refuses_a_missing_gpu() -> None:
    torch = pytest.importorskip("torch")
    assert resolve_device("cpu") == "cpu"
    assert resolve_device("auto") in ("cpu", "cuda")
    with pytest.raises(ValueError, match="unknown device"):
        resolve_device("abacus")
    if not torch.cuda.is_available():
        with pytest.raises(ValueError, match="no CUDA GPU"):
            resolve_device("cuda")
