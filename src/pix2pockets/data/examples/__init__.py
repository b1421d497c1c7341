"""The bundled example photo (a ``pix2pockets synth`` render of a 9-ft table) and its exact labels."""

from __future__ import annotations

from importlib import resources

EXAMPLE_PHOTO = "table_example.jpg"
EXAMPLE_LABELS = "table_example.labels.json"


def example_photo_path() -> str:
    """Path of the bundled example photo."""
    return str(resources.files(__name__).joinpath(EXAMPLE_PHOTO))


def example_labels_path() -> str:
    """Path of the bundled example photo's label file (balls and diamonds as rendered)."""
    return str(resources.files(__name__).joinpath(EXAMPLE_LABELS))
