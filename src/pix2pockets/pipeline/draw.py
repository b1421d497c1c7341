"""The result picture: the photo with the shot drawn in perspective, a top-down diagram, a text line.

Everything is drawn with OpenCV primitives and its built-in Hershey font (nothing is downloaded).
Colours are RGB.
"""

from __future__ import annotations

import itertools

import numpy as np

from pix2pockets.geometry.camera import PinholeCamera
from pix2pockets.geometry.raster import TableRaster
from pix2pockets.pipeline.result import LocatedBall, Suggestion
from pix2pockets.synth.palette import BALL_COLOURS as NUMBER_COLOURS
from pix2pockets.synth.palette import CLOTH_COLOURS
from pix2pockets.vision.image_io import capped_size
from pix2pockets.vision.table.cloth_edge import cloth_colour
from pix2pockets.vision.table.cloth_region import lab_of
from pix2pockets.vision.table.quad_geometry import quad_mask

CUE_PATH = (255, 255, 255)
OBJECT_PATH = (255, 210, 0)
GHOST = (255, 255, 255)
CUE_AFTER = (190, 225, 255)
"""Where the cue ball goes after the first ball (dashed), and where it stops (a ring)."""
SCRATCH = (255, 70, 70)
"""The ring where a planned stroke drops the cue ball."""
TABLE_LINE = (120, 255, 120)
IN_HAND = (40, 200, 255)
"""Ring round a cue ball put by ball in hand (photo and diagram)."""
CLOTH = (22, 92, 150)
"""Diagram cloth when the photo's cloth is not read."""
LIGHTNESS_WEIGHT = 0.5
"""Weight of Lab lightness against hue and chroma when the photo's cloth is matched to a cloth colour: the light over
a table changes how bright its cloth looks more than its hue."""
MIN_CLOTH_PIXELS = 100
"""Fewest pixels of the fitted playing surface in the photo for its cloth colour to be read."""
RAIL = (92, 56, 30)
POCKET = (15, 15, 15)
BALL_COLOURS = {
    "cue": (245, 245, 240),
    "black": (20, 20, 20),
    "solid": (230, 190, 20),
    "stripe": (200, 40, 40),
    "red": (200, 25, 35),
    "yellow": (245, 200, 35),
}
"""Diagram colours (RGB) by class name: a blackball set's balls are red and yellow."""
TEXT_BAND = 44  # [px]
MAX_PHOTO_SIDE = 1920
"""Longest side [px] of the photo in the result picture: a larger photo (a 12 MP phone photo) is drawn on a copy of
this size, so that its lines and text stay legible when the picture is viewed whole."""
UNSURE = (200, 225, 240)
UNSURE_SIGMA = 0.01
"""A ball located less surely than this [m] (``LocatedBall.position_sigma_m``) gets a ring on the diagram two of its
errors beyond its edge: it may lie anywhere inside."""


def _cv2():
    import cv2

    return cv2


def _sphere_outline(camera: PinholeCamera, centre_xy: np.ndarray, radius: float, n: int = 600) -> np.ndarray:
    """Image outline (convex hull) of a ball at ``centre_xy`` [m] resting on the cloth, int32 (k, 1, 2)."""
    cv2 = _cv2()
    rng = np.random.default_rng(0)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    pts = camera.project(np.array([centre_xy[0], centre_xy[1], radius]) + radius * d)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    return cv2.convexHull(np.round(pts).astype(np.int32))


def _project_path(camera: PinholeCamera, path: np.ndarray, z: float, samples: int = 20) -> np.ndarray:
    """A table polyline [m] at height ``z`` projected into the image (densely sampled), int32 (k, 1, 2)."""
    if len(path) < 2:
        return np.zeros((0, 1, 2), dtype=np.int32)
    pts = []
    for a, b in itertools.pairwise(path):
        s = np.linspace(0.0, 1.0, samples)[:, None]
        pts.append(a + s * (b - a))
    uv = camera.project_table(np.vstack(pts), z)
    uv = uv[np.all(np.isfinite(uv), axis=1)]
    return np.round(uv).astype(np.int32).reshape(-1, 1, 2)


def _arrow_head(img: np.ndarray, poly: np.ndarray, colour: tuple, size: int) -> None:
    """Two short strokes at the end of a polyline (int32 (k, 1, 2)), ``size`` [px] long."""
    cv2 = _cv2()
    pts = poly.reshape(-1, 2).astype(float)
    if len(pts) < 2:
        return
    end = pts[-1]
    back = pts[:-1][np.linalg.norm(pts[:-1] - end, axis=1) > 1.0]
    if not len(back):
        return
    d = end - back[-1]
    d /= np.linalg.norm(d)
    for sign in (1.0, -1.0):
        c, s_ = np.cos(sign * 2.6), np.sin(sign * 2.6)
        tip = end + size * np.array([c * d[0] - s_ * d[1], s_ * d[0] + c * d[1]])
        cv2.line(img, tuple(int(v) for v in end), tuple(int(v) for v in tip), colour, 2, cv2.LINE_AA)


def _dashed(img: np.ndarray, poly: np.ndarray, colour: tuple, thick: int, dash: int) -> None:
    """A polyline (int32 (k, 1, 2)) drawn as dashes ``dash`` [px] long with gaps as long."""
    cv2 = _cv2()
    pts = poly.reshape(-1, 2).astype(float)
    if len(pts) < 2:
        return
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    for start in np.arange(0.0, along[-1], 2 * dash):
        stops = np.linspace(start, min(start + dash, along[-1]), 6)
        piece = np.column_stack([np.interp(stops, along, pts[:, 0]), np.interp(stops, along, pts[:, 1])])
        cv2.polylines(img, [np.round(piece).astype(np.int32).reshape(-1, 1, 2)], False, colour, thick, cv2.LINE_AA)


def _ball_face(ball: LocatedBall) -> tuple[tuple[int, int, int], bool]:
    """Diagram colour (RGB) of a ball and whether it is drawn as a stripe: its own colour when its number is
    read with some certainty (a stripe's band), else a colour for its class."""
    number = ball.sure_number
    if number is None:
        return BALL_COLOURS[ball.ball_class], ball.ball_class == "stripe"
    base = NUMBER_COLOURS[number - 8 if number > 8 else number]
    return tuple(round(255 * v) for v in base), number > 8


def _striped_disc(img: np.ndarray, centre: tuple[int, int], radius: int, colour: tuple) -> None:
    """A white disc with a horizontal band of `colour` across its middle (a stripe seen from the side)."""
    cv2 = _cv2()
    x0, y0 = max(0, centre[0] - radius - 1), max(0, centre[1] - radius - 1)
    x1, y1 = min(img.shape[1], centre[0] + radius + 2), min(img.shape[0], centre[1] + radius + 2)
    if x1 <= x0 or y1 <= y0:
        return
    patch = img[y0:y1, x0:x1]
    disc = np.zeros(patch.shape[:2], dtype=np.uint8)
    cv2.circle(disc, (centre[0] - x0, centre[1] - y0), radius, 255, -1, cv2.LINE_AA)
    band = np.abs(np.arange(y0, y1) - centre[1]) <= 0.55 * radius
    face = np.where(band[:, None, None], np.array(colour, float), np.array((245.0, 245.0, 240.0)))
    alpha = disc[:, :, None] / 255.0
    patch[:] = np.round(patch * (1 - alpha) + face * alpha).astype(np.uint8)


def _draw_number(img: np.ndarray, centre: tuple[int, int], number: int, radius: int) -> None:
    """A ball's number in a small white disc at its centre, sized to a ball of `radius` [px]."""
    cv2 = _cv2()
    if number == 0 or radius < 6:
        return
    cv2.circle(img, centre, max(3, round(radius * 0.62)), (250, 250, 245), -1, cv2.LINE_AA)
    text = str(number)
    scale = radius / 24
    (tw, th), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, scale, 1)
    org = (centre[0] - tw // 2, centre[1] + th // 2)
    cv2.putText(img, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, (10, 10, 10), 1, cv2.LINE_AA)


def draw_photo(rgb: np.ndarray, result: Suggestion) -> np.ndarray:
    """The photo with the table outline, the ball markers and the shot drawn in perspective."""
    cv2 = _cv2()
    img = np.ascontiguousarray(rgb.copy())
    cam: PinholeCamera = result.camera  # type: ignore[assignment]
    spec = result.spec
    R = spec.ball_radius
    thick = max(2, round(img.shape[1] / 640))
    corners = np.round(result.corners_px).astype(np.int32).reshape(-1, 1, 2)
    cv2.polylines(img, [corners], True, TABLE_LINE, 1, cv2.LINE_AA)
    for ball, xy in zip(result.balls, result.layout.positions, strict=True):
        if ball.in_hand:  # not in the photo: the ball drawn where to put it
            outline = _sphere_outline(cam, xy, R)
            cv2.fillPoly(img, [outline], BALL_COLOURS["cue"], cv2.LINE_AA)
            cv2.polylines(img, [outline], True, IN_HAND, thick, cv2.LINE_AA)
            continue
        c = tuple(round(v) for v in ball.contact_px)
        cv2.circle(img, c, thick + 1, BALL_COLOURS[ball.ball_class], -1, cv2.LINE_AA)
    shot = result.shot
    cue_poly = _project_path(cam, shot.cue_path, R)
    obj_poly = _project_path(cam, shot.object_path, R)
    if len(cue_poly):
        cv2.polylines(img, [cue_poly], False, CUE_PATH, thick, cv2.LINE_AA)
        _arrow_head(img, cue_poly, CUE_PATH, 6 * thick)
    if len(obj_poly):
        cv2.polylines(img, [obj_poly], False, OBJECT_PATH, thick, cv2.LINE_AA)
        _arrow_head(img, obj_poly, OBJECT_PATH, 6 * thick)
    if shot.cue_after is not None and len(shot.cue_after) >= 2:
        _dashed(img, _project_path(cam, shot.cue_after, R), CUE_AFTER, thick, 4 * thick)
        end = _sphere_outline(cam, shot.cue_after[-1], R)
        cv2.polylines(img, [end], True, SCRATCH if shot.cue_pocketed else CUE_AFTER, thick, cv2.LINE_AA)
    if shot.ghost is not None:
        cv2.polylines(img, [_sphere_outline(cam, shot.ghost, R)], True, GHOST, thick, cv2.LINE_AA)
    if shot.target_ball is not None:
        target_xy = result.layout.positions[shot.target_ball]
        cv2.polylines(img, [_sphere_outline(cam, target_xy, R * 1.35)], True, OBJECT_PATH, thick, cv2.LINE_AA)
    return img


CLOTH_NAMES = tuple(CLOTH_COLOURS)
CLOTH_RGB = np.round(np.array([CLOTH_COLOURS[n] for n in CLOTH_NAMES]) * 255).astype(np.uint8)
"""The cloth colours a diagram is drawn in (RGB), those the renderer draws tables in."""


def photo_cloth(rgb: np.ndarray, result: Suggestion) -> tuple[int, int, int]:
    """The diagram's cloth colour (RGB): of the cloth colours :data:`CLOTH_RGB`, the one nearest (in CIE Lab, lightness
    weighted :data:`LIGHTNESS_WEIGHT`) to the photo's cloth inside the fitted playing surface
    (:func:`~pix2pockets.vision.table.cloth_edge.cloth_colour`, balls left out); :data:`CLOTH` where too little of it
    is in the photo."""
    inside = quad_mask(np.asarray(result.corners_px, dtype=float) - 0.5, rgb.shape)
    if inside.sum() < MIN_CLOTH_PIXELS:
        return CLOTH
    boxes = np.array([b.bbox_px for b in result.balls], dtype=float).reshape(-1, 4)
    weight = np.array([LIGHTNESS_WEIGHT, 1.0, 1.0])
    gap = np.linalg.norm((lab_of(CLOTH_RGB[None]).reshape(-1, 3) - cloth_colour(rgb, inside, boxes)) * weight, axis=1)
    return tuple(int(v) for v in CLOTH_RGB[int(np.argmin(gap))])


def draw_diagram(result: Suggestion, height: int, cloth: tuple[int, int, int] = CLOTH) -> np.ndarray:
    """A top-down diagram of the located layout with the shot, ``height`` pixels tall, its cloth ``cloth`` (RGB); the
    rails carry sights where the table was fitted to some (``evidence["diamonds"]``)."""
    cv2 = _cv2()
    spec = result.spec
    margin_frac = 0.06
    # width from the table's aspect so the diagram is `height` tall
    width = round(height / (spec.width / spec.length * (1 - 2 * margin_frac) + 2 * margin_frac))
    raster = TableRaster.fit(spec, width, margin_frac)
    w, h = raster.window_px
    img = np.full((h, w, 3), RAIL, dtype=np.uint8)
    m = raster.margin_px
    cv2.rectangle(
        img, (int(m[0]), int(m[1])), (int(m[0] + raster.surface_px[0]), int(m[1] + raster.surface_px[1])), cloth, -1
    )
    px = raster.length_to_pixels
    for pocket in spec.pockets:
        c = tuple(round(v) for v in raster.table_to_pixels(pocket.centre))
        cv2.circle(img, c, max(3, int(px(pocket.capture_radius * 0.8))), POCKET, -1, cv2.LINE_AA)
    if result.evidence.get("diamonds", 0) > 0:  # a table with sights; pub and home tables often have none
        for d in spec.diamonds:
            c = tuple(round(v) for v in raster.table_to_pixels(d))
            cv2.circle(img, c, 2, (230, 230, 230), -1, cv2.LINE_AA)
    r = max(3, round(px(spec.ball_radius)))
    thick = max(1, r // 4)
    shot = result.shot
    for path, colour in ((shot.cue_path, CUE_PATH), (shot.object_path, OBJECT_PATH)):
        if len(path) >= 2:
            poly = np.round(raster.table_to_pixels(path)).astype(np.int32).reshape(-1, 1, 2)
            cv2.polylines(img, [poly], False, colour, thick, cv2.LINE_AA)
            _arrow_head(img, poly, colour, 3 * r)
    if shot.cue_after is not None and len(shot.cue_after) >= 2:
        poly = np.round(raster.table_to_pixels(shot.cue_after)).astype(np.int32).reshape(-1, 1, 2)
        _dashed(img, poly, CUE_AFTER, thick, 2 * r)
        end = tuple(int(v) for v in poly[-1, 0])
        cv2.circle(img, end, r, SCRATCH if shot.cue_pocketed else CUE_AFTER, thick, cv2.LINE_AA)
    centres = [tuple(round(v) for v in raster.table_to_pixels(xy)) for xy in result.layout.positions]
    for ball, c in zip(result.balls, centres, strict=True):  # rings first: the balls are drawn over them
        if ball.position_sigma_m is not None and ball.position_sigma_m >= UNSURE_SIGMA:
            cv2.circle(img, c, r + round(px(2 * ball.position_sigma_m)), UNSURE, 1, cv2.LINE_AA)
    for ball, c in zip(result.balls, centres, strict=True):
        colour, striped = _ball_face(ball)
        if striped:
            _striped_disc(img, c, r, colour)
        else:
            cv2.circle(img, c, r, colour, -1, cv2.LINE_AA)
        if ball.sure_number is not None:
            _draw_number(img, c, ball.sure_number, r)
        cv2.circle(img, c, r, (0, 0, 0), 1, cv2.LINE_AA)
        if ball.in_hand:
            cv2.circle(img, c, int(r * 1.6), IN_HAND, thick, cv2.LINE_AA)
    if shot.ghost is not None:
        c = tuple(round(v) for v in raster.table_to_pixels(shot.ghost))
        cv2.circle(img, c, r, GHOST, 1, cv2.LINE_AA)
    if shot.target_ball is not None:
        c = tuple(round(v) for v in raster.table_to_pixels(result.layout.positions[shot.target_ball]))
        cv2.circle(img, c, int(r * 1.5), OBJECT_PATH, thick, cv2.LINE_AA)
    if img.shape[0] != height:
        img = cv2.resize(img, (img.shape[1], height), interpolation=cv2.INTER_AREA)
    return img


def shown_photo_size(width: int, height: int) -> tuple[int, int]:
    """(width, height) [px] of a photo of that size in the result picture: its own, or its longer side cut to
    :data:`MAX_PHOTO_SIDE`."""
    return capped_size(width, height, MAX_PHOTO_SIDE)


def picture_copy(rgb: np.ndarray, result: Suggestion) -> tuple[np.ndarray, Suggestion]:
    """The photo and its answer as the result picture shows them: as they are, or a copy of
    :func:`shown_photo_size` with the answer's pixels scaled onto it."""
    h, w = rgb.shape[:2]
    size = shown_photo_size(w, h)
    if size == (w, h):
        return rgb, result
    small = _cv2().resize(rgb, size, interpolation=_cv2().INTER_AREA)
    return small, result.scaled(size[0] / w, size[1] / h, size)


def render_result(rgb: np.ndarray, result: Suggestion) -> np.ndarray:
    """Photo with the shot, the top-down diagram beside it (in the photo's cloth colour, :func:`photo_cloth`), and
    the text line below: RGB uint8. A photo larger than :data:`MAX_PHOTO_SIDE` is shown at that size."""
    cv2 = _cv2()
    rgb, result = picture_copy(rgb, result)
    photo = draw_photo(rgb, result)
    diagram = draw_diagram(result, photo.shape[0], photo_cloth(rgb, result))
    h = photo.shape[0]
    canvas = np.full((h + TEXT_BAND, photo.shape[1] + diagram.shape[1], 3), 24, dtype=np.uint8)
    canvas[:h, : photo.shape[1]] = photo
    canvas[: diagram.shape[0], photo.shape[1] :] = diagram
    text = result.text.encode("ascii", "replace").decode()
    scale = max(0.5, min(1.0, canvas.shape[1] / 2200))
    cv2.putText(
        canvas, text, (12, h + TEXT_BAND - 14), cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), 1, cv2.LINE_AA
    )
    return canvas


def encode_picture(rgb: np.ndarray, suffix: str = ".png", fast: bool = False) -> bytes:
    """Encode an RGB uint8 picture as ``.png`` or ``.jpg``/``.jpeg`` bytes.

    ``fast`` uses zlib level 1 for PNG: a photo barely compresses further and it is about twice as quick.
    """
    import cv2

    suffix = suffix.lower()
    if suffix not in (".png", ".jpg", ".jpeg"):
        raise ValueError(f"cannot encode a picture as {suffix!r}; use .png or .jpg")
    params = [cv2.IMWRITE_PNG_COMPRESSION, 1] if fast and suffix == ".png" else []
    ok, buf = cv2.imencode(".jpg" if suffix == ".jpeg" else suffix, np.ascontiguousarray(rgb[:, :, ::-1]), params)
    if not ok:
        raise ValueError(f"could not encode the picture as {suffix}")
    return buf.tobytes()
