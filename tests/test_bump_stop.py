"""The compiled bump stop (a spring with clearance between two body points, along one track
axis) against hand-computed forces: nothing inside the clearance, k (d - clearance) beyond it,
pushing the bodies apart only (never pulling), the moment of the force about each body's centre
from its lever arm."""

from __future__ import annotations

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

K_N_PER_M = 2.0e6
C_N_S_PER_M = 1.0e4
CLEARANCE_M = 0.03


def forces(y_b: float, vy_b: float = 0.0, lever_a_x: float = 0.0) -> np.ndarray:
    """Generalized forces of one lateral bump stop between body a (node 0) at rest at the
    origin and body b (node 1) at lateral ``y_b`` moving at ``vy_b``; the stop sits ``lever_a_x``
    ahead of both bodies' centres (zero angles: the angle coordinates take the moments
    directly)."""
    q = np.zeros(12)
    qt = np.zeros(12)
    q[7] = y_b
    qt[7] = vy_b
    qref = np.zeros(12)
    bs_int = np.array([[0, 1, 0, 0]], dtype=np.int64)
    row = np.zeros((1, BS_NREAL))
    row[0, BS_P0] = lever_a_x
    row[0, BS_P1] = lever_a_x  # the stop's two ends at the same point at rest
    row[0, BS_DIR] = 1
    row[0, BS_CLEAR] = CLEARANCE_M
    row[0, BS_K] = K_N_PER_M
    row[0, BS_C] = C_N_S_PER_M
    row[0, BS_D0] = 0.0
    out = np.zeros(12)
    _bump_stop(0, q, qt, qref, bs_int, row, out)
    return out


def test_no_force_inside_the_clearance():
    assert np.all(forces(0.029, vy_b=0.5) == 0.0)


def test_spring_force_beyond_the_clearance_pushes_the_bodies_apart():
    out = forces(0.04)  # 10 mm into the stop
    f = K_N_PER_M * (0.04 - CLEARANCE_M)
    assert out[7] == pytest.approx(-f, rel=1e-12)  # on body b, back towards a
    assert out[1] == pytest.approx(f, rel=1e-12)  # on body a, the reaction
    out = forces(-0.04)  # the other side
    assert out[7] == pytest.approx(f, rel=1e-12)


def test_damping_adds_while_compressing_and_never_pulls():
    f_spring = K_N_PER_M * 0.005
    closing = forces(0.035, vy_b=0.2)
    assert -closing[7] == pytest.approx(f_spring + C_N_S_PER_M * 0.2, rel=1e-12)
    # opening fast: the damper would pull the bodies together; the stop only pushes
    opening = forces(0.035, vy_b=-2.0)
    assert np.all(opening == 0.0)


def test_moment_about_the_body_centre_from_the_lever_arm():
    """A lateral force F at 1.5 m ahead of the bodies' centres: yaw moment 1.5 F on body a and
    -1.5 F on body b (the force acts at the midpoint of the stop's two ends, which lie 40 mm
    apart across the axis: no moment from that, docs/suspension.md)."""
    out = forces(0.04, lever_a_x=1.5)
    f = K_N_PER_M * 0.01
    assert out[5] == pytest.approx(1.5 * f, rel=1e-12)
    assert out[11] == pytest.approx(-1.5 * f, rel=1e-12)
