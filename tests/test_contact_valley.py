"""Several minima of the gap in one valley: the EU07 bogie's flange root on elastic track
(issue 28).

The pose: the EU07 bogie at 45 m/s on the default elastic track, where the patch-centroid kernel
of branch h5 made the solver fail at 1.259 s (docs/validation.md "What the patch centroid
changed elsewhere"): the leading wheelset 8.20 mm to the left, yaw 1.21 mrad, roll 0.29 mrad,
the left rail pushed 1.77 mm outwards, the wheelset's centre 625.5004 mm above the rails'
reference (an approach of about 125 um on the left wheel). S1002 on the track's rail at the
flange root (0.68-0.73 rad): the gap along the contact locus is flat within 6 um over 4 mm, and
a second minimum is born 4 mm from the first, deepens and takes over while both prominences
stay below 1 um. Before the rework of the weights the deeper minimum was faded with its own
small prominence as well, and the wheel's vertical force fell from 159 to 10 kN over 2 um.

Physics: at fixed height, roll and yaw, moving the wheelset towards the left rail deepens the
gap at every point where the contact angle is positive (here 0.68-0.73 rad), so the
interference grows everywhere and the normal load must not fall (Hertz: ``N = K delta^1.5``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.contact.evaluation import WheelsetContactModel
from railexu.model.assembly import wheelset_geometry
from railexu.track.track import track_from_dict
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
VERTICAL_M = 0.6255004
ROLL_RAD = 0.29e-3
YAW_RAD = 1.21e-3
RAILS = np.array([1.77e-3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
STEP_M = 0.5e-6
LATERAL_M = np.arange(8.15e-3, 8.25e-3, STEP_M)  # through the birth and the takeover


@pytest.fixture(scope="module")
def model() -> WheelsetContactModel:
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07_bogie.yaml")
    track = track_from_dict({"format_version": 1, "name": "elastic", "track_model": "elastic"})
    return WheelsetContactModel(wheelset_geometry(vehicle.wheelsets[0], track), vehicle.contact,
                                45.0)  # fmt: skip


def _left(model, lateral_m):
    """The left wheel's force (track frame) [N], its normal load [N], the number of points
    with load and the largest secant stiffness N / delta of a point [N/m]."""
    result = model.evaluate(lateral_m, VERTICAL_M, ROLL_RAD, YAW_RAD, rails=RAILS)
    points = [p for p in result.wheel("left") if p.normal_force_N > 0.0]
    normal = sum(p.normal_force_N for p in points)
    secant = max(p.normal_force_N / p.penetration_m for p in points)
    return np.asarray(result.wheel_force_N("left")), normal, len(points), secant


@pytest.fixture(scope="module")
def sweep(model):
    rows = [_left(model, y) for y in LATERAL_M]
    return (np.array([r[0] for r in rows]), np.array([r[1] for r in rows]),
            np.array([r[2] for r in rows]), np.array([r[3] for r in rows]))  # fmt: skip


def test_the_sweep_passes_through_two_minima_of_one_valley(model, sweep):
    """The sweep crosses the region where two minima of the flange-root valley carry load;
    the wheel's normal load stays within the run's range (100-400 kN)."""
    _, normal, count, _ = sweep
    assert set(count) == {1, 2}
    assert normal.min() > 1.0e5 and normal.max() < 4.0e5


def test_the_vertical_force_grows_into_the_rail(sweep):
    """The wheel's vertical force does not fall over any 0.5 um step (the minimum born in the
    valley takes load only as far as it exists; the deeper one keeps its weight)."""
    force, _, _, _ = sweep
    fz = force[:, 2]
    fall = np.diff(fz)
    assert np.all(fall >= -1.0e-6 * fz[1:]), (
        f"the vertical force falls by {-fall.min():.0f} N at "
        f"{LATERAL_M[1 + np.argmin(fall)] * 1e3:.4f} mm"
    )


def test_the_vertical_force_stays_within_a_bound_of_hertz(model, sweep):
    """A bound per step from Hertz's stiffness: over a lateral step ``dy`` the approach of a
    point grows by at most ``sin(gamma) dy <= dy``, so a patch of fixed shape changes its load
    by at most ``1.5 (N / delta) dy``. The patch's shape changes as well where the load passes
    from one minimum to the other (Hertz's curvature moves within the band of
    ``PATCH_CURVATURE_RATIO`` about the one the load's width implies; measured: 6.3 kN over
    0.5 um at 130 kN, seven times Hertz's bound), so the bound is ten times Hertz's.

    Not a proof of continuity: resolved at 1/800 um, a jump of 1.5 kN (1.1 % of the load)
    remains at 8.19778 mm, where the gap's minimum jumps by 0.7 mm within the flat valley
    bottom (17 nm of depth) and the patch's lattice spacing, taken from the contact angle at the
    minimum, with it (docs/validation.md); bounded here at 2 % of the load."""
    force, _, _, secant = sweep
    change = np.abs(np.diff(force[:, 2]))
    hertz = 1.5 * np.maximum(secant[1:], secant[:-1]) * STEP_M
    assert np.all(change <= 10.0 * hertz), f"{np.max(change / hertz):.1f} times Hertz's bound"
    i = int(np.argmax(change))
    fine = np.linspace(LATERAL_M[i], LATERAL_M[i + 1], 33)
    fz = np.array([_left(model, y)[0][2] for y in fine])
    assert np.max(np.abs(np.diff(fz))) < 0.02 * fz.max()
