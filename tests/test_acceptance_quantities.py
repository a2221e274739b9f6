"""EN 14363 quantities of one section (railexu.assessment.acceptance.quantities) on synthetic
time series whose every processed value is known by hand: constants plus sines.

The record: 400 m at 20 m/s sampled at 200 Hz (2 cm apart), window 100-300 m (10 s). Hand values
and tolerances:

- the 99.85 % value of ``c + A sin`` over whole periods is ``c + A sin(pi (0.9985 - 0.5))``
  (the arcsine distribution of a sine's samples), its 50 % value ``c``, its rms ``A / sqrt 2``;
  sampling a 2 Hz sine at 200 Hz puts the sample quantiles within 1e-4 A of these;
- a 2 m sliding mean of a sine of 2 m wavelength is zero (whole periods): the 2 m means of
  ``c + B sin(2 pi x / 2 m)`` are ``c`` to the interpolation error (1e-3 relative);
- the zero-phase Butterworth filters (order 4, run both ways) change a 2 Hz sine by less than
  1e-6 (low pass at 20 Hz: gain 1 / (1 + (2/20)^8); the 0.4-10 Hz band pass has its centre at
  2 Hz); the 10 Hz low pass passes a 5 Hz sine with the bilinear-transform gain
  ``1 / (1 + (tan(pi 5/200) / tan(pi 10/200))^8)`` = 0.99622 (1e-4 relative).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from railexu.assessment.acceptance.programme import SectionSpec
from railexu.assessment.acceptance.quantities import section_values, static_wheel_load_N
from railexu.errors import InputError
from railexu.simulation.timeseries import TimeSeries

FS_HZ, SPEED, LENGTH_M = 200.0, 20.0, 400.0
T = np.arange(0.0, LENGTH_M / SPEED + 1e-9, 1.0 / FS_HZ)
X = SPEED * T
Q0 = 100e3  # static wheel load (N)
P9985 = math.sin(math.pi * (0.9985 - 0.5))  # 99.85 % value of a unit sine


def _sine(amplitude: float, frequency_Hz: float) -> np.ndarray:
    return amplitude * np.sin(2.0 * math.pi * frequency_Hz * T)


def _vehicle():
    bodies = (SimpleNamespace(name="car_body", mass_kg=30e3),
              SimpleNamespace(name="bogie_1", mass_kg=3e3))  # fmt: skip
    points = (SimpleNamespace(name="body_front", body="car_body"),
              SimpleNamespace(name="bogie_1_frame", body="bogie_1"))  # fmt: skip
    wheelsets = tuple(SimpleNamespace(axle_load_N=2 * Q0, mass_kg=1.5e3) for _ in range(2))
    return SimpleNamespace(bodies=bodies, measurement_points=points, wheelsets=wheelsets,
                           total_mass_kg=2 * 2 * Q0 / 9.81, gravity_m_per_s2=9.81)  # fmt: skip


def _section(direction: str | None) -> SectionSpec:
    return SectionSpec(
        zone="z", index=0, name="z_001", kind="curve" if direction else "straight",
        radius_m=300.0 if direction else None, direction=direction, cant_m=0.15,
        speed_m_per_s=SPEED, cant_deficiency_m=0.1, length_m=200.0, run_in_m=100.0, seed=1,
        quality={}, irregularities={},
    )  # fmt: skip


def _series() -> TimeSeries:
    """A left curve: the right wheels are the outer ones, pushed towards the centre (+y)."""
    wave_2m = np.sin(2.0 * math.pi * X / 2.0)
    cols = {"time_s": T, "distance_m": X}
    for i in (1, 2):
        cols[f"ws{i}_right_Y_N"] = 30e3 * i + 5e3 * wave_2m  # Y/Q = 0.3 i on the right wheel
        cols[f"ws{i}_left_Y_N"] = np.full(T.size, -10e3)  # sum Y = 30 i - 10 kN (+ 2 m wave)
        cols[f"ws{i}_right_Q_N"] = np.full(T.size, Q0 + 10e3 * (i - 1))
        cols[f"ws{i}_left_Q_N"] = Q0 + _sine(20e3 * i, 2.0)
        cols[f"ws{i}_lateral_m"] = np.zeros(T.size)
    # car body: an accelerometer's quasi-static 0.6 m/s^2 towards the centre of the left curve
    # (+y: the specific force of the centripetal acceleration, docs/conventions.md) plus 0.8
    # m/s^2 at 2 Hz
    cols["body_front_acc_y_m_per_s2"] = 0.6 + _sine(0.8, 2.0)
    cols["body_front_acc_z_m_per_s2"] = _sine(1.2, 2.0)
    cols["bogie_1_frame_acc_y_m_per_s2"] = _sine(3.0, 5.0)
    cols["bogie_1_frame_acc_z_m_per_s2"] = np.zeros(T.size)
    return TimeSeries(cols)


@pytest.fixture(scope="module")
def curve_values():
    return section_values(_series(), _vehicle(), _section("left"))


def test_wheel_force_quantities_against_hand_values(curve_values):
    v = curve_values.values
    # Y/Q of the right wheel of wheelset 2: 60 kN / 110 kN, the 2 m wave averaging out
    assert v["Y_over_Q_2m"] == pytest.approx(60e3 / 110e3, rel=1e-3)
    assert curve_values.processing["Y_over_Q_2m"].where == "ws2_right"
    # sum Y of wheelset 2: 60 - 10 = 50 kN
    assert v["sum_Y_2m"] == pytest.approx(50e3, rel=1e-3)
    # Q_max: the left wheel of wheelset 2, 100 kN + 40 kN x sin(pi 0.4985)
    assert v["Q_max"] == pytest.approx(Q0 + 40e3 * P9985, rel=1e-4)
    assert curve_values.processing["Q_max"].where == "ws2_left"
    # quasi-static: 50 % of the outer (right) wheel's Y = 60 kN, of its Q = 110 kN
    assert v["Y_qst"] == pytest.approx(60e3, rel=1e-3)
    assert v["Q_qst"] == pytest.approx(Q0 + 10e3, rel=1e-9)


def test_the_rms_of_sum_y_is_the_band_of_its_oscillation(curve_values):
    """Normal method's instability criterion: each axle's sum Y is 30 i - 10 kN plus a 5 kN
    wave of 2 m wavelength, 10 Hz at 20 m/s; the band of the largest rms holds it (the gain of
    the order-4 band pass 8-12 Hz at 10 Hz is 0.996, of 7.5-11.5 Hz 0.9996) and removes the
    constant, so the 100 m sliding rms is 5 kN / sqrt 2 (1 %)."""
    assert curve_values.values["sum_Y_rms"] == pytest.approx(5e3 / math.sqrt(2.0), rel=0.01)
    how = curve_values.processing["sum_Y_rms"]
    assert "running stability" in how.clause and "100 m sliding rms" in how.window


def test_car_body_and_bogie_frame_accelerations_against_hand_values(curve_values):
    v = curve_values.values
    assert v["car_body_acc_y_max"] == pytest.approx(0.8 * P9985, rel=1e-4)
    assert v["car_body_acc_y_rms"] == pytest.approx(0.8 / math.sqrt(2.0), rel=1e-4)
    assert v["car_body_acc_z_max"] == pytest.approx(1.2 * P9985, rel=1e-4)
    assert v["car_body_acc_z_rms"] == pytest.approx(1.2 / math.sqrt(2.0), rel=1e-4)
    assert v["car_body_acc_y_qst"] == pytest.approx(0.6, rel=1e-4)  # towards the centre
    ratio = math.tan(math.pi * 5.0 / FS_HZ) / math.tan(math.pi * 10.0 / FS_HZ)
    assert v["bogie_frame_acc_y_max"] == pytest.approx(3.0 / (1.0 + ratio**8), rel=1e-4)
    assert v["bogie_frame_acc_y_rms"] == pytest.approx(3.0 / math.sqrt(2.0), rel=1e-3)
    assert "f0" in curve_values.processing["bogie_frame_acc_y_rms"].filter


def test_the_bogie_frame_rms_takes_the_band_of_the_largest_oscillation():
    """Two oscillations of the frame, 1 m/s^2 at 3 Hz and 2 m/s^2 at 8.5 Hz, 5.5 Hz apart (more
    than the 4 Hz band): the rms is the stronger one's, 2 / sqrt(2), within 2 % (the other's
    leakage through the Butterworth band), and its band holds 8.5 Hz; the periodogram's peak
    is not needed to find it (railexu's rule, docs/acceptance.md)."""
    series = _series()
    cols = {n: series[n] for n in series.columns}
    cols["bogie_1_frame_acc_y_m_per_s2"] = _sine(1.0, 3.0) + _sine(2.0, 8.5)
    values = section_values(TimeSeries(cols), _vehicle(), _section("left"))
    assert values.values["bogie_frame_acc_y_rms"] == pytest.approx(2.0 / math.sqrt(2.0), rel=0.02)
    band = values.processing["bogie_frame_acc_y_rms"].filter.split(": ")[-1].split(" Hz")[0]
    low, high = (float(f) for f in band.split("-"))
    assert low < 8.5 < high


def test_every_value_says_how_it_was_processed(curve_values):
    assert curve_values.window_m == (100.0, 300.0)
    for name, value in curve_values.values.items():
        assert math.isfinite(value), name
        how = curve_values.processing[name]
        assert how.filter and how.window and how.statistic and "EN 14363" in how.clause
    assert curve_values.units["Q_max"] == "N" and curve_values.units["Y_over_Q_2m"] == "1"
    assert curve_values.regressors(["cant_deficiency", "curvature"]) == [0.1, 1 / 300.0]


def test_straight_section_has_no_quasi_static_values():
    values = section_values(_series(), _vehicle(), _section(None))
    for name in ("Y_qst", "Q_qst", "car_body_acc_y_qst"):
        assert math.isnan(values.values[name]) and "straight" in values.notes[name]
    assert values.values["sum_Y_2m"] == pytest.approx(50e3, rel=1e-3)


def test_a_window_outside_the_record_and_missing_forces_are_refused():
    far = SectionSpec(**{**_section("left").__dict__, "run_in_m": 350.0})
    with pytest.raises(InputError, match="does not lie within the record"):
        section_values(_series(), _vehicle(), far)
    cols = {"time_s": T, "distance_m": X, "ws1_lateral_m": np.zeros(T.size)}
    with pytest.raises(InputError, match="lacks the wheel forces"):
        section_values(TimeSeries(cols), _vehicle(), _section("left"))


def test_static_wheel_load_from_declared_axle_loads_or_the_weight():
    assert static_wheel_load_N(_vehicle()) == pytest.approx(Q0)
    undeclared = _vehicle()
    undeclared.wheelsets = tuple(SimpleNamespace(axle_load_N=None, mass_kg=1.5e3)
                                 for _ in range(2))  # fmt: skip
    assert static_wheel_load_N(undeclared) == pytest.approx(Q0)  # 400 kN / 4 wheels


def test_section_values_have_a_json_form(curve_values):
    import json

    data = json.loads(json.dumps(curve_values.to_dict()))
    assert data["section"] == "z_001" and data["window_m"] == [100.0, 300.0]
    assert data["processing"]["Q_max"]["where"] == "ws2_left"


def test_a_zone_from_synthetic_sections_against_mean_plus_k_s():
    """Five straight sections whose sum Y differs by 2 kN steps (50, 52, ..., 58 kN): the zone's
    estimate is mean + 2.2 s = 54 kN + 2.2 x 3.1623 kN, against alpha (10 + 2 Q0 / 3) kN."""
    from railexu.assessment.acceptance.limits import zone_limits
    from railexu.assessment.acceptance.programme import TrackQuality, Zone
    from railexu.assessment.acceptance.statistics import evaluate_zone

    quality = TrackQuality("QN1", "german_low", (3.0, 25.0), (7e-4, 7e-4), (1e-3, 1e-3))
    zone = Zone(name="z", kind="straight", n_sections=5, section_length_m=200.0,
                run_in_m=100.0, method="one_dimensional", min_sections=5,
                track_quality=quality, speed_m_per_s=SPEED)  # fmt: skip
    values = []
    for k, section in enumerate(zone.sections()):
        ts = _series()
        ts.columns["ws2_left_Y_N"] = ts.columns["ws2_left_Y_N"] + 2e3 * k
        values.append(section_values(ts, _vehicle(), section))
    limits = zone_limits("wagon", zone, _vehicle())
    result = evaluate_zone(zone, values, limits)
    c = result.criteria["sum_Y_2m"]
    assert c.value == pytest.approx(54e3 + 2.2 * math.sqrt(40e6 / 4.0), rel=1e-3)
    assert c.limit == pytest.approx(0.85 * (10e3 + 2.0 * Q0 / 3.0))
    assert c.passed is True  # 60.96 kN <= 65.17 kN
    assert result.criteria["Y_qst"].value is None  # straight track: not evaluated
    assert result.criteria["Q_max"].limit == pytest.approx(Q0 + 90e3)  # 72 km/h: no cap


def test_quasi_static_values_agree_with_the_curving_statistics(curve_values):
    """Y_qst and Q_qst follow the rule of simulation/curving.py (50 % value of the outer wheel
    in the constant-radius curve); the signals here pass the 20 Hz low pass unchanged but for a
    10 Hz ripple whose median is zero, so both give the same values (1e-3)."""
    from railexu.simulation.curving import curving_statistics
    from railexu.track.alignment import alignment_from_sections

    curve = {"type": "curve", "length_m": 1000.0, "curvature_1_per_m": 1 / 300, "cant_m": 0.15}
    ts = _series()
    zeros = np.zeros(T.size)
    extra = {"cant_deficiency_m": np.full(T.size, 0.1)}
    for i in (1, 2):
        extra.update({f"ws{i}_s_m": X, f"ws{i}_yaw_rad": zeros, f"ws{i}_left_Tgamma_N": zeros,
                      f"ws{i}_right_Tgamma_N": zeros})  # fmt: skip
    ts = TimeSeries({**ts.columns, **extra})
    stats = curving_statistics(ts, alignment_from_sections([curve]), ["ws1", "ws2"],
                               window=(100.0, 300.0, "test"))  # fmt: skip
    wheelsets = stats["curves"][0]["wheelsets"]
    y_qst = max(w["Y_outer_N"]["quasi_static"] for w in wheelsets)
    q_qst = max(w["Q_outer_N"]["quasi_static"] for w in wheelsets)
    assert curve_values.values["Y_qst"] == pytest.approx(y_qst, rel=1e-3)
    assert curve_values.values["Q_qst"] == pytest.approx(q_qst, rel=1e-9)
