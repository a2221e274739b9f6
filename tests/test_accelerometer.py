"""Car-body accelerations as an accelerometer fixed in the body measures them (issue 27): the
specific force (absolute acceleration minus gravity) in the body's own axes, the vertical
reading less g (docs/conventions.md, "Accelerations"). Hand calculations of rigid-body
kinematics in the moving track frame."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.simulation.recorder import accelerometer_readings

G = 9.81


def _frame(phi: float, yaw_rate: float = 0.0, speed: float = 0.0) -> np.ndarray:
    """The frame motion of railexu.model.forces.frame_motion in a constant curve (no roll
    rate): roll phi (Rx, left side up), yaw rate V kappa."""
    fm = np.zeros(12)
    fm[1] = phi
    fm[3], fm[4] = yaw_rate * math.sin(phi), yaw_rate * math.cos(phi)
    fm[8], fm[9] = math.cos(phi) * speed * yaw_rate, -math.sin(phi) * speed * yaw_rate
    fm[10], fm[11] = -G * math.sin(phi), G * (1.0 - math.cos(phi))
    return fm


def _read(fm, angles=(0.0, 0.0, 0.0), qtt=(0.0,) * 6, lever=(0.0, 0.0, 0.0), position=None):
    position = lever if position is None else position
    out = accelerometer_readings(
        np.array([[qtt]]), np.array([lever]), np.array([[angles]]), np.array([[position]]),
        fm[None, :], G,
    )  # fmt: skip
    return out[0, 0]


def test_at_rest_on_level_track_the_readings_are_zero():
    assert _read(np.zeros(12)) == pytest.approx([0.0, 0.0], abs=1e-12)


def test_at_rest_on_canted_track_the_lateral_reading_is_g_sin_of_the_total_roll():
    """100 mm cant on 1.5 m (left curve: the right rail high, the track rolled by -phi) and
    the body rolled by a further theta: the accelerometer reads g sin(-phi + theta) across
    and g cos(-phi + theta) - g vertically."""
    phi = math.asin(0.1 / 1.5)
    for theta in (0.0, 0.01, -0.02):
        total = -phi + theta
        assert _read(_frame(-phi), (theta, 0.0, 0.0)) == pytest.approx(
            [G * math.sin(total), G * math.cos(total) - G], abs=1e-12
        )


def test_in_a_steady_curve_the_lateral_reading_is_the_uncompensated_acceleration():
    """30 m/s in R 600 m with 100 mm cant: V^2/R cos(phi) - g sin(phi) = 0.842 m/s^2 across the
    track plane (issue 27: the old kinematic signal recorded 0); plus g times the body's own
    roll relative to the track; vertically V^2/R sin(phi) + g cos(phi) - g."""
    v, radius = 30.0, 600.0
    phi = math.asin(0.1 / 1.5)
    a = v * v / radius
    fm = _frame(-phi, v / radius, v)
    lateral = a * math.cos(phi) - G * math.sin(phi)
    assert lateral == pytest.approx(0.842, abs=1e-3)
    vertical = a * math.sin(phi) + G * math.cos(phi) - G
    assert _read(fm) == pytest.approx([lateral, vertical], abs=1e-12)
    theta = 0.005  # rolled outwards (to the right in a left curve: about +x)
    reading = _read(fm, (theta, 0.0, 0.0))
    assert reading[0] == pytest.approx(lateral + G * theta, rel=2e-3)
    # 2 m above the rails the point is 2 sin(phi) nearer the curve's centre: its centripetal
    # acceleration is (V/R)^2 (R - 2 sin(phi))
    a_high = (v / radius) ** 2 * (radius - 2.0 * math.sin(phi))
    high = _read(fm, position=(0.0, 0.0, 2.0))
    assert high == pytest.approx(
        [a_high * math.cos(phi) - G * math.sin(phi),
         a_high * math.sin(phi) + G * math.cos(phi) - G], abs=1e-12
    )  # fmt: skip


def test_the_body_kinematics_add_to_the_reading():
    """On level track at rest the relative accelerations are read as they are: a lateral
    acceleration of 0.3 m/s^2 and a roll acceleration of 1 rad/s^2 at 1.2 m above the centre
    give 0.3 - 1.2 across (the kinematic part, railexu.simulation.recorder.point_accelerations)."""
    reading = _read(np.zeros(12), qtt=(0.0, 0.3, 0.1, 1.0, 0.0, 0.0), lever=(0.0, 0.0, 1.2))
    assert reading == pytest.approx([0.3 - 1.2, 0.1], abs=1e-12)
