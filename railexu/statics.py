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

Statically indeterminate arrangements (four springs under a body) share the load by stiffness,
as the real vehicle does. The result gives the wheel loads for pressing the wheelsets onto the
rails and the preload of every spring.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .vehicle import SpringDamper, TorsionSpring, Vehicle

CONTACT_STIFFNESS_N_PER_M = 2.0e9
HOLD_STIFFNESS = 1.0e9
REGULARISATION = 1.0e-3  # N/m or N m/rad: removes mechanisms, carries < 1 mN


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def attachment_point(vehicle: Vehicle, body: str, position: tuple[float, float, float]):
    """Where an element acts on a body (vehicle axes): on a wheelset it acts on the axle (its
    axlebox), whatever height and longitudinal position the file gives, so that the force never
    turns with the spinning wheelset."""
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
    """

    wheel_loads_N: np.ndarray
    element_forces: dict
    total_weight_N: float


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
        if isinstance(el, SpringDamper):
            pa = attachment_point(vehicle, el.bodies[0], el.position_m)
            pb = attachment_point(vehicle, el.bodies[1], el.position_m)
            T = point_map(el.bodies[1], pb) - point_map(el.bodies[0], pa)
            K += T.T @ np.diag(el.stiffness_N_per_m) @ T
            maps[el.name] = T
        elif isinstance(el, TorsionSpring):
            axis = "xyz".index(el.axis)
            T = rotation_map(el.bodies[1], axis) - rotation_map(el.bodies[0], axis)
            K += el.stiffness_N_m_per_rad * np.outer(T, T)
            maps[el.name] = T

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

    u = np.linalg.solve(K, F)
    loads = np.array(
        [[-CONTACT_STIFFNESS_N_PER_M * (t @ u) for t in per_side] for per_side in contact_maps]
    )
    forces: dict = {}
    for el in vehicle.suspension:
        if isinstance(el, SpringDamper):
            forces[el.name] = -np.asarray(el.stiffness_N_per_m) * (maps[el.name] @ u)
        elif isinstance(el, TorsionSpring):
            forces[el.name] = -el.stiffness_N_m_per_rad * float(maps[el.name] @ u)
    total = sum(masses) * g - sum(load.force_N[2] for load in vehicle.loads if load.static)
    return StaticSolution(wheel_loads_N=loads, element_forces=forces, total_weight_N=total)


def static_axle_loads_N(vehicle: Vehicle, wheel_lateral_m: float = 0.75) -> dict[str, float]:
    """Static load of each wheelset on the rails [N] (sum of its two wheel loads) from
    :func:`static_equilibrium`, with the contact points ``wheel_lateral_m`` from the wheelset
    centre (0.75 m: the tape circles of a standard-gauge wheelset)."""
    solution = static_equilibrium(vehicle, [wheel_lateral_m] * len(vehicle.wheelsets))
    return {
        ws.name: float(solution.wheel_loads_N[i].sum()) for i, ws in enumerate(vehicle.wheelsets)
    }
