"""An independent reference for the tests: the frictionless normal contact of two elastic
half-spaces on a grid, and the undeformed gap of a wheel and its rail in the contact's plane.

Nothing here uses railexu's contact code: the wheel and rail enter only as their profiles
(:class:`railexu.profiles.Profile`, read from the same files) and their placement in the track
(:class:`railexu.contact.placement.WheelRailPair`: the tape circle's distance from the wheelset
centre and the rail's origin and cant).

Normal problem (Kalker, *Three-dimensional elastic bodies in rolling contact*, 1990, ch. 5;
Johnson, *Contact Mechanics*, 1985, 3.25): a uniform pressure ``p`` on a rectangle
``|xi| < dx/2, |eta| < dy/2`` of the surface of a half-space displaces the surface point ``(x, y)``
by ``p / (pi E*) * integral 1/r dA`` (Love 1929), with the combined modulus of two bodies of one
material ``1 / E* = 2 (1 - nu^2) / E = (1 - nu) / G``. On the elements in contact the deformed
gap vanishes, ``sep(x, y) - approach + u(p) = 0``, elsewhere ``p = 0`` and the gap is open; the
load is prescribed and the approach is the extra unknown. The active set (the elements in
contact) is found by Kalker's iteration (his NORM algorithm): solve on the set, drop the
elements with negative pressure, add those where the deformed surfaces overlap, until it does
not change.

The problems here are symmetric in the rolling direction ``x`` (no yaw), so only ``x > 0`` is
discretised and each element carries its mirror image: a quarter of the cost of a full grid.

Tangential problem: Kalker's linear theory (steady rolling, no slip anywhere; Kalker 1990
ch. 5) on the normal solution's contact area, longitudinal tractions only (Cerruti's
displacement of a uniformly loaded rectangle), for creepages that vary from element to element:
:func:`linear_theory_radius` is the rolling radius whose uniform creepage gives the patch's
longitudinal creep force.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
from scipy.special import ellipe, ellipk


def _love_primitive(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``F(u, v)`` with ``d2F / du dv = 1 / sqrt(u^2 + v^2)`` and ``F(0, v) = F(u, 0) = 0``:
    ``u asinh(v / |u|) + v asinh(u / |v|)`` (Johnson eq. 3.25, Love 1929)."""
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(u != 0.0, u * np.arcsinh(v / np.abs(u)), 0.0)
        b = np.where(v != 0.0, v * np.arcsinh(u / np.abs(v)), 0.0)
    return a + b


def rectangle_integral(x_m, y_m, dx_m: float, dy_m: float) -> np.ndarray:
    """``integral 1/r dA`` [m] over the rectangle ``|xi| < dx/2, |eta| < dy/2`` seen from the
    surface point ``(x, y)`` [m]. At the centre of a square of side ``2c``: ``8 c ln(1 + 2^0.5)``.
    """
    hx, hy = 0.5 * dx_m, 0.5 * dy_m
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    f = _love_primitive
    return f(x + hx, y + hy) - f(x - hx, y + hy) - f(x + hx, y - hy) + f(x - hx, y - hy)


@dataclass(frozen=True)
class Solution:
    """Pressure on the half grid ``x > 0`` and what follows from it.

    Attributes:
        x_m, y_m: element centres (``x`` the rolling direction, ``x > 0``; ``y`` lateral) [m].
        pressure_pa: pressure on each element [Pa] (the element at ``-x`` carries the same).
        approach_m: the approach of the two bodies (overlap of the undeformed surfaces at the
            separation's zero) [m].
        area_m2: one element's area [m^2].
        iterations: active-set iterations.
    """

    x_m: np.ndarray
    y_m: np.ndarray
    pressure_pa: np.ndarray
    approach_m: float
    area_m2: float
    iterations: int

    @property
    def load_N(self) -> float:
        return 2.0 * float(self.pressure_pa.sum()) * self.area_m2

    @property
    def centroid_y_m(self) -> float:
        """Lateral centroid of the pressure [m]."""
        return float(np.sum(self.pressure_pa * self.y_m) / np.sum(self.pressure_pa))

    @property
    def contact_area_m2(self) -> float:
        return 2.0 * float(np.count_nonzero(self.pressure_pa > 0.0)) * self.area_m2


def solve_symmetric(
    x_m: np.ndarray,
    y_m: np.ndarray,
    separation_m: np.ndarray,
    dx_m: float,
    dy_m: float,
    e_star_pa: float,
    load_N: float,
    *,
    approach_guess_m: float | None = None,
    max_iterations: int = 60,
) -> Solution:
    """Frictionless normal contact under a prescribed load on the elements ``(x, y)`` (``x > 0``,
    mirrored to ``-x``) of a regular grid of ``dx`` x ``dy``, with the undeformed separation
    ``sep`` [m] of the surfaces (any zero).

    Kalker's active-set iteration with the approach as the extra unknown of the load equation
    (the system kept symmetric: the load row divided by ``-2 dx dy``). It starts from the
    elements with ``sep <= sep_min + approach_guess / 2`` (Hertz's contact edge lies where the
    separation is half the approach), or, without a guess, within a fifth of the separations'
    lower range.

    Raises:
        RuntimeError: no converged active set within ``max_iterations``.
    """
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    sep = np.asarray(separation_m, dtype=float)
    # scaled to entries of order one: q = p dx / (pi E*) [m], M = integral(1/r dA) / dx
    influence = _influence_matrix(x, y, dx_m, dy_m) / dx_m
    to_pressure = np.pi * e_star_pa / dx_m
    area = dx_m * dy_m
    if approach_guess_m is None:
        active = sep <= sep.min() + 0.5 * (np.percentile(sep, 20) - sep.min())
    else:
        active = sep <= sep.min() + 0.5 * approach_guess_m
    p = np.zeros_like(sep)
    approach = 0.0
    iterations = 0
    while iterations < max_iterations:
        iterations += 1
        idx = np.flatnonzero(active)
        n = idx.size
        mat = np.zeros((n + 1, n + 1))
        mat[:n, :n] = influence[np.ix_(idx, idx)]
        mat[:n, n] = -1.0
        mat[n, :n] = -1.0
        rhs = np.concatenate([-sep[idx], [-load_N / (2.0 * area * to_pressure)]])
        sol = scipy.linalg.solve(mat, rhs, assume_a="sym", check_finite=False)
        p = np.zeros_like(sep)
        p[idx] = sol[:n]  # q until the loop ends
        approach = float(sol[n])
        negative = p < 0.0
        if np.any(negative):
            active &= ~negative
            continue
        gap = sep - approach + influence @ p
        overlap = (~active) & (gap < 0.0)
        if not np.any(overlap):
            break
        active |= overlap
    else:
        raise RuntimeError(f"no converged contact area after {max_iterations} iterations")
    return Solution(x, y, p * to_pressure, approach, area, iterations)


def _influence_matrix(x: np.ndarray, y: np.ndarray, dx_m: float, dy_m: float) -> np.ndarray:
    """``integral 1/r dA`` of element ``j`` and its mirror image at ``-x`` seen from element
    ``i`` [m], from a table over the grid's offsets (the elements lie on one regular grid)."""
    ix = np.rint((x - x.min()) / dx_m).astype(int)
    iy = np.rint((y - y.min()) / dy_m).astype(int)
    nx, ny = ix.max() + 1, iy.max() + 1
    x0 = x.min() - ix.min() * dx_m  # x of column 0 (the grid's first x > 0)
    ox = np.arange(-nx + 1, nx) * dx_m
    oy = np.arange(-ny + 1, ny) * dy_m
    direct = rectangle_integral(ox[:, None], oy[None, :], dx_m, dy_m)
    sx = (np.arange(0, 2 * nx - 1) + 0.0) * dx_m + 2.0 * x0
    mirror = rectangle_integral(sx[:, None], oy[None, :], dx_m, dy_m)
    di = ix[:, None] - ix[None, :] + nx - 1
    dj = iy[:, None] - iy[None, :] + ny - 1
    si = ix[:, None] + ix[None, :]
    return direct[di, dj] + mirror[si, dj]


def check_inside_grid(sol: Solution, x_edge_m: float, y_edges_m: tuple[float, float]) -> None:
    """Raise if a loaded element lies on the grid's outer row (the patch may be cut off)."""
    loaded = sol.pressure_pa > 0.0
    dx = np.min(np.diff(np.unique(sol.x_m))) if np.unique(sol.x_m).size > 1 else 0.0
    if np.any(sol.x_m[loaded] >= x_edge_m - 0.6 * dx):
        raise RuntimeError("the contact reaches the grid's edge in x")
    if np.any(sol.y_m[loaded] <= y_edges_m[0]) or np.any(sol.y_m[loaded] >= y_edges_m[1]):
        raise RuntimeError("the contact reaches the grid's edge in y")


# -- tangential: Kalker's linear theory (full adhesion, steady rolling) ---------------------------


def _cerruti_primitive(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``G(u, v)`` with ``d2G / du dv = u^2 / r^3``: ``v asinh(u / |v|)`` (``d/du`` of it is
    ``v / r``, whose ``d/dv`` is ``u^2 / r^3``)."""
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(v != 0.0, v * np.arcsinh(u / np.abs(v)), 0.0)


def tangential_rectangle_integral(x_m, y_m, dx_m: float, dy_m: float, nu: float) -> np.ndarray:
    """``integral ((1 - nu) / r + nu x^2 / r^3) dA`` [m] over the rectangle ``|xi| < dx/2,
    |eta| < dy/2`` seen from ``(x, y)``: the longitudinal surface displacement of a uniform
    longitudinal traction (Cerruti; Johnson 1985 eq. 3.86a, Kalker 1990 ch. 5) is this times
    ``q / (2 pi G)`` on one body, ``q / (pi G)`` for the difference of two bodies of one
    material."""
    hx, hy = 0.5 * dx_m, 0.5 * dy_m
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)

    def corners(f):
        return f(x + hx, y + hy) - f(x - hx, y + hy) - f(x + hx, y - hy) + f(x - hx, y - hy)

    return (1.0 - nu) * corners(_love_primitive) + nu * corners(_cerruti_primitive)


def linear_theory_forces(
    x_m: np.ndarray,
    y_m: np.ndarray,
    dx_m: float,
    dy_m: float,
    creepages: np.ndarray,
    shear_modulus_pa: float,
    nu: float,
) -> np.ndarray:
    """Longitudinal creep force [N] of steady rolling in full adhesion (Kalker's linear theory)
    on the contact area of the elements ``(x, y)`` (a regular grid, both signs of ``x``), for
    each column of ``creepages`` (one creepage per element: a creepage that varies across the
    patch, as the rolling radius does).

    Steady rolling in the direction ``-x`` of the material (leading edge at ``+x``): no slip
    anywhere, ``(u_I - u_I+) / dx = creepage_I`` with ``I+`` the element upstream of ``I``
    (Kalker's discretisation of the steady state; ``u`` of all elements, inside the area or
    not, from the tractions inside). Lateral tractions are left out (the coupling through
    ``nu``): for a uniform creepage on an ellipse ``a / b = 0.5`` this gives Kalker's ``C11``
    within 1 % of CONTACT's exact half-space value (tested). The force's sign is that of the
    traction solving the equations; only ratios are used.
    """
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    ox = x[:, None] - x[None, :]
    oy = y[:, None] - y[None, :]
    here = tangential_rectangle_integral(ox, oy, dx_m, dy_m, nu)
    upstream = tangential_rectangle_integral(ox + dx_m, oy, dx_m, dy_m, nu)
    matrix = (here - upstream) / (np.pi * shear_modulus_pa * dx_m)
    traction = np.linalg.solve(matrix, np.asarray(creepages, dtype=float))
    return traction.sum(axis=0) * dx_m * dy_m


def linear_theory_radius(patch: PatchResult, dx_m: float, dt_m: float, nu: float) -> float:
    """The rolling radius [m] that gives the patch's longitudinal creep force in Kalker's linear
    theory: a uniform creepage ``1 - Omega r_eff / V`` gives the same force as the creepage
    ``1 - Omega r(y) / V`` of the wheel's radius under each strip of the contact area (the
    area of the half-space's normal solution). ``r_eff = r_ref + F[r - r_ref] / F[1]`` (the
    theory is linear; the shear modulus drops out)."""
    sol = patch.solution
    loaded = sol.pressure_pa > 0.0
    x = np.concatenate([sol.x_m[loaded], -sol.x_m[loaded]])
    t = np.concatenate([sol.y_m[loaded], sol.y_m[loaded]])
    _, _, radius, _ = patch.plane.section(t)
    r_ref = float(np.mean(radius))
    creepages = np.column_stack([np.ones_like(t), radius - r_ref])
    force = linear_theory_forces(x, t, dx_m, dt_m, creepages, 1.0e11, nu)
    return r_ref + float(force[1] / force[0])


# -- Hertz (Johnson 1985, 3.26 and 4.2) ----------------------------------------------------------


@dataclass(frozen=True)
class HertzEllipse:
    """Hertz's solution for the separation ``A x^2 + B y^2`` (``A <= B``) under load ``P``."""

    a_m: float  # semi-axis along x (the larger one)
    b_m: float  # semi-axis along y
    p0_pa: float
    approach_m: float
    load_N: float


def hertz_from_shape(curv_a: float, curv_b: float, a_m: float, e_star_pa: float) -> HertzEllipse:
    """Hertz's ellipse for the separation ``A x^2 + B y^2`` with ``A <= B`` [1/m] and the semi-axis
    ``a`` along ``x``: the load, ``b``, ``p0`` and the approach follow.

    The pressure ``p0 (1 - x^2/a^2 - y^2/b^2)^0.5`` displaces the surface by
    ``delta - A x^2 - B y^2`` inside the ellipse with (``e^2 = 1 - b^2/a^2``, ``K, E`` the
    complete elliptic integrals of modulus ``e``) ``delta = p0 b K / E*``,
    ``A = p0 b (K - E) / (E* a^2 e^2)``, ``B = p0 b ((a^2/b^2) E - K) / (E* a^2 e^2)``; for
    ``e -> 0`` these are the sphere's ``delta = pi a p0 / (2 E*)``, ``A = B = pi p0 / (4 a E*)``.
    The ratio ``B / A`` fixes ``e`` (solved by bisection), then ``A`` fixes ``p0``.
    """
    ratio = curv_b / curv_a

    def shape_ratio(e2: float) -> float:
        k, e = ellipk(e2), ellipe(e2)  # scipy's argument is m = e^2
        return (e / (1.0 - e2) - k) / (k - e)

    if ratio <= 1.0 + 1e-12:
        e2 = 0.0
    else:
        lo, hi = 1e-12, 1.0 - 1e-15
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if shape_ratio(mid) < ratio:
                lo = mid
            else:
                hi = mid
        e2 = 0.5 * (lo + hi)
    b = a_m * np.sqrt(1.0 - e2)
    k, e = ellipk(e2), ellipe(e2)
    if e2 == 0.0:
        p0 = 4.0 * a_m * e_star_pa * curv_a / np.pi
    else:
        p0 = curv_a * e_star_pa * a_m**2 * e2 / (b * (k - e))
    return HertzEllipse(
        a_m=a_m,
        b_m=float(b),
        p0_pa=float(p0),
        approach_m=float(p0 * b * k / e_star_pa),
        load_N=float(2.0 / 3.0 * np.pi * a_m * b * p0),
    )


# -- wheel and rail: the undeformed separation in the contact's plane ----------------------------


@dataclass(frozen=True)
class WheelOnRail:
    """One wheel over its rail in the left-type track frame (``docs/conventions.md``: ``y``
    outwards, ``z`` up), at zero yaw.

    Args:
        pair: the placed wheel and rail (profiles, tape circle, rail origin and cant).
        lateral_m: the wheelset centre's lateral position in this wheel's left-type frame [m]
            (the left wheel: the wheelset's ``y``; the right wheel: ``-y``).
        roll_rad: the wheelset's roll in this frame (the right wheel: ``-phi``).
    """

    pair: object
    lateral_m: float
    roll_rad: float

    # the wheelset centre's height does not matter: the approach absorbs it
    @property
    def _centre_z(self) -> float:
        return self.pair.nominal_radius_m

    def rail_z(self, y_m):
        """Height of the rail's surface at track ``y`` [m]."""
        oy, oz = self.pair.rail_origin_track_m
        return self.pair.rail_canted.height(np.asarray(y_m) - oy) + oz

    def rail_slope(self, y_m):
        oy, _ = self.pair.rail_origin_track_m
        return self.pair.rail_canted.slope(np.asarray(y_m) - oy)

    def wheel_point(self, s_m):
        """The wheel's lowest circle point at profile coordinate ``s`` (track ``y, z``) and its
        derivative along ``s``; the circle's radius ``r0 + F(s)``."""
        s = np.asarray(s_m, dtype=float)
        f = self.pair.wheel.height(s)
        df = self.pair.wheel.slope(s)
        r = self.pair.nominal_radius_m + f
        c, sn = np.cos(self.roll_rad), np.sin(self.roll_rad)
        e = self.pair.tape_circle_lateral_m
        wy = self.lateral_m + c * (e + s) + sn * r
        wz = self._centre_z + sn * (e + s) - c * r
        return wy, wz, c + sn * df, sn - c * df, r

    def vertical_gap(self, s_m):
        """Vertical distance of the wheel point ``s`` above the rail [m] (any zero)."""
        wy, wz, *_ = self.wheel_point(s_m)
        return wz - self.rail_z(wy)

    def deepest_s(self, s_min_m: float = -0.035, s_max_m: float = 0.045) -> float:
        """Profile coordinate of the smallest vertical gap (scan at 10 um)."""
        s = np.arange(s_min_m, s_max_m, 1.0e-5)
        return float(s[np.argmin(self.vertical_gap(s))])

    def plane(self, y_ref_m: float) -> PlaneSection:
        """The contact's plane through the rail point at track ``y_ref`` (tangent to the rail)."""
        return PlaneSection(self, y_ref_m)


class PlaneSection:
    """The undeformed separation of wheel and rail measured along the normal of a plane tangent
    to the rail at ``y_ref``, as a function of the plane's lateral coordinate ``t`` (the
    approximation of CONTACT's planar contact: both bodies are half-spaces bounded by this
    plane; the surfaces' lateral curvature enters only through the separation)."""

    def __init__(self, wheel: WheelOnRail, y_ref_m: float):
        self.wheel = wheel
        self.y_ref_m = float(y_ref_m)
        self.z_ref_m = float(wheel.rail_z(y_ref_m))
        self.angle_rad = float(np.arctan(wheel.rail_slope(y_ref_m)))

    def _point(self, t):
        c, s = np.cos(self.angle_rad), np.sin(self.angle_rad)
        return self.y_ref_m + t * c, self.z_ref_m + t * s, c, s

    def section(self, t_m):
        """At the plane's coordinates ``t`` [m]: the separation along the normal [m], the wheel's
        profile coordinate ``s`` [m] and rolling radius [m] where the normal meets the wheel,
        and the separation's curvature along the rolling direction [1/m]."""
        t = np.asarray(t_m, dtype=float)
        py, pz, c, sn = self._point(t)
        ny, nz = -sn, c
        w = self.wheel
        # rail: P + lam n on the rail (Newton; the rail's slope varies slowly)
        lam_r = np.zeros_like(t)
        for _ in range(8):
            yr = py + lam_r * ny
            f = w.rail_z(yr) - (pz + lam_r * nz)
            df = w.rail_slope(yr) * ny - nz
            lam_r = lam_r - f / df
        # wheel: the profile point whose offset from P is along n, (W(s) - P) . t_hat = 0
        e = w.pair.tape_circle_lateral_m
        cr, sr = np.cos(w.roll_rad), np.sin(w.roll_rad)
        s = (py - w.lateral_m - sr * w.pair.nominal_radius_m) / cr - e
        for _ in range(12):
            wy, wz, dwy, dwz, _r = w.wheel_point(s)
            h = (wy - py) * c + (wz - pz) * sn
            dh = dwy * c + dwz * sn
            s = s - h / dh
        wy, wz, _, _, r = w.wheel_point(s)
        lam_w = (wy - py) * ny + (wz - pz) * nz
        # the circle of radius r bends away from the plane by x^2 / (2 r) along its principal
        # normal (to the axle), whose component along n is cos(angle - roll) (Meusnier)
        kappa_x = np.cos(self.angle_rad - w.roll_rad) / r
        return lam_w - lam_r, s, r, kappa_x


@dataclass(frozen=True)
class PatchResult:
    """The half-space solution of one wheel and what the rolling radius is there."""

    solution: Solution
    plane: PlaneSection
    centroid_t_m: float
    centroid_s_m: float  # wheel profile coordinate at the pressure centroid
    centroid_radius_m: float
    mean_radius_m: float  # pressure-weighted mean rolling radius
    area_centroid_s_m: float  # wheel profile coordinate at the contact area's centroid


def wheel_patch(
    wheel: WheelOnRail,
    load_N: float,
    e_star_pa: float,
    *,
    dx_m: float = 1.0e-3,
    dt_m: float = 5.0e-4,
    half_width_m: float = 0.03,
) -> PatchResult:
    """Pressure of one wheel on its rail under ``load_N`` (along the plane's normal) and the
    rolling radius at the pressure's centroid.

    Two passes: a coarse one (4 ``dx`` x 4 ``dt``) on the plane at the deepest point of the
    vertical gap finds the approach and the patch; the fine one uses the plane at the coarse
    pressure centroid (CONTACT's reference point is likewise a centroid of the overlap) and the
    elements where the rigid overlap at 1.3 times the coarse approach is positive (the contact
    lies inside the overlap region of the half-spaces, whose displacements are positive).
    """
    s_deep = wheel.deepest_s()
    wy, *_ = wheel.wheel_point(s_deep)
    plane = wheel.plane(float(wy))
    coarse = _solve_on_plane(plane, load_N, e_star_pa, 4 * dx_m, 4 * dt_m, half_width_m, None)
    t_c = coarse.centroid_y_m
    y_c = plane.y_ref_m + t_c * np.cos(plane.angle_rad)
    plane = wheel.plane(float(y_c))
    sol = _solve_on_plane(plane, load_N, e_star_pa, dx_m, dt_m, half_width_m, coarse.approach_m)
    t_c = sol.centroid_y_m
    _, s_c, r_c, _ = plane.section(np.array([t_c]))
    _, s_e, r_e, _ = plane.section(sol.y_m)
    weights = sol.pressure_pa
    loaded = weights > 0.0
    t_area = float(np.mean(sol.y_m[loaded]))
    _, s_a, _, _ = plane.section(np.array([t_area]))
    return PatchResult(
        solution=sol,
        plane=plane,
        centroid_t_m=t_c,
        centroid_s_m=float(s_c[0]),
        centroid_radius_m=float(r_c[0]),
        mean_radius_m=float(np.sum(weights * r_e) / np.sum(weights)),
        area_centroid_s_m=float(s_a[0]),
    )


def _solve_on_plane(plane, load_N, e_star_pa, dx, dt, half_width, approach_guess):
    t = np.arange(-half_width, half_width + 0.5 * dt, dt)
    d, _s, _r, kx = plane.section(t)
    d = d - d.min()
    # without a guess, generous: 1 mm of separation holds any wheel-rail patch under a few
    # hundred kN; with one, 1.3 times it (the contact lies inside the overlap region)
    reach = 1.0e-3 if approach_guess is None else 1.3 * approach_guess
    n_x = int(np.ceil(np.sqrt(2.0 * reach / kx.min()) / dx)) + 1
    x = (np.arange(n_x) + 0.5) * dx
    xx, tt = np.meshgrid(x, t, indexing="ij")
    sep = d[None, :] + 0.5 * kx[None, :] * xx**2
    keep = sep <= reach
    sol = solve_symmetric(
        xx[keep], tt[keep], sep[keep], dx, dt, e_star_pa, load_N, approach_guess_m=approach_guess
    )
    if approach_guess is not None and sol.approach_m > reach:
        raise RuntimeError("the fine grid does not hold the overlap region")
    check_inside_grid(sol, x[-1] + 0.5 * dx, (t[0], t[-1]))
    return sol
