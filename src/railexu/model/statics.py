"""Static equilibrium of a vehicle standing on its rails (linear statics).

The vehicle is meant to start in static equilibrium at its nominal geometry: the suspension
springs are preloaded with their static forces (the design state of a loaded vehicle), so that
every body sits at its nominal position and the dynamics starts without a settling transient.
The static forces come from a linear static analysis of the whole vehicle under gravity and the
external loads:

- 6 small displacements (3 translations, 3 rotations) per body and wheelset;
- each spring-damper adds ``T^T diag(k) T`` with ``T`` mapping the two bodies' displacements to
  the relative displacement of its attachment points; torsion springs likewise;
- each wheel stands on a stiff vertical spring at its contact point (the Hertz contact,
  linearised); the wheelsets are held longitudinally, laterally and in yaw by stiff springs at
  the contacts (creep forces do that when rolling; statically there is no load in these
  directions for gravity loading) and in spin;
- a tiny regularisation stiffness on every coordinate removes the mechanism of bodies held in
  only some directions (it carries no load when none acts in those directions).

Nonlinear springs (force-deflection tables, ``docs/suspension.md``) make the statics nonlinear:
Newton's method linearises each about its current deflection with its tangent stiffness (a few
iterations for monotone tables); their static deflection is kept for the compiled elements.
Air springs carry their load on their static stiffness ``k1``, anti-roll bars are torsion
springs about x; dampers, friction and link elements carry no static load.

Statically indeterminate arrangements (four springs under a body) share the load by stiffness,
as the real vehicle does. The result gives the wheel loads for pressing the wheelsets onto the
rails and the preload of every spring.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from railexu.model.characteristics import characteristic_table, table_force
from railexu.vehicle.vehicle import (
    NonlinearSpring,
    SpringDamper,
    TorsionSpring,
    Vehicle,
    linear_part,
)

CONTACT_STIFFNESS_N_PER_M = 2.0e9
HOLD_STIFFNESS = 1.0e9
REGULARISATION = 1.0e-3  # N/m or N m/rad: removes mechanisms, carries < 1 mN


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def attachment_point(vehicle: Vehicle, body: str, position: tuple[float, float, float]):
    """Where an element acts on a body (vehicle axes), for the statics: on a wheelset at the
    axle's centre line (the axle's x and height, the given lateral position). At rest the
    forces there are vertical, and the moment of a vertical force about the axle's centre does
    not depend on the height; the dynamics place the point on the axlebox at the given height
    and carry its moment into the axle (:mod:`railexu.model.assembly`, ``docs/suspension.md``)."""
    names = [w.name for w in vehicle.wheelsets]
    if body in names:
        ws = vehicle.wheelset(body)
        return np.array([ws.position_x_m, position[1], ws.nominal_radius_m])
    return np.asarray(position, dtype=float)


@dataclass(frozen=True)
class StaticSolution:
    """Static forces of a vehicle at rest on its rails.

    Attributes:
        wheel_loads_N: ``(n_wheelsets, 2)`` vertical load of the left and right wheel [N].
        element_forces: per spring-damper, the force it exerts on its **second** body [N]
            (track axes); per torsion spring, its moment on the second body about its axis [N m].
        total_weight_N: weight of the vehicle plus vertical external loads (downward positive).
        static_deflections: per nonlinear spring, its deflection at rest [m] (the table's
            force there is its static force).
    """

    wheel_loads_N: np.ndarray
    element_forces: dict
    total_weight_N: float
    static_deflections: dict = field(default_factory=dict)  # nonlinear springs [m]


def static_equilibrium(vehicle: Vehicle, wheel_lateral_m: list[float]) -> StaticSolution:
    """Linear static equilibrium of ``vehicle`` on its rails.

    Args:
        vehicle: the vehicle.
        wheel_lateral_m: lateral distance of each wheelset's contact points from its centre [m]
            (the tape circles, 0.75 m for standard wheelsets).
    """
    names = [b.name for b in vehicle.bodies] + [w.name for w in vehicle.wheelsets]
    index = {n: i for i, n in enumerate(names)}
    centres = [np.asarray(b.position_m) for b in vehicle.bodies]
    centres += [np.asarray(w.position_m) for w in vehicle.wheelsets]
    n = 6 * len(names)
    K = np.eye(n) * REGULARISATION
    F = np.zeros(n)
    g = vehicle.gravity_m_per_s2

    def point_map(body: str, point: np.ndarray) -> np.ndarray:
        """3 x n matrix: displacement of ``point`` fixed to ``body``."""
        i = index[body]
        m = np.zeros((3, n))
        m[:, 6 * i : 6 * i + 3] = np.eye(3)
        m[:, 6 * i + 3 : 6 * i + 6] = -_skew(point - centres[i])
        return m

    def rotation_map(body: str, axis: int) -> np.ndarray:
        i = index[body]
        m = np.zeros(n)
        m[6 * i + 3 + axis] = 1.0
        return m

    # gravity and external loads
    masses = [b.mass_kg for b in vehicle.bodies] + [w.mass_kg for w in vehicle.wheelsets]
    for i, m in enumerate(masses):
        F[6 * i + 2] -= m * g
    for load in vehicle.loads:
        if not load.static:
            continue  # applied suddenly at the start, not part of the rest state
        p = attachment_point(vehicle, load.body, load.position_m)
        F += point_map(load.body, p).T @ np.asarray(load.force_N)

    # suspension
    maps: dict = {}
    for el in vehicle.suspension:
        lin = linear_part(el)
        if isinstance(lin, SpringDamper):
            pa = attachment_point(vehicle, el.bodies[0], el.position_m)
            pb = attachment_point(vehicle, el.bodies[1], el.position_m)
            T = point_map(el.bodies[1], pb) - point_map(el.bodies[0], pa)
            K += T.T @ np.diag(lin.stiffness_N_per_m) @ T
            maps[el.name] = T
        elif isinstance(lin, TorsionSpring):
            axis = "xyz".index(lin.axis)
            T = rotation_map(el.bodies[1], axis) - rotation_map(el.bodies[0], axis)
            K += lin.stiffness_N_m_per_rad * np.outer(T, T)
            maps[el.name] = T
        elif isinstance(el, NonlinearSpring):
            pa = attachment_point(vehicle, el.bodies[0], el.position_m)
            pb = attachment_point(vehicle, el.bodies[1], el.position_m)
            axis = "xyz".index(el.direction)
            maps[el.name] = (point_map(el.bodies[1], pb) - point_map(el.bodies[0], pa))[axis]
    # wheels on rails
    contact_maps = []
    for w, ws in enumerate(vehicle.wheelsets):
        i = index[ws.name]
        e = wheel_lateral_m[w]
        per_side = []
        for side in (1.0, -1.0):
            p = np.array([ws.position_x_m, side * e, 0.0])
            T = point_map(ws.name, p)
            K += CONTACT_STIFFNESS_N_PER_M * np.outer(T[2], T[2])
            K += HOLD_STIFFNESS * (np.outer(T[0], T[0]) + np.outer(T[1], T[1]))
            per_side.append(T[2])
        contact_maps.append(per_side)
        K[6 * i + 4, 6 * i + 4] += HOLD_STIFFNESS  # spin (pitch of the wheelset)

    nonlinear = [el for el in vehicle.suspension if isinstance(el, NonlinearSpring)]
    u = _solve_with_nonlinear_springs(K, F, nonlinear, maps)
    loads = np.array(
        [[-CONTACT_STIFFNESS_N_PER_M * (t @ u) for t in per_side] for per_side in contact_maps]
    )
    forces: dict = {}
    deflections: dict = {}
    for el in vehicle.suspension:
        lin = linear_part(el)
        if isinstance(lin, SpringDamper):
            forces[el.name] = -np.asarray(lin.stiffness_N_per_m) * (maps[el.name] @ u)
        elif isinstance(lin, TorsionSpring):
            forces[el.name] = -lin.stiffness_N_m_per_rad * float(maps[el.name] @ u)
        elif isinstance(el, NonlinearSpring):
            d = float(maps[el.name] @ u)
            deflections[el.name] = d
            f = np.zeros(3)
            f["xyz".index(el.direction)] = -_table_force(el, d)
            forces[el.name] = f
    total = sum(masses) * g - sum(load.force_N[2] for load in vehicle.loads if load.static)
    return StaticSolution(wheel_loads_N=loads, element_forces=forces, total_weight_N=total,
                          static_deflections=deflections)  # fmt: skip


#: Newton iterations of the statics with nonlinear springs and their tolerance (relative force
#: mismatch between the linearisation and the table at the static deflection).
MAX_NEWTON_ITERATIONS = 50
NEWTON_TOLERANCE = 1.0e-10
#: Floor of a nonlinear spring's tangent stiffness in the Newton iteration, as a share of its
#: table's mean slope (a flat stretch, e.g. free play, would leave the body unsupported).
TANGENT_FLOOR = 1.0e-3


def _solve_with_nonlinear_springs(K, F, nonlinear, maps) -> np.ndarray:
    """Displacements of the statics: Newton's method on the nonlinear springs' tables (each
    linearised about its current deflection ``d_i``, ``F(d) = F(d_i) + k_t (d - d_i)``); one
    linear solve when there are none."""
    d = {el.name: 0.0 for el in nonlinear}
    for _ in range(MAX_NEWTON_ITERATIONS):
        K_all, F_all = K.copy(), F.copy()
        for el in nonlinear:
            t, di = maps[el.name], d[el.name]
            k_t = max(_tangent(el, di), TANGENT_FLOOR * _mean_slope(el))
            K_all += k_t * np.outer(t, t)
            F_all -= (_table_force(el, di) - k_t * di) * t
        u = np.linalg.solve(K_all, F_all)
        change = 0.0
        for el in nonlinear:
            new = float(maps[el.name] @ u)
            scale = max(abs(_table_force(el, new)), abs(_table_force(el, d[el.name])), 1.0)
            change = max(change, abs(_table_force(el, new) - _table_force(el, d[el.name])) / scale)
            d[el.name] = new
        if change < NEWTON_TOLERANCE:
            break
    return u


def _table_force(el: NonlinearSpring, d: float) -> float:
    """The element's force at deflection ``d``, as the compiled kernel computes it."""
    return table_force(characteristic_table(el.deflection_m, el.force_N, el.interpolation), d)


def _mean_slope(el: NonlinearSpring) -> float:
    """The mean slope of the table [N/m]."""
    x, f = el.deflection_m, el.force_N
    return (f[-1] - f[0]) / (x[-1] - x[0])


def _tangent(el: NonlinearSpring, d: float, h: float = 1.0e-7) -> float:
    """The table's slope at ``d`` [N/m] (central difference over 0.2 um)."""
    return (_table_force(el, d + h) - _table_force(el, d - h)) / (2.0 * h)


def static_axle_loads_N(vehicle: Vehicle, wheel_lateral_m: float = 0.75) -> dict[str, float]:
    """Static load of each wheelset on the rails [N] (sum of its two wheel loads) from
    :func:`static_equilibrium`, with the contact points ``wheel_lateral_m`` from the wheelset
    centre (0.75 m: the tape circles of a standard-gauge wheelset)."""
    solution = static_equilibrium(vehicle, [wheel_lateral_m] * len(vehicle.wheelsets))
    return {
        ws.name: float(solution.wheel_loads_N[i].sum()) for i, ws in enumerate(vehicle.wheelsets)
    }
