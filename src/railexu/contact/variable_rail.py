"""Quasi-static contact of a wheel on a variable rail profile: switches and crossings.

The rail of one side is a :class:`~railexu.profiles.variable.VariableProfile` (one curve per
slice through the flangeway, or several rails: wing rail, nose, check rail, whose topmost
surface counts at each lateral position). The wheel is a body of revolution. Because the rail
changes along the track (a nose rising 1:10), contact is not under the axle: the search is
three-dimensional, on a grid in ``x`` (along the track, from the wheel's axle) and ``y``.

Method:

1. *Interpenetration.* On a coarse grid over the wheel's width and ``|x| <= x_max`` the
   overlap ``h(x, y) = z_wheel(x, y) - z_rail(s + x, y)`` (z downwards, positive = overlap),
   with ``z_wheel = z_ws + z_w(y_w) - (r - sqrt(r^2 - x^2))``, ``r = r_0 + z_w(y_w)``.
2. *Patches.* Every connected region with ``h > -near_m`` on the coarse grid is a candidate
   patch, refined on a fine grid (``dx``, ``dy``, CONTACT's DX and DS) over its bounding box;
   it is a patch if it overlaps there. The margin ``near_m`` (30 um, more than the coarse
   grid's error of ``dx^2 / (8 r)`` = 0.3 um along the wheel and the rail's change over a
   coarse cell) makes sure that an overlap the coarse grid cannot see is still found on the
   fine one: the force is continuous in the wheel's position. A region cannot be missed in
   the flangeway (the grid covers every lateral position) and a patch cannot jump between
   rails (each patch is the overlap region itself, wherever it lies).
3. *Normal problem per patch.* The contact plane is tilted by the rail's slope angle at the
   patch's deepest point (on the fine grid the rail's curves are monotone cubics between their
   resampled points, not straight: a kink every 0.2 mm would give the pressure a false
   logarithmic peak): the normal overlap is ``h cos(delta)`` and the lateral element size
   ``dy / cos(delta)``; the pressure follows from the elastic half-space
   (:func:`railexu.contact.halfspace.solve_normal`), frictionless. The normal force acts along
   the plane's normal: vertical component ``N cos(delta)``, lateral ``N sin(delta)``.
4. *Tangential problem per patch* (when a :class:`~railexu.contact.variable_creep.WheelMotion`
   is given): the patch's creepages from the wheelset's speed and pitch rate at its pressure
   centre (with the pressure-weighted rail slope), and its creep forces ``Fx`` (along the
   track) and ``Fs`` (laterally in the contact plane) on the pressure grid of step 3
   (:mod:`railexu.contact.variable_creep`, CONTACT's axes and signs). The vertical and
   lateral forces on the rail then include them: ``N cos(delta) + Fs sin(delta)`` and
   ``Fs cos(delta) - N sin(delta)`` (CONTACT's FZ(TR), FY(TR)). With the same material on
   both sides the normal problem does not depend on the tangential one (Kalker 1990,
   quasi-identity), so the normal pressure is solved once.

Without a motion only the normal problem is solved (frictionless). The wheelset is not rolled
or yawed.
Coordinates: those of CONTACT's right wheel on its right rail (``y`` towards the field side, the
rail profile's own ``y``; ``z`` down), in metres; ``s`` along the track.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

from railexu.contact.halfspace import solve_normal
from railexu.contact.variable_creep import (
    PatchCreepage,
    WheelMotion,
    mean_slope_angle,
    patch_creepages,
    tangential_forces,
)
from railexu.errors import ComputationError
from railexu.profiles.variable import VariableProfile
from railexu.profiles.variable.rails import rail_index


@dataclass(frozen=True)
class WheelSection:
    """A wheel profile ``z_w(y_w)`` (z down, positive = larger radius) [m] on its axle.

    Attributes:
        points_m: profile points ``(y_w, z_w)`` [m], ``y_w`` increasing.
        nominal_radius_m: radius where ``z_w = 0`` [m].
        y_offset_m: rail-profile ``y`` of the wheel profile's origin at zero lateral
            displacement [m] (CONTACT: ``FBDIST/2 - FBPOS - RAILY0``).
    """

    points_m: np.ndarray
    nominal_radius_m: float
    y_offset_m: float = 0.0

    @classmethod
    def from_pair(cls, pair) -> WheelSection:
        """The wheel of a placed :class:`~railexu.contact.placement.WheelRailPair` as the
        dynamics places it over its rail (no cant): the wheel table's lateral coordinate from
        the tape circle and radius increase, the tape circle ``e`` from the track centre, the
        rail's own origin at ``y0`` in track axes: ``y_offset = e - y0`` [m]."""
        table = pair.wheel_table
        u = table.y0_m + table.step_m * np.arange(table.z.size)
        offset = pair.tape_circle_lateral_m - pair.rail_origin_track_m[0]
        return cls(np.column_stack([u, table.z]), pair.nominal_radius_m, offset)

    def height(self, y_w: np.ndarray) -> np.ndarray:
        """``z_w`` [m] at ``y_w``; NaN outside the profile."""
        p = self.points_m
        f = PchipInterpolator(p[:, 0], p[:, 1], extrapolate=False)
        return f(y_w)


@dataclass(frozen=True)
class Patch:
    """One contact patch (SI units, rail-profile coordinates, z down).

    Attributes:
        x_m, y_m, z_m: pressure centre on the rail surface [m].
        angle_rad: contact angle ``delta`` (rail slope, positive = surface rising to larger y
            ... as CONTACT's DELTCP, negative on the gauge face of a right rail).
        normal_force_n: normal force N [N].
        vertical_force_n, lateral_force_n: the patch's force on the rail, vertically (z down
            positive) and laterally [N]: ``N cos(delta) + Fs sin(delta)``,
            ``Fs cos(delta) - N sin(delta)``.
        max_overlap_m: largest undeformed overlap along the normal [m].
        area_m2: contact area [m^2].
        rail_index: which rail of the side carries it, 0 the gauge side's (nose), 1 the field
            side's (wing rail): the rail whose surface is on top at the pressure centre, at its
            own station ``s + x`` (:func:`railexu.profiles.variable.rails.rail_index`: by the
            slices' boundary feature, else separate curves in lateral order or the two sides
            of a single curve's deepest point).
        fx_n, fs_n: the creep forces on the rail [N] along the track and laterally in the
            contact plane (CONTACT's FX, FS; 0 without a motion).
        creepage: the patch's creepages (``None`` without a motion).
    """

    x_m: float
    y_m: float
    z_m: float
    angle_rad: float
    normal_force_n: float
    vertical_force_n: float
    lateral_force_n: float
    max_overlap_m: float
    area_m2: float
    rail_index: int
    fx_n: float = 0.0
    fs_n: float = 0.0
    creepage: PatchCreepage | None = None


@dataclass(frozen=True)
class ContactSettings:
    """Grid and material of the quasi-static S&C contact (CONTACT's DX, DS, G, POISS)."""

    dx_m: float = 2.0e-4
    dy_m: float = 2.0e-4
    coarse_dx_m: float = 1.0e-3
    coarse_dy_m: float = 2.5e-4
    x_max_m: float = 0.08
    shear_modulus_pa: float = 82.0e9
    poisson: float = 0.28
    margin_m: float = 1.0e-3
    near_m: float = 3.0e-5

    @property
    def e_star_pa(self) -> float:
        """``E* = G / (1 - nu)`` for two bodies of one material [Pa]."""
        return self.shear_modulus_pa / (1.0 - self.poisson)


def _overlap(rail, wheel, s_m, y_ws_m, z_ws_m, x, y, smooth=False):
    """Overlap ``h(x, y)`` [m] (positive = wheel below the rail surface), ``-inf`` off rail;
    ``smooth``: the rail's curves as monotone cubics between their points (the fine grid's
    pressure), else straight between them (the coarse search)."""
    return _overlap_and_rail(rail, wheel, s_m, y_ws_m, z_ws_m, x, y, smooth)[0]


def _overlap_and_rail(rail, wheel, s_m, y_ws_m, z_ws_m, x, y, smooth):
    """:func:`_overlap` and the rail's heights ``z(x, y)`` [m] on the grid it used."""
    zw = wheel.height(y - y_ws_m - wheel.y_offset_m)
    r = wheel.nominal_radius_m + zw
    drop = r[None, :] - np.sqrt(np.maximum(r[None, :] ** 2 - x[:, None] ** 2, 0.0))
    z_wheel = z_ws_m + zw[None, :] - drop
    z_rail = rail.heights_on_grid(s_m + x, y, smooth=smooth)
    h = z_wheel - z_rail
    return np.where(np.isfinite(h), h, -np.inf), z_rail


def patches_at(
    rail: VariableProfile,
    wheel: WheelSection,
    s_m: float,
    y_ws_m: float,
    z_ws_m: float,
    settings: ContactSettings = ContactSettings(),
    motion: WheelMotion | None = None,
) -> list[Patch]:
    """The contact patches of a wheel at track position ``s``, lateral ``y_ws``, height ``z_ws``.

    Args:
        rail: the rail (or rails) of the side.
        wheel: the wheel profile and its placement.
        s_m: the wheel's track position [m]; y_ws_m: lateral displacement [m]; z_ws_m: vertical
            position [m] (down positive, CONTACT's Z_WS).
        motion: the wheelset's speed, pitch rate and friction: creep forces per patch; ``None``
            frictionless.
    """
    st = settings
    yw = wheel.points_m[:, 0] + y_ws_m + wheel.y_offset_m
    yc = np.arange(yw[0] + st.coarse_dy_m, yw[-1], st.coarse_dy_m)
    xc = np.arange(-st.x_max_m, st.x_max_m + 0.5 * st.coarse_dx_m, st.coarse_dx_m)
    hc = _overlap(rail, wheel, s_m, y_ws_m, z_ws_m, xc, yc)
    labels, n = ndimage.label(hc > -st.near_m)
    out = []
    for lab in range(1, n + 1):
        ii, jj = np.nonzero(labels == lab)
        x0 = xc[ii.min()] - st.coarse_dx_m - st.margin_m
        x1 = xc[ii.max()] + st.coarse_dx_m + st.margin_m
        y0 = yc[jj.min()] - st.coarse_dy_m - st.margin_m
        y1 = yc[jj.max()] + st.coarse_dy_m + st.margin_m
        box = (x0, x1, y0, y1)
        patch = _solve_patch(rail, wheel, s_m, y_ws_m, z_ws_m, box, st, motion)
        if patch is not None:
            out.append(patch)
    return _merge_duplicates(sorted(out, key=lambda p: p.y_m))


def _solve_patch(rail, wheel, s_m, y_ws_m, z_ws_m, box, st, motion=None) -> Patch | None:
    """The normal (and with ``motion`` the tangential) problem on the fine grid over one
    coarse patch's box."""
    x0, x1, y0, y1 = box
    x = np.arange(x0, x1 + 0.5 * st.dx_m, st.dx_m)
    y = np.arange(y0, y1 + 0.5 * st.dy_m, st.dy_m)
    h, z_rail = _overlap_and_rail(rail, wheel, s_m, y_ws_m, z_ws_m, x, y, smooth=True)
    if not np.any(h > 0.0):
        return None
    i, j = np.unravel_index(int(np.argmax(h)), h.shape)
    zr = z_rail[i]
    jm, jp = max(j - 1, 0), min(j + 1, y.size - 1)
    slope = (zr[jp] - zr[jm]) / (y[jp] - y[jm]) if jp > jm else 0.0
    if not math.isfinite(slope):
        slope = 0.0
    delta = math.atan(slope)
    cos_d = math.cos(delta)
    hn = np.where(h > 0.0, h, np.minimum(h, 0.0)) * cos_d
    hn = np.where(np.isfinite(hn), hn, -1.0)
    p = solve_normal(hn, st.dx_m, st.dy_m / cos_d, st.e_star_pa)
    area = st.dx_m * st.dy_m / cos_d
    force = float(p.sum() * area)
    if force <= 0.0:
        return None
    w = p / p.sum()
    xm = float(np.sum(w.sum(axis=1) * x))
    ym = float(np.sum(w.sum(axis=0) * y))
    zm = float(np.interp(ym, y, np.where(np.isfinite(zr), zr, 0.0)))
    fx = fs = 0.0
    creep = None
    if motion is not None:
        r_w = wheel.nominal_radius_m + float(
            wheel.height(np.array([ym - y_ws_m - wheel.y_offset_m]))[0]
        )
        if not math.isfinite(r_w):
            raise ComputationError(
                f"creepages at s = {s_m:.4f} m: the patch's centre y = {ym * 1e3:.2f} mm lies "
                "beside the wheel's profile"
            )
        with np.errstate(invalid="ignore"):  # NaN beside the rail: left out of the mean
            slope = np.gradient(z_rail, y, axis=1)
        creep = patch_creepages(xm, r_w, mean_slope_angle(p, slope), motion)
        fx, fs = tangential_forces(
            p, x - xm, (y - ym) / cos_d, creep, motion, st.shear_modulus_pa, st.poisson
        )
    sin_d = math.sin(delta)
    return Patch(
        x_m=xm,
        y_m=ym,
        z_m=zm,
        angle_rad=delta,
        normal_force_n=force,
        vertical_force_n=force * cos_d + fs * sin_d,
        lateral_force_n=fs * cos_d - force * sin_d,
        max_overlap_m=float(h.max() * cos_d),
        area_m2=float(np.count_nonzero(p > 0.0) * area),
        rail_index=int(rail_index(rail, s_m + xm, np.array([ym]))[0]),
        fx_n=float(fx),
        fs_n=float(fs),
        creepage=creep,
    )


@dataclass(frozen=True)
class RailForces:
    """The forces of all patches of a wheel on its rail(s) in track axes [N] (CONTACT's TOTAL
    FORCES ON RAIL: FX(TR), FY(TR), FZ(TR); ``x`` along the track, ``y`` towards the field
    side, ``z`` down)."""

    longitudinal_n: float
    lateral_n: float
    vertical_n: float


def total_forces(patches: list[Patch]) -> RailForces:
    """The sum of the patches' forces on the rail in track axes: ``FX``, ``Fs cos(delta) -
    N sin(delta)``, ``N cos(delta) + Fs sin(delta)`` [N]."""
    return RailForces(
        longitudinal_n=float(sum(p.fx_n for p in patches)),
        lateral_n=float(sum(p.lateral_force_n for p in patches)),
        vertical_n=float(sum(p.vertical_force_n for p in patches)),
    )


def _merge_duplicates(patches: list[Patch]) -> list[Patch]:
    """Two coarse regions whose fine boxes found the same patch: keep one."""
    out: list[Patch] = []
    for p in patches:
        if out and abs(p.y_m - out[-1].y_m) < 1e-6 and abs(p.x_m - out[-1].x_m) < 1e-6:
            continue
        out.append(p)
    return out


def press_wheel(
    rail: VariableProfile,
    wheel: WheelSection,
    s_m: float,
    y_ws_m: float,
    load_n: float,
    settings: ContactSettings = ContactSettings(),
    *,
    tol_n: float = 1.0,
    motion: WheelMotion | None = None,
) -> tuple[float, list[Patch]]:
    """The vertical position ``z_ws`` [m] at which the patches carry ``load_n`` vertically
    (with ``motion`` their creep forces' vertical components included, as CONTACT's FZ).

    Raises:
        ComputationError: no position carries the load (the wheel is off its rails).
    """

    def excess(z: float) -> float:
        return (
            sum(
                p.vertical_force_n
                for p in patches_at(rail, wheel, s_m, y_ws_m, z, settings, motion)
            )
            - load_n
        )

    z_touch = _touch_height(rail, wheel, s_m, y_ws_m, settings)
    lo, hi = z_touch - 1.0e-4, z_touch + 2.0e-4  # lo: 0.1 mm above the coarse grid's touch
    while excess(hi) < 0.0:
        hi += 2.0e-4
        if hi - z_touch > 3.0e-3:
            raise ComputationError(
                f"no vertical position carries {load_n:.0f} N at s = {s_m:.4f} m, "
                f"y = {y_ws_m * 1e3:.2f} mm"
            )
    z = brentq(excess, lo, hi, xtol=1.0e-9, rtol=1.0e-12, maxiter=60)
    patches = patches_at(rail, wheel, s_m, y_ws_m, z, settings, motion)
    total = sum(p.vertical_force_n for p in patches)
    if abs(total - load_n) > max(tol_n, 1e-3 * load_n):
        raise ComputationError(f"pressing the wheel: {total:.1f} N against {load_n:.1f} N")
    return z, patches


def rail_touch_heights(
    rail: VariableProfile,
    wheel: WheelSection,
    s_m: float,
    y_ws_m: float,
    x_max_m: float = 0.06,
    dx_m: float = 2.0e-3,
    dy_m: float = 2.5e-4,
) -> np.ndarray:
    """The rigid wheel's height ``z_ws`` [m, down] at which it first touches rail 0 and rail 1
    of the side (e.g. the blade and the stock rail) at ``s``: the largest overlap over the
    wheel's width and ``|x| <= x_max`` along the track on a ``dx`` x ``dy`` grid, each point
    given to the rail on top there at ``s + x`` (:func:`~railexu.profiles.variable.rails.
    rail_index`). NaN for a rail not within the wheel's reach. The geometry alone: the rail
    whose touch height is the smaller carries a rigid wheel; where they are equal it touches
    both at once."""
    yw = wheel.points_m[:, 0] + y_ws_m + wheel.y_offset_m
    yy = np.arange(yw[0] + dy_m, yw[-1], dy_m)
    xx = np.arange(-x_max_m, x_max_m + 0.5 * dx_m, dx_m)
    h = _overlap(rail, wheel, s_m, y_ws_m, 0.0, xx, yy)
    best = np.full(2, -np.inf)
    for i, x in enumerate(xx):
        k = rail_index(rail, s_m + x, yy)
        for r in (0, 1):
            row = h[i][(k == r) & np.isfinite(h[i])]
            if row.size:
                best[r] = max(best[r], float(row.max()))
    return np.where(np.isfinite(best), -best, np.nan)


def _touch_height(rail, wheel, s_m, y_ws_m, settings) -> float:
    """``z_ws`` [m] at which the wheel first touches (largest overlap zero), coarse grid."""
    st = settings
    yw = wheel.points_m[:, 0] + y_ws_m + wheel.y_offset_m
    yc = np.arange(yw[0] + st.coarse_dy_m, yw[-1], st.coarse_dy_m)
    xc = np.arange(-st.x_max_m, st.x_max_m + 0.5 * st.coarse_dx_m, st.coarse_dx_m)
    h = _overlap(rail, wheel, s_m, y_ws_m, 0.0, xc, yc)
    if not np.any(np.isfinite(h)):
        raise ComputationError(f"the wheel at s = {s_m:.4f} m is beside its rails")
    return -float(np.max(h))
