"""Profile representation: the graph ``z(y)``, its sampled tables, and how the graph is built.

See the package docstring (:mod:`railexu.profiles`) for the conventions and the smoothing.
Everything here is in metres and radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import CubicSpline, PPoly
from scipy.optimize import brentq

from railexu.errors import InputError

#: Steepest slope angle [deg] the graph ``z(y)`` keeps; steeper parts are only in ``outline_m``.
#: Flange contact needs wheel/rail angles up to ~72 deg, the rail cant adds ~1.4 deg.
MAX_SLOPE_DEG = 80.0
#: ``tan(MAX_SLOPE_DEG)`` = 5.671: the largest ``|dz/dy|`` of a graph.
MAX_SLOPE = math.tan(math.radians(MAX_SLOPE_DEG))
#: Largest distance along the curve between two nodes of the graph spline [m].
GRAPH_NODE_SPACING_M = 1.0e-4
#: Largest distance along the curve between two points of ``outline_m`` of analytic profiles [m].
OUTLINE_SPACING_M = 5.0e-5

PROFILE_KINDS = ("wheel", "rail")


class ProfileError(InputError):
    """A profile that cannot be read or built (bad file, unknown name, not a graph)."""


def _readonly(a: ArrayLike, ndim: int | None = None) -> np.ndarray:
    arr = np.array(a, dtype=np.float64, copy=True)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"expected a {ndim}-d array, got shape {arr.shape}")
    arr.flags.writeable = False
    return arr


# ---------------------------------------------------------------------------------------------
# Sampled tables for the compiled kernel
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SampledProfile:
    """A profile graph on the uniform grid ``y_i = y0_m + i * step_m``, ``i = 0 .. n-1``.

    Attributes:
        y0_m: first grid abscissa [m].
        step_m: grid step [m].
        z: height ``z(y_i)`` [m] (wheel: radius increase ``F``).
        dz: slope ``dz/dy(y_i)`` [-].
        d2z: second derivative ``d2z/dy2(y_i)`` [1/m].

    A compiled kernel does O(1) look-ups: with ``u = (y - y0) / step``, ``i = floor(u)``,
    ``t = u - i``, it interpolates ``z`` with the cubic Hermite polynomial through
    ``(z[i], dz[i])`` and ``(z[i+1], dz[i+1])``, takes the slope as the derivative of that cubic,
    and interpolates ``d2z`` linearly between ``d2z[i]`` and ``d2z[i+1]``; :meth:`lookup` is the
    reference implementation. Outside ``[y0, y0 + (n-1) step]`` there is no value.
    """

    y0_m: float
    step_m: float
    z: np.ndarray
    dz: np.ndarray
    d2z: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "y0_m", float(self.y0_m))
        object.__setattr__(self, "step_m", float(self.step_m))
        if not self.step_m > 0.0:
            raise ValueError(f"step_m must be > 0, got {self.step_m}")
        for name in ("z", "dz", "d2z"):
            object.__setattr__(self, name, _readonly(getattr(self, name), ndim=1))
        if not (self.z.size == self.dz.size == self.d2z.size) or self.z.size < 2:
            raise ValueError("z, dz and d2z must have the same length >= 2")

    @property
    def n(self) -> int:
        """Number of grid nodes."""
        return int(self.z.size)

    @property
    def y_end_m(self) -> float:
        """Last grid abscissa ``y0 + (n-1) step`` [m]."""
        return self.y0_m + (self.n - 1) * self.step_m

    @property
    def y_m(self) -> np.ndarray:
        """The grid abscissae [m]."""
        return self.y0_m + self.step_m * np.arange(self.n)

    def as_table(self) -> np.ndarray:
        """The ``(n, 3)`` C-contiguous table ``[z, dz, d2z]`` the kernel reads."""
        return np.ascontiguousarray(np.column_stack([self.z, self.dz, self.d2z]))

    def lookup(self, y: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Reference look-up ``(z [m], dz/dy [-], d2z/dy2 [1/m])`` at ``y`` [m]; NaN outside."""
        y = np.asarray(y, dtype=np.float64)
        u = (y - self.y0_m) / self.step_m
        inside = (u >= 0.0) & (u <= self.n - 1.0)
        i = np.clip(np.floor(np.where(inside, u, 0.0)).astype(np.intp), 0, self.n - 2)
        t = np.where(inside, u, 0.0) - i
        h = self.step_m
        z0, z1 = self.z[i], self.z[i + 1]
        d0, d1 = self.dz[i] * h, self.dz[i + 1] * h
        t2, t3 = t * t, t * t * t
        val = (2 * t3 - 3 * t2 + 1) * z0 + (t3 - 2 * t2 + t) * d0
        val += (-2 * t3 + 3 * t2) * z1 + (t3 - t2) * d1
        der = (6 * t2 - 6 * t) * z0 + (3 * t2 - 4 * t + 1) * d0
        der += (6 * t - 6 * t2) * z1 + (3 * t2 - 2 * t) * d1
        sec = (1 - t) * self.d2z[i] + t * self.d2z[i + 1]
        nan = np.nan
        return (
            np.where(inside, val, nan),
            np.where(inside, der / h, nan),
            np.where(inside, sec, nan),
        )


# ---------------------------------------------------------------------------------------------
# The underlying curve: smooth parametric segments (y(t), z(t)), t in [0, 1]
# ---------------------------------------------------------------------------------------------

_Eval = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class _Segment:
    """One smooth (at least C2) piece of a profile curve, parameter ``t`` in ``[0, 1]``.

    ``eval(t)`` returns ``(y, z, y_t, z_t, y_tt, z_tt)`` [m]; ``breaks`` are parameter values
    (including 0 and 1) where the segment's own polynomial pieces meet: graph nodes go there.
    Consecutive segments of a profile meet with a common point and tangent (C1); the curvature
    may jump between them (e.g. arc to straight line).
    """

    breaks: np.ndarray = np.array([0.0, 1.0])

    def eval(self, t: np.ndarray) -> _Eval:  # pragma: no cover - interface
        raise NotImplementedError

    def rotated(self, angle: float) -> _Segment:
        return _RotatedSegment(self, angle)


class _GraphSegment(_Segment):
    """``z = f(y)`` for ``y0 <= y <= y1``; ``f(y)`` returns ``(z, z', z'')``."""

    def __init__(self, y0: float, y1: float, f: Callable[[np.ndarray], tuple]) -> None:
        self.y0, self.y1, self.f = float(y0), float(y1), f

    def eval(self, t: np.ndarray) -> _Eval:
        t = np.asarray(t, dtype=np.float64)
        length = self.y1 - self.y0
        y = self.y0 + t * length
        z, dz, d2z = (np.broadcast_to(np.asarray(v, dtype=np.float64), y.shape) for v in self.f(y))
        zero = np.zeros_like(y)
        return y, z, zero + length, dz * length, zero, d2z * length * length


class _ArcSegment(_Segment):
    """Circular arc, centre ``(cy, cz)``, radius ``r``, polar angle from ``phi0`` to ``phi1``."""

    def __init__(self, cy: float, cz: float, r: float, phi0: float, phi1: float) -> None:
        self.cy, self.cz, self.r = float(cy), float(cz), float(r)
        self.phi0, self.phi1 = float(phi0), float(phi1)
        self.y0 = self.cy + self.r * math.cos(self.phi0)
        self.z0 = self.cz + self.r * math.sin(self.phi0)

    def eval(self, t: np.ndarray) -> _Eval:
        t = np.asarray(t, dtype=np.float64)
        dphi = self.phi1 - self.phi0
        phi = self.phi0 + t * dphi
        c, s = np.cos(phi), np.sin(phi)
        r = self.r
        # position relative to the start point by sum-to-product formulas, so that a flat arc
        # (R300 crown) keeps full relative precision in z - z0 (no cancellation of R sin phi)
        half = 0.5 * (phi - self.phi0)
        mid = 0.5 * (phi + self.phi0)
        chord = 2.0 * r * np.sin(half)
        return (
            self.y0 - chord * np.sin(mid),
            self.z0 + chord * np.cos(mid),
            -r * s * dphi,
            r * c * dphi,
            -r * c * dphi * dphi,
            -r * s * dphi * dphi,
        )


class _LineSegment(_Segment):
    """Straight line from ``p0`` to ``p1`` (may be steep or vertical)."""

    def __init__(self, p0: Sequence[float], p1: Sequence[float]) -> None:
        self.p0 = np.asarray(p0, dtype=np.float64)
        self.p1 = np.asarray(p1, dtype=np.float64)

    def eval(self, t: np.ndarray) -> _Eval:
        t = np.asarray(t, dtype=np.float64)
        d = self.p1 - self.p0
        zero = np.zeros_like(t)
        return (
            self.p0[0] + t * d[0],
            self.p0[1] + t * d[1],
            zero + d[0],
            zero + d[1],
            zero,
            zero,
        )


class _CurveSegment(_Segment):
    """A parametric spline ``(Y(u), Z(u))``, ``u`` from ``u[0]`` to ``u[-1]`` (scipy splines).

    ``fy`` and ``fz`` are callables ``f(u, nu)`` (``PPoly`` / ``BSpline``); ``ubreaks`` their
    breakpoints.
    """

    def __init__(self, fy: Callable, fz: Callable, ubreaks: np.ndarray) -> None:
        self.fy, self.fz = fy, fz
        self.u0, self.u1 = float(ubreaks[0]), float(ubreaks[-1])
        self.breaks = (np.asarray(ubreaks, dtype=np.float64) - self.u0) / (self.u1 - self.u0)
        self.breaks[0], self.breaks[-1] = 0.0, 1.0

    def eval(self, t: np.ndarray) -> _Eval:
        t = np.asarray(t, dtype=np.float64)
        du = self.u1 - self.u0
        u = np.clip(self.u0 + t * du, self.u0, self.u1)
        return (
            self.fy(u, 0),
            self.fz(u, 0),
            self.fy(u, 1) * du,
            self.fz(u, 1) * du,
            self.fy(u, 2) * du * du,
            self.fz(u, 2) * du * du,
        )


class _RotatedSegment(_Segment):
    """A segment rotated counter-clockwise by ``angle`` in the (y outwards, z up) plane about
    the origin: a positive angle tilts a rail head towards ``-y`` (the gauge side)."""

    def __init__(self, base: _Segment, angle: float) -> None:
        self.base, self.angle = base, float(angle)
        self.breaks = base.breaks

    def eval(self, t: np.ndarray) -> _Eval:
        c, s = math.cos(self.angle), math.sin(self.angle)
        y, z, yt, zt, ytt, ztt = self.base.eval(t)
        return (
            c * y - s * z,
            s * y + c * z,
            c * yt - s * zt,
            s * yt + c * zt,
            c * ytt - s * ztt,
            s * ytt + c * ztt,
        )

    def rotated(self, angle: float) -> _Segment:
        return _RotatedSegment(self.base, self.angle + angle)


def _rotate_points(points: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    y, z = points[:, 0], points[:, 1]
    return np.column_stack([c * y - s * z, s * y + c * z])


def _segment_nodes(seg: _Segment, spacing: float) -> np.ndarray:
    """Parameter values of the nodes on ``seg``: its breaks, subdivided so that the distance
    along the curve between nodes is at most ``spacing``."""
    b = np.asarray(seg.breaks, dtype=np.float64)
    k = 16
    frac = np.linspace(0.0, 1.0, k + 1)
    tt = b[:-1, None] + (b[1:] - b[:-1])[:, None] * frac[None, :]
    y, z = seg.eval(tt.ravel())[:2]
    y, z = y.reshape(tt.shape), z.reshape(tt.shape)
    length = np.hypot(np.diff(y, axis=1), np.diff(z, axis=1)).sum(axis=1)
    m = np.maximum(1, np.ceil(length / spacing)).astype(int)
    parts = [b[:1]]
    for i in range(b.size - 1):
        parts.append(np.linspace(b[i], b[i + 1], m[i] + 1)[1:])
    return np.concatenate(parts)


def _outline_from_segments(segments: Sequence[_Segment], spacing: float) -> np.ndarray:
    pts = []
    for k, seg in enumerate(segments):
        t = _segment_nodes(seg, spacing)
        y, z = seg.eval(t)[:2]
        p = np.column_stack([y, z])
        pts.append(p if k == 0 else p[1:])
    return np.vstack(pts)


# ---------------------------------------------------------------------------------------------
# The graph spline
# ---------------------------------------------------------------------------------------------


def _quintic_hermite(
    x: np.ndarray, z: np.ndarray, d1: np.ndarray, d2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients (scipy ``PPoly`` layout, shape (6, n-1)) of the piecewise quintic with the
    given value, slope and second derivative at the nodes ``x`` (C2 across the nodes)."""
    h = np.diff(x)
    z0, z1 = z[:-1], z[1:]
    a1, a2 = d1[:-1], 0.5 * d2[:-1]
    r0 = z1 - (z0 + a1 * h + a2 * h * h)
    r1 = d1[1:] - (a1 + d2[:-1] * h)
    r2 = d2[1:] - d2[:-1]
    a3 = (20 * r0 - 8 * r1 * h + r2 * h * h) / (2 * h**3)
    a4 = (-30 * r0 + 14 * r1 * h - 2 * r2 * h * h) / (2 * h**4)
    a5 = (12 * r0 - 6 * r1 * h + r2 * h * h) / (2 * h**5)
    return np.vstack([a5, a4, a3, a2, a1, z0]), h


def _graph_from_segments(
    segments: Sequence[_Segment],
    kind: str,
    *,
    spacing: float = GRAPH_NODE_SPACING_M,
    tan_limit: float = MAX_SLOPE,
    what: str = "profile",
) -> PPoly:
    """The graph ``z(y)`` of a curve made of C1-joined smooth segments, as a scipy ``PPoly``.

    Nodes are placed along every segment at most ``spacing`` apart (and at the segment's own
    breakpoints); each carries the exact ``z``, ``z' = z_t / y_t`` and
    ``z'' = (z_tt y_t - y_tt z_t) / y_t^3`` of the curve, and a quintic Hermite polynomial joins
    neighbouring nodes, so the graph is C2 inside a segment. At a junction of two segments both
    sides use the mean value and slope and their own one-sided second derivative (C1; the
    curvature jumps as in the drawn profile).

    The graph domain is the stretch of the curve around the *anchor* (rail: the highest point;
    wheel: the point nearest the tape circle ``y = 0``) on which ``y`` increases and
    ``|dz/dy| <= tan_limit``; its ends are found to machine precision (``brentq``).
    """
    node_t, node_k = [], []
    for k, seg in enumerate(segments):
        t = _segment_nodes(seg, spacing)
        node_t.append(t)
        node_k.append(np.full(t.size, k))
    t_all = np.concatenate(node_t)
    k_all = np.concatenate(node_k)
    evals = [seg.eval(t) for seg, t in zip(segments, node_t, strict=True)]
    y, z, yt, zt = (np.concatenate([e[j] for e in evals]) for j in range(4))
    ok = (yt > 0.0) & (np.abs(zt) <= tan_limit * yt)
    if not np.any(ok):
        raise ProfileError(
            f"{what}: no part of the curve has increasing lateral coordinate and "
            f"|slope| <= tan({MAX_SLOPE_DEG:g} deg): cannot build a graph z(y)"
        )
    if kind == "rail":
        anchor = int(np.argmax(np.where(ok, z, -np.inf)))
    else:
        anchor = int(np.argmin(np.where(ok, np.abs(y), np.inf)))
    bad = np.flatnonzero(~ok)
    lo = int(bad[bad < anchor].max()) + 1 if np.any(bad < anchor) else 0
    hi = int(bad[bad > anchor].min()) - 1 if np.any(bad > anchor) else t_all.size - 1

    def g_of(seg: _Segment) -> Callable[[float], float]:
        def g(t: float) -> float:
            _, _, a, b, _, _ = seg.eval(np.array([t]))
            return float(abs(b[0]) - tan_limit * a[0])

        return g

    t_lo_cut = t_hi_cut = None
    if lo > 0 and k_all[lo - 1] == k_all[lo]:
        seg = segments[k_all[lo]]
        t_lo_cut = brentq(g_of(seg), t_all[lo - 1], t_all[lo], xtol=1e-15, rtol=1e-15)
    if hi < t_all.size - 1 and k_all[hi + 1] == k_all[hi]:
        seg = segments[k_all[hi]]
        t_hi_cut = brentq(g_of(seg), t_all[hi], t_all[hi + 1], xtol=1e-15, rtol=1e-15)

    pieces = []  # per segment: node arrays (y, z, z', z'')
    k_first, k_last = int(k_all[lo]), int(k_all[hi])
    index = np.arange(t_all.size)
    for k in range(k_first, k_last + 1):
        t = t_all[(k_all == k) & (index >= lo) & (index <= hi)]
        if k == k_first and t_lo_cut is not None:
            t = np.concatenate([[t_lo_cut], t])
        if k == k_last and t_hi_cut is not None:
            t = np.concatenate([t, [t_hi_cut]])
        sy, sz, syt, szt, sytt, sztt = segments[k].eval(t)
        # drop nodes closer than 1e-3 spacing to their predecessor (an exact cut replaces the
        # node next to it)
        keep = np.concatenate([[True], np.diff(sy) > 1e-3 * spacing])
        if k == k_last and t_hi_cut is not None and keep.size > 2 and not keep[-1]:
            keep[-1], keep[-2] = True, False
        sy, sz, syt, szt, sytt, sztt = (a[keep] for a in (sy, sz, syt, szt, sytt, sztt))
        if sy.size < 2:
            continue
        if np.any(np.diff(sy) <= 0.0):
            y_bad = sy[1:][np.diff(sy) <= 0.0][0]
            raise ProfileError(
                f"{what}: the curve folds back at y = {y_bad * 1e3:.6g} mm inside the graph "
                "domain: expected increasing lateral coordinates"
            )
        pieces.append([sy, sz, szt / syt, (sztt * syt - sytt * szt) / syt**3])
    if not pieces:
        raise ProfileError(f"{what}: the graph domain is empty")
    # junctions: common point and tangent (mean of the two sides), one-sided curvature
    for left, right in zip(pieces[:-1], pieces[1:], strict=True):
        gaps = [left[j][-1] - right[j][0] for j in range(3)]
        if abs(gaps[0]) > 1e-9 or abs(gaps[1]) > 1e-9 or abs(gaps[2]) > 1e-6:
            raise ProfileError(
                f"{what}: segments do not join with a common point and tangent at "
                f"y = {right[0][0]:.6g} m (gaps {gaps[0]:.3g} m, {gaps[1]:.3g} m, "
                f"slope {gaps[2]:.3g})"
            )
        for j in range(3):
            mean = 0.5 * (left[j][-1] + right[j][0])
            left[j][-1] = right[j][0] = mean
    x = np.concatenate([pieces[0][0]] + [p[0][1:] for p in pieces[1:]])
    coef = np.hstack([_quintic_hermite(*p)[0] for p in pieces])
    return PPoly(coef, x, extrapolate=True)


# ---------------------------------------------------------------------------------------------
# Profile
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile: a smooth graph ``z(y)`` plus the full outline.

    Axes follow ``docs/conventions.md``: lateral coordinate ``y`` [m] positive outwards (field
    side); wheel: ``y`` = ``s`` from the tape circle, value = radius increase ``F`` (flange
    positive, ``r = r0 + F``); rail: height [m], up positive.

    Attributes:
        name: short name (``"S1002"``, a file stem, ...).
        kind: ``"wheel"`` or ``"rail"``.
        lateral_m: knot abscissae of the graph spline [m], strictly increasing; the graph domain
            is ``[lateral_m[0], lateral_m[-1]]``.
        height_m: graph values at the knots [m].
        flange_back_m: wheel only, lateral coordinate of the flange back [m] (S1002: -0.070).
        inclination_rad: rail only, cant already contained in the points [rad] (0 upright).
        source: where the profile comes from.
        smoothing: one line: how the curve was smoothed into the graph.
        outline_m: ``(n, 2)`` polyline ``(lateral, height)`` [m] of the whole profile including
            steep and vertical parts (flange back, gauge face), for plots and gauge measurement.

    Between the knots the graph is the scipy ``PPoly`` :attr:`spline` (C2 where the underlying
    profile is, C1 everywhere). Outside the domain :meth:`height` continues linearly with the
    end slope (``second_derivative`` = 0 there); contact code should stay inside
    ``[y_min, y_max]``. Arrays are read-only; profiles compare by identity.

    A ``Profile`` built directly from ``lateral_m``/``height_m`` (no private spline) uses the
    not-a-knot cubic spline through those points.
    """

    name: str
    kind: str
    lateral_m: np.ndarray
    height_m: np.ndarray
    flange_back_m: float | None
    inclination_rad: float
    source: str
    smoothing: str
    outline_m: np.ndarray
    _spline: PPoly | None = field(default=None, repr=False)
    _segments: tuple = field(default=(), repr=False)

    def __post_init__(self) -> None:
        if self.kind not in PROFILE_KINDS:
            raise ValueError(f"profile kind {self.kind!r}: expected 'wheel' or 'rail'")
        lat = _readonly(self.lateral_m, ndim=1)
        hgt = _readonly(self.height_m, ndim=1)
        if lat.size < 2 or lat.size != hgt.size:
            raise ValueError("lateral_m and height_m must have the same length >= 2")
        if np.any(np.diff(lat) <= 0.0):
            raise ValueError("lateral_m must be strictly increasing")
        outline = _readonly(self.outline_m)
        if outline.ndim != 2 or outline.shape[1] != 2:
            raise ValueError(f"outline_m must have shape (n, 2), got {outline.shape}")
        object.__setattr__(self, "lateral_m", lat)
        object.__setattr__(self, "height_m", hgt)
        object.__setattr__(self, "outline_m", outline)
        if self.flange_back_m is not None:
            object.__setattr__(self, "flange_back_m", float(self.flange_back_m))
        object.__setattr__(self, "inclination_rad", float(self.inclination_rad))
        spline = self._spline
        if spline is None:
            spline = CubicSpline(lat, hgt, bc_type="not-a-knot")
            spline = PPoly(spline.c, spline.x, extrapolate=True)
            object.__setattr__(self, "_spline", spline)
        object.__setattr__(self, "_d1", spline.derivative(1))
        object.__setattr__(self, "_d2", spline.derivative(2))

    # -- domain ------------------------------------------------------------------------------

    @property
    def y_min(self) -> float:
        """Lower end of the graph domain [m]."""
        return float(self.lateral_m[0])

    @property
    def y_max(self) -> float:
        """Upper end of the graph domain [m]."""
        return float(self.lateral_m[-1])

    @property
    def spline(self) -> PPoly:
        """The graph as a scipy ``PPoly`` over ``lateral_m`` (do not evaluate outside)."""
        return self._spline

    # -- evaluation --------------------------------------------------------------------------

    def _clip(self, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        y = np.asarray(y, dtype=np.float64)
        return y, np.clip(y, self.y_min, self.y_max)

    def height(self, y: ArrayLike) -> np.ndarray:
        """Graph value ``z(y)`` [m] (wheel: radius increase ``F``), vectorised over ``y`` [m]."""
        y, yc = self._clip(y)
        return np.asarray(self._spline(yc) + self._d1(yc) * (y - yc))

    def slope(self, y: ArrayLike) -> np.ndarray:
        """Slope ``dz/dy`` [-] at ``y`` [m]."""
        _, yc = self._clip(y)
        return np.asarray(self._d1(yc))

    def second_derivative(self, y: ArrayLike) -> np.ndarray:
        """Second derivative ``d2z/dy2`` [1/m] at ``y`` [m] (0 outside the domain)."""
        y, yc = self._clip(y)
        return np.asarray(np.where(y == yc, self._d2(yc), 0.0))

    def curvature(self, y: ArrayLike) -> np.ndarray:
        """Signed geometric curvature ``z'' / (1 + z'^2)^1.5`` [1/m] at ``y`` [m]
        (positive where the graph is convex from below, e.g. a wheel flange root)."""
        d1 = self.slope(y)
        return np.asarray(self.second_derivative(y) / (1.0 + d1 * d1) ** 1.5)

    # -- derived profiles --------------------------------------------------------------------

    def sampled(
        self, step_m: float = 1.0e-4, y_min: float | None = None, y_max: float | None = None
    ) -> SampledProfile:
        """Uniform table ``y_i = y_min + i step_m`` (last node ``<= y_max``) for the kernel.

        Args:
            step_m: grid step [m].
            y_min, y_max: table range [m]; default the graph domain. A range beyond the domain
                gets the linear continuation of :meth:`height`.
        """
        lo = self.y_min if y_min is None else float(y_min)
        hi = self.y_max if y_max is None else float(y_max)
        if not step_m > 0.0:
            raise ValueError(f"step_m must be > 0, got {step_m}")
        if not hi - lo >= step_m:
            raise ValueError(f"table range [{lo}, {hi}] m is shorter than one step {step_m} m")
        n = int(math.floor((hi - lo) / step_m * (1.0 + 1e-12))) + 1
        y = lo + step_m * np.arange(n)
        return SampledProfile(
            y0_m=lo,
            step_m=float(step_m),
            z=self.height(y),
            dz=self.slope(y),
            d2z=self.second_derivative(y),
        )

    def canted(self, angle_rad: float) -> Profile:
        """This rail tilted towards the gauge side (``-y``) by ``angle_rad`` [rad] about its own
        origin: the outline and the underlying curve are rotated counter-clockwise in the
        (y outwards, z up) plane and the graph is rebuilt (same smoothing and slope limit);
        ``inclination_rad`` grows by ``angle_rad``. The top of the head is not moved to 0.
        """
        if self.kind != "rail":
            raise ValueError(
                f"profile {self.name!r} is a {self.kind} profile: only rails are canted"
            )
        angle = float(angle_rad)
        if angle == 0.0:
            return self
        segments = self._segments
        if not segments:
            spline, d1, d2 = self._spline, self._d1, self._d2

            def f(y: np.ndarray) -> tuple:
                return spline(y), d1(y), d2(y)

            segments = (_GraphSegment(self.y_min, self.y_max, f),)
        rotated = tuple(seg.rotated(angle) for seg in segments)
        return _make_profile(
            name=f"{self.name} canted {math.degrees(angle):.4g} deg",
            kind=self.kind,
            segments=rotated,
            outline=_rotate_points(self.outline_m, angle),
            flange_back_m=None,
            inclination_rad=self.inclination_rad + angle,
            source=f"{self.source}, canted by {angle:.6g} rad",
            smoothing=self.smoothing,
        )


def _make_profile(
    *,
    name: str,
    kind: str,
    segments: Sequence[_Segment],
    outline: np.ndarray | None,
    flange_back_m: float | None,
    inclination_rad: float,
    source: str,
    smoothing: str,
    what: str | None = None,
) -> Profile:
    """Build a :class:`Profile` from its underlying curve (C1-joined smooth segments)."""
    segments = tuple(segments)
    spline = _graph_from_segments(segments, kind, what=what or f"profile {name!r}")
    if outline is None:
        outline = _outline_from_segments(segments, OUTLINE_SPACING_M)
    return Profile(
        name=name,
        kind=kind,
        lateral_m=spline.x,
        height_m=spline.c[-1, :].tolist() + [float(spline(spline.x[-1]))],
        flange_back_m=flange_back_m if kind == "wheel" else None,
        inclination_rad=inclination_rad if kind == "rail" else 0.0,
        source=source,
        smoothing=smoothing,
        outline_m=outline,
        _spline=spline,
        _segments=segments,
    )
