"""Training of the detector and the crop models (needs the ``train`` extra: torch, onnx)."""
