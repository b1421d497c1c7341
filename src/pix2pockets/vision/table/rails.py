"""Rail lines through diamond centres and their labelling: which diamond of the table each one is.

1. **Rail lines.** Iterative RANSAC line fits split the diamond centres into rails: the line through the
   most diamonds wins, its inliers are removed, and so on, up to four lines.
2. **Labelling.** Pairs of rail lines are hypothesised to be particular rails of the table (bottom, foot,
   top, head), with the diamonds on them in either direction and at any run of consecutive diamond positions.
   Each hypothesis gives a homography from which all 18 diamonds are projected; the hypothesis matching
   the most diamonds (then the smallest residual, measured in table metres) wins. A short rail has 3 diamonds and
   a long rail 6, split by the side pocket, so the spacing pattern tells the long rails from the short
   ones even when diamonds are hidden. Reflected hypotheses are rejected: a camera above the table sees the
   table frame with its handedness reversed in pixel coordinates (``v`` down).
"""

from __future__ import annotations

import itertools
import math

import cv2
import numpy as np

from pix2pockets.geometry.homography import apply_homography, fit_homography
from pix2pockets.geometry.table import TableSpec
from pix2pockets.vision.table.errors import TableFitError, counted

RAIL_DIAMONDS: tuple[tuple[int, ...], ...] = ((0, 1, 2, 3, 4, 5), (6, 7, 8), (9, 10, 11, 12, 13, 14), (15, 16, 17))
"""Diamond indices of each rail in ``TableSpec.diamonds`` order: bottom, foot, top, head."""
MIN_DIAMONDS = 4
"""Diamonds on rail lines a labelling needs (two rails of two)."""
MAX_HYPOTHESES = 2000  # rail-assignment hypotheses tried before giving up on better ones


def _line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    d = q - p
    n = math.hypot(*d)
    if n < 1e-9:
        return None
    normal = np.array([-d[1], d[0]]) / n
    return np.array([normal[0], normal[1], -normal @ p])


def tls_line(points: np.ndarray) -> np.ndarray:
    """Total-least-squares line ``(a, b, c)`` with ``a^2 + b^2 = 1`` through points (n, 2)."""
    mean = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - mean)
    normal = vt[-1]
    return np.array([normal[0], normal[1], -normal @ mean])


def fit_rail_lines(points: np.ndarray, tol_px: float, max_lines: int = 4) -> list[np.ndarray]:
    """Split points into collinear groups by iterative RANSAC (exhaustive over point pairs).

    Args:
        points: diamond centres (n, 2) [px].
        tol_px: inlier distance to a line [px].
        max_lines: most lines to extract.

    Returns:
        Index arrays into ``points``, one per line (each with >= 2 points), sorted along the line.
    """
    remaining = np.arange(len(points))
    lines: list[np.ndarray] = []
    while len(lines) < max_lines and len(remaining) >= 2:
        pts = points[remaining]
        best: tuple[int, float, np.ndarray] | None = None
        for i, j in itertools.combinations(range(len(pts)), 2):
            line = _line_through(pts[i], pts[j])
            if line is None:
                continue
            dist = np.abs(pts @ line[:2] + line[2])
            inl = dist < tol_px
            key = (int(inl.sum()), -float(np.sum(dist[inl] ** 2)))
            if best is None or key > best[:2]:
                best = (key[0], key[1], inl)
        if best is None or best[0] < 2:
            break
        inl = best[2]
        if inl.sum() >= 3:  # refine on the inliers, then take the inliers of the refined line
            line = tls_line(pts[inl])
            refined = np.abs(pts @ line[:2] + line[2]) < tol_px
            if refined.sum() >= inl.sum():
                inl = refined
        idx = remaining[inl]
        direction = points[idx[-1]] - points[idx[0]]
        order = np.argsort(points[idx] @ direction)
        lines.append(idx[order])
        remaining = remaining[~inl]
    return lines


# ----------------------------------------------------------------------------- labelling
def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    x2, y2 = np.concatenate([x[1:], x[:1]]), np.concatenate([y[1:], y[:1]])
    return 0.5 * float(np.sum(x * y2 - x2 * y))


def _match_diamonds(
    H_img_to_table: np.ndarray, diamonds: np.ndarray, table_xy: np.ndarray, tol_m: float
) -> tuple[np.ndarray, float]:
    """Match diamonds to the table's diamonds (one-to-one, nearest in table metres). Returns (index per diamond,
    cost)."""
    xy = apply_homography(H_img_to_table, diamonds)
    d = np.linalg.norm(xy[:, None, :] - table_xy[None, :, :], axis=-1)
    d = np.where(np.isfinite(d), d, np.inf)
    index = np.full(len(diamonds), -1)
    nearest = np.argmin(d, axis=1)
    near = d[np.arange(len(diamonds)), nearest]
    # greedy, surest first: each table diamond goes to the nearest photo diamond that has it as its own nearest
    order = np.argsort(near, kind="stable")
    order = order[near[order] < tol_m]
    _, first = np.unique(nearest[order], return_index=True)
    taken = order[first]
    index[taken] = nearest[taken]
    return index, float(np.sum(near[taken] ** 2))


def _positions_along(spec: TableSpec, rail: int) -> np.ndarray:
    """Positions [m] of a rail's diamonds along the rail, in ``RAIL_DIAMONDS`` order."""
    xy = spec.diamonds[list(RAIL_DIAMONDS[rail])]
    return np.linalg.norm(xy - xy[0], axis=1)


def _cross_ratio(t: np.ndarray) -> np.ndarray:
    """Cross-ratios of consecutive quadruples of 1-D positions (projective invariants)."""
    a, b, c, d = t[:-3], t[1:-2], t[2:-1], t[3:]
    return ((c - a) * (d - b)) / ((c - b) * (d - a))


def _line_candidates(points: np.ndarray, line: np.ndarray, spec: TableSpec) -> list[tuple[int, np.ndarray]]:
    """Possible (rail, diamond indices) for the diamonds of one line, sorted along it.

    Any ordered subset of a rail's diamonds in either direction, pruned by cross-ratios (4 or more diamonds:
    exact projective invariants) or by a loose spacing-ratio check (3 diamonds).
    """
    pts = points[line]
    t = np.linalg.norm(pts - pts[0], axis=1)
    k = len(line)
    out = []
    for rail, ids in enumerate(RAIL_DIAMONDS):
        if k > len(ids):
            continue
        pos = _positions_along(spec, rail)
        for subset in itertools.combinations(range(len(ids)), k):
            for direction in (1, -1):
                sub = list(subset[::direction])
                tp = pos[sub]
                if k >= 4:
                    cr_img, cr_tab = _cross_ratio(t), _cross_ratio(tp)
                    if np.any(np.abs(np.log(np.abs(cr_img / cr_tab))) > 0.15):
                        continue
                elif k == 3:
                    r_img = (t[1] - t[0]) / max(t[2] - t[1], 1e-9)
                    r_tab = abs(tp[1] - tp[0]) / max(abs(tp[2] - tp[1]), 1e-9)
                    if abs(np.log(r_img / r_tab)) > np.log(4.0):
                        continue
                out.append((rail, np.array([ids[i] for i in sub])))
    return out


def _without_stray_diamond(points: np.ndarray, line: np.ndarray, spec: TableSpec) -> list[np.ndarray]:
    """The line itself, or when its diamonds fit no run of diamonds (a false diamond on the rail: a pocket jaw, a
    cushion edge, a mark on the cap) the variants without one diamond that do. Lines of 4+ diamonds only."""
    if len(line) < 4 or _line_candidates(points, line, spec):
        return [line]
    variants = [np.delete(line, i) for i in range(len(line))]
    good = [v for v in variants if _line_candidates(points, v, spec)]
    return good or [line]


def _hypotheses(points: np.ndarray, line_a: np.ndarray, line_b: np.ndarray, spec: TableSpec):
    """Yield (diamond indices, diamond indices) for two lines assigned to two different rails."""

    # only the end diamonds of each line enter the minimal 4-point homography: candidates that differ only
    # inside a line give the same map, so they are tried once (the interior is checked by the matching)
    def ends(line: np.ndarray) -> dict[tuple[int, int, int], None]:
        return {(r, int(d[0]), int(d[-1])): None for r, d in _line_candidates(points, line, spec)}

    cand_a, cand_b = ends(line_a), ends(line_b)
    diamonds = np.array([line_a[0], line_a[-1], line_b[0], line_b[-1]])
    for ra, a0, a1 in cand_a:
        for rb, b0, b1 in cand_b:
            if ra != rb:
                yield diamonds, np.array([a0, a1, b0, b1])


def label_candidates(
    diamonds: np.ndarray, lines: list[np.ndarray], spec: TableSpec, tol_m: float | None = None, keep: int = 4
) -> list[np.ndarray]:
    """The best few distinct labellings (diamond index per diamond, -1 unmatched), best first.

    Few diamonds can leave near-ties (e.g. two diamonds on a short rail next to a long rail: shifted by one
    diamond, a general homography still fits); the camera fit then decides (:func:`fit_table`).
    Labellings that differ only by the 180-degree turn count once.

    Raises:
        TableFitError: when no hypothesis matches at least ``MIN_DIAMONDS`` diamonds on two rails.
    """
    table_xy = spec.diamonds
    tol_m = tol_m if tol_m is not None else 0.25 * spec.length / 8
    usable, group = [], []
    for g, ln in enumerate(x for x in lines if len(x) >= 2):
        for variant in _without_stray_diamond(diamonds, ln, spec):
            usable.append(variant)
            group.append(g)
    best: tuple[int, float] | None = None
    found: dict[tuple, tuple[tuple[int, float], np.ndarray]] = {}
    pairs = sorted(
        ((a, b) for a, b in itertools.combinations(range(len(usable)), 2) if group[a] != group[b]),
        key=lambda ab: (-min(len(usable[ab[0]]), len(usable[ab[1]])), -len(usable[ab[0]]) - len(usable[ab[1]])),
    )
    strong = sum(len(x) >= 3 for x in usable)
    if strong >= 2:  # two-diamond lines only join hypotheses when there are not enough longer lines
        pairs = [(a, b) for a, b in pairs if len(usable[a]) >= 3 and len(usable[b]) >= 3]
    elif strong == 1:
        # greedy two-diamond lines are arbitrary: pair the long line with every pair of the other diamonds
        main = next(i for i, x in enumerate(usable) if len(x) >= 3)
        rest = np.setdiff1d(np.arange(len(diamonds)), usable[main])
        extra = [np.array(p) for p in itertools.combinations(rest.tolist(), 2)]
        if len(extra) <= 45:
            base = len(usable)
            usable = usable + extra
            pairs = [(main, base + k) for k in range(len(extra))]
    n_on_lines = sum(len(x) for x in usable)
    tried = 0
    for a, b in pairs:
        if tried > MAX_HYPOTHESES:
            break
        if best is not None and best[0] >= n_on_lines:
            break  # every diamond on a rail line is explained: no better hypothesis exists
        hypotheses = [hyp for hyp in _hypotheses(diamonds, usable[a], usable[b], spec) if len(hyp[0]) >= 4]
        room = max(MAX_HYPOTHESES - tried, 0)
        tried += len(hypotheses)  # past MAX_HYPOTHESES the outer loop stops, above
        for H in _seen_maps(diamonds, table_xy, hypotheses[:room]):
            Hinv = _safe_inv(H)
            if Hinv is None:
                continue
            index, cost = _match_diamonds(Hinv, diamonds, table_xy, tol_m)
            if best is not None and (index >= 0).sum() < best[0] - 4:
                continue  # hopeless: skip the refits
            for _ in range(2):  # refit on all matched diamonds
                m = index >= 0
                if m.sum() < 4 or len({_rail_of(int(j)) for j in index[m]}) < 2:
                    break
                try:
                    Hinv = _safe_inv(fit_homography(table_xy[index[m]], diamonds[m]))
                except ValueError:
                    break
                if Hinv is None:
                    break
                before = index
                index, cost = _match_diamonds(Hinv, diamonds, table_xy, tol_m)
                if np.array_equal(index, before):
                    break  # the same diamonds again: a refit would give the same map
            turned = np.where(index >= 0, (index + 9) % 18, -1)
            key_t = min(tuple(index), tuple(turned))
            score = (int((index >= 0).sum()), -cost)
            if key_t not in found or score > found[key_t][0]:
                found[key_t] = (score, index)
            if best is None or score > best:
                best = score
    ranked = sorted(found.values(), key=lambda si: si[0], reverse=True)
    ranked = [
        (sc, ix) for sc, ix in ranked if len({_rail_of(int(j)) for j in ix[ix >= 0]}) >= 2 and sc[0] >= MIN_DIAMONDS
    ]
    if not ranked:
        n = 0 if best is None else best[0]
        raise TableFitError(
            f"too few table points: {counted(n, 'diamond')} could be matched "
            f"(need {MIN_DIAMONDS} on at least two rails)"
        )
    top = ranked[0][0][0]
    return [ix for sc, ix in ranked if sc[0] >= top - 1][:keep]


def _seen_maps(
    diamonds: np.ndarray, table_xy: np.ndarray, hypotheses: list[tuple[np.ndarray, np.ndarray]]
) -> list[np.ndarray]:
    """The table -> image homographies (3, 3) of the hypotheses (photo diamond indices, table diamond indices; the
    photo diamonds the same four for all) that see their diamonds from above the table, in order.

    The hypothesis diamonds are seen, so in front of the camera: one sign of w for all four (the map is scaled to
    w > 0); with w > 0 a camera above the table reverses handedness (det H < 0), a reflection would not.
    """
    if not hypotheses:
        return []
    image = diamonds[hypotheses[0][0]].astype(np.float32)
    table = table_xy[np.array([table_idx for _, table_idx in hypotheses])]  # (n, 4, 2)
    maps = np.array([cv2.getPerspectiveTransform(points.astype(np.float32), image) for points in table])
    w = table[..., 0] * maps[:, 2, None, 0] + table[..., 1] * maps[:, 2, None, 1] + maps[:, 2, None, 2]
    finite = np.isfinite(maps).all(axis=(1, 2))
    one_side = (w > 0).all(axis=1) | (w < 0).all(axis=1)
    maps = np.where((w[:, 0] < 0)[:, None, None], -maps, maps)
    ok = finite & one_side
    ok[ok] = np.linalg.det(maps[ok]) < 0
    return list(maps[ok])


def _safe_inv(H: np.ndarray) -> np.ndarray | None:
    """Inverse of a homography, or ``None`` when it is (nearly) singular."""
    if not np.all(np.isfinite(H)) or np.linalg.cond(H) > 1e12:
        return None
    return np.linalg.inv(H)


def _rail_of(diamond: int) -> int:
    for r, ids in enumerate(RAIL_DIAMONDS):
        if diamond in ids:
            return r
    raise ValueError(diamond)
