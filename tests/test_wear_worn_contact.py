"""The contact on a worn flange root that the wear loop produced (issue 30, docs/wear.md "Worn
profiles that diverge").

The profile: the loaded wagon's leading outer wheel after 2.48 km of
``studies/wear/curvy_10.yaml`` (``tests/data/wear/hbbins_loaded_ws1_right_2p48km.txt``, its
header says how it was made): 3 mm smoothing, about 50 um taken off the flange root
(s = -32 mm). The pose: the leading wheelset of that route's R 250 m case (15 m/s, 130 mm cant,
left curve: the right wheel is the outer one) with those profiles, the mean over the case's
evaluation window (vertical, roll and yaw in the local track frame; lateral -6.10 mm).

Physics (the bound of branch h5's flange-root patch test, issue 28): at fixed height, roll
and yaw, moving the wheelset towards the outer rail deepens the gap at every point where the
contact angle is positive (the rail rises towards its gauge side), so the elastic interference
grows everywhere and the wheel's normal load must not fall (Hertz: ``N = K delta^1.5``), and
it must not jump over a micrometre. The new S1002 meets both over the sweep, and so does the
worn profile (issue 30, branch hE). On 05bea86 the worn profile's load fell in two places (then a
strict expected failure):
- -6.119 .. -6.134 mm, by up to 3.6 kN per um at 100-127 kN: the flank point (1.21 rad) became
  vertically deeper than the flange-root point (0.48 rad), which became the junior of the pair
  while its approach along its normal (125 um) was larger than the flank's (50 um);
- -6.223 .. -6.233 mm, by up to 4.6 kN per um at 280-297 kN, one minimum on the flank: its
  patch's load left the flange-root side as the flank deepened 2.8 times faster in the
  vertical, the approach ``-g_min cos(gamma_centroid)`` fell with the centroid's turn towards
  the flank (215 -> 197 um) and Hertz's curvature bound, from the load's variance, rose (1.9 ->
  3.6 1/m).
The kernel now measures the patch along the normal (the approach the largest ``-g cos(gamma)``
over the valley's overlap, the curvature bound from the area of the interference along the
normal; docs/validation.md): the load grows at every 1 um step (0 .. 357 kN).

The second part (``test_r300_*``) is the pose at which the wear loop from new profiles stopped
at 6.34 km on 05bea86 (R 300 m diverged down to 0.25 ms): there the load fell from 163.7 to
139.8 kN over 53 um (up to 666 N/um), the flange root's weight falling as the junior of the
flank while the flank's patch did not take its overlap; with the patch along the normal it
grows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.contact.evaluation import WheelsetContactModel
from railexu.model.assembly import wheelset_geometry
from railexu.study.wear.route import load_route
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
WORN = ROOT / "tests" / "data" / "wear" / "hbbins_loaded_ws1_right_2p48km.txt"
VERTICAL_M = 0.46001
ROLL_RAD = -0.000535
YAW_RAD = -0.0209
LATERAL_M = np.arange(-5.70e-3, -6.30e-3, -1.0e-6)  # towards the outer (right) rail, 1 um
#: the checks cover the loads the runs reach: 2.7 times the static wheel load (110 kN; the case
#: recorded at most 135 kN on this wheel's flange-root point) [N]
MAX_LOAD_N = 3.0e5


@pytest.fixture(scope="module")
def track(tmp_path_factory):
    route = load_route(ROOT / "studies" / "wear" / "curvy_10.yaml")
    case = next(c for c in route.cases if c.name == "R250" and c.direction == "forward")
    return load_track(case.write_track(route, tmp_path_factory.mktemp("worn_contact")))


def _model(track, right_profile: str) -> WheelsetContactModel:
    ws1 = f"wheelsets.ws1.wheel_profile={{left: S1002, right: '{right_profile}'}}"
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml", [ws1])
    return WheelsetContactModel(wheelset_geometry(vehicle.wheelsets[0], track), vehicle.contact,
                                15.0)  # fmt: skip


def _outer(model, lateral_m: float) -> tuple[float, np.ndarray]:
    """The outer wheel's normal load [N] and force (track frame) [N]."""
    result = model.evaluate(lateral_m, VERTICAL_M, ROLL_RAD, YAW_RAD)
    normal = sum(p.normal_force_N for p in result.wheel("right"))
    return normal, np.asarray(result.wheel_force_N("right"))


def _sweep(model) -> tuple:
    """The model, the outer wheel's normal load [N] and force [N] along the sweep."""
    rows = [_outer(model, y) for y in LATERAL_M]
    return model, np.array([r[0] for r in rows]), np.array([r[1] for r in rows])


def _load_grows(normal: np.ndarray) -> None:
    fall = np.where(normal[1:] < MAX_LOAD_N, np.diff(normal), 0.0)
    assert np.all(fall >= -1.0e-6 * normal[1:]), (
        f"the load falls by {-fall.min():.0f} N over 1 um at "
        f"{LATERAL_M[1 + np.argmin(fall)] * 1e3:.4f} mm"
    )


def _no_jump(model, force: np.ndarray) -> None:
    """The largest change of the force over one 1 um step, resolved at 1/8 um: a continuous
    force changes by at most about 1/8 of it (plus its curvature) over a sub-step; a jump keeps
    its size (the bound of branch h5's flange-root patch test, issue 28)."""
    change = np.linalg.norm(np.diff(force, axis=0), axis=1)
    change = np.where(np.linalg.norm(force[1:], axis=1) < MAX_LOAD_N, change, 0.0)
    i = int(np.argmax(change))
    fine = np.array([_outer(model, y)[1] for y in np.linspace(LATERAL_M[i], LATERAL_M[i + 1], 9)])
    sub = np.linalg.norm(np.diff(fine, axis=0), axis=1)
    assert sub.max() < 0.25 * change[i], (
        f"the force jumps by {sub.max():.0f} N within 1/8 um at {LATERAL_M[i] * 1e3:.4f} mm "
        f"(the step's change {change[i]:.0f} N)"
    )


@pytest.fixture(scope="module")
def new_sweep(track):
    return _sweep(_model(track, "S1002"))


@pytest.fixture(scope="module")
def worn_sweep(track):
    return _sweep(_model(track, str(WORN)))


def test_the_sweep_covers_the_operating_load(new_sweep, worn_sweep):
    """The flange-root point of that wheel carried 110 kN on average in the case (at most
    135 kN): the sweep passes through that load on both profiles."""
    for _, normal, _ in (new_sweep, worn_sweep):
        assert normal.min() < 1.1e5 < normal.max()


def test_new_profile_load_grows_and_does_not_jump(new_sweep):
    model, normal, force = new_sweep
    _load_grows(normal)
    _no_jump(model, force)


def test_worn_profile_load_grows_into_the_rail(worn_sweep):
    _load_grows(worn_sweep[1])


def test_worn_profile_force_does_not_jump(worn_sweep):
    _no_jump(worn_sweep[0], worn_sweep[2])


# The pose at which the route's R 300 m case diverged at 6.35 km on 05bea86 (docs/wear.md "Worn
# profiles that diverge", issue 30): the leading wheelset 9 ms before "SolveDynamic terminated"
# (2.5599 s, 41.0 m, 0.25 ms), with the outer (right) wheel's profile of that step; R 300 m,
# 120 mm cant, 16 m/s, left curve.
WORN_6P35 = ROOT / "tests" / "data" / "wear" / "hbbins_loaded_ws1_right_6p35km.txt"
R300_POSE = (0.45997, -0.00054078, -0.01786)  # vertical [m], roll, yaw [rad]
R300_LATERAL_M = np.arange(-6.250e-3, -6.360e-3, -1.0e-6)  # through the recorded -6.299 mm


@pytest.fixture(scope="module")
def r300_sweep(tmp_path_factory):
    """The outer wheel's normal load [N] along the sweep at the R 300 m pose."""
    route = load_route(ROOT / "studies" / "wear" / "curvy_10.yaml")
    case = next(c for c in route.cases if c.name == "R300" and c.direction == "forward")
    track = load_track(case.write_track(route, tmp_path_factory.mktemp("worn_r300")))
    ws1 = f"wheelsets.ws1.wheel_profile={{left: S1002, right: '{WORN_6P35}'}}"
    vehicle = load_vehicle(ROOT / "vehicles" / "hbbins_loaded.yaml", [ws1])
    model = WheelsetContactModel(wheelset_geometry(vehicle.wheelsets[0], track), vehicle.contact,
                                 16.0)  # fmt: skip
    points = (model.evaluate(y, *R300_POSE).wheel("right") for y in R300_LATERAL_M)
    return np.array([sum(p.normal_force_N for p in wheel) for wheel in points])


def test_r300_load_grows_into_the_rail(r300_sweep):
    """At the pose where R 300 m diverged: the load grows at every 1 um step (on 05bea86 it fell
    by 24 kN while every point's own Hertz load grew), and the sweep passes through the load
    the case recorded on that wheel (about 157 kN)."""
    normal = r300_sweep
    assert normal.min() < 1.57e5 < normal.max()
    fall = np.diff(normal)
    assert np.all(fall >= -1.0e-6 * normal[1:])
