"""Stand-ins for the detector, the number reader and the planner: exact labels and a simple planner.

They let tests and benchmarks run the photo pipeline without the trained models (or measure the pipeline's other
stages alone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pix2pockets.geometry import PinholeCamera, TableSpec
from pix2pockets.state import Ball, Shot, TableLayout
from pix2pockets.vision.classes import CLASS_NAMES, DIAMOND_ID
from pix2pockets.vision.detect.analytic import analytic_detections, standard_views
from pix2pockets.vision.detect.detections import Detections

SPEC = TableSpec()


def example_layout() -> TableLayout:
    numbers = [0, 1, 2, 8, 9, 10]
    pos = [[0.6, 0.6], [1.9, 0.95], [1.2, 0.3], [1.5, 0.7], [2.1, 0.3], [0.4, 1.0]]
    return TableLayout(tuple(Ball.numbered(n) for n in numbers), np.array(pos), SPEC)


@dataclass
class LabelDetector:
    """Returns the exact labels of a known camera and layout (any image of the camera's size)."""

    camera: PinholeCamera
    layout: TableLayout
    drop: tuple[int, ...] = ()  # layout indices to leave out (e.g. the cue ball)
    diamonds: bool = True

    def detect(self, image_rgb: np.ndarray) -> Detections:
        det = analytic_detections(self.camera, self.layout.without(list(self.drop)))
        if not self.diamonds:
            det = det[~det.is_diamond]
        return det


@dataclass(frozen=True)
class Candidate:
    shot: Shot
    target: int | None
    pocket: int | None
    kind: str | None
    success_probability: float | None
    value: float = 0.0
    hitpoint: object = None
    safety: bool = False


class NearestPocketPlanner:
    """Direct shot: the own ball closest to a pocket, ghost-ball aim; a safety when there is none."""

    name = "nearest-pocket"

    def suggest(self, layout, state, rng=None):
        cue = layout.cue_index
        own = layout.indices_of(state.group.ball_class) or (
            [layout.black_index] if layout.black_index is not None else []
        )
        spec = layout.spec
        out = []
        for i in own:
            for k, p in enumerate(spec.pockets):
                d = float(np.linalg.norm(p.aim - layout.positions[i]))
                u = (p.aim - layout.positions[i]) / d
                ghost = layout.positions[i] - 2 * spec.ball_radius * u
                shot = Shot.toward(tuple(layout.positions[cue]), tuple(ghost), 2.0)
                out.append(Candidate(shot, i, k, "direct", max(0.05, 1.0 - d), 1.0 - d))
        if not out:
            return [Candidate(Shot(angle=0.0, speed=1.0), None, None, None, 0.0, -1.0, safety=True)]
        return sorted(out, key=lambda c: -c.value)


def camera(view: str = "45") -> PinholeCamera:
    return standard_views(SPEC)[view]


def blank_image(cam: PinholeCamera) -> np.ndarray:
    w, h = cam.image_size
    img = np.zeros((h, w, 3), dtype=np.uint8)
    img[:] = (30, 90, 40)
    return img


def angle_deg(a: float) -> float:
    return math.degrees(a) % 360


class ExampleLabelsDetector:
    """Exact labels of the bundled example photo (full silhouette boxes)."""

    def __init__(self) -> None:
        import json
        from pathlib import Path

        from pix2pockets.data.examples import example_labels_path

        self.labels = json.loads(Path(example_labels_path()).read_text())

    def detect(self, image_rgb: np.ndarray) -> Detections:
        from pix2pockets.vision.detect.analytic import detections_from_synth_labels

        return detections_from_synth_labels(self.labels, silhouette=True)


@dataclass
class LabelNumberReader:
    """Reads each ball's number from the known layout: the number of the ball whose centre projects nearest the
    box."""

    camera: PinholeCamera
    layout: TableLayout

    def numbers(self, image_rgb: np.ndarray, boxes: np.ndarray, class_ids: np.ndarray, aspect=None):
        from pix2pockets.vision.stages.ball_numbers import N_NUMBERS, assign_numbers

        centres = self.camera.project_table(self.layout.positions, SPEC.ball_radius)
        mid = 0.5 * (boxes[:, :2] + boxes[:, 2:])
        nearest = np.linalg.norm(mid[:, None] - centres[None], axis=2).argmin(axis=1)
        probs = np.full((len(boxes), N_NUMBERS), 0.01)
        probs[np.arange(len(boxes)), [self.layout.balls[i].number for i in nearest]] = 1.0
        return assign_numbers(probs, class_ids)


@dataclass
class LabelsDetector:
    """Returns the labelled balls and diamonds of a synth render (its label dict), minus the classes in ``drop``."""

    labels: dict
    drop: tuple[str, ...] = ()

    def detect(self, image_rgb: np.ndarray) -> Detections:
        rows = [(b["class_id"], b["box_px"]) for b in self.labels["balls"] if b["labelled"]]
        rows += [(DIAMOND_ID, d["box_px"]) for d in self.labels["diamonds"] if d["labelled"]]
        rows = [r for r in rows if CLASS_NAMES[r[0]] not in self.drop]
        boxes = np.array([box for _, box in rows], dtype=float).reshape(-1, 4)
        return Detections(boxes, np.ones(len(rows)), np.array([c for c, _ in rows], dtype=int))
