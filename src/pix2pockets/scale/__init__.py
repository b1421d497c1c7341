"""Spreading the heavy jobs over processes or machines with Ray (the optional ``ray`` extra).

Work is split by index (layouts of ``evaluate planner``, scenes of ``synth``); each piece depends only on its
seed and index, so the merged result is the one a single process gives. See docs/scale-out.md.
"""

from pix2pockets.scale.ray_pool import RayPool, add_ray_arguments, require_ray, split_range

__all__ = ["RayPool", "add_ray_arguments", "require_ray", "split_range"]
