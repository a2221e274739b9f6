"""Evaluate a run: :func:`summarize` turns a time series into a :class:`RunSummary`.

The steps, each a function of its own: the finite rows and the evaluation window
(:func:`evaluation_window`), the wheel forces (low-passed, Y/Q, raw peaks:
:func:`_wheel_forces`), the axles' sum Y (:func:`_axle_forces`), the oscillation frequency f0
of the stability band, running stability and hunting, ride comfort; the criteria themselves are
in :mod:`railexu.assessment`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from railexu.assessment.comfort import COMFORT_RECORD_S, PointComfort, point_comfort
from railexu.assessment.en14363 import (
    DEFAULT_CATEGORY,
    LOWPASS_HZ,
    SAFETY_STEP_M,
    SAFETY_WINDOW_M,
    SIDES,
    alpha_for,
    nadal_limit,
    running_stability_criterion,
    sum_y_criterion,
    track_shifting_limit_N,
    y_over_q_criterion,
    y_over_q_values,
)
from railexu.assessment.filters import dominant_frequency, lowpass
from railexu.assessment.hunting import FINAL_FRACTION, detect_hunting, wheelset_oscillations
from railexu.assessment.safety import (
    flange_climb_criterion,
    flange_climb_not_applicable,
    has_flange,
    wheel_unloading_criterion,
)
from railexu.assessment.signals import amplitude, window_means, zero_crossing_wavelength
from railexu.assessment.steady_track import RULE as STEADY_TRACK_RULE
from railexu.assessment.steady_track import curvature_under, longest_constant_span
from railexu.results.summary import (
    EvaluationWindow,
    FlangeContact,
    Peak,
    RunSummary,
    WheelsetSummary,
)
from railexu.results.timeseries import ResultsError, TimeSeries

FloatArray = NDArray[np.float64]

#: Default start of the evaluation window: 20 m, or this fraction of the run if less.
DEFAULT_EVALUATE_FROM_M = 20.0
DEFAULT_EVALUATE_FROM_FRACTION = 0.10
#: Y/Q is evaluated only where Q exceeds this fraction of the mean static wheel load.
MIN_LOAD_FRACTION = 0.05
#: Contact angle above which a loaded contact counts as a flange contact.
FLANGE_CONTACT_ANGLE_RAD = math.radians(45.0)
#: The frequency f0 of the running-stability band is looked for in this band (Hz).
F0_SEARCH_BAND_HZ = (0.3, 15.0)


@dataclass
class _Run:
    """The finite part of a run and its evaluation window."""

    ts: TimeSeries
    n: int
    x: FloatArray
    fs: float
    window: EvaluationWindow
    inside: NDArray[np.bool_]

    @property
    def start(self) -> float:
        return self.window.from_m

    @property
    def end(self) -> float:
        return self.window.to_m

    def col(self, name: str) -> FloatArray:
        return self.ts[name][: self.n]


@dataclass
class _WheelForces:
    """Per wheel: low-passed Y and Q, low-passed Y/Q; raw peaks in the window."""

    y: dict = field(default_factory=dict)
    q: dict = field(default_factory=dict)
    y_over_q: dict = field(default_factory=dict)
    raw_peak: Peak = field(default_factory=Peak)
    raw_2m: float | None = None
    max_abs_y: float | None = None


def y_over_q(ts: TimeSeries, wheelset: int, side: str, min_load_N: float) -> FloatArray:
    """Signed Y/Q (-) of one wheel from the recorded (unfiltered) forces, positive for the
    flanging wheel; NaN where ``Q <= min_load_N``.

    ``Y`` (``ws{i}_{side}_Y_N``) is the lateral force on the wheel in the track frame, positive
    to the left; the flange pushes the wheel towards the track centre, so a flange-type force is
    ``Y < 0`` on the left wheel and ``Y > 0`` on the right wheel. The value returned is
    ``-Y/Q`` for the left wheel and ``+Y/Q`` for the right wheel.
    """
    return y_over_q_values(
        ts[f"ws{wheelset}_{side}_Y_N"], ts[f"ws{wheelset}_{side}_Q_N"], side, min_load_N
    )


def _finite_rows(ts: TimeSeries) -> int:
    """Number of leading rows in which every column is finite (rows after a divergence are
    meaningless and are dropped from the summary)."""
    finite = np.ones(len(ts), dtype=bool)
    for values in ts.columns.values():
        finite &= np.isfinite(values)
    bad = np.flatnonzero(~finite)
    return int(bad[0]) if bad.size else len(ts)


def evaluation_window(
    x: FloatArray, evaluate_from_m: float | None, evaluate_to_m: float | None
) -> EvaluationWindow:
    """The evaluation window of a run covering ``x`` (m).

    Default start: 20 m after the first sample, or 10 % of the distance covered if that is less
    (the start-up transient of the initial offset). Default end: the last sample. A window
    that does not overlap the run (a run stopped before ``evaluate_from``) falls back to the
    whole run, and the rule says so."""
    if x.size == 0:
        return EvaluationWindow(math.nan, math.nan, "empty run")
    x0, x1 = float(x[0]), float(x[-1])
    if evaluate_from_m is None:
        lead = min(DEFAULT_EVALUATE_FROM_M, DEFAULT_EVALUATE_FROM_FRACTION * (x1 - x0))
        start = x0 + lead
        rule = (
            f"default: from {DEFAULT_EVALUATE_FROM_M:g} m (or "
            f"{DEFAULT_EVALUATE_FROM_FRACTION:.0%} of the run if less) to the end"
        )
    else:
        start, rule = max(float(evaluate_from_m), x0), "evaluate_from"
    end = x1 if evaluate_to_m is None else min(float(evaluate_to_m), x1)
    rule += ", evaluate_to" if evaluate_to_m is not None else ""
    if not end > start:
        return EvaluationWindow(x0, x1, rule + "; the run ends before the window: the whole run")
    return EvaluationWindow(start, end, rule)


def _near_unloaded(q: FloatArray, min_load_N: float, fs_Hz: float) -> NDArray[np.bool_]:
    """Samples where the recorded wheel load is at most ``min_load_N`` (a lifted or unloaded
    wheel: Y/Q is undefined there; the wheel-unloading criterion judges them).

    Only these samples are left out, not a neighbourhood of them (railexu's choice): in flange
    impacts the flanging wheel bounces off its rail for a few milliseconds at every impact, and
    leaving out everything within one period of the 20 Hz low pass of such a sample (as an
    earlier version did) removed exactly the windows with the largest Y/Q: on the EU07 bogie at
    45 m/s the criterion fell from 0.73 to 0.37. The quotient of the filtered forces stays
    bounded next to a lift-off because the filtered load does (``y_over_q_values`` drops
    filtered loads at or below ``min_load_N`` too). ``fs_Hz`` is kept for the signature."""
    del fs_Hz
    return np.asarray(q) <= min_load_N


def _oscillation_frequency(
    lead: FloatArray | None, sum_y: Mapping[str, FloatArray], inside, fs_Hz: float
) -> float | None:
    """f0 of EN 14363's stability band: the frequency of the leading wheelset's lateral motion
    in the window (if it does not move: of the axle with the largest sum Y), from the mean
    spacing of its zero crossings, or the periodogram's peak if fewer than two periods show."""
    if np.count_nonzero(inside) <= 16:
        return None
    if lead is not None and amplitude(lead[inside]) > 0.0:
        values = lead[inside]
    elif sum_y:
        values = max(sum_y.values(), key=lambda v: float(np.std(v[inside])))[inside]
    else:
        return None
    # the mean spacing of zero crossings (on the time axis) is sharper than a periodogram bin
    t = np.arange(values.size) / fs_Hz
    period = zero_crossing_wavelength(t, values, min_periods=2.0)
    if period is not None and F0_SEARCH_BAND_HZ[0] <= 1.0 / period <= F0_SEARCH_BAND_HZ[1]:
        return 1.0 / period
    return dominant_frequency(values, fs_Hz, F0_SEARCH_BAND_HZ)


def _sample_rate(t: FloatArray) -> float:
    return 1.0 / float(np.median(np.diff(t))) if t.size > 1 else math.nan


def _check_arguments(ts: TimeSeries, wheelset_names: list[str], loads: list[float]) -> list[int]:
    indices = ts.wheelset_indices()
    if len(wheelset_names) != len(indices):
        raise ResultsError(
            f"{len(wheelset_names)} wheelset names for {len(indices)} wheelsets in the series"
        )
    if len(loads) != len(indices) or not loads:
        raise ResultsError(
            f"{len(loads)} static axle loads for {len(indices)} wheelsets; give one per wheelset"
        )
    return indices


def _wheelsets(run: _Run, names: list[str], indices: list[int]) -> list[WheelsetSummary]:
    """Largest |lateral| over the window; amplitude and largest |lateral| over its last 10 %."""
    x, inside = run.x, run.inside
    span = float(x[inside][-1] - x[inside][0]) if np.any(inside) else 0.0
    final = inside & (x >= (x[inside][-1] - FINAL_FRACTION * span)) if np.any(inside) else inside
    out = []
    for name, i in zip(names, indices, strict=True):
        lat = run.col(f"ws{i}_lateral_m")
        out.append(
            WheelsetSummary(
                name=str(name),
                max_abs_lateral_m=float(np.max(np.abs(lat[inside]))) if np.any(inside) else None,
                final_amplitude_m=amplitude(lat[final]) if np.any(final) else None,
                final_max_abs_lateral_m=float(np.max(np.abs(lat[final])))
                if np.any(final)
                else None,
            )
        )
    return out


def _flange_contact(run: _Run, indices: list[int], angle_rad: float) -> FlangeContact:
    """Whether and where first a wheel's largest contact angle exceeds ``angle_rad`` in the
    window, and over how many metres per wheel."""
    x, inside = run.x, run.inside
    out = FlangeContact()
    first = None
    for i in indices:
        for side in SIDES:
            col = f"ws{i}_{side}_max_angle_rad"
            if col not in run.ts:
                continue
            flag = inside & (run.col(col) > angle_rad)
            if np.any(flag):
                k = int(np.argmax(flag))
                first = x[k] if first is None else min(first, x[k])
                dx = np.gradient(x) if x.size > 1 else np.zeros_like(x)
                out.length_m[f"ws{i}_{side}"] = float(np.sum(dx[flag]))
    out.occurred = first is not None
    out.first_distance_m = None if first is None else float(first)
    return out


def summarize(
    ts: TimeSeries,
    *,
    wheelset_names: list[str],
    status: dict,
    realtime_factor: float,
    speed_m_per_s: float,
    friction: float,
    flange_angle_rad: float,
    static_axle_loads_N: list[float],
    category: str = DEFAULT_CATEGORY,
    locomotive: bool | None = None,
    evaluate_from_m: float | None = None,
    evaluate_to_m: float | None = None,
    track_irregular: bool | None = None,
    hunting_threshold_m: float = 1.0e-3,
    flange_contact_angle_rad: float = FLANGE_CONTACT_ANGLE_RAD,
    flange_height_m: float | None = None,
    comfort_points: Sequence[str] | None = None,
) -> RunSummary:
    """Assess a run: every criterion of :class:`RunSummary` over the evaluation window.

    Rows from the first non-finite value on (a diverged run) are ignored. Forces are low-pass
    filtered (EN 14363, 20 Hz) over the whole finite record before the window is cut, so the
    filter's start-up does not fall into the window.

    Args:
        ts: the recorded time series.
        wheelset_names: one name per wheelset, in index order (1 = leading).
        status: run status, copied into the summary.
        realtime_factor: simulated time / wall-clock time (-).
        speed_m_per_s: vehicle speed (m/s), for the hunting frequency.
        friction: wheel-rail friction coefficient (-), for Nadal's limit.
        flange_angle_rad: maximum flange angle (rad), for Nadal's limit.
        static_axle_loads_N: static load of each axle (N), one per wheelset.
        category: vehicle category (``locomotive``, ``coach``, ``multiple_unit``, ``wagon``):
            EN 14363's alpha of the track-shifting limit.
        locomotive: deprecated; ``False`` means ``category="wagon"``.
        evaluate_from_m, evaluate_to_m: evaluation window (m); see :func:`evaluation_window`.
        track_irregular: the track has irregularities (then EN 14363's running-stability
            criterion decides hunting); None if unknown.
        hunting_threshold_m: amplitude above which an oscillation can count as hunting (m).
        flange_contact_angle_rad: contact angle above which a contact is a flange contact.
        flange_height_m: height of the wheel's flange tip above its tape circle [m]; below
            :data:`railexu.assessment.safety.MIN_FLANGE_HEIGHT_M` the wheel has no flange:
            no Nadal limit and the flange-climb criterion not applicable (None: unknown, a
            flange assumed).
        comfort_points: the measurement points where ride comfort is evaluated (the car
            body's: :attr:`railexu.vehicle.vehicle.Vehicle.car_body_points`); None: every
            recorded point.

    Raises:
        ResultsError: wheelset names or static axle loads do not match the wheelsets, or the
            distance axis decreases.
        InputError: unknown category.
    """
    if locomotive is False:
        category = "wagon"
    alpha = alpha_for(category)
    indices = _check_arguments(ts, wheelset_names, static_axle_loads_N)
    run = _finite_run(ts, evaluate_from_m, evaluate_to_m)
    mean_axle_load = float(np.mean(static_axle_loads_N))
    min_load_N = MIN_LOAD_FRACTION * 0.5 * mean_axle_load
    flanged = has_flange(flange_height_m)
    nadal = nadal_limit(flange_angle_rad, friction) if flanged else None
    shift_limit = track_shifting_limit_N(mean_axle_load, alpha)
    q0 = {f"ws{i}_{s}": 0.5 * load for i, load in zip(indices, static_axle_loads_N, strict=True)
          for s in SIDES}  # fmt: skip
    wheels = _wheel_forces(run, indices, min_load_N)
    sum_y, raw_sum = _axle_forces(run, wheels, dict(zip(indices, wheelset_names, strict=True)))
    lead = run.col(f"ws{indices[0]}_lateral_m") if indices else None
    f0 = _oscillation_frequency(lead, sum_y, run.inside, run.fs)
    stability = running_stability_criterion(
        run.x, run.fs, sum_y, f0, run.start, run.end, shift_limit
    )
    hunting = detect_hunting(
        run.x[run.inside],
        None if lead is None else lead[run.inside],
        speed_m_per_s,
        hunting_threshold_m,
        track_irregular,
        stability,
        _oscillations(run, indices, flange_contact_angle_rad),
    )
    comfort, note = _comfort(run, comfort_points)
    x, start, end = run.x, run.start, run.end
    return RunSummary(
        status=dict(status),
        realtime_factor=realtime_factor,
        window=run.window,
        category=category,
        wheelsets=_wheelsets(run, wheelset_names, indices),
        flange_contact=_flange_contact(run, indices, flange_contact_angle_rad),
        max_abs_lateral_force_N=wheels.max_abs_y,
        raw_y_over_q=wheels.raw_peak,
        raw_y_over_q_2m=wheels.raw_2m,
        nadal_limit=nadal,
        y_over_q=y_over_q_criterion(x, wheels.y_over_q, start, end),
        raw_sum_y_N=raw_sum,
        sum_y=sum_y_criterion(x, sum_y, start, end, shift_limit, alpha, category),
        running_stability=stability,
        wheel_unloading=wheel_unloading_criterion(x, wheels.q, q0, start, end),
        flange_climb=(
            flange_climb_criterion(x, wheels.y_over_q, nadal, start, end)
            if flanged
            else flange_climb_not_applicable(flange_height_m)
        ),
        hunting=hunting,
        comfort=comfort,
        comfort_note=note,
    )


def _oscillations(run: _Run, indices: list[int], angle_rad: float) -> list[dict]:
    """The wheelsets' sustained or growing oscillations (lateral displacement, angle of attack)
    in the window (:func:`~railexu.assessment.hunting.wheelset_oscillations`), each with
    whether a wheel of its wheelset was in flange contact (contact angle above ``angle_rad``)."""
    out = []
    for i in indices:
        inside = _steady_part(run, i)
        if np.count_nonzero(inside) < 32:
            continue
        signals = {}
        for quantity in ("lateral_m", "yaw_rad"):
            if f"ws{i}_{quantity}" in run.ts:
                signals[f"ws{i}_{quantity}"] = run.col(f"ws{i}_{quantity}")[inside]
        angles = [run.col(c)[inside] for c in (f"ws{i}_{s}_max_angle_rad" for s in SIDES)
                  if c in run.ts]  # fmt: skip
        flange = {f"ws{i}": any(bool(np.any(a > angle_rad)) for a in angles)}
        found = wheelset_oscillations(run.ts.time_s[: run.n][inside], signals, flange)
        x = run.x[inside]
        for o in found:
            o["fit_span_m"] = [float(x[0]), float(x[-1])]
            o["fit_rule"] = STEADY_TRACK_RULE
        out.extend(found)
    return out


def _steady_part(run: _Run, i: int) -> NDArray[np.bool_]:
    """The evaluation window's samples where wheelset ``i`` is not in a curve transition
    (:func:`railexu.assessment.steady_track.longest_constant_span`); the whole window on
    straight track or when the track's curvature was not recorded."""
    needed = ("track_curvature_1_per_m", "ws1_s_m", f"ws{i}_s_m")
    if not all(c in run.ts for c in needed):
        return run.inside
    kappa = curvature_under(run.col(f"ws{i}_s_m"), run.col("ws1_s_m"),
                            run.col("track_curvature_1_per_m"))  # fmt: skip
    return longest_constant_span(kappa, run.inside)


def _finite_run(ts: TimeSeries, evaluate_from_m, evaluate_to_m) -> _Run:
    """The rows up to the first non-finite value, their sample rate and evaluation window."""
    n = _finite_rows(ts)
    x, t = ts.distance_m[:n], ts.time_s[:n]
    if n > 1 and np.any(np.diff(x) < 0):
        raise ResultsError("distance_m decreases; expected a non-decreasing distance axis")
    window = evaluation_window(x, evaluate_from_m, evaluate_to_m)
    inside = (x >= window.from_m - 1e-9) & (x <= window.to_m + 1e-9)
    return _Run(ts, n, x, _sample_rate(t), window, inside)


def _wheel_forces(run: _Run, indices: list[int], min_load_N: float) -> _WheelForces:
    """Low-passed Y, Q and Y/Q of every wheel (over the whole finite record), with the raw
    maxima in the window: largest |Y|, largest Y/Q sample, largest 2 m mean of the raw Y/Q."""
    out = _WheelForces()
    inside = run.inside
    for wheel, side in ((f"ws{i}_{s}", s) for i in indices for s in SIDES):
        if f"{wheel}_Y_N" not in run.ts or f"{wheel}_Q_N" not in run.ts or run.n == 0:
            continue
        y, q = run.col(f"{wheel}_Y_N"), run.col(f"{wheel}_Q_N")
        if np.any(inside):
            m = float(np.max(np.abs(y[inside])))
            out.max_abs_y = m if out.max_abs_y is None else max(out.max_abs_y, m)
        yq_raw = np.where(inside, y_over_q_values(y, q, side, min_load_N), np.nan)
        if np.any(np.isfinite(yq_raw)):
            k = int(np.nanargmax(yq_raw))
            if out.raw_peak.value is None or yq_raw[k] > out.raw_peak.value:
                out.raw_peak = Peak(float(yq_raw[k]), wheel, float(run.x[k]))
        _, means = window_means(run.x, yq_raw, SAFETY_WINDOW_M, SAFETY_STEP_M, run.start, run.end)
        if np.any(np.isfinite(means)):
            best = float(np.nanmax(means))
            out.raw_2m = best if out.raw_2m is None else max(out.raw_2m, best)
        out.y[wheel], out.q[wheel] = lowpass(y, run.fs, LOWPASS_HZ), lowpass(q, run.fs, LOWPASS_HZ)
        yq = y_over_q_values(out.y[wheel], out.q[wheel], side, min_load_N)
        out.y_over_q[wheel] = np.where(_near_unloaded(q, min_load_N, run.fs), np.nan, yq)
    return out


def _axle_forces(
    run: _Run, wheels: _WheelForces, names: dict[int, str]
) -> tuple[dict[str, FloatArray], float | None]:
    """Low-passed sum Y of every axle (by wheelset name) and the largest raw |sum Y| in the
    window."""
    sum_y, raw = {}, None
    for i, name in names.items():
        left, right = f"ws{i}_left", f"ws{i}_right"
        if left not in wheels.y or right not in wheels.y:
            continue
        sum_y[name] = wheels.y[left] + wheels.y[right]
        if np.any(run.inside):
            both = run.col(f"{left}_Y_N") + run.col(f"{right}_Y_N")
            r = float(np.max(np.abs(both[run.inside])))
            raw = r if raw is None else max(raw, r)
    return sum_y, raw


def _comfort(run: _Run, only: Sequence[str] | None = None) -> tuple[dict[str, PointComfort], str]:
    """EN 12299 and Sperling at every recorded measurement point (of ``only`` if given: the car
    body's; a bogie frame's is not a ride), and a note on the record's length."""
    ts, fs, inside = run.ts, run.fs, run.inside
    points = [p for p in ts.measurement_points() if only is None or p in only]
    if not points:
        return {}, "no accelerations recorded (columns <point>_acc_y_m_per_s2, _acc_z_m_per_s2)"
    out = {}
    for p in points:
        ay, az = f"{p}_acc_y_m_per_s2", f"{p}_acc_z_m_per_s2"
        out[p] = point_comfort(
            p,
            run.col(ay) if ay in ts else None,
            run.col(az) if az in ts else None,
            fs,
            keep=inside,
        )
    duration = float(np.count_nonzero(inside) / fs) if fs > 0 else 0.0
    note = f"evaluated over {duration:.1f} s"
    if duration < COMFORT_RECORD_S:
        note += (
            f"; EN 12299 asks for {COMFORT_RECORD_S:g} s (60 blocks of 5 s): N_MV of a shorter "
            "run rests on fewer blocks"
        )
    return out, note
