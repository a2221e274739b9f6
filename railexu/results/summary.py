"""The summary of a run: a typed :class:`RunSummary` with the assessment of every criterion.

:func:`summarize` evaluates a run's time series over its **evaluation window** (from
``evaluate_from`` to ``evaluate_to``, m; by default from 20 m, or 10 % of the distance covered if
that is less, to the end: the start-up transient after the initial offset is left out) and
returns a :class:`RunSummary`. ``RunSummary.to_dict()`` is the content of ``summary.json``; the
summary also reads like that dict (``summary["hunting"]["detected"]``), so code written for the
dict keeps working.

The criteria and their sources are in :mod:`railexu.assessment` and ``docs/assessment.md``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..assessment.comfort import COMFORT_RECORD_S, PointComfort, point_comfort
from ..assessment.criterion import Criterion, finite_or_none
from ..assessment.en14363 import (
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
from ..assessment.filters import dominant_frequency, lowpass
from ..assessment.hunting import FINAL_FRACTION, HuntingResult, detect_hunting
from ..assessment.safety import flange_climb_criterion, wheel_unloading_criterion
from ..assessment.signals import amplitude, window_means, zero_crossing_wavelength
from .timeseries import ResultsError, TimeSeries

FloatArray = NDArray[np.float64]

#: Version of the ``summary.json`` layout (1: before the typed summary and the assessment).
FORMAT_VERSION = 2
#: Default start of the evaluation window: 20 m, or this fraction of the run if less.
DEFAULT_EVALUATE_FROM_M = 20.0
DEFAULT_EVALUATE_FROM_FRACTION = 0.10
#: Y/Q is evaluated only where Q exceeds this fraction of the mean static wheel load.
MIN_LOAD_FRACTION = 0.05
#: Contact angle above which a loaded contact counts as a flange contact.
FLANGE_CONTACT_ANGLE_RAD = math.radians(45.0)
#: The frequency f0 of the running-stability band is looked for in this band (Hz).
F0_SEARCH_BAND_HZ = (0.3, 15.0)


# ----------------------------------------------------------------------------------------------
# Typed summary
# ----------------------------------------------------------------------------------------------


@dataclass
class EvaluationWindow:
    """The stretch of the run every statistic and maximum is taken over (m)."""

    from_m: float
    to_m: float
    rule: str

    def to_dict(self) -> dict:
        return {"from_m": finite_or_none(self.from_m), "to_m": finite_or_none(self.to_m),
                "rule": self.rule}  # fmt: skip


@dataclass
class WheelsetSummary:
    """Lateral motion of one wheelset over the evaluation window (m)."""

    name: str
    max_abs_lateral_m: float | None
    final_amplitude_m: float | None
    final_max_abs_lateral_m: float | None

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "max_abs_lateral_m": finite_or_none(self.max_abs_lateral_m),
            "final_amplitude_m": finite_or_none(self.final_amplitude_m),
            "final_max_abs_lateral_m": finite_or_none(self.final_max_abs_lateral_m),
        }


@dataclass
class FlangeContact:
    """Flange contact in the evaluation window: whether, where first, and how long per wheel."""

    occurred: bool = False
    first_distance_m: float | None = None
    length_m: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "occurred": bool(self.occurred),
            "first_distance_m": finite_or_none(self.first_distance_m),
            "length_m": {k: finite_or_none(v) for k, v in self.length_m.items()},
        }


@dataclass
class Peak:
    """A raw (unwindowed) maximum: value, where and at which distance."""

    value: float | None = None
    where: str | None = None
    distance_m: float | None = None


@dataclass
class RunSummary(Mapping):
    """Summary of a run (SI units): the evaluation window, the motion, every criterion.

    It behaves like the dict of :meth:`to_dict` for reading (``summary["max_Y_over_Q"]``,
    ``summary.get("hunting")``), and ``summary[key] = value`` adds an extra top-level entry
    (timings, settings, warnings: see :attr:`extra`).
    """

    status: dict
    realtime_factor: float | None
    window: EvaluationWindow
    category: str
    wheelsets: list[WheelsetSummary]
    flange_contact: FlangeContact
    max_abs_lateral_force_N: float | None
    raw_y_over_q: Peak
    raw_y_over_q_2m: float | None
    nadal_limit: float
    y_over_q: Criterion
    raw_sum_y_N: float | None
    sum_y: Criterion
    running_stability: Criterion
    wheel_unloading: Criterion
    flange_climb: Criterion
    hunting: HuntingResult
    comfort: dict[str, PointComfort] = field(default_factory=dict)
    comfort_note: str = ""
    extra: dict = field(default_factory=dict)

    # -- verdicts ---------------------------------------------------------------------------

    @property
    def safety_criteria(self) -> dict[str, Criterion]:
        """The criteria whose exceedance makes a run unsafe, by name."""
        return {
            "y_over_q": self.y_over_q,
            "sum_y": self.sum_y,
            "running_stability": self.running_stability,
            "wheel_unloading": self.wheel_unloading,
            "flange_climb": self.flange_climb,
        }

    @property
    def exceedances(self) -> list[str]:
        """Names of the safety criteria exceeded (empty for a safe run)."""
        return [name for name, c in self.safety_criteria.items() if c.exceeded]

    @property
    def safety_exceeded(self) -> bool:
        """True when any safety criterion is exceeded: the run's status should say so."""
        return bool(self.exceedances)

    def state_with_exceedances(self, state: str) -> str:
        """The run state to report: ``"completed_with_exceedances"`` for a ``"completed"`` run
        that exceeds a safety criterion, else ``state`` unchanged (``"derailed"`` stays)."""
        return (
            "completed_with_exceedances" if state == "completed" and self.safety_exceeded else state
        )

    # -- JSON form ---------------------------------------------------------------------------

    def to_dict(self) -> dict:
        """The content of ``summary.json`` (JSON-serialisable; None where undefined)."""
        raw = self.raw_y_over_q
        out: dict[str, Any] = {
            "format_version": FORMAT_VERSION,
            "status": _jsonable(dict(self.status)),
            "realtime_factor": finite_or_none(self.realtime_factor),
            "evaluation_window": self.window.to_dict(),
            "wheelsets": [w.to_dict() for w in self.wheelsets],
            "flange_contact": self.flange_contact.to_dict(),
            "max_abs_lateral_force_N": finite_or_none(self.max_abs_lateral_force_N),
            "max_Y_over_Q": {
                "value": finite_or_none(raw.value),
                "wheel": raw.where,
                "distance_m": finite_or_none(raw.distance_m),
                "value_2m": finite_or_none(self.raw_y_over_q_2m),
                "value_en14363": self.y_over_q.value,
                "limit": self.y_over_q.limit,
                "nadal_limit": finite_or_none(self.nadal_limit),
                "exceeded": self.y_over_q.exceeded,
                "pass": self.y_over_q.passed,
            },
            "max_sum_Y_N": {
                "value": self.sum_y.value,
                "raw_value": finite_or_none(self.raw_sum_y_N),
                "wheelset": self.sum_y.where,
                "distance_m": self.sum_y.distance_m,
                "limit_N": self.sum_y.limit,
                "exceeded": self.sum_y.exceeded,
                "pass": self.sum_y.passed,
            },
            "running_stability": {
                "rms_sum_Y_N": self.running_stability.value,
                "limit_N": self.running_stability.limit,
                "band_Hz": self.running_stability.details.get("band_Hz"),
                "exceeded": self.running_stability.exceeded,
                "pass": self.running_stability.passed,
            },
            "hunting": self.hunting.to_dict(),
            "assessment": {
                "category": self.category,
                "safety_exceeded": self.safety_exceeded,
                "exceedances": self.exceedances,
                "criteria": {k: c.to_dict() for k, c in self.safety_criteria.items()},
            },
            "comfort": {
                "points": {k: c.to_dict() for k, c in self.comfort.items()},
                "note": self.comfort_note,
            },
        }
        out.update(_jsonable(self.extra))
        return out

    # -- dict-style access -----------------------------------------------------------------

    def __getitem__(self, key: str) -> Any:
        return self.to_dict()[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.extra[key] = value

    def __iter__(self) -> Iterator[str]:
        return iter(self.to_dict())

    def __len__(self) -> int:
        return len(self.to_dict())


# ----------------------------------------------------------------------------------------------
# Summarize
# ----------------------------------------------------------------------------------------------


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
    """Samples within one period of the low-pass cut-off (1 / 20 Hz) of a sample where the
    recorded wheel load is at most ``min_load_N``: there the filtered Q and Y still carry the
    lift-off, and their quotient is meaningless (railexu's choice)."""
    unloaded = q <= min_load_N
    if not np.any(unloaded) or not fs_Hz > 0:
        return unloaded
    half = int(math.ceil(fs_Hz / LOWPASS_HZ))
    near = np.convolve(unloaded.astype(float), np.ones(2 * half + 1), mode="full")
    return near[half : half + unloaded.size] > 0.0


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


def _wheelsets(ts, names, indices, n, x, inside) -> list[WheelsetSummary]:
    span = float(x[inside][-1] - x[inside][0]) if np.any(inside) else 0.0
    final = inside & (x >= (x[inside][-1] - FINAL_FRACTION * span)) if np.any(inside) else inside
    out = []
    for name, i in zip(names, indices, strict=True):
        lat = ts[f"ws{i}_lateral_m"][:n]
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


def _flange_contact(ts, indices, n, x, inside, angle_rad) -> FlangeContact:
    out = FlangeContact()
    first = None
    for i in indices:
        for side in SIDES:
            col = f"ws{i}_{side}_max_angle_rad"
            if col not in ts:
                continue
            flag = inside & (ts[col][:n] > angle_rad)
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

    Raises:
        ResultsError: wheelset names or static axle loads do not match the wheelsets, or the
            distance axis decreases.
        InputError: unknown category.
    """
    if locomotive is False:
        category = "wagon"
    alpha = alpha_for(category)
    indices = _check_arguments(ts, wheelset_names, static_axle_loads_N)
    n = _finite_rows(ts)
    x, t = ts.distance_m[:n], ts.time_s[:n]
    if n > 1 and np.any(np.diff(x) < 0):
        raise ResultsError("distance_m decreases; expected a non-decreasing distance axis")
    window = evaluation_window(x, evaluate_from_m, evaluate_to_m)
    start, end = window.from_m, window.to_m
    inside = (x >= start - 1e-9) & (x <= end + 1e-9)
    fs = _sample_rate(t)
    names = dict(zip(indices, wheelset_names, strict=True))
    q0 = {f"ws{i}_{s}": 0.5 * load for i, load in zip(indices, static_axle_loads_N, strict=True)
          for s in SIDES}  # fmt: skip
    min_load_N = MIN_LOAD_FRACTION * 0.5 * float(np.mean(static_axle_loads_N))
    nadal = nadal_limit(flange_angle_rad, friction)
    shift_limit = track_shifting_limit_N(float(np.mean(static_axle_loads_N)), alpha)

    y_lp, q_lp, yq_lp = {}, {}, {}
    raw, raw_2m = Peak(), None
    max_abs_y = None
    for i in indices:
        for side in SIDES:
            wheel = f"ws{i}_{side}"
            if f"{wheel}_Y_N" not in ts or f"{wheel}_Q_N" not in ts or n == 0:
                continue
            y, q = ts[f"{wheel}_Y_N"][:n], ts[f"{wheel}_Q_N"][:n]
            if np.any(inside):
                m = float(np.max(np.abs(y[inside])))
                max_abs_y = m if max_abs_y is None else max(max_abs_y, m)
            yq_raw = np.where(inside, y_over_q_values(y, q, side, min_load_N), np.nan)
            if np.any(np.isfinite(yq_raw)):
                k = int(np.nanargmax(yq_raw))
                if raw.value is None or yq_raw[k] > raw.value:
                    raw = Peak(float(yq_raw[k]), wheel, float(x[k]))
            _, means = window_means(x, yq_raw, SAFETY_WINDOW_M, SAFETY_STEP_M, start, end)
            if np.any(np.isfinite(means)):
                best = float(np.nanmax(means))
                raw_2m = best if raw_2m is None else max(raw_2m, best)
            y_lp[wheel], q_lp[wheel] = lowpass(y, fs, LOWPASS_HZ), lowpass(q, fs, LOWPASS_HZ)
            yq = y_over_q_values(y_lp[wheel], q_lp[wheel], side, min_load_N)
            yq_lp[wheel] = np.where(_near_unloaded(q, min_load_N, fs), np.nan, yq)
    sum_y, raw_sum = {}, None
    for i in indices:
        left, right = f"ws{i}_left", f"ws{i}_right"
        if left in y_lp and right in y_lp:
            sum_y[names[i]] = y_lp[left] + y_lp[right]
            if np.any(inside):
                r = float(np.max(np.abs((ts[f"{left}_Y_N"] + ts[f"{right}_Y_N"])[:n][inside])))
                raw_sum = r if raw_sum is None else max(raw_sum, r)

    lead = ts[f"ws{indices[0]}_lateral_m"][:n] if indices else None
    f0 = _oscillation_frequency(lead, sum_y, inside, fs)
    stability = running_stability_criterion(x, fs, sum_y, f0, start, end, shift_limit)
    hunting = detect_hunting(
        x[inside],
        None if lead is None else lead[inside],
        speed_m_per_s,
        hunting_threshold_m,
        track_irregular,
        stability,
    )
    comfort, note = _comfort(ts, n, fs, inside)
    return RunSummary(
        status=dict(status),
        realtime_factor=realtime_factor,
        window=window,
        category=category,
        wheelsets=_wheelsets(ts, wheelset_names, indices, n, x, inside),
        flange_contact=_flange_contact(ts, indices, n, x, inside, flange_contact_angle_rad),
        max_abs_lateral_force_N=max_abs_y,
        raw_y_over_q=raw,
        raw_y_over_q_2m=raw_2m,
        nadal_limit=nadal,
        y_over_q=y_over_q_criterion(x, yq_lp, start, end),
        raw_sum_y_N=raw_sum,
        sum_y=sum_y_criterion(x, sum_y, start, end, shift_limit, alpha, category),
        running_stability=stability,
        wheel_unloading=wheel_unloading_criterion(x, q_lp, q0, start, end),
        flange_climb=flange_climb_criterion(x, yq_lp, nadal, start, end),
        hunting=hunting,
        comfort=comfort,
        comfort_note=note,
    )


def _comfort(ts: TimeSeries, n: int, fs: float, inside) -> tuple[dict[str, PointComfort], str]:
    points = ts.measurement_points()
    if not points:
        return {}, "no accelerations recorded (columns <point>_acc_y_m_per_s2, _acc_z_m_per_s2)"
    out = {}
    for p in points:
        ay, az = f"{p}_acc_y_m_per_s2", f"{p}_acc_z_m_per_s2"
        out[p] = point_comfort(
            p,
            ts[ay][:n] if ay in ts else None,
            ts[az][:n] if az in ts else None,
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


# ----------------------------------------------------------------------------------------------
# summary.json
# ----------------------------------------------------------------------------------------------


def _jsonable(obj: Any) -> Any:
    """A JSON-serialisable copy: numpy scalars and arrays to Python, non-finite to None."""
    if hasattr(obj, "to_dict") and callable(obj.to_dict):
        return _jsonable(obj.to_dict())
    if isinstance(obj, Mapping):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_jsonable(v) for v in obj.tolist()]
    if isinstance(obj, bool | np.bool_):
        return bool(obj)
    if isinstance(obj, int | np.integer):
        return int(obj)
    if isinstance(obj, float | np.floating):
        return finite_or_none(obj)
    if isinstance(obj, Path):
        return str(obj)
    return obj


def write_summary(summary: Mapping[str, Any] | RunSummary, path: str | Path) -> Path:
    """Write ``summary`` (a :class:`RunSummary` or a dict) as JSON (indent 2); non-finite
    numbers become ``null``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(_jsonable(summary), indent=2, allow_nan=False)
    path.write_text(text + "\n", encoding="utf-8")
    return path


def read_summary(path: str | Path) -> dict:
    """Read a summary written by :func:`write_summary` (as a dict).

    Raises:
        ResultsError: naming the file, if it cannot be read or is not a JSON object.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ResultsError(f"{path}: cannot read summary: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise ResultsError(f"{path}: invalid JSON at line {exc.lineno}: {exc.msg}") from None
    if not isinstance(data, dict):
        raise ResultsError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data
