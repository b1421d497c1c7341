"""Exact labels from the id buffer: ball and diamond boxes, visibility, reference points, camera.

Box convention: YOLO boxes are the **visible extent** of each object (the bounding box of its pixels that
are neither hidden by another object nor by a 2-D occluder/overlay), clipped to the image. Diamonds are
tiny, so their box is the projected outline of the sight, padded to at least ``MIN_DIAMOND_BOX_PX`` and clipped.
The label file also keeps each ball's full silhouette box (clipped) so a consumer can choose.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.state.ball_set import class_name
from pix2pockets.synth import scene_codes as sc
from pix2pockets.synth.scene import Scene
from pix2pockets.synth.shading import OVAL_AXES, SQUARE_HALF
from pix2pockets.vision.classes import CLASS_NAMES, DIAMOND_ID, MIN_DIAMOND_BOX_PX

BALL_MIN_VISIBLE = 0.3
"""A ball goes into the YOLO labels when at least this fraction of its silhouette is visible."""
BALL_MIN_PIXELS = 6
DIAMOND_MIN_VISIBLE = 0.5
DIAMOND_MIN_SIGNAL = 12
"""A diamond goes into the YOLO labels only when drawing it changes some pixel of the final photo (after
blur, noise and compression) by at least this much (0-255, largest channel): a sight that is there in the
geometry but cannot be seen (sub-pixel at a grazing angle, the rail's own colour, washed out by blur) is not
something a detector, or a person labelling photos, can find."""
DIAMOND_SIGNAL_MARGIN_PX = 2
"""The signal is looked for this far around a diamond's box [px] (blur spreads a small sight)."""
CLASS_OF_NUMBER = {0: 0, 8: 1, **{n: 2 for n in range(1, 8)}, **{n: 3 for n in range(9, 16)}}


def sphere_outline_px(cam: PinholeCamera, centre: np.ndarray, radius: float, n: int = 48) -> np.ndarray | None:
    """Image outline (n, 2) of a sphere's silhouette (its contour generator), or ``None`` when the sphere
    reaches behind the camera."""
    c = cam.position
    v = np.asarray(centre, float) - c
    d = float(np.linalg.norm(v))
    if d <= radius * 1.01:
        return None
    axis = v / d
    q = c + v * (1 - radius**2 / d**2)
    rho = radius * math.sqrt(1 - radius**2 / d**2)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    pts = q + rho * (np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2)
    if np.any(cam.world_to_camera(pts)[:, 2] <= 1e-3):
        return None
    return cam.project(pts)


def polygon_area(poly: np.ndarray) -> float:
    """Shoelace area of a closed polygon (n, 2) [px^2]."""
    x, y = poly[:, 0], poly[:, 1]
    return float(abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1))) / 2)


def diamond_outline(scene: Scene, k: int, n: int = 16) -> np.ndarray:
    """Outline of diamond ``k`` on the rail cap in table coordinates (n, 3) [m]."""
    g = scene.geo
    dr = g[sc.G_DR]
    xy = scene.spec.diamonds[k]
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    shape = int(scene.shade[sc.S_DIA_SHAPE] + 0.5)
    long_rail = k < 6 or 9 <= k < 15
    if shape == sc.SIGHT_RHOMBUS:
        along, across = 1.6 * dr, 0.8 * dr
        ax, ay = (along, across) if long_rail else (across, along)
        pts = np.array([[ax, 0], [0, ay], [-ax, 0], [0, -ay]])
    elif shape == sc.SIGHT_SQUARE:
        s = SQUARE_HALF * dr
        pts = np.array([[s, s], [-s, s], [-s, -s], [s, -s]])
    elif shape == sc.SIGHT_OVAL:
        along, across = OVAL_AXES[0] * dr, OVAL_AXES[1] * dr
        ax, ay = (along, across) if long_rail else (across, along)
        pts = np.column_stack([ax * np.cos(th), ay * np.sin(th)])
    else:
        pts = dr * np.column_stack([np.cos(th), np.sin(th)])
    return np.column_stack([pts + xy, np.full(len(pts), g[sc.G_HR])])


def _clip_box(box: np.ndarray, w: int, h: int) -> list[float] | None:
    x0, y0, x1, y1 = max(box[0], 0.0), max(box[1], 0.0), min(box[2], float(w)), min(box[3], float(h))
    if x1 <= x0 or y1 <= y0:
        return None
    return [round(float(x0), 2), round(float(y0), 2), round(float(x1), 2), round(float(y1), 2)]


def _inside(p: np.ndarray, w: int, h: int) -> bool:
    return bool(np.all(np.isfinite(p)) and 0 <= p[0] < w and 0 <= p[1] < h)


def _peak_in_box(values: np.ndarray, box: list[float], margin: int) -> int:
    """Largest value of ``values`` (H, W) inside the xyxy box [px] grown by ``margin`` pixels."""
    h, w = values.shape
    x0, y0 = max(int(np.floor(box[0])) - margin, 0), max(int(np.floor(box[1])) - margin, 0)
    x1, y1 = min(int(np.ceil(box[2])) + margin, w), min(int(np.ceil(box[3])) + margin, h)
    return int(values[y0:y1, x0:x1].max()) if x1 > x0 and y1 > y0 else 0


def camera_dict(cam: PinholeCamera, kind: str) -> dict:
    """The camera as JSON: intrinsics K, pose (R, t: X_cam = R X_world + t), image size, centre and orientation."""
    return {
        "kind": kind,
        "K": np.round(cam.K, 6).tolist(),
        "R": np.round(cam.R, 9).tolist(),
        "t": np.round(cam.t, 9).tolist(),
        "image_size": list(cam.image_size),
        "position_m": np.round(cam.position, 6).tolist(),
        "orientation": "portrait" if cam.image_size[1] > cam.image_size[0] else "landscape",
    }


def build_labels(
    scene: Scene,
    cam: PinholeCamera,
    ids: np.ndarray,
    occluded: np.ndarray,
    sil_count: np.ndarray,
    diamond_signal: np.ndarray | None = None,
) -> dict:
    """Ball, diamond, corner and pocket labels for one render.

    Args:
        scene: the rendered scene.
        cam: the camera.
        ids: id buffer from the ray caster (H, W).
        occluded: pixels covered by 2-D occluders or overlays (H, W) bool.
        sil_count: pixels per ball whose ray meets the ball's sphere, occluded or not (n,).
        diamond_signal: per pixel, how much the diamonds change the final photo (H, W) [0-255]; when given,
            a diamond is labelled only if it reaches ``DIAMOND_MIN_SIGNAL`` within its box.
    """
    w, h = cam.image_size
    counts, hidden, boxes = object_stats(ids, occluded, sc.ID_BALL0 + 16)
    spec = scene.spec
    r = spec.ball_radius
    balls = []
    for i, (ball, centre) in enumerate(zip(scene.layout.balls, scene.ball_centres, strict=True)):
        k = sc.ID_BALL0 + i
        outline = sphere_outline_px(cam, centre, centre[2])  # on the cloth: centre height = radius
        area = polygon_area(outline) if outline is not None else float("nan")
        full_box = (
            _clip_box(np.array([*outline.min(axis=0), *outline.max(axis=0)]), w, h) if outline is not None else None
        )
        vis_px = int(counts[k])
        vis_box = None
        if vis_px > 0:
            b = boxes[k]
            vis_box = [float(b[0]), float(b[1]), float(b[2] + 1), float(b[3] + 1)]
        in_frame_px = int(sil_count[i])
        frame_px = in_frame_px if not math.isfinite(area) else max(area, 1e-9)
        in_frame_fraction = min(1.0, in_frame_px / frame_px) if math.isfinite(area) else 1.0
        visible_fraction = min(1.0, vis_px / frame_px) if frame_px > 0 else 0.0
        occluded_fraction = 1.0 - vis_px / in_frame_px if in_frame_px > 0 else 1.0
        labelled = visible_fraction >= BALL_MIN_VISIBLE and vis_px >= BALL_MIN_PIXELS and vis_box is not None
        balls.append(
            {
                "number": int(ball.number),
                "class": class_name(CLASS_NAMES[CLASS_OF_NUMBER[int(ball.number)]], scene.ball_set),
                "class_id": CLASS_OF_NUMBER[int(ball.number)],
                "centre_table_m": np.round(centre, 6).tolist(),
                "centre_px": np.round(cam.project(centre), 3).tolist(),
                "contact_px": np.round(cam.project(np.array([centre[0], centre[1], 0.0])), 3).tolist(),
                "box_px": vis_box,
                "silhouette_box_px": full_box,
                "silhouette_area_px": round(area, 2) if math.isfinite(area) else None,
                "visible_px": vis_px,
                "in_frame_fraction": round(float(in_frame_fraction), 4),
                "visible_fraction": round(float(visible_fraction), 4),
                "occluded_fraction": round(float(max(0.0, occluded_fraction)), 4),
                "hidden_by_occluder_px": int(hidden[k]),
                "labelled": bool(labelled),
            }
        )

    diamonds = []
    hr = float(scene.geo[sc.G_HR])
    for k, xy in enumerate(spec.diamonds):
        idk = sc.ID_DIAMOND0 + k
        p3 = np.array([xy[0], xy[1], hr])
        centre_px = cam.project(p3)
        outline = cam.project(diamond_outline(scene, k))
        in_frame = _inside(centre_px, w, h)
        entry = {
            "index": k,
            "table_m": np.round(p3, 6).tolist(),
            "px": np.round(centre_px, 3).tolist() if np.all(np.isfinite(centre_px)) else None,
            "in_frame": in_frame,
            "box_px": None,
            "visible_fraction": 0.0,
            "labelled": False,
        }
        front = np.all(np.isfinite(outline)) and np.all(cam.world_to_camera(diamond_outline(scene, k))[:, 2] > 1e-3)
        if scene.has_sights and front:  # plain rails keep the sight positions, unlabelled
            area = polygon_area(outline)
            if area < 8.0:
                if in_frame:
                    u, v = int(centre_px[0]), int(centre_px[1])
                    vis = float(ids[v, u] in (idk, sc.ID_CAP) and not occluded[v, u])
                else:
                    vis = 0.0
            else:
                vis = min(1.0, counts[idk] / area)
            lo, hi = outline.min(axis=0), outline.max(axis=0)
            c = (lo + hi) / 2
            half = np.maximum((hi - lo) / 2, MIN_DIAMOND_BOX_PX / 2)
            box = _clip_box(np.array([*(c - half), *(c + half)]), w, h)
            entry["box_px"] = box
            entry["visible_fraction"] = round(float(vis), 4)
            seen = True
            if diamond_signal is not None and box is not None:
                signal = _peak_in_box(diamond_signal, box, DIAMOND_SIGNAL_MARGIN_PX)
                entry["signal"] = signal
                seen = signal >= DIAMOND_MIN_SIGNAL
            entry["labelled"] = bool(in_frame and box is not None and vis >= DIAMOND_MIN_VISIBLE and seen)
        diamonds.append(entry)

    corners = []
    hc = float(scene.geo[sc.G_H])
    for k, xy in enumerate(spec.corners):
        p_nose = cam.project(np.array([xy[0], xy[1], hc]))
        p_cloth = cam.project(np.array([xy[0], xy[1], 0.0]))
        corners.append(
            {
                "index": k,
                "table_m": np.round(xy, 6).tolist(),
                "px": np.round(p_nose, 3).tolist() if np.all(np.isfinite(p_nose)) else None,
                "px_cloth": np.round(p_cloth, 3).tolist() if np.all(np.isfinite(p_cloth)) else None,
                "in_frame": _inside(p_nose, w, h),
            }
        )
    return {
        "balls": balls,
        "diamonds": diamonds,
        "corners": corners,
        "pockets": pocket_labels(scene, cam, ids, occluded),
        "heights_m": {"diamonds": hr, "corners": hc, "ball_centres": r},
        "table": {"name": spec.name, "length_m": spec.length, "width_m": spec.width, "ball_radius_m": r},
    }


POCKET_SURFACE_IDS = (sc.ID_CLOTH, sc.ID_HOLE, sc.ID_LINER)
"""Ids that count as seeing a pocket's mouth point: the cloth there, the hole, or the pocket's liner ring."""


def pocket_labels(scene: Scene, cam: PinholeCamera, ids: np.ndarray, occluded: np.ndarray) -> list[dict]:
    """The six pockets in ``TableSpec.pockets`` order, their mouth centres (``Pocket.aim``) on the cloth.

    Each entry: ``index``, ``name``, ``kind`` (corner | side), ``table_m`` (aim x, y and z = 0 [m]), ``px`` (its
    projection [px], None behind the camera), ``in_frame``, ``visible`` (the pixel at ``px`` shows the cloth, the
    hole or the liner and no person, prop or overlay covers it), ``hole_table_m`` (centre of the drawn drop hole
    at cloth level [m]), ``hole_radius_m`` and ``hole_px`` (the hole centre projected [px]).
    """
    w, h = cam.image_size
    out = []
    for k, pocket in enumerate(scene.spec.pockets):
        p3 = np.array([pocket.aim[0], pocket.aim[1], 0.0])
        p = cam.project(p3)
        ok = bool(np.all(np.isfinite(p)) and cam.world_to_camera(p3)[2] > 1e-3)
        in_frame = ok and _inside(p, w, h)
        visible = False
        if in_frame:
            u, v = int(p[0]), int(p[1])
            visible = bool(ids[v, u] in POCKET_SURFACE_IDS and not occluded[v, u])
        hole = scene.holes[k]
        hole3 = np.array([hole[0], hole[1], 0.0])
        hp = cam.project(hole3)
        hole_ok = bool(np.all(np.isfinite(hp)) and cam.world_to_camera(hole3)[2] > 1e-3)
        out.append(
            {
                "index": k,
                "name": pocket.name,
                "kind": pocket.kind.value,
                "table_m": [round(float(pocket.aim[0]), 6), round(float(pocket.aim[1]), 6), 0.0],
                "px": np.round(p, 3).tolist() if ok else None,
                "in_frame": in_frame,
                "visible": visible,
                "hole_table_m": [round(float(hole[0]), 6), round(float(hole[1]), 6), 0.0],
                "hole_radius_m": round(float(hole[2]), 6),
                "hole_px": np.round(hp, 3).tolist() if hole_ok else None,
            }
        )
    return out


def yolo_lines(labels: dict) -> list[str]:
    """YOLO rows ``class cx cy w h`` (normalised) for the labelled balls and diamonds."""
    w, h = labels["image_size"]
    rows = []
    for ball in labels["balls"]:
        if ball["labelled"]:
            rows.append((ball["class_id"], ball["box_px"]))
    for diamond in labels["diamonds"]:
        if diamond["labelled"]:
            rows.append((DIAMOND_ID, diamond["box_px"]))
    out = []
    for cls, (x0, y0, x1, y1) in rows:
        out.append(f"{cls} {(x0 + x1) / 2 / w:.6f} {(y0 + y1) / 2 / h:.6f} {(x1 - x0) / w:.6f} {(y1 - y0) / h:.6f}")
    return out


@njit(cache=True)
def object_stats(ids, occluded, n_ids):
    """Per id: visible pixel count, count hidden by 2-D occluders, and the bbox of the visible pixels.

    Returns:
        counts (n_ids,) visible pixels, hidden (n_ids,) pixels covered by ``occluded``, boxes (n_ids, 4)
        as x0, y0, x1, y1 (inclusive pixel indices; -1 when no pixel is visible).
    """
    counts = np.zeros(n_ids, np.int64)
    hidden = np.zeros(n_ids, np.int64)
    boxes = np.full((n_ids, 4), -1, np.int64)
    H, W = ids.shape
    for v in range(H):
        for u in range(W):
            k = ids[v, u]
            if k <= 0 or k >= n_ids:
                continue
            if occluded[v, u]:
                hidden[k] += 1
                continue
            if counts[k] == 0:
                boxes[k, 0] = u
                boxes[k, 1] = v
                boxes[k, 2] = u
                boxes[k, 3] = v
            else:
                if u < boxes[k, 0]:
                    boxes[k, 0] = u
                if u > boxes[k, 2]:
                    boxes[k, 2] = u
                if v < boxes[k, 1]:
                    boxes[k, 1] = v
                if v > boxes[k, 3]:
                    boxes[k, 3] = v
            counts[k] += 1
    return counts, hidden, boxes
