"""The bundled example photo with its exact labels, and a detector that returns them (fast, deterministic)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pix2pockets.data.examples import example_photo_path


@pytest.fixture(scope="session")
def rendered():
    """(file bytes, labels) of the bundled example photo (a pix2pockets.synth render)."""
    photo = Path(example_photo_path())
    labels = photo.with_name(photo.stem + ".labels.json")
    if not (photo.is_file() and labels.is_file()):
        pytest.skip("the bundled example photo or its labels are missing from this build")
    return photo.read_bytes(), json.loads(labels.read_text())
