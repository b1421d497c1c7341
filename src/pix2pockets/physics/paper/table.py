"""Table geometry for the ``paper`` kernel: cushions as convex polygons, pockets as capture circles."""

from __future__ import annotations

from functools import cache

import numpy as np

from pix2pockets.geometry.raster import PAPER_LAYOUT, paper_table
from pix2pockets.geometry.table import TableSpec
from pix2pockets.physics.paper._kernel import KIND_CUSHION, KIND_JAW


def cushion_polygons(spec: TableSpec) -> np.ndarray:
    """The six cushions as convex quadrilaterals [m], shape (6, 4, 2), in ``cushion_segments`` order.

    Vertices: jaw end, jaw point, jaw point, jaw end. :func:`~pix2pockets.geometry.raster.paper_table`
    gets the paper's exact cushion shapes; any other table is built from its cushion noses and jaw faces.
    """
    if spec == paper_table():
        return PAPER_LAYOUT.to_table(PAPER_LAYOUT.cushion_polygons)
    jaws = spec.jaw_segments
    out = np.empty((6, 4, 2))
    for c, (a, b) in enumerate(spec.cushion_segments):
        ja = jaws[int(np.argmin(np.linalg.norm(jaws[:, 0] - a, axis=1)))]
        jb = jaws[int(np.argmin(np.linalg.norm(jaws[:, 0] - b, axis=1)))]
        out[c] = [ja[1], a, b, jb[1]]
    return out


@cache
def pack_table(spec: TableSpec) -> tuple[np.ndarray, ...]:
    """Table geometry as the arrays the kernel reads.

    Returns:
        ``(poly, edge_kind, edge_index, vertex_kind, vertex_index, pocket_centres, capture_radii)``:
        cushion polygons [m] (6, 4, 2); for each polygon edge ``k`` (from vertex ``k`` to ``k + 1``) and
        each vertex, the event it reports: a cushion (index into ``cushion_segments``) for the face and
        back edges, a jaw (index into ``jaw_segments``) for the jaw faces and all vertices; the pocket
        capture circles [m] (6, 2) and (6,).
    """
    poly = np.ascontiguousarray(cushion_polygons(spec))
    jaw_starts = spec.jaw_segments[:, 0]

    def jaw_of(point: np.ndarray) -> int:
        return int(np.argmin(np.linalg.norm(jaw_starts - point, axis=1)))

    edge_kind = np.empty((6, 4), dtype=np.int64)
    edge_index = np.empty((6, 4), dtype=np.int64)
    vertex_kind = np.full((6, 4), KIND_JAW, dtype=np.int64)
    vertex_index = np.empty((6, 4), dtype=np.int64)
    for c in range(6):
        ja, jb = jaw_of(poly[c, 1]), jaw_of(poly[c, 2])
        edge_kind[c] = (KIND_JAW, KIND_CUSHION, KIND_JAW, KIND_CUSHION)
        edge_index[c] = (ja, c, jb, c)
        vertex_index[c] = (ja, ja, jb, jb)
    centres = np.ascontiguousarray(spec.pocket_centres.astype(float))
    radii = np.array([p.capture_radius for p in spec.pockets], dtype=float)
    return poly, edge_kind, edge_index, vertex_kind, vertex_index, centres, radii
