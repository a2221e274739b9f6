"""The default measurement points of EN 14363's simplified measuring method (issue 27): each
bogie frame carries a point above its outermost wheelsets, its lateral acceleration is recorded
and reaches the acceptance's ``bogie_frame_acc_y_*`` quantities, and ride comfort (EN 12299)
stays on the car body."""

from __future__ import annotations

from pathlib import Path

import pytest

from railexu.assessment.acceptance.quantities import _points
from railexu.results.run import RunSettings, run
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
CAR_POINTS = {"body_front", "body_centre", "body_rear"}


@pytest.mark.parametrize("name", ["eu07", "manchester_coach_extended"])
def test_each_bogie_frame_has_points_above_its_outermost_wheelsets(name):
    vehicle = load_vehicle(name)
    frames = {p.name: p for p in vehicle.measurement_points if p.body != vehicle.car_body}
    wheelsets = {w.name: w.position_x_m for w in vehicle.wheelsets}
    assert len(frames) == 4  # two bogies of two wheelsets
    for point in frames.values():
        ws = point.name.rsplit("_above_", 1)[1]
        body = next(b for b in vehicle.bodies if b.name == point.body)
        assert point.position_m == (wheelsets[ws], body.position_m[1], body.position_m[2])
    assert set(vehicle.car_body_points) == CAR_POINTS


def test_a_two_axle_wagon_has_no_bogie_frame_points():
    vehicle = load_vehicle("hbbins_loaded")
    assert {p.name for p in vehicle.measurement_points} == CAR_POINTS


def test_points_given_in_the_file_replace_the_defaults():
    vehicle = load_vehicle("eu07").replace(
        "measurement_points", {"floor": {"body": "car_body", "position": [0.0, 0.0, 1.2]}}
    )
    assert [p.name for p in vehicle.measurement_points] == ["floor"]


@pytest.fixture(scope="module")
def eu07_short_run():
    settings = RunSettings(speed_m_per_s=20.0, distance_m=12.0, initial_lateral_m=0.002,
                           output_interval_s=0.002)  # fmt: skip
    vehicle = load_vehicle("eu07")
    return vehicle, run(vehicle, load_track(ROOT / "tracks" / "straight.yaml"), settings)


def test_frame_accelerations_are_recorded_and_comfort_stays_on_the_car_body(eu07_short_run):
    vehicle, result = eu07_short_run
    ts = result.timeseries
    on_car, on_frames = _points(vehicle, ts)
    assert set(on_car) == CAR_POINTS
    assert set(on_frames) == {"bogie_1_above_ws1", "bogie_1_above_ws2",
                              "bogie_2_above_ws3", "bogie_2_above_ws4"}  # fmt: skip
    for p in on_frames:
        assert f"{p}_acc_y_m_per_s2" in ts
    assert set(result.summary["comfort"]["points"]) == CAR_POINTS
