"""The flange-root patch of the Manchester coach's leading wheelset in R 300 m (issue 28).

S1002 on a 60E1 gauge corner (1:40), yawed by 8.6 mrad at about 6.2 mm lateral: the gap along
the contact locus is nearly flat from the flange root (about 0.5 rad) to the flange (1.22 rad),
one conformal patch some 7 mm wide. A Hertz point at the deepest point of the gap jumped
between the two ends of that valley with micrometres of lateral motion, and the force's
direction and Hertz stiffness with it: before the fix the outer wheel's vertical force fell by
11.4 kN per micrometre of lateral displacement (118 kN over 20 um), the coach's raw wheel forces
chattered at 47 Hz with the wheel lifting off every cycle (docs/validation.md, issue 28).

Where the profiles are smooth, the force of a wheel and the point where it acts must be
continuous functions of the pose, with slopes a hand estimate bounds:

- Hertz, ``N = K delta^1.5``: ``dN/d(delta) = 1.5 N / delta``, and the approach per lateral
  motion is at most 1 (``sin`` of the contact angle), so per micrometre of lateral motion
  ``|dN| <= 1.5 N / delta * 1 um``: 2.3 kN at the sweep's largest 1.5 N / delta (about 230 kN at
  150 um); its direction turns with the point, by at most the rail head's curvature (60E1 gauge
  corner R 13 mm) times the point's motion.
- The point of a patch moves with the patch, by the order of the lateral motion (times the ratio
  of the gap's slopes, a few): bounded here by 20 um per micrometre, against 590 um before.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.contact.evaluation import WheelsetContactModel
from railexu.model.assembly import wheelset_geometry
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]

# the coach's leading wheelset in tracks/curve_r300.yaml at 20 m/s (vertical [m], roll, yaw
# [rad] in the local track frame; the right wheel is the outer one): a pose of the run
VERTICAL_M = 0.46016
ROLL_RAD = -0.00069
YAW_RAD = -0.0086
LATERAL_M = np.arange(-6.10e-3, -6.45e-3, -1.0e-6)  # through the two-point region, 1 um steps
STEP_M = 1.0e-6
GAUGE_CORNER_RADIUS_M = 0.013  # 60E1 (EN 13674-1)


@pytest.fixture(scope="module")
def model() -> WheelsetContactModel:
    vehicle = load_vehicle(ROOT / "vehicles" / "manchester_coach_extended.yaml")
    track = load_track(ROOT / "tracks" / "curve_r300.yaml")
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    return WheelsetContactModel(geometry, vehicle.contact, 20.0)


def _outer_wheel(model, lateral_m, yaw_rad=YAW_RAD):
    """Force on the outer wheel (track frame) [N], its normal force [N], the force-weighted
    wheel coordinate of its points [m], largest N / delta [N/m] and number of loaded points."""
    result = model.evaluate(lateral_m, VERTICAL_M, ROLL_RAD, yaw_rad)
    points = [p for p in result.wheel("right") if p.normal_force_N > 0.0]
    normal = sum(p.normal_force_N for p in points)
    place = sum(p.normal_force_N * p.wheel_lateral_m for p in points) / normal
    stiffness = max(p.normal_force_N / p.penetration_m for p in points)
    return result.wheel_force_N("right"), normal, place, stiffness, len(points)


def test_the_sweep_crosses_the_two_point_region(model):
    counts = {_outer_wheel(model, y)[4] for y in LATERAL_M[::5]}
    assert counts == {1, 2}


@pytest.mark.parametrize("component", [1, 2], ids=["lateral", "vertical"])
def test_the_wheel_force_is_lipschitz_in_the_lateral_displacement(model, component):
    rows = [_outer_wheel(model, y) for y in LATERAL_M]
    force = np.array([r[0][component] for r in rows])
    normal = np.array([r[1] for r in rows])
    place = np.array([r[2] for r in rows])
    stiffness = np.array([r[3] for r in rows])
    # Hertz's slope over one step, and the turn of the force with its point on the rail's arc
    # (both ends of each step: the larger); 1.5 for the damping-free margin of the estimate
    hertz = 1.5 * np.maximum(stiffness[1:], stiffness[:-1]) * STEP_M
    turn = np.maximum(normal[1:], normal[:-1]) * np.abs(np.diff(place)) / GAUGE_CORNER_RADIUS_M
    jump = np.abs(np.diff(force))
    assert np.all(jump <= 1.5 * (hertz + turn)), (
        f"largest step {jump.max():.0f} N at {LATERAL_M[np.argmax(jump)] * 1e3:.4f} mm"
    )


def test_the_point_of_the_force_moves_continuously(model):
    place = np.array([_outer_wheel(model, y)[2] for y in LATERAL_M])
    assert np.max(np.abs(np.diff(place))) < 20.0 * STEP_M


def test_the_wheel_force_is_continuous_in_yaw(model):
    """Yaw moves the flange point ahead of the axle and changes the gap's valley the same way;
    1 urad steps through the region at -6.25 mm: the Hertz bound per step with the approach per
    yaw of the flange lead (r tan(gamma) ~ 0.46 m * 2.7, at most 1.3 um per urad)."""
    yaws = np.arange(-7.6e-3, -9.6e-3, -2.0e-6)
    rows = [_outer_wheel(model, -6.25e-3, yaw) for yaw in yaws]
    force = np.array([r[0] for r in rows])
    stiffness = np.array([r[3] for r in rows])
    place = np.array([r[2] for r in rows])
    hertz = 1.5 * np.maximum(stiffness[1:], stiffness[:-1]) * 1.3e-6 * 2.0
    jump = np.linalg.norm(np.diff(force[:, 1:], axis=0), axis=1)
    assert np.all(jump <= 2.0 * hertz + 1.0e3)
    assert np.max(np.abs(np.diff(place))) < 40.0e-6
