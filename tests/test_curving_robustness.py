"""The EU07 in tracks/curve_r300.yaml past the end of the cant ramp (170 m), where its leading
wheelsets run at the S1002/60E1 flange-root two-point contact, must run through for slightly
different inputs, not only for the one of tests/test_curving.py (17.2 m/s from 120 m, 2 ms):
before the contact search became independent of its scan grid
(tests/test_contact_scan_robustness.py), a rounding-level change of that run made it stop with
a Newton failure at 165 m. Speeds +-0.2 m/s, a start 5 cm further on and a 2.5 % shorter time
step move the states the Newton iterations try by far more than rounding."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    ("speed_m_per_s", "start_m", "time_step_s"),
    [(17.0, 120.0, 2.0e-3), (17.4, 120.0, 2.0e-3), (17.2, 120.05, 1.95e-3)],
    ids=["17.0mps", "17.4mps", "start+5cm_step1.95ms"],
)
def test_the_eu07_passes_the_two_point_contact_for_perturbed_runs(
    speed_m_per_s, start_m, time_step_s
):
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    track = load_track(ROOT / "tracks" / "curve_r300.yaml", [f"start={start_m} m"])
    settings = RunSettings(speed_m_per_s=speed_m_per_s, distance_m=70.0, initial_lateral_m=0.0,
                           time_step_s=time_step_s)  # fmt: skip
    result = run(vehicle, track, settings)
    assert result.status["state"] in COMPLETED_STATES, result.status
    ts = result.timeseries
    assert ts["ws4_s_m"].max() > 175.0  # every wheelset past the end of the ramp (170 m)
    assert np.any(ts["ws1_right_n_contacts"] == 2)  # through the two-point contact
