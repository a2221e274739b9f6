"""Creepages and creep forces of one patch of the quasi-static S&C contact (issue 29).

The tangential problem of :mod:`railexu.contact.variable_rail`, in CONTACT's wheel-rail axes and
signs (E.A.H. Vollebregt, CONTACT, eve70a/CONTACT, Apache-2.0; the definitions below are
checked against the creepages its ``examples_s+c`` reference outputs print, CKSI, CETA, CPHI,
in ``tests/test_sc_contact_creep.py``): ``x`` along the track (forward), ``y`` towards the
field side of the right rail, ``z`` down; the contact plane is tilted about ``x`` by the
contact angle ``delta`` only (not pitched, even 46 mm ahead of the axle), with the in-plane
lateral axis ``s = (0, cos delta, sin delta)`` and the rail's normal ``n = (0, -sin delta,
cos delta)``.

**Creepages** (rail at rest, the wheelset moving at ``V`` with the pitch rate ``omega``,
CONTACT's VPITCH, negative when rolling forward, and the lateral speed ``V_y``). A wheel point
at ``x`` ahead of the axle on the wheel's radius ``r_w`` there lies ``d = sqrt(r_w^2 - x^2)``
below the axle and moves with ``v = (V + omega d, V_y, -omega x)``. With the rolling speed
``V_r = (V + |omega| d) / 2`` (the mean of the two bodies' speeds along ``x`` relative to the
contact; CONTACT's VELOC) the creepages are the rail's velocity minus the wheel's::

    xi  = -(V + omega d) / V_r
    eta = -(V_y cos delta - omega x sin delta) / V_r
    phi = omega sin delta / V_r          [1/m]   (-(omega . n) / V_r)

so that ``xi < 0`` when the wheel's surface turns faster than it moves (traction). With
CONTACT's own reference point, angle and wheel surface (``d = r0 + ZCP(W) + approach``) they
reproduce its printed creepages: on ``cross_brute`` (x = 45.8 mm, delta = -0.0199)
-5.197e-3, 1.985e-3, 4.337e-2 1/m against CONTACT's -5.197e-3, 1.980e-3, 4.328e-2 1/m (the
angle is printed to 1e-4 rad). railexu's patch takes ``x`` and ``r_w`` at its pressure centre
and, for ``eta`` and ``phi``, the pressure-weighted mean of the rail's lateral slope over the
patch (:func:`mean_slope_angle`; the slope, and with it the spin, changes across a patch on a
rounded corner).

**Forces** (on the rail, along ``x`` and ``s``; equal and opposite on the wheel), with the
signs of Kalker's linear theory ``Fx = -G a b c11 xi``, ``Fs = -G a b c22 eta - G (ab)^1.5 c23
phi`` (Kalker 1990), by the law named in ``tangential``:

- ``"fastsim_grid"`` (default): Kalker's simplified theory (FASTSIM, Kalker, VSD 11 (1982)
  1-13) marched along every grid strip of the patch from its leading edge (largest ``x``) with
  the traction bound ``mu p(x, y)`` of the patch's own half-space pressure; spin turns about
  the pressure centre. The flexibilities make the no-slip force on the patch's own strips
  Kalker's linear force of the equivalent ellipse (``b`` half the contact's width in the plane,
  ``a = A / (pi b)`` so that ``pi a b`` is the contact's area ``A``; Kalker's coefficients
  for its ``a/b``, :func:`railexu.contact.kalker.kalker_coefficients`):
  ``L1 = M1 / (G a b c11)``, ``L2 = M1 / (G a b c22)``, ``L3 = M2 / (G (ab)^1.5 c23)`` with the
  strips' moments ``M1 = int (x_lead - x) dA``, ``M2 = int (x_lead^2 - x^2) / 2 dA``
  (:func:`strip_moments`); on an ellipse these are FASTSIM's own ``8 a / (3 c11 G)``, ...,
  ``pi a sqrt(a/b) / (4 c23 G)``. Where a cell slides, its traction ``mu p`` acts against
  its slip ``L (p - p_trial)`` (``L = diag(L1, L2)``; Coulomb's law in FASTSIM's elastic
  model, solved per cell by Newton's method): with ``L1 != L2`` scaling the trial traction
  back along itself would turn full sliding towards ``(xi / L1, eta / L2)`` instead of against
  the creepage. Full sliding gives exactly ``mu N`` (the bound integrates to it cell by
  cell) against the creepage.
- ``"exact"``: Kalker's exact steady rolling problem on the patch's grid with its half-space
  pressure (:mod:`railexu.contact.halfspace_tangential`: Cerruti's influence coefficients,
  Coulomb's law element by element, spin about the pressure centre), the problem CONTACT's
  reference solves. Against CONTACT's ``examples_s+c`` cases within 5 % of mu N where the
  normal forces agree (the stock rail's FX 6.6 %), where ``fastsim_grid`` is within 10 %
  but for the wing rail's skewed patch on the whole crossing (16.4 %). Not the default: it is
  not better on every component (0.1-2.1 % of mu N further on 5 of 14) and costs 0.5-5
  times FASTSIM on the 0.2 x 0.2 mm grid, 7-170 times on CONTACT's 0.2 x 0.05 mm.
- any creep law of :data:`railexu.contact.parameters.CREEP_MODELS` (``"polach"``,
  ``"fastsim"``, ...): that law on the equivalent ellipse with the normal force ``N``
  (:func:`railexu.contact.creep.creep_forces`).

The comparison with CONTACT is in docs/switches-and-crossings.md, "Validation against
CONTACT", "Creep forces" and "The exact tangential solution".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railexu.contact.creep import creep_forces
from railexu.contact.halfspace_tangential import solve_tangential
from railexu.contact.kalker import kalker_coefficients
from railexu.contact.parameters import CREEP_MODELS
from railexu.errors import InputError, did_you_mean

#: The tangential solutions by name: the patch's own grid, or a creep law on its ellipse.
TANGENTIAL_MODELS: tuple[str, ...] = ("fastsim_grid", "exact", *CREEP_MODELS)


@dataclass(frozen=True)
class WheelMotion:
    """The wheelset's motion and the friction of a quasi-static S&C contact (CONTACT's VS, VY,
    VPITCH and FSTAT = FKIN).

    Attributes:
        speed_m_per_s: forward speed ``V`` [m/s] (> 0).
        pitch_rate_rad_per_s: rotation about the axle [rad/s], CONTACT's sign (``z`` down:
            negative when rolling forward; ``-V / r`` rolls freely on the radius ``r``).
        lateral_speed_m_per_s: lateral speed ``V_y`` [m/s], towards the field side.
        friction: friction coefficient ``mu`` [-] (>= 0).
        tangential: the tangential solution, one of :data:`TANGENTIAL_MODELS`.
    """

    speed_m_per_s: float
    pitch_rate_rad_per_s: float
    lateral_speed_m_per_s: float = 0.0
    friction: float = 0.3
    tangential: str = "fastsim_grid"

    def __post_init__(self) -> None:
        for name in ("speed_m_per_s", "pitch_rate_rad_per_s", "lateral_speed_m_per_s", "friction"):
            if not math.isfinite(getattr(self, name)):
                raise InputError(f"WheelMotion.{name} must be finite, got {getattr(self, name)}")
        if self.speed_m_per_s <= 0.0:
            raise InputError(f"WheelMotion.speed_m_per_s must be > 0, got {self.speed_m_per_s}")
        if self.friction < 0.0:
            raise InputError(f"WheelMotion.friction must be >= 0, got {self.friction}")
        key = str(self.tangential).strip().lower().replace("-", "_").replace(" ", "_")
        if key not in TANGENTIAL_MODELS:
            hint = did_you_mean(key, TANGENTIAL_MODELS, cutoff=0.5)
            raise InputError(
                f"WheelMotion.tangential: unknown tangential solution {self.tangential!r}."
                f"{hint if hint.startswith(' Did') else ''} Valid: {', '.join(TANGENTIAL_MODELS)}."
            )
        object.__setattr__(self, "tangential", key)


@dataclass(frozen=True)
class PatchCreepage:
    """The creepages of one patch (CONTACT's CKSI, CETA, CPHI and VELOC; module doc).

    Attributes:
        xi: longitudinal creepage [-]; eta: lateral creepage in the contact plane [-];
        phi_per_m: spin creepage [1/m]; rolling_speed_m_per_s: ``V_r`` [m/s];
        angle_rad: the angle ``delta`` they were computed with [rad].
    """

    xi: float
    eta: float
    phi_per_m: float
    rolling_speed_m_per_s: float
    angle_rad: float


def patch_creepages(
    x_m: float, wheel_radius_m: float, angle_rad: float, motion: WheelMotion
) -> PatchCreepage:
    """The creepages at a patch ``x_m`` [m] ahead of the axle, on the wheel's radius
    ``wheel_radius_m`` [m] there, with the contact angle ``angle_rad`` (module doc)."""
    om = motion.pitch_rate_rad_per_s
    depth = math.sqrt(max(wheel_radius_m**2 - x_m**2, 0.0))
    v = motion.speed_m_per_s
    v_roll = 0.5 * (v + abs(om) * depth)
    sin_d, cos_d = math.sin(angle_rad), math.cos(angle_rad)
    xi = -(v + om * depth) / v_roll
    eta = -(motion.lateral_speed_m_per_s * cos_d - om * x_m * sin_d) / v_roll
    phi = om * sin_d / v_roll
    return PatchCreepage(xi, eta, phi, v_roll, angle_rad)


def mean_slope_angle(pressure_pa: np.ndarray, rail_slope: np.ndarray) -> float:
    """The patch's angle for its creepages [rad]: ``atan`` of the pressure-weighted mean of the
    rail's lateral slope ``dz/dy`` over the loaded cells (NaN cells left out). On a rounded
    corner the slope changes across the patch; the spin and the lateral creepage are linear in
    it, so their patch values are the weighted means (module doc)."""
    w = np.where((pressure_pa > 0.0) & np.isfinite(rail_slope), pressure_pa, 0.0)
    total = float(w.sum())
    if total <= 0.0:
        return 0.0
    return math.atan(float(np.sum(w * np.where(np.isfinite(rail_slope), rail_slope, 0.0))) / total)


def equivalent_ellipse(
    pressure_pa: np.ndarray, dx_m: float, ds_m: float
) -> tuple[float, float, float]:
    """``(a, b, area)`` [m, m, m^2] of the ellipse standing for a patch: ``b`` half the
    contact's width (in the plane, cells of ``ds_m``), ``a = area / (pi b)``."""
    loaded = pressure_pa > 0.0
    cols = np.nonzero(loaded.any(axis=0))[0]
    area = float(np.count_nonzero(loaded)) * dx_m * ds_m
    b = 0.5 * (cols[-1] - cols[0] + 1) * ds_m
    return area / (math.pi * b), b, area


def grid_fastsim(
    pressure_pa: np.ndarray,
    x_m: np.ndarray,
    s_m: np.ndarray,
    creep: PatchCreepage,
    friction: float,
    flexibility_m_per_pa: tuple[float, float, float],
) -> tuple[float, float, float]:
    """FASTSIM on a patch's grid: ``(Fx, Fs, Mn)`` [N, N, N m] (module doc).

    Args:
        pressure_pa: the pressure on the grid, rows along ``x_m`` (increasing), columns along
            ``s_m``.
        x_m, s_m: the cells' centres along the track and in the plane, from the spin's pole
            (the pressure centre) [m], uniform.
        creep: the creepages; friction: ``mu``.
        flexibility_m_per_pa: ``(L1, L2, L3)`` [m/Pa].
    """
    l1, l2, l3 = flexibility_m_per_pa
    dx = float(x_m[1] - x_m[0]) if x_m.size > 1 else 1.0
    ds = float(s_m[1] - s_m[0]) if s_m.size > 1 else 1.0
    gx = creep.xi / l1 - creep.phi_per_m * s_m / l3  # rigid slip over flexibility [Pa/m]
    px = np.zeros(s_m.size)
    py = np.zeros(s_m.size)
    inside = np.zeros(s_m.size, dtype=bool)
    fx = fs = mn = 0.0
    for i in range(x_m.size - 1, -1, -1):
        bound = friction * pressure_pa[i]
        step = np.where(inside, dx, 0.5 * dx)  # from the cell edge where the strip enters
        x_mid = x_m[i] + 0.5 * step
        px = np.where(inside, px, 0.0) - step * gx
        py = np.where(inside, py, 0.0) - step * (creep.eta / l2 + creep.phi_per_m * x_mid / l3)
        px, py = _onto_bound(px, py, bound, l1, l2)
        inside = pressure_pa[i] > 0.0
        px, py = np.where(inside, px, 0.0), np.where(inside, py, 0.0)
        fx += float(px.sum())
        fs += float(py.sum())
        mn += float(np.sum(x_m[i] * py - s_m * px))
    w = dx * ds
    return fx * w, fs * w, mn * w


def strip_moments(pressure_pa: np.ndarray, x_m: np.ndarray, s_m: np.ndarray) -> tuple[float, float]:
    """``(M1, M2)`` of a patch's strips [m^3, m^4]: ``M1 = int (x_lead - x) dA`` and
    ``M2 = int (x_lead^2 - x^2) / 2 dA`` over the loaded cells, ``x_lead`` the leading edge of
    the cell's run of contact along its strip (``x`` from the spin's pole). In adhesion
    FASTSIM gives ``Fx = -(xi / L1) M1`` and the spin's ``Fs = -(phi / L3) M2``; on an ellipse
    ``M1 = 8 a^2 b / 3`` and ``M2 = pi a^3 b / 4`` (Kalker's L1, L3). Computed by the same
    march as :func:`grid_fastsim` without a bound."""
    unbounded = 1.0e30
    m1 = -grid_fastsim(pressure_pa, x_m, s_m, PatchCreepage(1.0, 0.0, 0.0, 1.0, 0.0),
                       unbounded, (1.0, 1.0, 1.0))[0]  # fmt: skip
    m2 = -grid_fastsim(pressure_pa, x_m, s_m, PatchCreepage(0.0, 0.0, 1.0, 1.0, 0.0),
                       unbounded, (1.0, 1.0, 1.0))[1]  # fmt: skip
    return m1, m2


def _onto_bound(
    px: np.ndarray, py: np.ndarray, bound: np.ndarray, l1: float, l2: float, steps: int = 30
) -> tuple[np.ndarray, np.ndarray]:
    """The cells' tractions: the trial ``(px, py)`` where it lies within ``bound``, else the
    traction of magnitude ``bound`` against the slip ``L (p - p_trial)``, ``L = diag(l1, l2)``:
    ``p_i = p_trial_i L_i / (L_i + m)`` with ``m >= 0`` such that ``|p| = bound`` (Newton's
    method, monotone from a start left of the root: ``|p(m)|`` is convex and decreasing). For
    ``l1 = l2`` this is the trial scaled back, FASTSIM's rule."""
    mag = np.hypot(px, py)
    slide = mag > bound
    if not np.any(slide):
        return px, py
    free = slide & (bound <= 0.0)  # outside the contact: no traction
    px, py = np.where(free, 0.0, px), np.where(free, 0.0, py)
    slide &= ~free
    if not np.any(slide):
        return px, py
    # start left of the root: with min(l1, l2) for both, |p| would reach the bound at m0
    lmin = min(l1, l2)
    m = np.where(slide, lmin * (mag / np.where(slide, bound, 1.0) - 1.0), 0.0)
    for _ in range(steps):
        qx, qy = px * l1 / (l1 + m), py * l2 / (l2 + m)
        norm = np.hypot(qx, qy)
        if np.all(np.abs(norm - bound)[slide] <= 1e-10 * bound[slide]):
            break
        slope = -(qx * qx / (l1 + m) + qy * qy / (l2 + m)) / np.where(norm > 0.0, norm, 1.0)
        step = np.where(
            slide & (slope < 0.0), (norm - bound) / np.where(slope < 0.0, -slope, 1.0), 0.0
        )
        m = m + np.maximum(step, 0.0)
    qx, qy = px * l1 / (l1 + m), py * l2 / (l2 + m)
    norm = np.hypot(qx, qy)
    scale = bound / np.where(norm > 0.0, norm, 1.0)  # the last Newton step's residual
    return np.where(slide, qx * scale, px), np.where(slide, qy * scale, py)


def tangential_forces(
    pressure_pa: np.ndarray,
    x_m: np.ndarray,
    s_m: np.ndarray,
    creep: PatchCreepage,
    motion: WheelMotion,
    shear_modulus_pa: float,
    poisson: float,
) -> tuple[float, float]:
    """The creep forces ``(Fx, Fs)`` [N] on the rail of a patch by ``motion.tangential``.

    Args:
        pressure_pa: the patch's pressure on its grid [Pa] (rows ``x_m``, columns ``s_m``).
        x_m, s_m: cell centres from the pressure centre, along the track and in the contact
            plane [m].
        creep: the patch's creepages; motion: friction and the law's name.
        shear_modulus_pa, poisson: ``G`` [Pa] and ``nu`` of both bodies.
    """
    dx = float(x_m[1] - x_m[0])
    ds = float(s_m[1] - s_m[0])
    normal = float(pressure_pa.sum()) * dx * ds
    if normal <= 0.0:
        return 0.0, 0.0
    if motion.tangential == "exact":
        qx, qs = solve_tangential(
            pressure_pa, x_m, s_m, creep.xi, creep.eta, creep.phi_per_m, motion.friction,
            shear_modulus_pa, poisson,
        )  # fmt: skip
        return float(qx.sum()) * dx * ds, float(qs.sum()) * dx * ds
    a, b, _ = equivalent_ellipse(pressure_pa, dx, ds)
    c11, c22, c23 = kalker_coefficients(a / b, poisson)
    g = shear_modulus_pa
    if motion.tangential == "fastsim_grid":
        m1, m2 = strip_moments(pressure_pa, x_m, s_m)
        l3 = m2 / (g * (a * b) ** 1.5 * c23)
        if not l3 > 0.0:  # strips mostly behind the pole: the ellipse's own L3 (Kalker 1982)
            l3 = math.pi * a * math.sqrt(a / b) / (4.0 * c23 * g)
        flex = (m1 / (g * a * b * c11), m1 / (g * a * b * c22), l3)
        fx, fs, _ = grid_fastsim(pressure_pa, x_m, s_m, creep, motion.friction, flex)
        return fx, fs
    return creep_forces(
        motion.tangential, creep.xi, creep.eta, creep.phi_per_m, normal, a, b, g, c11, c22,
        c23, motion.friction, creep.rolling_speed_m_per_s,
    )  # fmt: skip
