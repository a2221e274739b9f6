"""The bogie's yaw (rotational) resistance and its X factor (EN 14363:2016, 6.2; UIC 530-2).

A bogie (or a wheelset of a two-axle wagon, held in its axle guards) is turned against the car
body about the vertical axis through its centre at a low, constant angular speed, as on the
turntables of the test rig: from 0 to the angle ``+psi_max`` it takes in the smallest curve of
the test (``asin(a / R)``, ``a`` the distance of the running gear from the vehicle's centre,
R 150 m), back through ``-psi_max`` and to 0 again. The moment the rig applies, ``M_z(psi)``,
is the sum of the moments of every suspension element between the running gear and the body
it is turned against; the test's quantity is

    X = max |M_z| / (2a* Q0)

with ``2a*`` the running gear's wheelbase (a bogie's; for a two-axle wagon the distance of its
axles) and ``Q0`` its static wheel load; the test passes when ``X <= X_lim`` (0.1).
``docs/acceptance-quasistatic.md`` gives what of this is public and what is railexu's
assumption.

The moments come from the model's own force laws, quasi-statically (no inertia):

- the nonlinear elements (tables, friction, UIC links, Maxwell dampers) through the compiled
  kernel :func:`railexu.model.suspension_forces.element_force`, their internal coordinates
  (a slider behind its stick stiffness, a damper behind its bush) advanced by implicit Euler
  steps of their own first-order law (the small internal mass is left out);
- the bump stops by the law of :mod:`railexu.model.forces` (free play, then a linear spring
  and damper that only push), :func:`railexu.model.forces.bump_stop_law`;
- the linear connectors (spring-dampers, air springs' shear, torsion springs about z) as the
  Exudyn connectors of :mod:`railexu.model.assembly` act: ``F = F_static - k d - c v``.

Only the yaw of the running gear changes; its other coordinates and the body's stay at the
static position (the rig holds them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from railexu.errors import InputError
from railexu.model.body_points import point_state
from railexu.model.forces import bump_stop_law
from railexu.model.statics import StaticSolution, attachment_point, static_equilibrium
from railexu.model.suspension_forces import (
    LAW_PLASTIC,
    LAW_TABLE,
    SI_INTERNAL,
    SI_LAW,
    SI_LAW_N,
    SI_LAW_START,
    SR_CV,
    SR_D0,
    SR_FC,
    SR_KS,
    SR_P0,
    SR_P1,
    element_force,
    kernel_arrays,
    kernel_elements,
    table_value,
)
from railexu.vehicle.vehicle import BumpStop, SpringDamper, TorsionSpring, Vehicle, linear_part

#: Clause of the test (EN 14363:2016, stationary tests: the bogie's rotational resistance).
CLAUSE = "EN 14363:2016, 6.2 (bogie rotational resistance); UIC 530-2 for freight wagons"
#: Limit of the X factor. railexu's assumption: the value 0.1 of UIC 530-2 / EN 14363:2016 6.2
#: as commonly cited; the standard's text was not available to check it.
X_LIMIT = 0.1
#: Radius of the smallest curve whose angle the running gear is turned to [m] (the 150 m of the
#: twist test, EN 14363:2016 6.1; railexu's assumption for 6.2).
TEST_RADIUS_M = 150.0
#: Angular speed of the turn [rad/s]: 1 mrad/s (0.06 deg/s), railexu's assumption of a "low"
#: speed; the viscous forces at it are small against the elastic and friction ones.
ANGULAR_SPEED_RAD_PER_S = 1.0e-3
#: Steps per quarter cycle (0 -> psi_max) of the quasi-static sweep.
STEPS_PER_QUARTER = 200
#: Lateral distance of the wheels' contact points from the wheelset centre for the statics [m].
WHEEL_LATERAL_M = 0.75


@dataclass(frozen=True)
class YawResistanceResult:
    """The yaw-resistance test of one running gear.

    Attributes:
        running_gear: the bogie (or wheelset) turned.
        body: the body it is turned against.
        elements: the suspension elements between them (whose moments are summed).
        angle_rad: the angle of the sweep (0 -> +max -> -max -> 0) [rad].
        moment_N_m: the moment the rig applies about z at each angle [N m] (positive in the
            direction of positive yaw: it resists the turn).
        max_moment_N_m: ``max |M_z|`` over the sweep [N m].
        wheelbase_m: ``2a*`` [m].
        static_wheel_load_N: ``Q0`` [N], the mean static wheel load of the running gear.
        x_factor: ``max |M_z| / (2a* Q0)`` [-].
        limit: ``X_lim`` [-].
        passed: ``x_factor <= limit``.
        radius_m: the curve radius the maximum angle belongs to (None: angle given) [m].
        angular_speed_rad_per_s: speed of the turn [rad/s].
        clause: the standard and clause.
        rule: how the value was computed (window of the statistic: the whole sweep).
    """

    running_gear: str
    body: str
    elements: tuple[str, ...]
    angle_rad: np.ndarray = field(repr=False)
    moment_N_m: np.ndarray = field(repr=False)
    max_moment_N_m: float
    wheelbase_m: float
    static_wheel_load_N: float
    x_factor: float
    limit: float
    passed: bool
    radius_m: float | None
    angular_speed_rad_per_s: float
    clause: str = CLAUSE
    rule: str = (
        "railexu: X = max |M_z| / (2a* Q0) over one quasi-static cycle 0 -> +psi_max -> "
        "-psi_max -> 0; 2a* the running gear's wheelbase, Q0 its mean static wheel load"
    )

    def to_dict(self) -> dict:
        """The verdict as plain values (JSON), without the sweep's arrays."""
        return {
            "test": "bogie yaw resistance",
            "running_gear": self.running_gear,
            "body": self.body,
            "elements": list(self.elements),
            "max_angle_rad": float(np.max(np.abs(self.angle_rad))),
            "max_moment_N_m": self.max_moment_N_m,
            "wheelbase_m": self.wheelbase_m,
            "static_wheel_load_N": self.static_wheel_load_N,
            "x_factor": self.x_factor,
            "limit": self.limit,
            "pass": self.passed,
            "radius_m": self.radius_m,
            "angular_speed_rad_per_s": self.angular_speed_rad_per_s,
            "clause": self.clause,
            "rule": self.rule,
        }


def yaw_resistance_test(
    vehicle: Vehicle,
    running_gear: str | None = None,
    *,
    max_angle_rad: float | None = None,
    radius_m: float = TEST_RADIUS_M,
    angular_speed_rad_per_s: float = ANGULAR_SPEED_RAD_PER_S,
    limit: float = X_LIMIT,
    steps_per_quarter: int = STEPS_PER_QUARTER,
) -> YawResistanceResult:
    """Turn ``running_gear`` against its body and compute the X factor (module docstring).

    Args:
        vehicle: the vehicle.
        running_gear: a bogie frame (a body carrying wheelsets) or a wheelset; default: the
            first bogie, or the first wheelset of a vehicle without bogies.
        max_angle_rad: the largest angle of the sweep [rad]; default ``asin(a / radius_m)``.
        radius_m: the curve radius of the default angle [m].
        angular_speed_rad_per_s: speed of the turn [rad/s].
        limit: ``X_lim``.
        steps_per_quarter: steps from 0 to the largest angle.

    Raises:
        InputError: an unknown running gear, no element between it and a body, a running gear
            at the vehicle's centre without ``max_angle_rad``, or absurd numbers.
    """
    rig = _Rig(vehicle, running_gear)
    psi_max = _max_angle(rig, max_angle_rad, radius_m)
    _check_positive("angular_speed_rad_per_s", angular_speed_rad_per_s)
    _check_positive("limit", limit)
    if not isinstance(steps_per_quarter, int) or steps_per_quarter < 4:
        raise InputError("yaw resistance test: steps_per_quarter must be an integer >= 4")
    angles, rates = _sweep(psi_max, angular_speed_rad_per_s, steps_per_quarter)
    moments = rig.moments(angles, rates)
    m_max = float(np.max(np.abs(moments)))
    x = m_max / (rig.wheelbase_m * rig.wheel_load_N)
    return YawResistanceResult(
        running_gear=rig.gear,
        body=rig.body,
        elements=rig.element_names,
        angle_rad=angles,
        moment_N_m=moments,
        max_moment_N_m=m_max,
        wheelbase_m=rig.wheelbase_m,
        static_wheel_load_N=rig.wheel_load_N,
        x_factor=x,
        limit=limit,
        passed=bool(x <= limit),
        radius_m=None if max_angle_rad is not None else radius_m,
        angular_speed_rad_per_s=angular_speed_rad_per_s,
    )


def _check_positive(name: str, value: float) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and value > 0.0):
        raise InputError(f"yaw resistance test: {name} must be a positive finite number, got "
                         f"{value!r}")  # fmt: skip


def _max_angle(rig: _Rig, max_angle_rad: float | None, radius_m: float) -> float:
    """The sweep's largest angle: given, or ``asin(a / R)`` [rad]."""
    if max_angle_rad is not None:
        _check_positive("max_angle_rad", max_angle_rad)
        if max_angle_rad > 0.2:
            raise InputError(f"yaw resistance test: max_angle_rad {max_angle_rad:g} rad is more "
                             "than 0.2 rad (11 deg): is the unit wrong?")  # fmt: skip
        return float(max_angle_rad)
    _check_positive("radius_m", radius_m)
    a = abs(rig.gear_x_m)
    if a < 1.0e-6:
        raise InputError(f"yaw resistance test: {rig.gear} sits at the vehicle's centre; give "
                         "max_angle_rad")  # fmt: skip
    if a >= radius_m:
        raise InputError(f"yaw resistance test: radius {radius_m:g} m is not larger than the "
                         f"running gear's distance {a:g} m from the centre")  # fmt: skip
    return math.asin(a / radius_m)


def _sweep(psi_max: float, omega: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Angles and angular rates of the cycle 0 -> +max -> -max -> 0 at constant speed."""
    up = np.linspace(0.0, psi_max, n + 1)
    down = np.linspace(psi_max, -psi_max, 2 * n + 1)[1:]
    back = np.linspace(-psi_max, 0.0, n + 1)[1:]
    angles = np.concatenate((up, down, back))
    rates = np.concatenate(
        (np.full(n + 1, omega), np.full(2 * n, -omega), np.full(n, omega))
    )  # fmt: skip
    rates[0] = 0.0
    return angles, rates


class _Rig:
    """The running gear, the body it turns against and their elements, in the two-node
    coordinates of the compiled kernels (node 0 the body, node 1 the running gear; each
    ``x, y, z, roll, pitch, yaw`` about its centre in vehicle axes)."""

    def __init__(self, vehicle: Vehicle, running_gear: str | None) -> None:
        self.vehicle = vehicle
        wheelsets = {w.name for w in vehicle.wheelsets}
        bodies = {b.name for b in vehicle.bodies}
        self.gear = running_gear or _default_running_gear(vehicle)
        if self.gear not in wheelsets | bodies:
            raise InputError(f"yaw resistance test: no body or wheelset {self.gear!r} in "
                             f"{vehicle.name}")  # fmt: skip
        links = [el for el in vehicle.suspension
                 if self.gear in el.bodies and not set(el.bodies) & (wheelsets - {self.gear})
                 and el.bodies[0] != el.bodies[1]]  # fmt: skip
        others = sorted({b for el in links for b in el.bodies} - {self.gear})
        if len(others) != 1:
            what = "no body" if not others else f"several bodies ({', '.join(others)})"
            raise InputError(f"yaw resistance test: {self.gear} is connected to {what}; "
                             "it must turn against one body")  # fmt: skip
        self.body = others[0]
        self.elements = links
        self.element_names = tuple(el.name for el in links)
        self.statics = static_equilibrium(vehicle, [WHEEL_LATERAL_M] * len(vehicle.wheelsets))
        self.centres = {self.body: self._centre(self.body), self.gear: self._centre(self.gear)}
        self.gear_x_m = float(self.centres[self.gear][0])
        self.wheelbase_m, self.wheel_load_N = _wheelbase_and_load(vehicle, self.gear,
                                                                  self.statics)  # fmt: skip
        self._build_kernels()

    def _centre(self, name: str) -> np.ndarray:
        for b in self.vehicle.bodies:
            if b.name == name:
                return np.asarray(b.position_m, dtype=float)
        return np.asarray(self.vehicle.wheelset(name).position_m, dtype=float)

    def _local(self, name: str, position) -> np.ndarray:
        """An element's attachment point relative to the centre of ``name`` (vehicle axes)."""
        return attachment_point(self.vehicle, name, position) - self.centres[name]

    def _build_kernels(self) -> None:
        slot = {self.body: 0, self.gear: 1}
        names = set(self.element_names)
        kernel = [e for e in kernel_elements(self.vehicle, self.statics)
                  if e.bodies[0] in slot and e.bodies[1] in slot
                  and _base_name(e.name, names) is not None]  # fmt: skip
        local = {}
        for e in kernel:
            la, lb = self._local(e.bodies[0], e.position_m), self._local(e.bodies[1], e.position_m)
            ga = self.centres[e.bodies[0]] + la
            gb = self.centres[e.bodies[1]] + lb
            local[e.name] = ((la, lb), float(gb[e.axis] - ga[e.axis]))
        self.n_internal = sum(1 for e in kernel if e.internal)
        self.si, self.sr, self.tab = kernel_arrays(kernel, slot, local, 12)
        self.qref = np.concatenate((self.centres[self.body], np.zeros(3),
                                    self.centres[self.gear], np.zeros(3),
                                    np.zeros(self.n_internal)))  # fmt: skip
        self.stops = []
        self.linear = []
        for el in self.elements:
            lin = linear_part(el)
            if isinstance(el, BumpStop):
                self.stops.append(el)
            elif isinstance(lin, SpringDamper | TorsionSpring):
                self.linear.append(lin)

    # -- the moment at one state --------------------------------------------------------------
    def moments(self, angles: np.ndarray, rates: np.ndarray) -> np.ndarray:
        """The rig's moment about z [N m] along the sweep (internal states carried along)."""
        n = 12 + self.n_internal
        q = np.zeros(n)
        qt = np.zeros(n)
        out = np.empty(angles.size)
        for k, (psi, rate) in enumerate(zip(angles, rates, strict=True)):
            dt = abs(psi - angles[k - 1]) / abs(rate) if k and rate else 0.0
            q[11], qt[11] = psi, rate
            self._advance_internal(q, qt, dt)
            out[k] = -self._yaw_force(q, qt)
        return out

    def _yaw_force(self, q: np.ndarray, qt: np.ndarray) -> float:
        """Generalized force on the running gear's yaw: the moment about z of every element
        on it [N m]."""
        gen = np.zeros(q.size)
        for e in range(self.si.shape[0]):
            element_force(e, q, qt, self.qref, self.si, self.sr, self.tab, gen)
        moment = gen[11]
        for el in self.stops:
            moment += self._stop_moment(el, q, qt)
        for lin in self.linear:
            moment += self._linear_moment(lin, q, qt)
        return float(moment)

    def _point(self, slot: int, local, q, qt):
        p, v, r = np.empty(3), np.empty(3), np.empty(3)
        point_state(6 * slot, local[0], local[1], local[2], q, qt, self.qref, p, v, r)
        return p, v, r

    def _relative(self, el, q, qt):
        """Relative displacement (from the nominal geometry) and velocity of the element's
        second point from its first, and the lever of its running-gear point, with the sign of
        a force on the running gear (+1: it is the second body)."""
        a, b = el.bodies
        slot = {self.body: 0, self.gear: 1}
        la, lb = self._local(a, el.position_m), self._local(b, el.position_m)
        pa, va, _ = self._point(slot[a], la, q, qt)
        pb, vb, _ = self._point(slot[b], lb, q, qt)
        nominal = (self.centres[b] + lb) - (self.centres[a] + la)
        _, _, lever = self._point(1, lb if b == self.gear else la, q, qt)
        return pb - pa - nominal, vb - va, lever, (1.0 if b == self.gear else -1.0)

    def _stop_moment(self, el: BumpStop, q, qt) -> float:
        d, v, lever, sign = self._relative(el, q, qt)
        axis = "xyz".index(el.direction)
        f_b = bump_stop_law(d[axis], v[axis], el.clearance_m, el.stiffness_N_per_m,
                            el.damping_N_s_per_m)  # fmt: skip
        force = np.zeros(3)
        force[axis] = sign * f_b
        return float(lever[0] * force[1] - lever[1] * force[0])

    def _linear_moment(self, lin, q, qt) -> float:
        static = self.statics.element_forces[lin.name]
        if isinstance(lin, TorsionSpring):
            if lin.axis != "z":
                return 0.0
            sign = 1.0 if lin.bodies[1] == self.gear else -1.0
            rel = q[11] if sign > 0 else -q[11]
            rel_t = qt[11] if sign > 0 else -qt[11]
            k, c = lin.stiffness_N_m_per_rad, lin.damping_N_m_s_per_rad
            return sign * (float(static) - k * rel - c * rel_t)
        d, v, lever, sign = self._relative(lin, q, qt)
        f_b = (np.asarray(static) - np.asarray(lin.stiffness_N_per_m) * d
               - np.asarray(lin.damping_N_s_per_m) * v)  # fmt: skip
        force = sign * f_b
        return float(lever[0] * force[1] - lever[1] * force[0])

    # -- internal coordinates -----------------------------------------------------------------
    def _advance_internal(self, q: np.ndarray, qt: np.ndarray, dt: float) -> None:
        """One implicit Euler step of every internal coordinate's first-order law: a slider
        behind its stick spring flows at ``(|f_s| - F_c) / eta``; a damper behind its bush
        moves at the rate where the bush force equals the damper's."""
        for e in range(self.si.shape[0]):
            iu = self.si[e, SI_INTERNAL]
            if iu < 0:
                continue
            d = self._kernel_deflection(e, q, qt)
            u_old = q[iu]
            k_s = self.sr[e, SR_KS]
            if dt <= 0.0:
                qt[iu] = 0.0
                continue
            if self.si[e, SI_LAW] == LAW_PLASTIC:
                u_new = _plastic_step(d, u_old, k_s, self.sr[e, SR_FC], self.sr[e, SR_CV], dt)
            else:
                u_new = self._maxwell_step(e, d, u_old, k_s, dt)
            q[iu] = u_new
            qt[iu] = (u_new - u_old) / dt

    def _kernel_deflection(self, e: int, q, qt) -> float:
        axis = self.si[e, 2]
        pa, _, _ = self._point(self.si[e, 0], self.sr[e, SR_P0 : SR_P0 + 3], q, qt)
        pb, _, _ = self._point(self.si[e, 1], self.sr[e, SR_P1 : SR_P1 + 3], q, qt)
        return float(pb[axis] - pa[axis] - self.sr[e, SR_D0])

    def _maxwell_step(self, e: int, d: float, u_old: float, k_s: float, dt: float) -> float:
        """Implicit Euler of ``k_s (d - u) = g(u') + c_v u'`` for the rate ``u'``."""
        c_v = self.sr[e, SR_CV]
        start, n = self.si[e, SI_LAW_START], self.si[e, SI_LAW_N]

        def law(w: float) -> float:
            g = table_value(self.tab, start, n, w) if self.si[e, SI_LAW] == LAW_TABLE else 0.0
            return g + c_v * w

        def residual(w: float) -> float:
            return k_s * (d - u_old - dt * w) - law(w)

        bound = max(abs(d - u_old) / dt, 1.0e-12)
        lo, hi = -bound, bound
        if residual(lo) * residual(hi) > 0.0:
            return u_old
        return u_old + dt * brentq(residual, lo, hi, xtol=1.0e-15, rtol=1.0e-12)


def _plastic_step(d: float, u_old: float, k_s: float, f_c: float, eta: float, dt: float) -> float:
    """Implicit Euler step of the viscoplastic slider ``eta u' = sign(f) max(0, |f| - F_c)``,
    ``f = k_s (d - u)`` (:mod:`railexu.model.suspension_forces`), in closed form."""
    trial = k_s * (d - u_old)
    if abs(trial) <= f_c:
        return u_old
    a = k_s * dt / eta
    s = math.copysign(1.0, trial)
    f_new = (trial + a * s * f_c) / (1.0 + a)
    return d - f_new / k_s


def _base_name(kernel_name: str, names: set[str]) -> str | None:
    """The vehicle element a kernel element belongs to (a UIC link's ``_x``/``_y`` rows, an
    air spring's ``_reservoir``)."""
    if kernel_name in names:
        return kernel_name
    for suffix in ("_x", "_y", "_reservoir"):
        if kernel_name.endswith(suffix) and kernel_name[: -len(suffix)] in names:
            return kernel_name[: -len(suffix)]
    return None


def _default_running_gear(vehicle: Vehicle) -> str:
    """The first bogie (a body carrying wheelsets and itself carried by another body), else
    the first wheelset (a vehicle without bogies: the car body carries the wheelsets)."""
    wheelsets = {w.name for w in vehicle.wheelsets}
    for b in vehicle.bodies:
        carried_by = {n for el in vehicle.suspension if b.name in el.bodies
                      for n in el.bodies} - wheelsets - {b.name}  # fmt: skip
        if carried_by and _carried_wheelsets(vehicle, b.name, wheelsets):
            return b.name
    if not vehicle.wheelsets:
        raise InputError(f"yaw resistance test: {vehicle.name} has no wheelsets")
    return vehicle.wheelsets[0].name


def _carried_wheelsets(vehicle: Vehicle, body: str, wheelsets: set[str]) -> list[str]:
    """The wheelsets connected to ``body`` by a suspension element, in the vehicle's order."""
    linked = {b for el in vehicle.suspension if body in el.bodies for b in el.bodies}
    return [w.name for w in vehicle.wheelsets if w.name in linked & wheelsets]


def _wheelbase_and_load(vehicle: Vehicle, gear: str, statics: StaticSolution):
    """``2a*`` [m] and ``Q0`` [N]: a bogie's wheelbase and its wheelsets' mean static wheel
    load; for a wheelset, the vehicle's wheelbase (two-axle wagon) and its own wheel load."""
    names = [w.name for w in vehicle.wheelsets]
    carried = _carried_wheelsets(vehicle, gear, set(names)) if gear not in names else [gear]
    group = carried if gear not in names else names
    xs = [vehicle.wheelset(n).position_x_m for n in group]
    wheelbase = max(xs) - min(xs)
    if len(group) < 2 or wheelbase <= 0.0:
        raise InputError(f"yaw resistance test: {gear} has no wheelbase (fewer than two "
                         "wheelsets)")  # fmt: skip
    loads = [statics.wheel_loads_N[names.index(n)] for n in carried]
    return float(wheelbase), float(np.mean(loads))
