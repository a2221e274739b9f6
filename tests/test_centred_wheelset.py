"""A free wheelset exactly centred on ideal straight track is in equilibrium: it must stay there
(nothing excites it), carrying half its axle load on each wheel. Before the Newton tolerance
fix its first steps failed: at rest in exact equilibrium the residual is the round-off of the
contact forces, which Exudyn's default absolute tolerance (1e-10) cannot meet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.track.track import track_from_dict
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    "wheel, rail, inclination",
    [("cone:0.05", "round:0.05", "none"), ("S1002", "UIC60", "1:40")],
    ids=["cone", "S1002"],
)
def test_an_exactly_centred_free_wheelset_stays_centred(wheel, rail, inclination):
    vehicle = load_vehicle(ROOT / "vehicles" / "wheelset.yaml",
                           [f"wheelsets.ws1.wheel_profile={wheel}"])  # fmt: skip
    track = track_from_dict({"format_version": 1, "name": "straight", "rail_profile": rail,
                             "inclination": inclination})  # fmt: skip
    result = run(vehicle, track, RunSettings(speed_m_per_s=5.0, distance_m=10.0,
                                             initial_lateral_m=0.0))  # fmt: skip
    assert result.status["state"] in COMPLETED_STATES, result.status
    ts = result.timeseries
    # symmetric equilibrium: only round-off moves it (1 nm, 1 nrad)
    assert np.max(np.abs(ts["ws1_lateral_m"])) < 1e-9
    assert np.max(np.abs(ts["ws1_yaw_rad"])) < 1e-9
    # each wheel carries half the weight and the journal loads (statics, Newton's first law);
    # 1e-4: the start-up settling of the vertical contact oscillation, after 0.5 s
    weight = vehicle.wheelsets[0].mass_kg * vehicle.gravity_m_per_s2 + sum(
        -load.force_N[2] for load in vehicle.loads
    )
    late = ts["time_s"] > 0.5
    for side in ("left", "right"):
        assert np.mean(ts[f"ws1_{side}_Q_N"][late]) == pytest.approx(0.5 * weight, rel=1e-4)
