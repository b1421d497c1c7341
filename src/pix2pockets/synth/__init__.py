"""Synthetic pool-table photos with exact labels: a domain-randomised CPU ray caster and dataset writer.

Public API:
    render_sample(seed, size) -> (RGB uint8 image, label dict)
    render(seed, size, portrait=share) -> Render (image, id buffer, occluder mask, labels); that share of phone
        views upright at (height, width)
    render_views(seed, size) -> [Render] for one layout seen from top, ~45 degrees and front
    write_dataset(out_dir, n, seed, ...) -> manifest (YOLO dataset in the Roboflow layout + JSON labels)
"""

from pix2pockets.synth.dataset import write_dataset
from pix2pockets.synth.renderer import DEFAULT_SIZE, Render, render, render_sample, render_views

__all__ = ["DEFAULT_SIZE", "Render", "render", "render_sample", "render_views", "write_dataset"]
