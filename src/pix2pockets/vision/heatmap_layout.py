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
IMAGENET_MEAN = (0.485, 0.456, 0.406)
IMAGENET_STD = (0.229, 0.224, 0.225)
