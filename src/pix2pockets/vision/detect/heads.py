"""Channel layout and constants shared by the heatmap detector's training code and its ONNX decoder.

The network outputs (N, N_OUT, H/STRIDE, W/STRIDE): channels 0-4 centre heatmaps of the five classes
(:data:`pix2pockets.vision.classes.CLASS_NAMES` order), 5 a class-agnostic ball heatmap, 6-7 the box size as
``log(w / STRIDE), log(h / STRIDE)``, 8-9 the sub-cell centre offset, 10-11 the ball-cloth contact point minus
the integer centre cell, in cells.
"""

from __future__ import annotations

STRIDE = 4
N_CLASSES = 5
BALL_ANY = 5
N_HEAT = 6
SIZE_SLICE = slice(6, 8)
OFFSET_SLICE = slice(8, 10)
CONTACT_SLICE = slice(10, 12)
N_OUT = 12
INPUT_MULTIPLE = 16
BALL_PEAK_RATIO = 0.6
"""A cell of the "any ball" heatmap is a ball candidate when it holds at least this share of the highest value in
its 3x3 neighbourhood (1.0 would be a strict local maximum). Two touching far balls, 6-9 px wide, often have
their centres in neighbouring stride-4 cells; a strict peak filter keeps only one of them. The decoder removes
the extra candidates around a single ball by box overlap (``docs/detector.md``)."""
BALL_NMS_IOU = 0.5
"""IoU above which the decoder merges two "any ball" candidates into the higher-scoring one."""
IMAGENET_MEAN = (0.485, 0.456, 0.406)
IMAGENET_STD = (0.229, 0.224, 0.225)
