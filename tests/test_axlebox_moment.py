"""The moment of a suspension element at a wheelset (issue 26): an element whose point on a
wheelset is away from the axle acts on the axlebox, which passes its force and moment into the
axle (all but the moment about the axle, which the bearing cannot carry and the axlebox's guide
passes to the other body). Checked against Newton's and Euler's laws: the element's forces and
moments on its two bodies balance exactly; in a steady curve the vehicle's roll-moment balance
about the track's centre line holds (rigid-body statics, docs/suspension.md)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from railexu.model.suspension_forces import (
    SI_BOX1,
    KernelElement,
    element_force,
    kernel_arrays,
)

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


def test_an_axlebox_element_balances_forces_and_moments():
    """A lateral and a vertical spring between a bogie frame (node 0) and a wheelset (node 1)
    declared 0.4 m above the axle, with the wheelset displaced, rolled, yawed and spun: the
    forces on the two nodes are opposite, the moments about the origin add up to zero, the
    spin gets no torque, and the wheelset feels the roll moment -dz F_y of the lateral force."""
    dz = 0.4
    elements = [
        KernelElement("lat", ("frame", "ws"), (0.0, 1.0, 0.625 + dz), axis=1,
                      parallel_stiffness_N_per_m=2.0e6),
        KernelElement("vert", ("frame", "ws"), (0.0, 1.0, 0.625 + dz), axis=2,
                      parallel_stiffness_N_per_m=1.0e6, static_deflection_m=0.07),
    ]  # fmt: skip
    la = np.array([0.0, 1.0, 0.625 + dz - 0.75])  # on the frame (centre at 0.75 m)
    lb = np.array([0.0, -dz, 1.0])  # on the axlebox: wheelset axes without spin
    local = {e.name: ((la, lb), 0.0) for e in elements}
    si, sr, tab = kernel_arrays(elements, {"frame": 0, "ws": 1}, local, 12,
                                {"lat": (False, True), "vert": (False, True)})  # fmt: skip
    assert np.all(si[:, SI_BOX1] == 1)
    qref = np.array([0.0, 0.0, 0.75, 0.0, 0.0, 0.0, 0.0, 0.0, 0.625, -0.5 * math.pi, 0.0, 0.0])
    q = np.array([0.0, 0.002, -0.001, 0.003, -0.002, 0.001,
                  0.0, -0.004, 0.0005, 0.002, 0.003, 1.234])  # fmt: skip
    qt = np.zeros(12)
    out = np.zeros(12)
    forces = [element_force(e, q, qt, qref, si, sr, tab, out) for e in range(2)]
    assert abs(forces[0]) > 1e3 and abs(forces[1]) > 1e3
    f_frame, f_ws = out[0:3], out[6:9]
    assert f_frame + f_ws == pytest.approx(np.zeros(3), abs=1e-6)
    total = np.zeros(3)
    for o, f in ((0, f_frame), (6, f_ws)):
        t0, t1 = qref[o + 3] + q[o + 3], qref[o + 4] + q[o + 4]
        moment = np.linalg.solve(_g_matrix(t0, t1).T, out[o + 3 : o + 6])
        total += moment + np.cross(qref[o : o + 3] + q[o : o + 3], f)
    # what remains is the couple of the element's own deflection, (p_b - p_a) x F_b, a few
    # millimetres times the force (every spring between two separate points has it; before,
    # the lever was the 0.4 m between the declared point and the axle)
    p_a = qref[0:3] + q[0:3] + _rotation(*(qref[3:6] + q[3:6])) @ la
    p_b = qref[6:9] + q[6:9] + _rotation(qref[9] + q[9], qref[10] + q[10], 0.0) @ lb
    assert np.linalg.norm(p_b - p_a) < 0.01
    assert total == pytest.approx(np.cross(p_b - p_a, f_ws), abs=1e-6 * np.max(np.abs(out)))
    assert out[11] == pytest.approx(0.0, abs=1e-9)  # no torque on the spin
    # the lateral force at dz above the axle rolls the wheelset by -dz F_y (+ the vertical
    # force's moment about the axle centre at the lateral lever 1 m)
    t0, t1 = qref[9] + q[9], qref[10] + q[10]
    m_ws = np.linalg.solve(_g_matrix(t0, t1).T, out[9:12])
    assert m_ws[0] == pytest.approx(-dz * f_ws[1] + 1.0 * f_ws[2], rel=0.02)
