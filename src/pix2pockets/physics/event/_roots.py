"""Real roots of low-degree polynomials on an interval, robust and allocation-free (numba).

Event times are the first instant a motion polynomial (degree <= 4 in time) drops to zero. Closed-form
quartic formulas lose precision near double roots (grazing contacts), so instead we split the interval
at the critical points (roots of the derivative, found the same way one degree lower, down to the
closed-form quadratic) and find the root in the one monotone piece that changes sign with a safeguarded
Newton iteration.

A polynomial is given by its coefficients ``c0 + c1 t + c2 t^2 + c3 t^3 + c4 t^4``.
"""

from __future__ import annotations

import math

from numba import njit

INF = math.inf
_TIME_TOL = 1e-13  # [s] bracket width at which a root is accepted
_MAX_ITER = 80


@njit(cache=True, inline="always")
def poly4(c0: float, c1: float, c2: float, c3: float, c4: float, t: float) -> float:
    """Value of the quartic at ``t``."""
    return c0 + t * (c1 + t * (c2 + t * (c3 + t * c4)))


@njit(cache=True, inline="always")
def dpoly4(c1: float, c2: float, c3: float, c4: float, t: float) -> float:
    """Derivative of the quartic at ``t``."""
    return c1 + t * (2.0 * c2 + t * (3.0 * c3 + t * 4.0 * c4))


@njit(cache=True)
def _bracketed_root(c0, c1, c2, c3, c4, a, b, fa) -> float:
    """Root of the quartic in ``[a, b]`` where it is monotone and changes sign (``fa`` = value at ``a``)."""
    x = 0.5 * (a + b)
    for _ in range(_MAX_ITER):
        fx = poly4(c0, c1, c2, c3, c4, x)
        if fx == 0.0:
            return x
        if (fx > 0.0) == (fa > 0.0):
            a, fa = x, fx
        else:
            b = x
        if b - a <= _TIME_TOL * (1.0 + abs(b)):
            break
        d = dpoly4(c1, c2, c3, c4, x)
        xn = x - fx / d if d != 0.0 else 0.5 * (a + b)
        x = xn if a < xn < b else 0.5 * (a + b)
    return 0.5 * (a + b)


@njit(cache=True)
def quadratic_roots(a: float, b: float, c: float, lo: float, hi: float) -> tuple[int, float, float]:
    """Real roots of ``a t^2 + b t + c`` strictly inside ``(lo, hi)``, ascending: (count, r0, r1)."""
    r0, r1 = INF, INF
    if a == 0.0:
        if b == 0.0:
            return 0, INF, INF
        r0 = -c / b
        if lo < r0 < hi:
            return 1, r0, INF
        return 0, INF, INF
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return 0, INF, INF
    sq = math.sqrt(disc)
    q = -0.5 * (b + sq) if b >= 0.0 else -0.5 * (b - sq)  # avoids cancellation
    r0 = q / a
    r1 = c / q if q != 0.0 else r0
    if r0 > r1:
        r0, r1 = r1, r0
    n = 0
    out0, out1 = INF, INF
    if lo < r0 < hi:
        out0 = r0
        n = 1
    if lo < r1 < hi and r1 != r0:
        if n == 0:
            out0 = r1
        else:
            out1 = r1
        n += 1
    return n, out0, out1


@njit(cache=True)
def cubic_roots(d0: float, d1: float, d2: float, d3: float, lo: float, hi: float) -> tuple[int, float, float, float]:
    """Real roots of ``d0 + d1 t + d2 t^2 + d3 t^3`` strictly inside ``(lo, hi)``, ascending."""
    # critical points of the cubic split (lo, hi) into monotone pieces
    k, e0, e1 = quadratic_roots(3.0 * d3, 2.0 * d2, d1, lo, hi)
    pts = (e0, e1)
    n = 0
    o0, o1, o2 = INF, INF, INF
    prev = lo
    fprev = poly4(d0, d1, d2, d3, 0.0, lo)
    for idx in range(k + 1):
        cur = pts[idx] if idx < k else hi
        fcur = poly4(d0, d1, d2, d3, 0.0, cur)
        root = INF
        if (fprev < 0.0 < fcur) or (fprev > 0.0 > fcur):
            root = _bracketed_root(d0, d1, d2, d3, 0.0, prev, cur, fprev)
        elif fcur == 0.0 and cur < hi:
            root = cur
        if root < INF:
            if n == 0:
                o0 = root
            elif n == 1:
                o1 = root
            else:
                o2 = root
            n += 1
        prev, fprev = cur, fcur
    return n, o0, o1, o2


@njit(cache=True)
def first_drop(c0: float, c1: float, c2: float, c3: float, c4: float, horizon: float) -> float:
    """First time in ``(0, horizon]`` at which the quartic goes from positive to ``<= 0``; ``inf`` if none.

    Pieces that start at a non-positive value (e.g. a pair already touching and separating) are skipped:
    only a fresh crossing counts. The returned time is accurate to about ``1e-13`` s.
    """
    if horizon <= 0.0:
        return INF
    k, r0, r1, r2 = cubic_roots(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 0.0, horizon)
    pts = (r0, r1, r2)
    prev = 0.0
    fprev = c0
    for idx in range(k + 1):
        cur = pts[idx] if idx < k else horizon
        fcur = poly4(c0, c1, c2, c3, c4, cur)
        if fprev > 0.0 and fcur <= 0.0:
            if fcur == 0.0:
                return cur
            return _bracketed_root(c0, c1, c2, c3, c4, prev, cur, fprev)
        prev, fprev = cur, fcur
    return INF
