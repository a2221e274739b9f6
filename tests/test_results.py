"""Tests for railexu.results (time series, summary metrics, limits) and the run figures.

All checks use synthetic series with known answers (wavelengths, amplitudes, means, limits),
not snapshots.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from railexu.report.figures import save_figure
from railexu.report.run_figures import run_figures
from railexu.results import (
    ResultsError,
    TimeSeries,
    nadal_limit,
    read_summary,
    sliding_mean,
    sliding_rms,
    summarize,
    track_shifting_limit_N,
    write_summary,
    y_over_q,
    zero_crossing_wavelength,
)

G = 9.81
V = 30.0  # m/s
KLINGEL_L = 2 * math.pi * math.sqrt(0.75 * 0.625 / 0.05)  # 19.24 m, Klingel (1883)
AXLE_LOAD_N = 80e3 * G / 4  # EU07: 80 t on 4 axles
WHEEL_LOAD_N = AXLE_LOAD_N / 2
SUMMARY_KEYS = {
    "status",
    "realtime_factor",
    "wheelsets",
    "flange_contact",
    "max_abs_lateral_force_N",
    "max_Y_over_Q",
    "max_sum_Y_N",
    "running_stability",
    "hunting",
    "format_version",
    "evaluation_window",
    "assessment",
    "comfort",
}


def make_ts(x, laterals, *, forces=None, angles=None, bodies=None) -> TimeSeries:
    """A series on distance ``x`` (speed V) with wheelset laterals and optional wheel data.

    ``forces[(i, side)] = (Y, Q)``; wheels without an entry get Y = 0, Q = static wheel load.
    """
    x = np.asarray(x, dtype=float)
    cols = {"time_s": x / V, "distance_m": x}
    forces = forces or {}
    angles = angles or {}
    for i, lat in enumerate(laterals, start=1):
        cols[f"ws{i}_lateral_m"] = np.broadcast_to(lat, x.shape)
        cols[f"ws{i}_yaw_rad"] = np.zeros_like(x)
        for side in ("left", "right"):
            y, q = forces.get((i, side), (0.0, WHEEL_LOAD_N))
            cols[f"ws{i}_{side}_Y_N"] = np.broadcast_to(y, x.shape)
            cols[f"ws{i}_{side}_Q_N"] = np.broadcast_to(q, x.shape)
            cols[f"ws{i}_{side}_n_contacts"] = np.ones_like(x)
            cols[f"ws{i}_{side}_max_angle_rad"] = np.broadcast_to(
                angles.get((i, side), 0.02), x.shape
            )
    for name, lat in (bodies or {}).items():
        cols[f"{name}_lateral_m"] = np.broadcast_to(lat, x.shape)
    return TimeSeries(cols)


def summary_of(ts: TimeSeries, **kw) -> dict:
    n = ts.wheelset_count()
    args = {
        "wheelset_names": [f"axle {i}" for i in range(1, n + 1)],
        "status": {"state": "completed", "distance_m": float(np.max(ts.distance_m, initial=0.0))},
        "realtime_factor": 0.5,
        "speed_m_per_s": V,
        "friction": 0.36,
        "flange_angle_rad": math.radians(70),
        "static_axle_loads_N": [AXLE_LOAD_N] * n,
    }
    args.update(kw)
    return summarize(ts, **args)


# ----------------------------------------------------------------------------------------------
# Limits
# ----------------------------------------------------------------------------------------------


def test_nadal_limit_70deg_mu036():
    assert nadal_limit(math.radians(70), 0.36) == pytest.approx(1.20, abs=0.005)
    # frictionless: the limit is tan(gamma)
    assert nadal_limit(math.radians(60), 0.0) == pytest.approx(math.tan(math.radians(60)))


def test_track_shifting_limit_eu07():
    assert abs(AXLE_LOAD_N - 196.2e3) < 1e-6  # 2Q0 = 196.2 kN
    assert track_shifting_limit_N(196.2e3) == pytest.approx(75.4e3, rel=1e-12)
    assert track_shifting_limit_N(AXLE_LOAD_N) == pytest.approx(75.4e3, abs=1.0)
    assert track_shifting_limit_N(AXLE_LOAD_N, 0.85) == pytest.approx(0.85 * 75.4e3, abs=1.0)


# ----------------------------------------------------------------------------------------------
# Signal helpers
# ----------------------------------------------------------------------------------------------


def nonuniform_axis(length_m: float, n: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    steps = rng.uniform(0.5, 1.5, n - 1)
    return np.concatenate(([0.0], np.cumsum(steps))) * length_m / steps.sum()


def test_sliding_mean_of_constant_is_constant():
    x = nonuniform_axis(50.0, 700)
    m = sliding_mean(x, np.full_like(x, 3.7), 2.0)
    assert np.all(np.isfinite(m))
    np.testing.assert_allclose(m, 3.7, rtol=1e-12)


def test_sliding_mean_of_sinusoid_over_whole_wavelengths_vanishes():
    lam = 4.0
    x = nonuniform_axis(200.0, 20000)
    m = sliding_mean(x, 5.0 * np.sin(2 * np.pi * x / lam + 0.4), 2 * lam)
    assert np.max(np.abs(m)) < 5.0 * 2e-3


def test_sliding_mean_of_linear_signal_is_value_at_window_centre():
    x = nonuniform_axis(30.0, 300)
    m = sliding_mean(x, 2.0 * x + 1.0, 4.0)
    centres = np.clip(x, x[0] + 2.0, x[-1] - 2.0)  # windows shifted inwards at the ends
    np.testing.assert_allclose(m, 2.0 * centres + 1.0, rtol=1e-12)


def test_sliding_mean_skips_nan_and_short_runs():
    x = np.linspace(0, 10, 101)
    v = np.full_like(x, 2.0)
    v[40:60] = np.nan
    m = sliding_mean(x, v, 1.0)
    assert np.nanmax(np.abs(m - 2.0)) < 1e-12
    assert np.all(np.isnan(sliding_mean(x, v, 20.0)))  # run shorter than the window


def test_sliding_rms_of_sinusoid():
    x = np.linspace(0.0, 300.0, 30001)
    r = sliding_rms(x, 4.0 * np.sin(2 * np.pi * x / 20.0), 100.0)
    np.testing.assert_allclose(r, 4.0 / math.sqrt(2), rtol=1e-3)


def test_zero_crossing_wavelength_of_sinusoid():
    x = np.arange(0.0, 400.0, 0.05)
    y = 3e-3 * np.sin(2 * np.pi * x / KLINGEL_L + 0.3) + 0.5e-3  # offset removed by the mean
    wl = zero_crossing_wavelength(x, y)
    assert wl == pytest.approx(KLINGEL_L, rel=0.005)
    # too short to show one period
    assert zero_crossing_wavelength(x[x < 15.0], y[x < 15.0]) is None


# ----------------------------------------------------------------------------------------------
# Hunting
# ----------------------------------------------------------------------------------------------


def test_hunting_sinusoid_wavelength_and_frequency():
    x = np.arange(0.0, 500.0, 0.05)
    ts = make_ts(x, [4e-3 * np.sin(2 * np.pi * x / KLINGEL_L), 0.0])
    h = summary_of(ts)["hunting"]
    assert h["detected"] is True
    assert h["wavelength_m"] == pytest.approx(KLINGEL_L, rel=0.005)
    assert h["frequency_Hz"] == pytest.approx(V / h["wavelength_m"], rel=1e-12)
    assert h["amplitude_m"] == pytest.approx(4e-3, rel=1e-3)


def test_decaying_oscillation_is_not_hunting():
    x = np.arange(0.0, 1000.0, 0.1)
    # amplitude still 3.7 mm > 1 mm at the end, but decaying by 22 % per quarter
    ts = make_ts(x, [10e-3 * np.exp(-x / 1000.0) * np.sin(2 * np.pi * x / 25.0)])
    h = summary_of(ts)["hunting"]
    assert h["detected"] is False
    assert h["amplitude_m"] > 1e-3
    assert h["wavelength_m"] == pytest.approx(25.0, rel=0.005)  # still reported: many periods
    # decayed to nothing: not hunting, no spurious wavelength from numerical noise
    y = 5e-3 * np.exp(-x / 20.0) * np.sin(2 * np.pi * x / 25.0)
    y += 1e-15 * np.sin(2 * np.pi * x / 0.3)
    h = summary_of(make_ts(x, [y]))["hunting"]
    assert h["detected"] is False


def test_growing_oscillation_is_hunting():
    x = np.arange(0.0, 1000.0, 0.1)
    ts = make_ts(x, [0.3e-3 * np.exp(x / 500.0) * np.sin(2 * np.pi * x / 25.0)])
    h = summary_of(ts)["hunting"]
    assert h["detected"] is True
    assert h["wavelength_m"] == pytest.approx(25.0, rel=0.005)


def test_small_limit_cycle_is_below_threshold():
    x = np.arange(0.0, 400.0, 0.1)
    ts = make_ts(x, [0.5e-3 * np.sin(2 * np.pi * x / 25.0)])
    h = summary_of(ts)["hunting"]
    assert h["detected"] is False
    assert h["wavelength_m"] == pytest.approx(25.0, rel=0.005)
    assert summary_of(ts, hunting_threshold_m=0.2e-3)["hunting"]["detected"] is True


def test_settling_offset_is_not_hunting():
    x = np.arange(0.0, 300.0, 0.1)
    ts = make_ts(x, [4e-3 * (1 - np.exp(-x / 30.0))])  # drifts to a steady 4 mm offset
    h = summary_of(ts)["hunting"]
    assert h["detected"] is False
    assert h["wavelength_m"] is None and h["frequency_Hz"] is None


# ----------------------------------------------------------------------------------------------
# Summary metrics
# ----------------------------------------------------------------------------------------------


def test_final_amplitude_over_last_ten_percent():
    x = np.linspace(0.0, 200.0, 2001)
    y = np.where(x < 180.0, -5e-3, 2e-3 * np.sin(2 * np.pi * (x - 180.0) / 10.0))
    s = summary_of(make_ts(x, [y, 0.0]))
    ws = s["wheelsets"]
    assert [w["name"] for w in ws] == ["axle 1", "axle 2"]
    assert ws[0]["max_abs_lateral_m"] == pytest.approx(5e-3)
    assert ws[0]["final_amplitude_m"] == pytest.approx(2e-3, rel=1e-6)
    assert ws[1]["final_amplitude_m"] == 0.0


def test_y_over_q_sign_convention_flanging_wheel_positive():
    x = np.linspace(0.0, 20.0, 201)
    q = WHEEL_LOAD_N
    # ws1 runs against the left rail: the flange pushes the left wheel to the right (Y < 0)
    ts = make_ts(
        x,
        [8e-3, 0.0],
        forces={
            (1, "left"): (-0.6 * q, q),
            (1, "right"): (-0.1 * q, q),
            (2, "right"): (0.3 * q, q),
        },
    )
    np.testing.assert_allclose(y_over_q(ts, 1, "left", 0.0), 0.6)
    np.testing.assert_allclose(y_over_q(ts, 1, "right", 0.0), -0.1)
    np.testing.assert_allclose(y_over_q(ts, 2, "right", 0.0), 0.3)
    m = summary_of(ts)["max_Y_over_Q"]
    assert m["wheel"] == "ws1_left"
    assert m["value"] == pytest.approx(0.6)
    assert m["value_2m"] == pytest.approx(0.6)
    assert m["nadal_limit"] == pytest.approx(1.20, abs=0.005)
    assert m["exceeded"] is False


def test_y_over_q_ignores_unloaded_wheels_and_uses_2m_mean():
    x = np.linspace(0.0, 40.0, 4001)
    q = np.full_like(x, WHEEL_LOAD_N)
    q[(x > 10) & (x < 12)] = 0.01 * WHEEL_LOAD_N  # lifted wheel: Y/Q would be 10
    y = np.where((x > 10) & (x < 12), 0.1 * WHEEL_LOAD_N, 0.0)
    y = y + np.where((x > 30.0) & (x < 30.5), 1.5 * WHEEL_LOAD_N, 0.0)  # 0.5 m spike of 1.5
    ts = make_ts(x, [0.0], forces={(1, "right"): (y, q)})
    m = summary_of(ts)["max_Y_over_Q"]
    assert m["value"] == pytest.approx(1.5)
    assert m["distance_m"] == pytest.approx(30.25, abs=0.3)
    assert m["value_2m"] == pytest.approx(1.5 * 0.5 / 2.0, rel=0.02)  # spike spread over 2 m
    assert m["exceeded"] is False  # the raw 1.5 > 1.20 but the 2 m mean is below


def test_track_shifting_force_and_running_stability():
    x = np.linspace(0.0, 150.0, 15001)
    sum_y = 60e3 * np.sin(2 * np.pi * x / 20.0)
    ts = make_ts(x, [0.0, 0.0], forces={(2, "left"): (sum_y, WHEEL_LOAD_N)})
    s = summary_of(ts)
    t = s["max_sum_Y_N"]
    assert t["limit_N"] == pytest.approx(75.4e3, abs=1.0)
    assert t["raw_value"] == pytest.approx(60e3, rel=1e-4)
    # 2 m mean of a 20 m sine: amplitude sin(pi/10)/(pi/10)
    assert t["value"] == pytest.approx(60e3 * math.sin(0.1 * math.pi) / (0.1 * math.pi), rel=1e-3)
    assert t["wheelset"] == "axle 2"
    assert t["exceeded"] is False
    r = s["running_stability"]
    assert r["limit_N"] == pytest.approx(0.5 * t["limit_N"])
    # EN 14363 band f0 +- 2 Hz around f0 = 30 m/s / 20 m = 1.5 Hz (lower edge raised to 0.5 Hz);
    # the band-passed sine keeps its rms A/sqrt(2) to 0.5 %: the 4th-order Butterworth passes
    # 1.5 Hz with a gain of 0.9999, the rest is the filter's start-up ripple in the first window
    assert r["band_Hz"] == pytest.approx([0.5, 3.5], rel=0.01)
    assert r["rms_sum_Y_N"] == pytest.approx(60e3 / math.sqrt(2), rel=5e-3)
    assert r["exceeded"] is True
    # freight wagon: alpha = 0.85
    assert summary_of(ts, locomotive=False)["max_sum_Y_N"]["limit_N"] == pytest.approx(
        0.85 * 75.4e3, abs=1.0
    )
    # shorter than 100 m: no running-stability value
    r_short = summary_of(ts.truncated(5000))["running_stability"]
    assert r_short["rms_sum_Y_N"] is None and r_short["exceeded"] is False


def test_track_shifting_exceeded():
    x = np.linspace(0.0, 10.0, 101)
    ts = make_ts(
        x, [0.0], forces={(1, "left"): (-40e3, WHEEL_LOAD_N), (1, "right"): (-40e3, WHEEL_LOAD_N)}
    )
    t = summary_of(ts)["max_sum_Y_N"]
    assert t["value"] == pytest.approx(80e3)
    assert t["exceeded"] is True
    assert summary_of(ts)["max_abs_lateral_force_N"] == pytest.approx(40e3)


def test_flange_contact_first_distance():
    x = np.linspace(0.0, 100.0, 1001)
    angle = np.where(x >= 37.25, math.radians(68.0), math.radians(2.0))
    ts = make_ts(x, [0.0, 0.0], angles={(2, "right"): angle})
    f = summary_of(ts)["flange_contact"]
    assert f["occurred"] is True
    assert f["first_distance_m"] == pytest.approx(37.3)  # first sample at or beyond 37.25 m
    f0 = summary_of(make_ts(x, [0.0, 0.0]))["flange_contact"]
    assert f0 == {"occurred": False, "first_distance_m": None, "length_m": {}}
    # how long: from 37.3 m to the end of the run (100 m), on the right wheel of axle 2
    assert f["length_m"] == {"ws2_right": pytest.approx(100.0 - 37.3, abs=0.15)}


def test_truncated_derailed_run_still_summarises(tmp_path):
    x = np.arange(0.0, 300.0, 0.1)
    y = 1e-3 * np.exp(x / 60.0) * np.sin(2 * np.pi * x / 20.0)
    angle = np.where(np.abs(y) > 7e-3, math.radians(70), 0.02)
    ts = make_ts(x, [y, 0.5 * y], angles={(1, "left"): angle})
    ts_cut = ts.truncated(int(np.argmax(np.abs(y) > 12e-3)) + 1)
    ts_cut.columns["ws1_lateral_m"][-1] = np.nan  # the last step diverged
    status = {"state": "derailed", "distance_m": 150.0, "time_s": 5.0, "reason": "flange climb"}
    s = summary_of(ts_cut, status=status)
    assert set(s) == SUMMARY_KEYS
    assert s["status"] == status
    assert s["flange_contact"]["occurred"] is True
    assert s["wheelsets"][0]["max_abs_lateral_m"] < 12e-3  # NaN row dropped
    json.dumps(s.to_dict(), allow_nan=False)
    path = write_summary(s, tmp_path / "out" / "summary.json")
    assert read_summary(path) == s.to_dict()


def test_summary_argument_checks():
    ts = make_ts(np.linspace(0, 10, 11), [0.0, 0.0])
    with pytest.raises(ResultsError, match="wheelset names"):
        summary_of(ts, wheelset_names=["a"])
    with pytest.raises(ResultsError, match="static axle loads"):
        summary_of(ts, static_axle_loads_N=[AXLE_LOAD_N])


# ----------------------------------------------------------------------------------------------
# TimeSeries and files
# ----------------------------------------------------------------------------------------------


def test_time_series_naming():
    x = np.linspace(0, 10, 11)
    ts = make_ts(x, [0.0, 0.0, 0.0, 0.0], bodies={"bogie_1": 0.0, "car_body": 0.0})
    assert ts.wheelset_count() == 4
    assert ts.wheelset_indices() == [1, 2, 3, 4]
    assert ts.body_names() == ["bogie_1", "car_body"]
    assert ts.names[:2] == ["time_s", "distance_m"]
    assert len(ts.truncated(3)) == 3 and len(ts) == 11


def test_time_series_validation():
    with pytest.raises(ResultsError, match="distance_m"):
        TimeSeries({"time_s": [0.0, 1.0]})
    with pytest.raises(ResultsError, match="rows"):
        TimeSeries({"time_s": [0.0, 1.0], "distance_m": [0.0]})
    ts = TimeSeries({"a_lateral_m": [1.0], "distance_m": [0.0], "time_s": [0.0]})
    assert ts.names == ["time_s", "distance_m", "a_lateral_m"]


def test_csv_round_trip(tmp_path):
    x = np.linspace(0.0, 12.345, 57)
    ts = make_ts(x, [1e-3 * np.sin(x), -2e-3 * np.cos(x)], bodies={"car_body": 1e-4 * x})
    path = ts.to_csv(tmp_path / "run" / "timeseries.csv")
    assert path.read_text().splitlines()[0] == ",".join(ts.names)
    back = TimeSeries.from_csv(path)
    assert back.names == ts.names
    for name in ts.names:
        np.testing.assert_allclose(back[name], ts[name], rtol=1e-8, atol=1e-300)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty file"),
        ("time_s,distance_m\n0,0\n1,x\n", "line 3: value 'x' is not a number"),
        ("time_s,distance_m\n0,0,0\n", "line 2: 3 fields, expected 2"),
        ("time_s,time_s\n0,0\n", "duplicate column"),
        ("time_s,ws1_lateral_m\n0,0\n", "distance_m"),
    ],
)
def test_csv_errors_name_file_and_problem(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ResultsError, match=message) as err:
        TimeSeries.from_csv(path)
    assert str(path) in str(err.value)


def test_missing_files(tmp_path):
    with pytest.raises(ResultsError, match="nope.csv"):
        TimeSeries.from_csv(tmp_path / "nope.csv")
    with pytest.raises(ResultsError, match="nope.json"):
        read_summary(tmp_path / "nope.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ResultsError, match="invalid JSON"):
        read_summary(bad)


# ----------------------------------------------------------------------------------------------
# Figures
# ----------------------------------------------------------------------------------------------


def test_run_figures_and_save(tmp_path):
    x = np.arange(0.0, 120.0, 0.1)
    y = 6e-3 * np.sin(2 * np.pi * x / 20.0)
    left_y = np.where(y > 5e-3, -30e3, 2e3)
    angle = np.where(y > 5e-3, math.radians(68), 0.02)
    ts = make_ts(
        x,
        [y, 0.8 * y],
        forces={(1, "left"): (left_y, WHEEL_LOAD_N)},
        angles={(1, "left"): angle},
        bodies={"bogie_1": 0.5 * y, "car_body": 0.1 * y},
    )
    s = summary_of(ts)
    figs = run_figures(ts, s, title="EU07 at 30 m/s")
    assert set(figs) == {"lateral_displacement", "lateral_force", "y_over_q", "wheel_load", "sum_y"}
    for fig in figs.values():
        for ax in fig.axes:
            assert ax.get_xlabel() and ax.get_ylabel() and "[" in ax.get_ylabel()
    # displacement: one line per wheelset and body, the hunting verdict in the title
    ax = figs["lateral_displacement"].axes[0]
    assert len(ax.get_lines()) == 4
    assert "hunting" in ax.get_title()
    # lateral force: one subplot per wheelset; a flange-contact marker at the start of each of
    # the 6 flange spans of ws1's left wheel (one per period of 20 m over 120 m)
    assert len(figs["lateral_force"].axes) == 2
    markers = [ln for ln in figs["lateral_force"].axes[0].get_lines() if ln.get_marker() == "v"]
    assert len(markers) == 1 and len(markers[0].get_xdata()) == 6
    # Y/Q: the EN 14363 limit and Nadal's value are labelled as such; the data reach
    # 30 kN / 98 kN = 0.31: the limit 0.8 (within 3 times the data) is drawn, Nadal's 1.20 is
    # written above the axis so that the data stay readable
    ax = figs["y_over_q"].axes[0]
    assert "EN 14363 limit (Y/Q)_lim = 0.80" in [ln.get_label() for ln in ax.get_lines()]
    assert "Nadal flange-climb value 1.20 (information)" in ax.texts[0].get_text()
    assert "EN 14363" in figs["y_over_q"].texts[0].get_text()  # suptitle names the limit's source
    # wheel load: Q and unloading side by side per wheelset, the unloading limit drawn
    assert len(figs["wheel_load"].axes) == 4
    assert figs["wheel_load"].axes[1].get_ylabel() == "unloading dQ/Q0 [-]"
    # sum Y: raw, 2 m mean and the limit +-75.4 kN (within 3 times the data's 30 kN: drawn)
    ax = figs["sum_y"].axes[0]
    assert ax.get_ylabel() == "sum Y [kN]"
    assert len(ax.get_lines()) == 4
    assert "EN 14363 limit 75.4 kN" in [ln.get_label() for ln in ax.get_lines()]
    assert len(run_figures(ts)) == 5  # without a summary
    paths = save_figure(figs["lateral_force"], tmp_path / "figs" / "lateral_force")
    assert [p.suffix for p in paths] == [".png", ".svg"]
    # the faster PNG compression keeps every pixel of Pillow's default
    from PIL import Image

    default = tmp_path / "default.png"
    figs["lateral_force"].savefig(default, dpi=130, format="png")
    assert np.array_equal(np.asarray(Image.open(paths[0])), np.asarray(Image.open(default)))


def test_a_one_metre_flange_contact_is_marked_on_a_500_m_run():
    """A 1 m flange contact in a 500 m run spans 2 pixels of a 10 inch figure; its marker (a
    triangle at its start, 7 points wide) is drawn whatever its length."""
    x = np.arange(0.0, 500.0, 0.05)
    angle = np.where((x >= 321.0) & (x < 322.0), math.radians(68), 0.02)
    ts = make_ts(x, [0.0], angles={(1, "right"): angle})
    ax = run_figures(ts, summary_of(ts))["lateral_force"].axes[0]
    (marker,) = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert marker.get_xdata() == pytest.approx([321.0])
    assert marker.get_markersize() >= 6
    assert marker.get_label() == "right flange contact (> 45 deg)"
