"""Codes the ray caster and its callers share: indices into the flat scene arrays and the object ids.

Scene parameters travel as flat arrays (``geo``, ``shade``, ``mats``) indexed by the ``G_*``, ``S_*`` and ``M_*``
constants, so the kernel has one fixed signature; the id buffer holds the ``ID_*`` codes, one per pixel.
"""

from __future__ import annotations

import math

import numpy as np

# ---- geometry vector indices (metres, table frame)
G_L, G_W, G_H, G_HR, G_CW, G_RW, G_ZA, G_BI, G_ZF, G_ZC = range(10)
G_RX0, G_RX1, G_RY0, G_RY1, G_LINER, G_DR, G_KC, G_KS, G_DC, G_SS, G_ZHB = range(10, 21)
# balls carry their own radii: a ball's centre rests at the height of its radius (Scene.ball_centres)
G_LEGS, G_LEGW, G_SKIRT = range(21, 24)  # legs: 0 closed cabinet, 4 or 6 legs; leg width, skirt depth [m]
G_RUGX, G_RUGY = range(24, 26)  # half-size of a rug under the table [m] (0: none)
G_PLATE, G_PLATE_SQ = range(26, 28)  # metal pocket plates on the rail cap: reach from the hole centre [m] (0: none),
# 1 square (Chebyshev reach) or 0 round
G_BOXW, G_BOXD, G_BOXZ0, G_BOXZ1 = range(28, 32)  # coin box on the foot end: half-width along y, reach beyond the
# apron face, bottom and top height [m] (half-width 0: none)
N_GEO = 32
# ---- shading vector indices
S_AMB, S_CLOTH_TEX, S_CLOTH_SCALE, S_RAIL_TEX, S_RAIL_GLOSS, S_RAIL_SHIN, S_BALL_KS, S_BALL_SHIN = range(8)
S_FLOOR_SCALE, S_BOUNCE, S_DIA_SHAPE, S_CUE_DOTS, S_BAND, S_NUMR, S_REFL, S_ROOM = range(8, 16)
S_CLOTH_NAP, S_AO, S_METAL_SHIN = range(16, 19)
N_SHADE = 19
# ---- material rows
M_CLOTH, M_RAIL, M_APRON, M_BODY, M_LINER, M_DIAMOND, M_CEIL, M_AMBCOL, M_WALLTINT, M_RUG, M_PLATE = range(11)
N_MATS = 11
# ---- sight shapes (shade[S_DIA_SHAPE]); small dots are round sights of a small radius
SIGHT_ROUND, SIGHT_RHOMBUS, SIGHT_PEARL, SIGHT_SQUARE, SIGHT_OVAL = range(5)

# ---- object ids in the id buffer
ID_NONE = 0
ID_CLOTH = 1
ID_CUSHION = 2
ID_NOSE = 3
ID_CAP = 4
ID_APRON = 5
ID_BODY = 6
ID_HOLE = 7
ID_LINER = 8
ID_FLOOR = 9
ID_WALL = 10
ID_CEIL = 11
ID_PLATE = 12  # metal corner caps and side-pocket plates on the rail
ID_BOX = 13  # coin box / ball-return front on the foot end of a coin-op table
ID_DIAMOND0 = 20  # diamonds 0-17 -> 20-37
ID_BALL0 = 40  # balls 0-15 -> 40-55

BALL_CUE, BALL_SOLID, BALL_STRIPE, BALL_PLAIN = 0, 1, 2, 3  # plain: one colour, no number (blackball reds, yellows)
INF = 1e30
KU = 0.8  # cushion undercut: the face below the nose runs KU m back per m of depth (hidden from above ~51 deg)
KN = 1.0 / math.sqrt(1.0 + KU * KU)
AA_OFFSETS = np.array([[-0.375, -0.125], [0.125, -0.375], [0.375, 0.125], [-0.125, 0.375]])  # rotated grid [px]
