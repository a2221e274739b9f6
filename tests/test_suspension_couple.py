"""The couple of a suspension element whose two ends separate (issue 26): every element between
two bodies applies its equal and opposite forces at the midpoint of its two ends, so the pair
of forces carries no couple and the element conserves angular momentum whatever the separation
(docs/suspension.md, "The couple of an element whose ends separate").

Checked against Newton's and Euler's laws: for a linear spring-damper, a nonlinear spring and a
bump stop with separated ends between two free bodies (and between a body and a spinning
wheelset), the forces and moments on the pair sum to zero about any point, to round-off; each
body gets half the couple ``(p_b - p_a) x F`` of the separated ends, as a coil spring's two
seats carry it; and the whole EU07 in a steady curve satisfies rigid-body statics about the
track's centre line within 5 % (before: 14 % short)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from railexu.model.forces import (
    BS_C,
    BS_CLEAR,
    BS_D0,
    BS_DIR,
    BS_K,
    BS_NREAL,
    BS_P0,
    BS_P1,
    _bump_stop,
)
from railexu.model.suspension_forces import KernelElement, element_force, kernel_arrays

ROOT = Path(__file__).resolve().parents[1]
G = 9.81


def _g_matrix(t0: float, t1: float) -> np.ndarray:
    """Global angular velocity = G theta_dot for Tait-Bryan Rxyz angles."""
    c0, s0, c1, s1 = math.cos(t0), math.sin(t0), math.cos(t1), math.sin(t1)
    return np.array([[1.0, 0.0, s1], [0.0, c0, -s0 * c1], [0.0, s0, c0 * c1]])


def _rotation(t0: float, t1: float, t2: float) -> np.ndarray:
    """Rx(t0) Ry(t1) Rz(t2)."""
    c0, s0, c1, s1 = math.cos(t0), math.sin(t0), math.cos(t1), math.sin(t1)
    c2, s2 = math.cos(t2), math.sin(t2)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, c0, -s0], [0.0, s0, c0]])
    ry = np.array([[c1, 0.0, s1], [0.0, 1.0, 0.0], [-s1, 0.0, c1]])
    rz = np.array([[c2, -s2, 0.0], [s2, c2, 0.0], [0.0, 0.0, 1.0]])
    return rx @ ry @ rz


def _force_and_moment(out: np.ndarray, q: np.ndarray, qref: np.ndarray, node: int):
    """The global force on node ``node`` and its moment about the node's centre, from the
    generalized forces (a global moment M acts on the angles as G^T M)."""
    o = 6 * node
    t0, t1 = qref[o + 3] + q[o + 3], qref[o + 4] + q[o + 4]
    moment = np.linalg.solve(_g_matrix(t0, t1).T, out[o + 3 : o + 6])
    return out[o : o + 3].copy(), moment


# a car body's spring seat above a bogie frame (node 0: car body, centre 1.0 m above the seat's
# level; node 1: bogie frame, centre 0.2 m below it), both displaced, rolled, pitched and yawed
# so that the seats separate by some 50 mm laterally, 10 mm vertically and a little longitudinally
QREF = np.array([0.0, 0.0, 1.95, 0.0, 0.0, 0.0, 0.0, 0.0, 0.75, 0.0, 0.0, 0.0])
Q = np.array([0.004, 0.025, -0.02, 0.012, -0.003, 0.004,
              -0.001, -0.013, 0.006, -0.004, 0.002, -0.006])  # fmt: skip
QT = np.array([0.1, 0.2, -0.05, 0.01, -0.02, 0.03, -0.1, 0.05, 0.02, 0.02, 0.01, -0.03])
SEAT = np.array([0.0, 1.0, 0.95])  # the spring seat, vehicle axes [m]


def _seat_points(q: np.ndarray, local_a, local_b, spin_b: bool = True):
    """The element's two ends (global) at ``q``."""
    p_a = QREF[0:3] + q[0:3] + _rotation(*(QREF[3:6] + q[3:6])) @ local_a
    t = QREF[9:12] + q[9:12]
    p_b = QREF[6:9] + q[6:9] + _rotation(t[0], t[1], t[2] if spin_b else 0.0) @ local_b
    return p_a, p_b


def _secondary_spring(table: bool = False) -> list[KernelElement]:
    """The EU07's secondary spring (per side: x 2 MN/m, y 0.35 MN/m, z 1.5 MN/m with 114 kN of
    static load, dampers 15 and 20 kN s/m), as the compiled linear elements railexu builds, or
    with a progressive table along z."""
    vertical = dict(parallel_stiffness_N_per_m=1.5e6, static_deflection_m=0.076)
    if table:
        deflection = np.array([-0.2, 0.0, 0.06, 0.1, 0.2])
        force = 1.5e6 * deflection * (1.0 + 2.0 * np.maximum(deflection - 0.06, 0.0))
        table_nm = np.column_stack([deflection, force])
        vertical = dict(spring_table=table_nm, static_deflection_m=0.076)
    return [
        KernelElement("s_x", ("body", "frame"), tuple(SEAT), 0,
                      parallel_stiffness_N_per_m=2.0e6),
        KernelElement("s_y", ("body", "frame"), tuple(SEAT), 1,
                      parallel_stiffness_N_per_m=0.35e6, parallel_damping_N_s_per_m=15e3),
        KernelElement("s_z", ("body", "frame"), tuple(SEAT), 2,
                      parallel_damping_N_s_per_m=20e3, **vertical),
    ]  # fmt: skip


@pytest.mark.parametrize("table", [False, True], ids=["linear", "table"])
def test_a_spring_with_separated_ends_balances_forces_and_moments(table):
    """The secondary spring between two free bodies whose seats have separated: the forces on
    the two bodies are opposite, the moments about the origin sum to zero (to round-off,
    1e-9 of the couple the separated ends would leave), and each body's moment about its
    centre is that of its force at the midpoint of the two ends: each body carries half the
    couple ``(p_b - p_a) x F`` of the separated ends (docs/suspension.md)."""
    elements = _secondary_spring(table)
    la = SEAT - QREF[0:3]
    lb = SEAT - QREF[6:9]
    local = {e.name: ((la, lb), 0.0) for e in elements}
    si, sr, tab = kernel_arrays(elements, {"body": 0, "frame": 1}, local, 12)
    out = np.zeros(12)
    for e in range(len(elements)):
        element_force(e, Q, QT, QREF, si, sr, tab, out)
    f_a, m_a = _force_and_moment(out, Q, QREF, 0)
    f_b, m_b = _force_and_moment(out, Q, QREF, 1)
    p_a, p_b = _seat_points(Q, la, lb)
    separation = p_b - p_a
    assert abs(separation[1]) > 0.03 and abs(separation[2]) > 0.005  # the seats have separated
    assert f_a[2] > 1.0e5  # carrying the car body: over 114 kN up on the body
    couple = np.linalg.norm(np.cross(separation, f_b))
    assert couple > 3.0e3  # what a force pair at the two ends would leave unbalanced [N m]
    assert f_a + f_b == pytest.approx(np.zeros(3), abs=1e-9 * np.linalg.norm(f_b))
    centre_a = QREF[0:3] + Q[0:3]
    centre_b = QREF[6:9] + Q[6:9]
    total = m_a + np.cross(centre_a, f_a) + m_b + np.cross(centre_b, f_b)
    assert total == pytest.approx(np.zeros(3), abs=1e-9 * couple)
    midpoint = 0.5 * (p_a + p_b)
    assert m_a == pytest.approx(np.cross(midpoint - centre_a, f_a), abs=1e-9 * couple)
    assert m_b == pytest.approx(np.cross(midpoint - centre_b, f_b), abs=1e-9 * couple)
    # the split: relative to the forces at the two ends, each body gets -(1/2) (p_b - p_a) x F_b
    half = -0.5 * np.cross(separation, f_b)
    assert m_a - np.cross(p_a - centre_a, f_a) == pytest.approx(half, abs=1e-9 * couple)
    assert m_b - np.cross(p_b - centre_b, f_b) == pytest.approx(half, abs=1e-9 * couple)


def test_a_spring_at_a_spinning_wheelset_balances_forces_and_moments():
    """A primary spring (the EU07's, at the axle's height) between a bogie frame (node 0) and a
    spinning wheelset (node 1) whose ends have separated: force and moment on the pair zero,
    and no torque on the spin (the axle's bearing carries none; the moment about the axle goes
    to the frame, docs/suspension.md "Elements at a wheelset")."""
    seat = (0.0, 1.05, 0.625)
    elements = [
        KernelElement(f"p_{a}", ("frame", "ws"), seat, i, parallel_stiffness_N_per_m=k,
                      static_deflection_m=s)
        for i, (a, k, s) in enumerate((("x", 8e6, 0.0), ("y", 2.5e6, 0.0), ("z", 1.1e6, 0.07)))
    ]  # fmt: skip
    qref = np.array([0.0, 0.0, 0.75, 0.0, 0.0, 0.0, 0.0, 0.0, 0.625, -0.5 * math.pi, 0.0, 0.0])
    la = np.array([0.0, 1.05, -0.125])
    lb = np.array([0.0, 0.0, 1.05])  # on the axle (the wheelset's third axis)
    local = {e.name: ((la, lb), 0.0) for e in elements}
    box = {e.name: (False, True) for e in elements}
    si, sr, tab = kernel_arrays(elements, {"frame": 0, "ws": 1}, local, 12, box)
    q = np.array([0.003, 0.004, -0.002, 0.004, -0.002, 0.003,
                  -0.002, -0.006, 0.001, 0.003, 0.004, 2.5])  # fmt: skip
    qt = np.zeros(12)
    out = np.zeros(12)
    for e in range(3):
        element_force(e, q, qt, qref, si, sr, tab, out)
    f_a, m_a = _force_and_moment(out, q, qref, 0)
    f_b, m_b = _force_and_moment(out, q, qref, 1)
    assert abs(f_b[2]) > 5e4
    assert f_a + f_b == pytest.approx(np.zeros(3), abs=1e-9 * np.linalg.norm(f_b))
    total = (m_a + np.cross(qref[0:3] + q[0:3], f_a)
             + m_b + np.cross(qref[6:9] + q[6:9], f_b))  # fmt: skip
    assert total == pytest.approx(np.zeros(3), abs=1e-6)
    assert out[11] == pytest.approx(0.0, abs=1e-9)  # no torque on the spin


def test_a_bump_stop_with_separated_ends_balances_forces_and_moments():
    """A lateral bump stop between the car body and the bogie frame, 20 mm into contact, the
    ends separated vertically by the bodies' roll: no couple on the pair (to round-off)."""
    row = np.zeros((1, BS_NREAL))
    row[0, BS_P0 : BS_P0 + 3] = SEAT - QREF[0:3]
    row[0, BS_P1 : BS_P1 + 3] = SEAT - QREF[6:9]
    row[0, BS_DIR] = 1
    row[0, BS_CLEAR] = 0.01
    row[0, BS_K] = 5.0e6
    row[0, BS_C] = 0.0
    row[0, BS_D0] = 0.0
    out = np.zeros(12)
    _bump_stop(0, Q, QT, QREF, np.array([[0, 1, 0, 0]], dtype=np.int64), row, out)
    f_a, m_a = _force_and_moment(out, Q, QREF, 0)
    f_b, m_b = _force_and_moment(out, Q, QREF, 1)
    assert abs(f_b[1]) > 5e4
    total = (m_a + np.cross(QREF[0:3] + Q[0:3], f_a)
             + m_b + np.cross(QREF[6:9] + Q[6:9], f_b))  # fmt: skip
    assert f_a + f_b == pytest.approx(np.zeros(3), abs=1e-9 * abs(f_b[1]))
    assert total == pytest.approx(np.zeros(3), abs=1e-9 * abs(f_b[1]))


def test_the_spring_dampers_are_compiled_elements():
    """Every spring-damper of the EU07 becomes compiled linear elements (one per axis with
    stiffness or damping) applied at the midpoint of its ends, none an Exudyn Cartesian
    spring-damper (which applies its forces at its two markers)."""
    from railexu.model.assembly import VehicleModel
    from railexu.track.track import load_track
    from railexu.vehicle.vehicle import SpringDamper, load_vehicle

    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    model = VehicleModel(vehicle, load_track(ROOT / "tracks" / "straight.yaml"), 10.0,
                         distance_m=10.0)  # fmt: skip
    names = {e.name for e in model.kernel_elements}
    for el in vehicle.suspension:
        if isinstance(el, SpringDamper):
            for i, axis in enumerate("xyz"):
                wanted = el.stiffness_N_per_m[i] > 0.0 or el.damping_N_s_per_m[i] > 0.0
                assert (f"{el.name}_{axis}" in names) == wanted, (el.name, axis)
    mbs = model.mbs
    kinds = {mbs.GetObject(i)["objectType"] for i in range(mbs.systemData.NumberOfObjects())}
    assert "ConnectorCartesianSpringDamper" not in kinds
