"""Quasi-static wheelset on its rails: rigid contact, pressed under load, sweeps over lateral shift.

- :func:`rigid_contact`: height and roll of a wheelset resting on rigid rails at lateral
  displacement ``y`` and yaw ``psi`` (both wheels just touch). The roll follows from
  ``g_left(phi) = g_right(phi)``: a vertical shift changes every gap by the same amount, so the
  roll is found first by a bracketed 1-D root search and the height then follows exactly.
- :func:`press_wheelset`: height and roll such that each wheel carries its vertical load
  (the vertical component of its total contact force, normal and tangential, over all its contact
  points), by alternating bracketed root searches on the two wheels' heights.
- :func:`rolling_radius_difference`: ``Delta r(y) = r_left - r_right`` of the rigid contact
  (positive when the wheelset moves to the left), from which :mod:`railexu.contact.conicity`
  computes the equivalent conicity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from railexu.contact.evaluation import WheelsetContactModel, WheelsetContactResult
from railexu.errors import ComputationError


class ContactSolveError(ComputationError):
    """A quasi-static contact problem without a solution (wheel off its rail, no convergence)."""


def _min_gaps(model: WheelsetContactModel, y: float, z: float, phi: float, psi: float):
    gl = model.gap_candidates("left", y, z, phi, psi)[1]
    gr = model.gap_candidates("right", y, z, phi, psi)[1]
    if gl.size == 0 or gr.size == 0:
        side = "left" if gl.size == 0 else "right"
        raise ContactSolveError(
            f"no contact candidate on the {side} wheel at y = {y * 1e3:.2f} mm, "
            f"psi = {psi * 1e3:.2f} mrad: the wheel is off its rail"
        )
    return float(np.min(gl)), float(np.min(gr))


@dataclass(frozen=True)
class RigidContact:
    """Wheelset on rigid rails: centre height [m] and roll [rad] at a lateral shift and yaw."""

    lateral_m: float
    yaw_rad: float
    vertical_m: float
    roll_rad: float


def rigid_contact(
    model: WheelsetContactModel, lateral_m: float, yaw_rad: float = 0.0
) -> RigidContact:
    """Height and roll of a wheelset whose two wheels just touch rigid rails.

    Args:
        model: the wheelset's contact model (geometry is what matters here).
        lateral_m: lateral displacement of the wheelset centre [m], positive to the left.
        yaw_rad: yaw angle [rad].
    """
    r0 = model.geometry.left.nominal_radius_m
    z0 = r0

    def h(phi: float) -> float:
        gl, gr = _min_gaps(model, lateral_m, z0, phi, yaw_rad)
        return gl - gr

    # Roll grows with y by ~ (delta r)/(2 e0): a few mrad with flange contact. Bracket outwards.
    lo, hi = -0.002, 0.002
    h_lo, h_hi = h(lo), h(hi)
    for _ in range(12):
        if h_lo * h_hi <= 0.0:
            break
        lo *= 2.0
        hi *= 2.0
        h_lo, h_hi = h(lo), h(hi)
    else:
        raise ContactSolveError(
            f"no rigid contact roll angle found at y = {lateral_m * 1e3:.2f} mm"
        )
    phi = brentq(h, lo, hi, xtol=1e-13, rtol=1e-13)
    gl, _ = _min_gaps(model, lateral_m, z0, phi, yaw_rad)
    return RigidContact(lateral_m, yaw_rad, z0 - gl, phi)


@dataclass(frozen=True)
class PressedWheelset:
    """Wheelset pressed onto its rails under given wheel loads."""

    lateral_m: float
    yaw_rad: float
    vertical_m: float
    roll_rad: float
    result: WheelsetContactResult


def axle_direction(roll_rad: float, yaw_rad: float) -> np.ndarray:
    """Unit vector of the axle (track frame) for ``R = Rx(roll) Rz(yaw)``: ``R e_y``."""
    return np.array(
        [-np.sin(yaw_rad), np.cos(roll_rad) * np.cos(yaw_rad), np.sin(roll_rad) * np.cos(yaw_rad)]
    )


def _evaluate(model: WheelsetContactModel, y, z, phi, psi, spin_rate: float | None):
    if spin_rate is None:
        return model.evaluate(y, z, phi, psi)
    omega = tuple(spin_rate * axle_direction(phi, psi))
    return model.evaluate(y, z, phi, psi, angular_velocity_rad_per_s=omega)


def _wheel_loads(
    model: WheelsetContactModel, y, z, phi, psi, spin_rate: float | None = None
) -> tuple[np.ndarray, object]:
    res = _evaluate(model, y, z, phi, psi, spin_rate)
    return np.array([res.wheel_force_N("left")[2], res.wheel_force_N("right")[2]]), res


def press_wheelset(
    model: WheelsetContactModel,
    lateral_m: float,
    yaw_rad: float,
    load_N: float | tuple[float, float],
    *,
    tolerance_N: float | None = None,
    relative_tolerance: float = 1e-7,
    max_sweeps: int = 100,
    spin_rate_rad_per_s: float | None = None,
) -> PressedWheelset:
    """Press a wheelset onto its rails until each wheel carries its vertical load.

    The wheelset rolls forward at the model's speed V with ``omega = V / r0`` about its axle; the
    load of a wheel is the vertical component of its total contact force (normal and tangential
    forces of all its contact points). The unknowns are the heights of the two wheels' planes,
    ``z_left = z + e0 sin(phi)`` and ``z_right = z - e0 sin(phi)``: each wheel's load depends
    mostly on its own height and falls monotonically as it rises, so alternating bracketed 1-D
    root searches (Gauss-Seidel) converge robustly even on a steep flange, whose vertical
    stiffness is a small fraction of the tread's.

    Args:
        model: the wheelset's contact model.
        lateral_m: lateral displacement [m]; yaw_rad: yaw [rad].
        load_N: vertical load per wheel [N], one value or ``(left, right)``.
        tolerance_N: accepted load error per wheel [N]; default ``relative_tolerance`` times
            the larger load (1e-7: 1 mN at 10 kN, far below what a load is known to). If the
            sweeps run out above it but within 1000 times it (1e-4 of the load), the state is
            accepted: the loads are then still far more precise than they are ever known.
        relative_tolerance: see ``tolerance_N``.
        spin_rate_rad_per_s: spin about the axle [rad/s]; ``None``: ``V / r0`` (nominal).
    """
    loads = np.broadcast_to(np.asarray(load_N, dtype=float), (2,)).copy()
    if np.any(loads <= 0.0):
        raise ContactSolveError(f"wheel loads must be > 0 N, got {loads}")
    if tolerance_N is None:
        tolerance_N = relative_tolerance * float(np.max(loads))
    e0 = model.geometry.left.tape_circle_lateral_m
    rigid = rigid_contact(model, lateral_m, yaw_rad)
    u = np.array(
        [
            rigid.vertical_m + e0 * np.sin(rigid.roll_rad),
            rigid.vertical_m - e0 * np.sin(rigid.roll_rad),
        ]
    )

    def pose(u_: np.ndarray) -> tuple[float, float]:
        return 0.5 * (u_[0] + u_[1]), float(np.arcsin((u_[0] - u_[1]) / (2.0 * e0)))

    def loads_at(u_: np.ndarray):
        z, phi = pose(u_)
        return _wheel_loads(model, lateral_m, z, phi, yaw_rad, spin_rate_rad_per_s)

    f, res = loads_at(u)
    for _ in range(max_sweeps):
        if np.max(np.abs(f - loads)) < tolerance_N:
            z, phi = pose(u)
            return PressedWheelset(lateral_m, yaw_rad, z, phi, res)
        for i in (0, 1):

            def residual(ui: float, i: int = i) -> float:
                trial = u.copy()
                trial[i] = ui
                return float(loads_at(trial)[0][i] - loads[i])

            hi = u[i] + 1.0e-5
            r_hi = residual(hi)
            while r_hi > 0.0:  # still loaded: lift further
                hi += 2.0e-4
                r_hi = residual(hi)
            lo = hi - 2.0e-4
            r_lo = residual(lo)
            for _ in range(40):
                if r_lo >= 0.0:
                    break
                lo -= 2.0e-4
                r_lo = residual(lo)
            else:
                raise ContactSolveError(
                    f"the {('left', 'right')[i]} wheel cannot carry {loads[i]:.0f} N at "
                    f"y = {lateral_m * 1e3:.2f} mm, yaw = {yaw_rad * 1e3:.2f} mrad"
                )
            u[i] = brentq(residual, lo, hi, xtol=1e-13, rtol=1e-14)
        f, res = loads_at(u)
    if np.max(np.abs(f - loads)) < 1.0e3 * tolerance_N:
        z, phi = pose(u)
        return PressedWheelset(lateral_m, yaw_rad, z, phi, res)
    raise ContactSolveError(
        f"wheelset could not be pressed onto the rails at y = {lateral_m * 1e3:.2f} mm, "
        f"yaw = {yaw_rad * 1e3:.2f} mrad: loads {f} N, wanted {loads} N"
    )


def rolling_radius_difference(
    model: WheelsetContactModel, lateral_m: np.ndarray, yaw_rad: float = 0.0
) -> np.ndarray:
    """Rolling radius difference ``r_left - r_right`` [m] of the rigid contact at each ``y`` [m].

    Where a wheel touches at two points, the radius of the point with the smaller gap (the one
    that touches first) is used.
    """
    out = np.empty(np.size(lateral_m))
    for i, y in enumerate(np.atleast_1d(lateral_m)):
        rc = rigid_contact(model, float(y), yaw_rad)
        radii = []
        for side in ("left", "right"):
            s, g = model.gap_candidates(side, float(y), rc.vertical_m, rc.roll_rad, yaw_rad)
            k = int(np.argmin(g))
            pair = model.geometry.left if side == "left" else model.geometry.right
            radii.append(pair.nominal_radius_m + float(pair.wheel.height(s[k])))
        out[i] = radii[0] - radii[1]
    return out


def free_rolling_spin_rate(
    model: WheelsetContactModel,
    lateral_m: float,
    vertical_m: float,
    roll_rad: float,
    yaw_rad: float = 0.0,
) -> float:
    """Spin rate [rad/s] at which a wheelset at this pose rolls freely: no net longitudinal
    creep force (the axle is not driven or braked).

    A centred wheelset rolls on its actual contact radius, which differs from the nominal
    radius r0 by the height of the contact point on the profile; spinning at ``V / r0`` instead
    would load both wheels with a longitudinal creep force in the same direction.
    """
    speed = model.speed_m_per_s
    r0 = model.geometry.left.nominal_radius_m
    axle = np.array(
        [-np.sin(yaw_rad), np.cos(roll_rad) * np.cos(yaw_rad), np.sin(roll_rad) * np.cos(yaw_rad)]
    )

    def fx(omega: float) -> float:
        res = model.evaluate(
            lateral_m, vertical_m, roll_rad, yaw_rad, angular_velocity_rad_per_s=tuple(omega * axle)
        )
        return float(res.force_N[0])

    lo, hi = 0.97 * speed / r0, 1.03 * speed / r0
    f_lo, f_hi = fx(lo), fx(hi)
    if f_lo * f_hi > 0.0:
        return speed / r0
    return float(brentq(fx, lo, hi, xtol=1e-12, rtol=1e-14))


def pitch_moment(
    model: WheelsetContactModel,
    lateral_m: float,
    vertical_m: float,
    roll_rad: float,
    yaw_rad: float,
    spin_rate_rad_per_s: float,
) -> float:
    """Moment of the contact forces about the axle [N m] at a pose and spin rate."""
    res = _evaluate(model, lateral_m, vertical_m, roll_rad, yaw_rad, spin_rate_rad_per_s)
    return float(np.dot(res.torque_Nm, axle_direction(roll_rad, yaw_rad)))


def free_rolling_pitch_rate(
    model: WheelsetContactModel,
    lateral_m: float,
    vertical_m: float,
    roll_rad: float,
    yaw_rad: float = 0.0,
) -> float:
    """Spin rate about the axle [rad/s] at which the contact forces exert no pitch moment.

    This is free rolling as CONTACT sets up the Manchester benchmark (Vollebregt, CONTACT user
    guide: the pitch rate is chosen so that the total pitch moment vanishes): the axle is
    neither driven nor braked. The moment falls monotonically with the spin rate (faster spin,
    more braking creep force), so a bracketed root within +-3 % of ``V / r0`` is searched; if
    the moment does not change sign there, ``V / r0`` is returned.
    """
    speed = model.speed_m_per_s
    r0 = 0.5 * (model.geometry.left.nominal_radius_m + model.geometry.right.nominal_radius_m)

    def m(omega: float) -> float:
        return pitch_moment(model, lateral_m, vertical_m, roll_rad, yaw_rad, omega)

    lo, hi = 0.97 * speed / r0, 1.03 * speed / r0
    if m(lo) * m(hi) > 0.0:
        return speed / r0
    return float(brentq(m, lo, hi, xtol=1e-12, rtol=1e-14))


def press_free_rolling(
    model: WheelsetContactModel,
    lateral_m: float,
    yaw_rad: float,
    load_N: float | tuple[float, float],
    *,
    iterations: int = 3,
    relative_tolerance: float = 1e-7,
) -> tuple[PressedWheelset, float]:
    """Press a freely rolling wheelset: load and zero pitch moment together.

    Alternates :func:`press_wheelset` at a spin rate and :func:`free_rolling_pitch_rate` at the
    pressed pose (the tangential forces change the loads only a little, so 2-3 rounds settle
    both to far below their tolerances). Returns the pressed state and the pitch rate [rad/s].
    """
    rate = None
    state = press_wheelset(model, lateral_m, yaw_rad, load_N, relative_tolerance=relative_tolerance)
    for _ in range(iterations):
        rate = free_rolling_pitch_rate(model, lateral_m, state.vertical_m, state.roll_rad, yaw_rad)
        state = press_wheelset(
            model, lateral_m, yaw_rad, load_N, relative_tolerance=relative_tolerance,
            spin_rate_rad_per_s=rate,
        )  # fmt: skip
    return state, float(rate)
