"""The image pass of the ray caster (numba, one core): one ray per pixel through
:func:`pix2pockets.synth.raycast.shade_ray`, and four more where the object id changes (adaptive anti-aliasing)."""

from __future__ import annotations

from numba import njit

from pix2pockets.synth import scene_codes as codes
from pix2pockets.synth.raycast import shade_ray

_pixel = njit(cache=True, inline="always")(shade_ray)  # inlined into the main pass
_pixel_call = njit(cache=True)(shade_ray)  # an ordinary call for the few anti-aliasing samples


@njit(cache=True)
def render_scene(
    Kinv,
    Rt,
    cam,
    width,
    height,
    geo,
    shade,
    mats,
    holes,
    diamonds,
    balls,
    rots,
    bcols,
    bkinds,
    bnums,
    bboxes,
    lights,
    digits,
    noise,
    grain,
    floor_tex,
    wall_tex,
    rgb,
    ids,
    depth,
    sil_count,
    mask,
):
    """Trace and shade the pixels where ``mask`` (H, W) is set. Writes ``rgb`` (H, W, 3), ``ids`` (H, W),
    ``depth`` (H, W): distance along the ray to the hit [m], and ``sil_count`` (n balls,): the number of
    traced pixels whose ray meets each ball's sphere at all (occluded or not). Pixels outside ``mask`` keep
    what the arrays hold.

    Pixels on object boundaries (an id differs from a 4-neighbour) get four more rays on a rotated grid
    and the mean colour (adaptive anti-aliasing); ids, depth and counts come from the centre ray.
    """
    for v in range(height):
        for u in range(width):
            if not mask[v, u]:
                continue
            r, g, b, hit, t = _pixel(
                u + 0.5,
                v + 0.5,
                True,
                Kinv,
                Rt,
                cam,
                geo,
                shade,
                mats,
                holes,
                diamonds,
                balls,
                rots,
                bcols,
                bkinds,
                bnums,
                bboxes,
                lights,
                digits,
                noise,
                grain,
                floor_tex,
                wall_tex,
                sil_count,
            )
            rgb[v, u, 0] = r
            rgb[v, u, 1] = g
            rgb[v, u, 2] = b
            ids[v, u] = hit
            depth[v, u] = t
    for v in range(height):
        for u in range(width):
            if not mask[v, u]:
                continue
            k = ids[v, u]
            edge = (
                (u > 0 and ids[v, u - 1] != k)
                or (u + 1 < width and ids[v, u + 1] != k)
                or (v > 0 and ids[v - 1, u] != k)
                or (v + 1 < height and ids[v + 1, u] != k)
            )
            if not edge:
                continue
            sr = rgb[v, u, 0]
            sg = rgb[v, u, 1]
            sb = rgb[v, u, 2]
            for j in range(4):
                r, g, b, hit, t = _pixel_call(
                    u + 0.5 + codes.AA_OFFSETS[j, 0],
                    v + 0.5 + codes.AA_OFFSETS[j, 1],
                    False,
                    Kinv,
                    Rt,
                    cam,
                    geo,
                    shade,
                    mats,
                    holes,
                    diamonds,
                    balls,
                    rots,
                    bcols,
                    bkinds,
                    bnums,
                    bboxes,
                    lights,
                    digits,
                    noise,
                    grain,
                    floor_tex,
                    wall_tex,
                    sil_count,
                )
                sr += r
                sg += g
                sb += b
            rgb[v, u, 0] = sr / 5.0
            rgb[v, u, 1] = sg / 5.0
            rgb[v, u, 2] = sb / 5.0
