"""Wheel and rail profiles: S1002, 60E1 (UIC60), test shapes, SIMPACK and text files.

Conventions (``docs/conventions.md``)
-------------------------------------
A profile is a curve in its own axes, SI units (m), lateral coordinate ``y`` positive
**outwards** (towards the field side):

- wheel: ``y`` = ``s`` from the tape circle (flange at negative ``s``), value = radius increase
  ``F(s)`` (flange positive, ``r = r0 + F``); :attr:`Profile.flange_back_m` is the flange back
  (S1002: -0.070 m);
- rail: ``y`` from the rail's reference point, value = height, up positive; the built-in rails
  are upright with the top of the head at (0, 0); :attr:`Profile.inclination_rad` is a cant the
  points already contain.

:class:`Profile` holds two views of the same curve: the smooth **graph** ``z(y)`` the contact code
evaluates (:meth:`Profile.height`, :meth:`~Profile.slope`, :meth:`~Profile.second_derivative`,
:meth:`~Profile.curvature`, :meth:`~Profile.sampled` for the compiled kernel), and
:attr:`Profile.outline_m`, the full polyline including steep and vertical parts, for plots and
gauge measurement.

Graph domain and slope limit
----------------------------
A graph cannot hold vertical tangents (S1002 flange back, the rail gauge face below the R13 arc).
The graph is the stretch of the curve around the anchor (rail: highest point; wheel: point
nearest the tape circle) on which ``y`` increases and ``|dz/dy| <= tan 80 deg = 5.671``
(:data:`MAX_SLOPE_DEG`); its ends are found to machine precision on the underlying curve. Flange
contact needs angles up to ~72 deg and a 1:40 cant adds 1.4 deg, so 80 deg leaves margin.
Domains: S1002 ``[-69.689, 60.000]`` mm (cut on the R20.5 flange back; the 70 deg flank is
inside); 60E1 ``[-35.818, +35.818]`` mm (cut on the R13 arcs 12.65 mm below the top; the gauge
point 14 mm below the top, at 86 deg, is only in ``outline_m``); 60E1 canted 1:40
``[-35.439, 36.184]`` mm; Manchester S1002 file ``[-69.613, 60.000]`` mm (its data stop at
78.8 deg); Manchester UIC60 file ``[-42.931, 28.692]`` mm. Outside its domain
:meth:`Profile.height` continues linearly with the end slope (z'' = 0); the sampled tables stop
at the domain.

Smoothing
---------
Every profile is first an *underlying curve*: a chain of smooth parametric segments
``(y(t), z(t))`` joined with a common point and tangent (C1). The graph is built from it the same
way for all profiles: nodes at most 0.1 mm apart along the curve (and at the segments' own
breakpoints) carry the curve's exact ``z``, ``z' = z_t / y_t`` and
``z'' = (z_tt y_t - y_tt z_t) / y_t^3``; a quintic Hermite polynomial joins neighbouring nodes
(a scipy ``PPoly``, :attr:`Profile.spline`). The graph is therefore C2 inside each segment and
C1 at the segment junctions, where the curvature jumps as in the drawn profile (arc to line).
Interpolation error of the quintic between 0.1 mm nodes: below 1e-10 m on the built-ins.

- S1002: segments are the published sections (lines, polynomials, arcs; the R20.5 flange back as
  an arc so that its vertical tangent at -70 mm is exact). The published coefficients leave
  jumps of 3.7e-5 mm at s = -26 mm and 1.2e-4 mm at s = -35 mm: over ``|s - s_j| <= 0.5`` mm the
  two neighbouring sections are blended, ``(1 - b) F_left + b F_right`` with the C2 quintic
  smoothstep ``b = 10x^3 - 15x^4 + 6x^5``, so F is C2 there. Measured: max deviation from the
  published definition 5.9e-5 mm (0.06 um, in the -35 mm band), slope and curvature continuous
  across both junctions. Other junctions meet to 6e-8 mm / 8e-9 in slope; the graph uses the
  mean of the two sides there.
- 60E1: R300 / R80 / R13 arcs and 1:20 side faces. The published centres are rounded to 1 um;
  the R80 and R13 centres are moved along the line of centres by 0.21 and 0.13 um so that the
  arcs are exactly tangent (tangent points at |y| = 10.500 and 25.988 mm).
- point files (SIMPACK, text): a parametric C2 cubic interpolating spline (scipy
  ``CubicSpline``, not-a-knot) through the points over their cumulated chord length, which
  follows steep parts without overshoot; with SIMPACK ``approx.smooth > 0`` a penalised cubic
  smoothing spline (``make_smoothing_spline``) with that lambda instead. The graph then comes
  from it as above.

Sampled tables
--------------
:meth:`Profile.sampled` gives a :class:`SampledProfile` (uniform grid ``y0 + i step``: ``z``,
``dz``, ``d2z``). A compiled kernel interpolates ``z`` with the cubic Hermite polynomial through
``(z, dz)`` of the two neighbouring nodes (slope = its derivative) and ``d2z`` linearly:
O(1) per look-up. The error against the graph is at most ``h^4/384 max|z''''|`` plus the
contributions of the curvature jumps inside a cell (see the tests). Measured at the default
0.1 mm step: about 1e-14 m typically and below 2 nm on every tread; the worst cell is the
S1002 R13 arc / 70 deg flank tangency, 0.2 um in height and 0.012 in slope (0.08 deg); at 0.05 mm
step 0.08 um. A step of 0.05 mm is worth it if flange contact matters.

SIMPACK files
-------------
:func:`read_simpack_profile` applies the spline block's keys in SIMPACK's order (numbered 1-7 in
the files' own comments, as CONTACT's ``read_simpack.m`` does): point.dist.min, shift,
rotate, bounds, mirror, inversion, units. After that SIMPACK's ``y`` points to the field side
and ``z`` down; the lateral coordinate is ``y``, a wheel's radius increase ``z``, a rail's height
``-z``.

The packaged Manchester benchmark files check both the reader and the analytic profiles:

- ``MBench_S1002``: the points lie on the published S1002 to 1.6e-6 mm (their 8-digit
  rounding); the interpolated graph is within 5.3e-4 mm of :func:`s1002` (largest at the
  curvature jumps next to the 70 deg flank, where the 0.4 mm point spacing cannot follow). Its
  flange-back point is commented out in the file; the registry sets ``flange_back_m = -0.070``.
- ``MBench_UIC60``: equals :func:`rail_60e1` canted by ``atan(1/40)`` with the tops aligned and
  the analytic profile shifted by -7.4917 mm laterally (the file's origin is the highest point
  of the canted head, which lies 300 sin(atan(1/40)) = 7.498 mm outwards of the rail axis):
  vertical residual 1.3e-4 mm rms, 1.2e-3 mm max (steep ends), normal distance <= 2.6e-4 mm down
  to 23 mm below the top, gauge face included. Mirrored, the fit is 0.59 mm rms: the file's
  **gauge side is at negative y**, its field side positive, as conventions.md wants, so it is used
  unmirrored. It is already canted: ``inclination_rad = atan(1/40)``.

Built-ins and files
-------------------
:func:`wheel_profile` / :func:`rail_profile` take a built-in name (case-insensitive: wheels
``S1002``, ``MBench_S1002``; rails ``UIC60`` = ``60E1`` (analytic, upright), ``MBench_UIC60``) or
a path (``.prw``/``.prr`` SIMPACK, anything else two-column text in mm).
"""

from railexu.profiles.builtin import (
    cone_wheel,
    flat_rail,
    rail_60e1,
    rail_60e1_geometry_mm,
    round_rail,
    s1002,
    s1002_analytic,
)
from railexu.profiles.core import (
    GRAPH_NODE_SPACING_M,
    MAX_SLOPE,
    MAX_SLOPE_DEG,
    Profile,
    ProfileError,
    SampledProfile,
)
from railexu.profiles.readers import (
    read_declared_text_profile,
    read_simpack_profile,
    read_xy_profile,
)
from railexu.profiles.registry import (
    BUILTIN_RAILS,
    BUILTIN_WHEELS,
    MBENCH_RAIL_INCLINATION_RAD,
    mbench_s1002,
    mbench_uic60,
    rail_profile,
    wheel_profile,
)

#: Alias: UIC60 is the former name of 60E1.
uic60 = rail_60e1

__all__ = [
    "BUILTIN_RAILS",
    "BUILTIN_WHEELS",
    "GRAPH_NODE_SPACING_M",
    "MAX_SLOPE",
    "MAX_SLOPE_DEG",
    "MBENCH_RAIL_INCLINATION_RAD",
    "Profile",
    "ProfileError",
    "SampledProfile",
    "cone_wheel",
    "flat_rail",
    "mbench_s1002",
    "mbench_uic60",
    "rail_60e1",
    "rail_60e1_geometry_mm",
    "rail_profile",
    "read_declared_text_profile",
    "read_simpack_profile",
    "read_xy_profile",
    "round_rail",
    "s1002",
    "s1002_analytic",
    "uic60",
    "wheel_profile",
]
