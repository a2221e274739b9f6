"""Wear and RCF of one run, per wheel and rail, where they land on the profiles
(railexu.results.wear, docs/wear.md)."""

from __future__ import annotations

import numpy as np
import pytest

from railexu.errors import InputError
from railexu.operation.run_settings import RunSettings
from railexu.results.run import run
from railexu.results.wear import RAIL_GRID, WHEEL_GRID, run_wear
from railexu.study.wear.route import RouteCase, load_route
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROUTE = """format_version: 1
name: test
sections:
  - {name: R200, share: 1, speed: 15 m/s, length: 10 m, radius: 200 m, cant: 0 mm,
     directions: forward}
  - {name: straight, share: 1, speed: 20 m/s, length: 10 m, directions: forward}
"""


def _run(tmp_path, case: RouteCase, route, outputs: bool = True):
    vehicle = load_vehicle("wheelset")
    track = load_track(case.write_track(route, tmp_path))
    settings = RunSettings(speed_m_per_s=case.speed_m_per_s, distance_m=case.distance_m,
                           contact_outputs=outputs)  # fmt: skip
    return vehicle, run(vehicle, track, settings)


@pytest.fixture(scope="module")
def curve(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wear_run")
    path = tmp / "route.yaml"
    path.write_text(ROUTE)
    route = load_route(path)
    case = route.cases[0]
    vehicle, result = _run(tmp, case, route)
    return case, result, run_wear(result.timeseries, vehicle,
                                  evaluate_from_m=case.evaluate_from_m)  # fmt: skip


def test_worn_area_is_the_integrated_volume_rate(curve):
    """Each wheel's area on the grid (per km) equals the patches' volume rates summed with the
    same weights: nothing is lost placing the strips on the profile."""
    _, _, wears = curve
    for w in wears:
        assert w.area_per_km_m2 == pytest.approx(w.volume_rate_per_km_m2, rel=1e-9)
        assert np.all(w.depth_per_km_m >= 0.0) and np.all(w.rail_depth_per_axle_m >= 0.0)


def test_outer_wheel_wears_at_its_flange_root(curve):
    """A left curve of R 200 m at 15 m/s without cant (1.1 m/s^2 uncompensated): the right
    (outer) wheel carries the lateral force on its flange root and wears there (s < -20 mm)
    far more than the inner wheel on its tread; the outer rail wears near its gauge corner
    (within 15 mm of the gauge line)."""
    _, _, wears = curve
    left, right = wears
    assert right.area_per_km_m2 > 10.0 * left.area_per_km_m2
    y = WHEEL_GRID[0] + WHEEL_GRID[1] * np.arange(WHEEL_GRID[2])
    assert y[np.argmax(right.depth_per_km_m)] < -0.020
    assert left.lateral_m[np.argmax(left.depth_per_km_m)] > -0.015
    ry = RAIL_GRID[0] + RAIL_GRID[1] * np.arange(RAIL_GRID[2])
    assert -0.005 < ry[np.argmax(right.rail_depth_per_axle_m)] < 0.015


def test_rcf_indices_per_wheel(curve):
    _, _, wears = curve
    left, right = wears
    s = right.summary()
    assert s["window_rule"] == "evaluate_from" and s["window_m"][0] == pytest.approx(35.0)
    assert np.isfinite(right.fi_surf_max) and np.isfinite(left.fi_surf_max)
    assert right.fi_surf_max > left.fi_surf_max
    assert np.all(right.wlrm_rail_per_axle >= 0.0)


def test_without_contact_outputs_is_input_error(tmp_path):
    path = tmp_path / "route.yaml"
    path.write_text(ROUTE)
    route = load_route(path)
    vehicle, result = _run(tmp_path, route.cases[1], route, outputs=False)
    with pytest.raises(InputError, match="contact_outputs"):
        run_wear(result.timeseries, vehicle)


def test_run_wear_files(curve, tmp_path):
    """wear.csv (profiles' grids and each wheel's and rail's columns) and wear.json (strict
    JSON, the window and the law) written into a run's folder."""
    import json

    from railexu.contact.wear.coefficients import COEFFICIENTS_FILE
    from railexu.report.wear_files import write_run_wear

    _, _, wears = curve
    csv_path, json_path = write_run_wear(tmp_path, wears, "archard_jendel", str(COEFFICIENTS_FILE))
    header = csv_path.read_text().splitlines()[0].split(",")
    assert header[:2] == ["wheel_lateral_m", "rail_lateral_m"]
    assert "ws1_right_rail_depth_per_axle_m" in header
    info = json.loads(json_path.read_text())
    assert info["law"] == "archard_jendel" and info["wheels"][1]["side"] == "right"
    data = np.genfromtxt(csv_path, delimiter=",", skip_header=1)
    j = header.index("ws1_right_wheel_depth_per_km_m")
    assert np.nansum(data[:, j]) * WHEEL_GRID[1] == pytest.approx(wears[1].area_per_km_m2, rel=1e-6)
