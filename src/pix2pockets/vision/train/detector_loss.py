"""CenterNet losses: penalty-reduced focal loss on heatmaps, L1 on regressions at object centres.

References:
    Zhou et al., "Objects as Points" (2019), eq. 1-3; Law and Deng, "CornerNet" (2018), focal loss variant.
"""

from __future__ import annotations

import torch

from pix2pockets.vision.classes import BALL_IDS, DIAMOND_ID
from pix2pockets.vision.detect.heads import CONTACT_SLICE, N_HEAT, OFFSET_SLICE, SIZE_SLICE


def focal_loss(logits: torch.Tensor, target: torch.Tensor, channel_mask: torch.Tensor) -> torch.Tensor:
    """Focal loss (alpha 2, beta 4) summed over supervised cells, divided by the number of peaks.

    Args:
        logits: (N, C, h, w) heatmap logits.
        target: (N, C, h, w) Gaussian targets in [0, 1] with exact 1 at centres.
        channel_mask: (N, C) 1 where a channel is supervised for that sample, or (N, C, h, w) per cell.
    """
    p = torch.sigmoid(logits).clamp(1e-4, 1 - 1e-4)
    pos = (target >= 0.999).float()
    m = channel_mask if channel_mask.ndim == 4 else channel_mask[:, :, None, None]
    pos_loss = -torch.log(p) * (1 - p) ** 2 * pos * m
    neg_loss = -torch.log(1 - p) * p**2 * (1 - target) ** 4 * (1 - pos) * m
    n_pos = (pos * m).sum().clamp(min=1.0)
    return (pos_loss.sum() + neg_loss.sum()) / n_pos


def _gather(out: torch.Tensor, index: torch.Tensor) -> torch.Tensor:
    """Values of (N, C, h, w) maps at flat cell indices (N, K) -> (N, K, C)."""
    n, c = out.shape[:2]
    flat = out.reshape(n, c, -1)
    return flat.gather(2, index[:, None, :].expand(n, c, index.shape[1])).permute(0, 2, 1)


CLASS_WEIGHT = 1.0


def ball_class_loss(out: torch.Tensor, batch: dict[str, torch.Tensor]) -> torch.Tensor:
    """Softmax cross-entropy over the four ball-class logits at each labelled ball centre.

    The focal loss treats the class heatmaps independently, so every head learns "ball here" and fires on every
    ball; this term makes them compete, which is what the class decision downstream needs.
    """
    label = batch["ball_class"]
    known = label >= 0
    if not bool(known.any()):
        return out.new_zeros(())
    logits = _gather(out[:, list(BALL_IDS)], batch["index"])  # (N, K, 4)
    return torch.nn.functional.cross_entropy(logits[known], label[known])


def heat_mask(batch: dict[str, torch.Tensor]) -> torch.Tensor:
    """(N, N_HEAT, h, w) supervised heatmap cells: whole channels from ``kind_mask``, plus the diamond channel
    off the table in ball-only photos (``off_table``)."""
    n, c = batch["kind_mask"].shape
    h, w = batch["heat"].shape[2:]
    m = batch["kind_mask"][:, :, None, None].expand(n, c, h, w).clone()
    m[:, DIAMOND_ID] = torch.maximum(m[:, DIAMOND_ID], batch["off_table"])
    return m


def detector_loss(out: torch.Tensor, batch: dict[str, torch.Tensor]) -> tuple[torch.Tensor, dict[str, float]]:
    """Total loss and its parts for a batch; see :class:`pix2pockets.vision.train.detector_targets.Sample`."""
    heat = focal_loss(out[:, :N_HEAT], batch["heat"], heat_mask(batch))
    m = batch["reg_mask"][..., None]
    n = m.sum().clamp(min=1.0)
    size = (torch.abs(_gather(out[:, SIZE_SLICE], batch["index"]) - batch["size"]) * m).sum() / n
    off = (torch.abs(_gather(out[:, OFFSET_SLICE], batch["index"]) - batch["offset"]) * m).sum() / n
    cm = batch["contact_mask"][..., None]
    cont = (torch.abs(_gather(out[:, CONTACT_SLICE], batch["index"]) - batch["contact"]) * cm).sum() / cm.sum().clamp(
        min=1.0
    )
    cls = ball_class_loss(out, batch)
    total = heat + size + off + 0.5 * cont + CLASS_WEIGHT * cls
    named = (("heat", heat), ("size", size), ("offset", off), ("contact", cont), ("class", cls))
    parts = {k: float(v.detach()) for k, v in named}
    return total, parts
