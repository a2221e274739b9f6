"""Built-in analytic profiles: S1002 wheel, 60E1 (UIC60) rail, and simple test shapes.

All functions return metres; the analytic definitions are written in millimetres as published.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike

from railexu.profiles.core import (
    MAX_SLOPE_DEG,
    Profile,
    _ArcSegment,
    _GraphSegment,
    _LineSegment,
    _make_profile,
)

# ---------------------------------------------------------------------------------------------
# S1002 (EN 13715), docs/theory.md section 2.2
# ---------------------------------------------------------------------------------------------

_AA, _BA = 1.364323640, 0.066666667
_B_POLY = np.polynomial.Polynomial(
    [
        0.0,
        -3.358537058e-02,
        1.565681624e-03,
        -2.810427944e-05,
        5.844240864e-08,
        -1.562379023e-08,
        5.309217349e-15,
        -5.957839843e-12,
        2.646656573e-13,
    ]
)
_C_POLY = np.polynomial.Polynomial(
    [
        -4.320221063e03,
        -1.038384026e03,
        -1.065501873e02,
        -6.051367875,
        -2.054332446e-01,
        -4.169739389e-03,
        -4.687195829e-05,
        -2.252755540e-07,
    ]
)
_AD, _BD, _CD = 16.446, 13.0, 26.210665
_AE, _BE = 93.576667419, 2.747477419
_AF, _BF, _CF = 8.834924130, 20.0, 58.558326413
_AG, _BG, _CG = 16.0, 12.0, 55.0
_AH, _BH, _CH = 9.519259302, 20.5, 49.5

#: Section limits of S1002 [mm], from the flange back to the outer end.
S1002_BREAKS_MM = (
    -70.0,
    -62.764705882,
    -49.662510381,
    -39.764473993,
    -38.426669071,
    -35.0,
    -26.0,
    32.15796,
    60.0,
)
#: Half-width [mm] of the band over which the jumps of the published coefficients at
#: s = -35 and s = -26 mm are blended.
S1002_BLEND_HALF_WIDTH_MM = 0.5


def _poly3(p: np.polynomial.Polynomial):
    d1, d2 = p.deriv(1), p.deriv(2)
    return lambda s: (p(s), d1(s), d2(s))


def _line3(a: float, b: float):
    return lambda s: (a + b * s, np.full_like(s, b), np.zeros_like(s))


def _circle3(az: float, r: float, cs: float, sign: float):
    """``az + sign * sqrt(r^2 - (s + cs)^2)`` and its derivatives."""

    def f(s):
        u = s + cs
        w = np.sqrt(r * r - u * u)
        return az + sign * w, -sign * u / w, -sign * r * r / w**3

    return f


_S1002_A = _line3(_AA, -_BA)
_S1002_B = _poly3(_B_POLY)
_S1002_C = _poly3(_C_POLY)
_S1002_D = _circle3(_AD, _BD, _CD, -1.0)
_S1002_E = _line3(-_AE, -_BE)
_S1002_F = _circle3(_AF, _BF, _CF, +1.0)
_S1002_G = _circle3(_AG, _BG, _CG, +1.0)
_S1002_H = _circle3(_AH, _BH, _CH, +1.0)


def s1002_analytic(s_mm: ArrayLike) -> np.ndarray:
    """The published S1002 definition ``F(s)`` [mm] at ``s`` [mm] (no smoothing), -70..60 mm.

    ``s`` from the tape circle, flange at negative ``s``; ``F`` = radius increase. Sections as
    in docs/theory.md section 2.2 (EN 13715); a point on a section limit takes the section on its
    positive side. NaN outside [-70, 60].
    """
    s = np.asarray(s_mm, dtype=np.float64)
    out = np.full(s.shape, np.nan)
    funcs = (_S1002_H, _S1002_G, _S1002_F, _S1002_E, _S1002_D, _S1002_C, _S1002_B, _S1002_A)
    brk = S1002_BREAKS_MM
    for i, f in enumerate(funcs):
        lo, hi = brk[i], brk[i + 1]
        sel = (s >= lo) & ((s < hi) if i < len(funcs) - 1 else (s <= hi))
        if np.any(sel):
            with np.errstate(invalid="ignore"):
                out[sel] = f(s[sel])[0]
    return out


def _smoothstep5(x: np.ndarray):
    """Quintic smoothstep ``b(x)`` on [0, 1] (C2 at both ends) and its two derivatives."""
    x = np.clip(x, 0.0, 1.0)
    b = x**3 * (10 - 15 * x + 6 * x * x)
    b1 = 30 * x * x * (1 - x) ** 2
    b2 = 60 * x * (1 - x) * (1 - 2 * x)
    return b, b1, b2


def _blend3(left, right, s0: float, w: float):
    """``(1 - b) left + b right`` over ``[s0 - w, s0 + w]``, with value and derivatives."""

    def f(s):
        b, b1, b2 = _smoothstep5((s - (s0 - w)) / (2 * w))
        b1, b2 = b1 / (2 * w), b2 / (4 * w * w)
        l0, l1, l2 = left(s)
        r0, r1, r2 = right(s)
        d0, d1, d2 = r0 - l0, r1 - l1, r2 - l2
        return l0 + b * d0, l1 + b * d1 + b1 * d0, l2 + b * d2 + 2 * b1 * d1 + b2 * d0

    return f


def _mm_graph(s0: float, s1: float, f) -> _GraphSegment:
    """A graph segment defined in millimetres, returned in metres."""

    def fm(y):
        z, d1, d2 = f(np.asarray(y) * 1e3)
        return np.asarray(z) * 1e-3, np.asarray(d1), np.asarray(d2) * 1e3

    return _GraphSegment(s0 * 1e-3, s1 * 1e-3, fm)


def _s1002_segments() -> tuple:
    brk = S1002_BREAKS_MM
    w = S1002_BLEND_HALF_WIDTH_MM
    # H: R20.5 flange back from the vertical tangent at s = -70 (polar angle pi) to G.
    phi_gh = math.atan2(_S1002_H(np.array(brk[1]))[0] - _AH, brk[1] + _CH)
    h_arc = _ArcSegment(-_CH * 1e-3, _AH * 1e-3, _BH * 1e-3, math.pi, float(phi_gh))
    return (
        h_arc,
        _mm_graph(brk[1], brk[2], _S1002_G),
        _mm_graph(brk[2], brk[3], _S1002_F),
        _mm_graph(brk[3], brk[4], _S1002_E),
        _mm_graph(brk[4], -35.0 - w, _S1002_D),
        _mm_graph(-35.0 - w, -35.0 + w, _blend3(_S1002_D, _S1002_C, -35.0, w)),
        _mm_graph(-35.0 + w, -26.0 - w, _S1002_C),
        _mm_graph(-26.0 - w, -26.0 + w, _blend3(_S1002_C, _S1002_B, -26.0, w)),
        _mm_graph(-26.0 + w, brk[7], _S1002_B),
        _mm_graph(brk[7], brk[8], _S1002_A),
    )


_GRAPH_SMOOTHING = (
    "graph z(y): C2 piecewise-quintic Hermite scipy PPoly through nodes <= 0.1 mm apart along "
    "the curve carrying its exact z, z', z''; C1 with one-sided curvature at section junctions; "
    f"cut where |slope| > tan {MAX_SLOPE_DEG:g} deg"
)


@functools.cache
def s1002() -> Profile:
    """The S1002 wheel profile (EN 13715) from its analytic definition.

    Lateral ``s`` from the tape circle, outwards positive (flange at negative ``s``), value
    ``F(s)`` = radius increase [m]. Flange back at ``s = -0.070`` m. The published coefficients
    leave jumps of 3.7e-5 mm at ``s = -26`` and 1.2e-4 mm at ``s = -35`` mm: over
    ``|s - s_j| <= 0.5`` mm the two neighbouring sections are blended with a C2 quintic
    smoothstep (deviation from either section below the jump, 0.12 um).
    """
    return _make_profile(
        name="S1002",
        kind="wheel",
        segments=_s1002_segments(),
        outline=None,
        flange_back_m=-0.070,
        inclination_rad=0.0,
        source="analytic S1002 (EN 13715)",
        smoothing=_GRAPH_SMOOTHING
        + "; published jumps at s=-26/-35 mm blended over +-0.5 mm by a C2 quintic smoothstep",
    )


# ---------------------------------------------------------------------------------------------
# 60E1 (UIC60) rail head, docs/theory.md section 2.3
# ---------------------------------------------------------------------------------------------

#: Published arc data of the 60E1 head [mm]: (radius, centre y, centre z) with the top at (0, 0).
RAIL_60E1_ARCS_MM = ((300.0, 0.0, -300.0), (80.0, 7.700, -80.135), (13.0, 23.016, -14.909))
#: Slope of the head side faces below the R13 arcs (the head widens downwards).
RAIL_60E1_SIDE_SLOPE = 1.0 / 20.0
#: Depth [mm] below the top down to which ``outline_m`` follows the side faces.
RAIL_60E1_OUTLINE_DEPTH_MM = 25.0


def rail_60e1_geometry_mm() -> dict:
    """The 60E1 head construction [mm], upright, top of head at (0, 0), field side ``y > 0``.

    The published centres are rounded to 1 um; R80 and R13 centres are moved along the line of
    centres (by 0.21 and 0.13 um) so that the arcs are exactly tangent. Returns the centres,
    the tangent points and the side-face tangent point / lower end (field side).
    """
    (r1, y1, z1), (r2, y2, z2), (r3, y3, z3) = RAIL_60E1_ARCS_MM
    c1 = np.array([y1, z1])
    u12 = np.array([y2, z2]) - c1
    c2 = c1 + (r1 - r2) * u12 / np.linalg.norm(u12)
    u23 = np.array([y3, z3]) - np.array([y2, z2])
    c3 = c2 + (r2 - r3) * u23 / np.linalg.norm(u23)
    t12 = c1 + r1 * (c2 - c1) / (r1 - r2)
    t23 = c2 + r2 * (c3 - c2) / (r2 - r3)
    a = math.atan(RAIL_60E1_SIDE_SLOPE)
    t3f = c3 + r3 * np.array([math.cos(a), math.sin(a)])
    depth = RAIL_60E1_OUTLINE_DEPTH_MM
    face_end = t3f + (t3f[1] + depth) * np.array([RAIL_60E1_SIDE_SLOPE, -1.0])
    return {
        "c300": c1,
        "c80": c2,
        "c13": c3,
        "t300_80": t12,
        "t80_13": t23,
        "t13_face": t3f,
        "face_end": face_end,
    }


def _rail_60e1_segments() -> tuple:
    g = {k: v * 1e-3 for k, v in rail_60e1_geometry_mm().items()}
    r1, r2, r3 = (a[0] * 1e-3 for a in RAIL_60E1_ARCS_MM)

    def ang(p, c):
        return math.atan2(p[1] - c[1], p[0] - c[0])

    # field side (y > 0) arcs, in the direction of increasing y
    a300 = ang(g["t300_80"], g["c300"])
    a80 = (ang(g["t300_80"], g["c80"]), ang(g["t80_13"], g["c80"]))
    a13 = (ang(g["t80_13"], g["c13"]), ang(g["t13_face"], g["c13"]))
    c80, c13 = g["c80"], g["c13"]
    mirror = np.array([-1.0, 1.0])
    return (
        _LineSegment(g["face_end"] * mirror, g["t13_face"] * mirror),
        _ArcSegment(-c13[0], c13[1], r3, math.pi - a13[1], math.pi - a13[0]),
        _ArcSegment(-c80[0], c80[1], r2, math.pi - a80[1], math.pi - a80[0]),
        _ArcSegment(g["c300"][0], g["c300"][1], r1, math.pi - a300, a300),
        _ArcSegment(c80[0], c80[1], r2, a80[0], a80[1]),
        _ArcSegment(c13[0], c13[1], r3, a13[0], a13[1]),
        _LineSegment(g["t13_face"], g["face_end"]),
    )


@functools.cache
def rail_60e1() -> Profile:
    """The 60E1 (UIC60) rail head from its arcs, upright, top of head at (0, 0), symmetric.

    R300 crown, R80 and R13 arcs (tangent), then 1:20 side faces (head widening downwards)
    down to 25 mm below the top in ``outline_m``; the graph stops on the R13 arcs where the
    slope reaches the limit (``|y| = 35.82`` mm, 12.65 mm below the top).
    """
    return _make_profile(
        name="60E1",
        kind="rail",
        segments=_rail_60e1_segments(),
        outline=None,
        flange_back_m=None,
        inclination_rad=0.0,
        source="analytic 60E1/UIC60 head (R300/R80/R13 arcs, 1:20 side faces)",
        smoothing=_GRAPH_SMOOTHING + "; arc centres moved <= 0.21 um for exact tangency",
    )


# ---------------------------------------------------------------------------------------------
# Simple shapes for tests
# ---------------------------------------------------------------------------------------------


def cone_wheel(
    conicity: float, half_width_m: float = 0.070, flange_back_m: float | None = -0.070
) -> Profile:
    """A pure cone without flange: ``F(s) = -conicity * s`` for ``|s| <= half_width_m`` [m].

    Args:
        conicity: cone slope [-] (radius decreases outwards for a positive value).
        half_width_m: half width of the tread [m].
        flange_back_m: a virtual flange back [m] used only to place the wheel on the axle
            (default -0.070 m, as S1002, so that the tape circles are 1.500 m apart).
    """
    k = float(conicity)
    if not half_width_m > 0.0:
        raise ValueError(f"half_width_m must be > 0, got {half_width_m}")
    if abs(k) > 1.0:
        raise ValueError(f"conicity {k} is not a plausible cone slope (|conicity| <= 1)")

    def f(y):
        return -k * y, np.full_like(y, -k), np.zeros_like(y)

    return _make_profile(
        name=f"cone {k:g}",
        kind="wheel",
        segments=(_GraphSegment(-half_width_m, half_width_m, f),),
        outline=None,
        flange_back_m=flange_back_m,
        inclination_rad=0.0,
        source=f"analytic cone, conicity {k:g}",
        smoothing="exact (straight line)",
    )


def flat_rail(width_m: float = 0.072) -> Profile:
    """A flat rail head ``z = 0`` for ``|y| <= width_m / 2`` [m], upright."""
    if not width_m > 0.0:
        raise ValueError(f"width_m must be > 0, got {width_m}")
    half = 0.5 * float(width_m)
    return _make_profile(
        name=f"flat {width_m * 1e3:g} mm",
        kind="rail",
        segments=(_LineSegment((-half, 0.0), (half, 0.0)),),
        outline=None,
        flange_back_m=None,
        inclination_rad=0.0,
        source="analytic flat rail",
        smoothing="exact (straight line)",
    )


def round_rail(radius_m: float, width_m: float = 0.072) -> Profile:
    """A circular rail head of radius ``radius_m`` [m], top at (0, 0), over ``|y| <= width/2``.

    ``z(y) = sqrt(R^2 - y^2) - R``; where the arc gets steeper than the slope limit the graph
    stops and only ``outline_m`` continues.
    """
    r = float(radius_m)
    if not r > 0.0:
        raise ValueError(f"radius_m must be > 0, got {radius_m}")
    if not 0.0 < width_m < 2.0 * r:
        raise ValueError(f"width_m must be in (0, 2 radius), got {width_m}")
    a = math.asin(0.5 * width_m / r)
    return _make_profile(
        name=f"round R{r * 1e3:g} mm",
        kind="rail",
        segments=(_ArcSegment(0.0, -r, r, 0.5 * math.pi + a, 0.5 * math.pi - a),),
        outline=None,
        flange_back_m=None,
        inclination_rad=0.0,
        source=f"analytic circular head, R = {r:g} m",
        smoothing=_GRAPH_SMOOTHING,
    )
