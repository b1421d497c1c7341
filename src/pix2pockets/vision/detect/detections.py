"""A container of detections: parallel numpy arrays with boolean-mask indexing.

Example:
    >>> import numpy as np
    >>> det = Detections(np.array([[10, 10, 20, 20.0]]), np.array([0.9]), np.array([0]))
    >>> det[det.confidence > 0.5].boxes.shape
    (1, 4)
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from pix2pockets.vision.classes import BALL_IDS, CLASS_NAMES, DIAMOND_ID


@dataclass(frozen=True, slots=True, eq=False)
class Detections:
    """Detections in one image, in pixels.

    Attributes:
        boxes: (n, 4) boxes ``x1, y1, x2, y2`` [px].
        confidence: (n,) scores in [0, 1].
        class_id: (n,) class ids (see :data:`pix2pockets.vision.classes.CLASS_NAMES`).
        contact: (n, 2) predicted ball-cloth contact points [px], NaN where unknown (diamonds, or detectors that
            do not predict it).
        own_score: (n,) each entry's score on its own evidence, before a detector weighed it against the
            rest of the image (the cue ball and the 8 are each in view at most once, so a detector may
            report their scores as image-level chances,
            :func:`pix2pockets.vision.detect.postprocess.at_most_one_posterior`).
            Equal to ``confidence`` unless given.
        ball_score: (n,) the class-agnostic score that a ball is in the entry's box (a detector's "any ball"
            evidence, whatever its class), NaN where unknown (diamonds, detectors without it).
        data: further per-entry arrays, each (n, ...), selected and joined with the rest; e.g.
            ``number_probs`` (n, 16): the ball-number reader's chances of numbers 0-15, NaN where not read.
        pixel_aspect: width over height of one pixel of the photo, as the detector measured it from the balls
            (:mod:`pix2pockets.vision.table.pixel_aspect`); None when not measured.
    """

    boxes: np.ndarray
    confidence: np.ndarray
    class_id: np.ndarray
    contact: np.ndarray = field(default=None)  # type: ignore[assignment]
    own_score: np.ndarray = field(default=None)  # type: ignore[assignment]
    ball_score: np.ndarray = field(default=None)  # type: ignore[assignment]
    data: dict[str, np.ndarray] = field(default_factory=dict)
    pixel_aspect: float | None = None

    def __post_init__(self) -> None:
        boxes = np.asarray(self.boxes, dtype=float).reshape(-1, 4)
        n = len(boxes)
        conf = np.asarray(self.confidence, dtype=float).reshape(-1)
        cls = np.asarray(self.class_id, dtype=int).reshape(-1)
        contact = (
            np.full((n, 2), np.nan) if self.contact is None else np.asarray(self.contact, dtype=float).reshape(-1, 2)
        )
        own = conf.copy() if self.own_score is None else np.asarray(self.own_score, dtype=float).reshape(-1)
        ball = np.full(n, np.nan) if self.ball_score is None else np.asarray(self.ball_score, dtype=float).reshape(-1)
        if not (len(conf) == len(cls) == len(contact) == len(own) == len(ball) == n):
            raise ValueError(
                f"Detections arrays differ in length: boxes {n}, confidence {len(conf)}, class_id {len(cls)}, "
                f"contact {len(contact)}, own_score {len(own)}, ball_score {len(ball)}"
            )
        data = {key: np.asarray(value) for key, value in self.data.items()}
        for key, value in data.items():
            if len(value) != n:
                raise ValueError(f"Detections data {key!r} has {len(value)} rows for {n} detections")
        if n and (cls.min() < 0 or cls.max() >= len(CLASS_NAMES)):
            raise ValueError(f"class ids must be in 0..{len(CLASS_NAMES) - 1}")
        object.__setattr__(self, "boxes", boxes)
        object.__setattr__(self, "confidence", conf)
        object.__setattr__(self, "class_id", cls)
        object.__setattr__(self, "contact", contact)
        object.__setattr__(self, "own_score", own)
        object.__setattr__(self, "ball_score", ball)
        object.__setattr__(self, "data", data)

    @classmethod
    def empty(cls) -> Detections:
        return cls(np.zeros((0, 4)), np.zeros(0), np.zeros(0, dtype=int))

    def __len__(self) -> int:
        return len(self.boxes)

    def __getitem__(self, index: np.ndarray | slice | list[int]) -> Detections:
        """Select detections by boolean mask, index array or slice."""
        return Detections(
            self.boxes[index],
            self.confidence[index],
            self.class_id[index],
            self.contact[index],
            self.own_score[index],
            self.ball_score[index],
            {key: value[index] for key, value in self.data.items()},
            self.pixel_aspect,
        )

    def scaled(self, sx: float, sy: float) -> Detections:
        """The same detections in the photo resized by ``sx`` across and ``sy`` down (boxes, contacts and the pixel
        aspect scaled)."""
        return replace(
            self,
            boxes=self.boxes * np.array([sx, sy, sx, sy]),
            contact=self.contact * np.array([sx, sy]),
            pixel_aspect=None if self.pixel_aspect is None else self.pixel_aspect * sx / sy,
        )

    @property
    def centres(self) -> np.ndarray:
        """(n, 2) box centres [px]."""
        return (self.boxes[:, :2] + self.boxes[:, 2:]) / 2

    @property
    def class_names(self) -> list[str]:
        return [CLASS_NAMES[i] for i in self.class_id]

    @property
    def is_ball(self) -> np.ndarray:
        return np.isin(self.class_id, BALL_IDS)

    @property
    def is_diamond(self) -> np.ndarray:
        return self.class_id == DIAMOND_ID

    def to_list(self) -> list[dict]:
        """JSON-ready list of ``{class, confidence, bbox_px, contact_px, own_score, ball_score}`` (the last three
        when known and, for ``own_score``, when it differs from ``confidence``)."""
        out = []
        for b, c, k, p, own, ball in zip(
            self.boxes, self.confidence, self.class_id, self.contact, self.own_score, self.ball_score, strict=True
        ):
            item = {
                "class": CLASS_NAMES[k],
                "confidence": round(float(c), 4),
                "bbox_px": [round(float(v), 2) for v in b],
            }
            if round(float(own), 4) != item["confidence"]:
                item["own_score"] = round(float(own), 4)
            if np.all(np.isfinite(p)):
                item["contact_px"] = [round(float(v), 2) for v in p]
            if np.isfinite(ball):
                item["ball_score"] = round(float(ball), 4)
            out.append(item)
        return out

    @staticmethod
    def concatenate(parts: list[Detections]) -> Detections:
        """The parts one after another; a ``data`` array missing from a part is NaN there, and the pixel aspect
        is the first part's that has one."""
        if not parts:
            return Detections.empty()
        data = {}
        for key in dict.fromkeys(k for p in parts for k in p.data):
            shape = next(p.data[key].shape[1:] for p in parts if key in p.data)
            data[key] = np.concatenate(
                [p.data[key] if key in p.data else np.full((len(p), *shape), np.nan) for p in parts]
            )
        return Detections(
            np.vstack([p.boxes for p in parts]),
            np.concatenate([p.confidence for p in parts]),
            np.concatenate([p.class_id for p in parts]),
            np.vstack([p.contact for p in parts]),
            np.concatenate([p.own_score for p in parts]),
            np.concatenate([p.ball_score for p in parts]),
            data,
            next((p.pixel_aspect for p in parts if p.pixel_aspect is not None), None),
        )
