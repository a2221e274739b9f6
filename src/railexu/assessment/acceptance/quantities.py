"""The EN 14363:2016 quantities of one test section, from a run's time series.

:func:`section_values` evaluates every quantity over the section's evaluation window
``[section.evaluate_from_m, section.evaluate_to_m]`` of the distance travelled (the run-in
before it is left out). The signals are filtered over the whole record first (a filter started
at the window's edge would ring into it), then cut to the window. Each value comes with how it
was processed (:class:`Processing`: filter, window, statistic, clause).

Quantities (``values`` keys; forces in N, accelerations in m/s^2):

============================ ==================================================================
``Y_over_Q_2m``              99.85 % of the 2 m sliding means (0.5 m steps) of Y/Q, forces
                             low-passed at 20 Hz, flanging wheel positive; largest wheel
``sum_Y_2m``                 larger magnitude of the 0.15 % and 99.85 % values of the 2 m means
                             of sum Y (20 Hz); largest axle
``sum_Y_rms``                normal method, running stability: sum Y band-passed at
                             ``f0 +- 2 Hz``, largest rms over 100 m windows in 10 m steps (the
                             whole window if shorter: railexu); f0 the band of the largest rms
                             in 1-10 Hz (railexu, as for the bogie frame); largest axle
``Q_max``                    99.85 % of the wheel force Q (20 Hz); largest wheel
``Y_qst``                    curves: 50 % of the outer wheel's Y towards the curve centre
                             (20 Hz); largest wheelset (the rule of
                             :func:`railexu.simulation.curving.curving_statistics`)
``Q_qst``                    curves: 50 % of the outer wheel's Q (20 Hz); largest wheelset
``car_body_acc_y_max``       larger magnitude of the 0.15 % and 99.85 % values of the car body's
``car_body_acc_z_max``       lateral / vertical acceleration band-passed 0.4-10 Hz; largest
                             car-body point
``car_body_acc_y_rms``       rms over the window's length of the same band-passed accelerations
``car_body_acc_z_rms``
``car_body_acc_y_qst``       curves: 50 % of the car body's lateral acceleration low-passed at
                             20 Hz, positive towards the curve's centre
``bogie_frame_acc_y_max``    simplified method: largest magnitude of the bogie frame's lateral
                             acceleration low-passed at 10 Hz; largest bogie point
``bogie_frame_acc_y_rms``    simplified method: the same acceleration band-passed at
                             ``f0 +- 2 Hz``, largest rms over 100 m windows in 10 m steps (the
                             whole window if shorter: railexu); f0 the band of the largest rms
                             in 1-10 Hz (railexu)
============================ ==================================================================

The percentiles, filters and windows are those of the EN 14363 / UIC 518 processing table
(``docs/acceptance.md`` gives the sources). Which body is which (railexu's rule): the heaviest
body is the car body; the measurement points on any other body are on bogie frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from railexu.assessment.en14363 import (
    LOWPASS_HZ,
    PERCENTILE_MAX,
    PERCENTILE_MIN,
    PERCENTILE_QUASI_STATIC,
    SAFETY_STEP_M,
    SAFETY_WINDOW_M,
    SIDES,
    STABILITY_HALF_BAND_HZ,
    STABILITY_STEP_M,
    STABILITY_WINDOW_M,
    y_over_q_values,
)
from railexu.assessment.filters import bandpass, lowpass
from railexu.assessment.signals import percentile, uniform_time_axis, window_means, window_rms
from railexu.errors import InputError
from railexu.vehicle.vehicle import heaviest_body

if TYPE_CHECKING:
    from railexu.assessment.acceptance.programme import SectionSpec

FloatArray = np.ndarray
STANDARD = "EN 14363:2016"
#: EN 14363: car-body accelerations (ride characteristics) are band-passed 0.4 Hz to 10 Hz.
RIDE_BAND_HZ = (0.4, 10.0)
#: EN 14363 simplified method: the bogie frame's lateral acceleration is low-passed at 10 Hz.
BOGIE_LOWPASS_HZ = 10.0
#: railexu: band in which the bogie frame's oscillation frequency f0 is looked for, and the
#: step of the candidate f0 (a quarter of the +-2 Hz band's half width).
BOGIE_F0_SEARCH_HZ = (1.0, 10.0)
BOGIE_F0_STEP_HZ = 0.5
#: railexu: Y/Q is evaluated only where Q exceeds this fraction of the static wheel load (as
#: railexu.results.evaluate.MIN_LOAD_FRACTION).
MIN_LOAD_FRACTION = 0.05


@dataclass(frozen=True)
class Processing:
    """How one value was formed: the filter, the window, the statistic and the clause."""

    filter: str
    window: str
    statistic: str
    clause: str
    where: str | None = None

    def to_dict(self) -> dict:
        return {"filter": self.filter, "window": self.window, "statistic": self.statistic,
                "clause": self.clause, "where": self.where}  # fmt: skip


@dataclass(frozen=True)
class SectionValues:
    """Every quantity of one section.

    Attributes:
        section: the section's conditions.
        values: quantity name -> value (SI; NaN when it could not be evaluated).
        units: quantity name -> unit.
        processing: quantity name -> :class:`Processing`.
        window_m: the evaluation window ``(from, to)`` in distance travelled (m).
        conditions: the section's conditions as run: ``cant_deficiency_m`` (the median of the
            recorded ``cant_deficiency_m`` column in the window if recorded, else the
            programme's), ``radius_m``, ``speed_m_per_s`` (median of ``speed_m_per_s`` if
            recorded), ``speed_capped`` (the section runs at the zone's maximum test speed)
            and ``transition_m`` (its entry transition, m).
        notes: quantities not evaluated, and why.
    """

    section: SectionSpec
    values: dict[str, float]
    units: dict[str, str]
    processing: dict[str, Processing]
    window_m: tuple[float, float]
    conditions: dict[str, Any] = field(default_factory=dict)
    notes: dict[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The JSON form: the section's name, window, conditions, values (None for NaN),
        units, processing and notes."""
        return {
            "section": self.section.name,
            "window_m": list(self.window_m),
            "conditions": dict(self.conditions),
            "values": {k: (v if math.isfinite(v) else None) for k, v in self.values.items()},
            "units": dict(self.units),
            "processing": {k: p.to_dict() for k, p in self.processing.items()},
            "notes": dict(self.notes),
        }

    def regressors(self, names: tuple[str, ...] | list[str]) -> list[float]:
        """The section's conditions ``cant_deficiency`` (m) and ``curvature`` (1/m) by name."""
        out = []
        for name in names:
            if name == "cant_deficiency":
                out.append(float(self.conditions["cant_deficiency_m"]))
            elif name == "curvature":
                radius = self.conditions.get("radius_m")
                out.append(0.0 if not radius else 1.0 / float(radius))
            else:
                raise ValueError(f"unknown regressor {name!r}")
        return out


class _Signals:
    """The record on a uniform time grid, with the window's mask."""

    def __init__(self, ts, names: list[str], window: tuple[float, float]) -> None:
        t, fs, resampled = uniform_time_axis(ts["time_s"], ts["distance_m"],
                                             *(ts[n] for n in names))  # fmt: skip
        self.fs_Hz = fs
        self.x = resampled[0]
        self.raw = dict(zip(names, resampled[1:], strict=True))
        self.inside = (self.x >= window[0]) & (self.x <= window[1])
        self.window = window

    def low(self, name: str, cutoff_Hz: float = LOWPASS_HZ) -> FloatArray:
        return lowpass(self.raw[name], self.fs_Hz, cutoff_Hz)

    def cut(self, values: FloatArray) -> FloatArray:
        return values[self.inside]


def section_values(ts, vehicle, section: SectionSpec) -> SectionValues:
    """Every EN 14363 quantity of one section (see the module doc).

    Args:
        ts: the section run's :class:`railexu.simulation.timeseries.TimeSeries`.
        vehicle: the :class:`railexu.vehicle.Vehicle` (measurement points, bodies, loads).
        section: the section's conditions and evaluation window.

    Raises:
        InputError: the window holds fewer than two samples or lies outside the record, or the
            series lacks the wheel forces.
    """
    window = (float(section.evaluate_from_m), float(section.evaluate_to_m))
    wheelsets = ts.wheelset_indices()
    forces = [f"ws{i}_{s}_{q}_N" for i in wheelsets for s in SIDES for q in ("Y", "Q")]
    missing = [n for n in forces if n not in ts]
    if not wheelsets or missing:
        raise InputError(f"section {section.name}: the time series lacks the wheel forces "
                         f"{', '.join(missing[:4]) or '(no wheelsets)'}")  # fmt: skip
    car, bogies = _points(vehicle, ts)
    accel = [f"{p}_acc_{d}_m_per_s2" for p in car + bogies for d in ("y", "z")]
    sig = _Signals(ts, forces + [n for n in accel if n in ts], window)
    n_inside = int(np.count_nonzero(sig.inside))
    if n_inside < 2 or window[1] > float(sig.x[-1]) + 1e-6 or window[0] < float(sig.x[0]) - 1e-6:
        raise InputError(
            f"section {section.name}: evaluation window {window[0]:g}-{window[1]:g} m does not "
            f"lie within the record ({float(sig.x[0]):g}-{float(sig.x[-1]):g} m)"
        )
    out = _Builder()
    q0 = static_wheel_load_N(vehicle)
    _wheel_forces(out, sig, wheelsets, q0, section)
    _sum_y_stability(out, sig, wheelsets)
    _car_body(out, sig, [p for p in car if f"{p}_acc_y_m_per_s2" in ts], section)
    _bogie_frames(out, sig, [p for p in bogies if f"{p}_acc_y_m_per_s2" in ts])
    return SectionValues(section, out.values, out.units, out.processing, window,
                         _conditions(ts, section, window), out.notes)  # fmt: skip


def static_wheel_load_N(vehicle) -> float:
    """``Q0``: the vehicle's weight over its wheels (N): the declared axle loads' mean over two
    if every wheelset declares one, else ``total mass g / (2 n_wheelsets)``."""
    declared = [ws.axle_load_N for ws in vehicle.wheelsets]
    if declared and all(d is not None for d in declared):
        return 0.5 * float(np.mean(declared))
    return vehicle.total_mass_kg * vehicle.gravity_m_per_s2 / (2.0 * len(vehicle.wheelsets))


def car_body_name(vehicle) -> str | None:
    """The car body: the heaviest body (railexu's rule, :attr:`Vehicle.car_body`), None if the
    vehicle has no body."""
    return heaviest_body(vehicle.bodies)


def bogie_mass_kg(vehicle) -> float | None:
    """Mass of one bogie for the simplified method's limit (kg): the mean mass of the bodies
    other than the car body plus their share of the wheelsets (railexu's rule); None if the
    vehicle has no such body."""
    car = car_body_name(vehicle)
    frames = [b.mass_kg for b in vehicle.bodies if b.name != car]
    if not frames:
        return None
    wheelsets = sum(ws.mass_kg for ws in vehicle.wheelsets)
    return float(np.mean(frames)) + wheelsets / len(frames)


class _Builder:
    def __init__(self) -> None:
        self.values: dict[str, float] = {}
        self.units: dict[str, str] = {}
        self.processing: dict[str, Processing] = {}
        self.notes: dict[str, str] = {}

    def add(self, name: str, value: float | None, unit: str, how: Processing) -> None:
        self.values[name] = math.nan if value is None else float(value)
        self.units[name] = unit
        self.processing[name] = how

    def skip(self, name: str, unit: str, note: str) -> None:
        self.values[name] = math.nan
        self.units[name] = unit
        self.notes[name] = note


def _largest(candidates: dict[str, float | None]) -> tuple[float | None, str | None]:
    best: tuple[float | None, str | None] = (None, None)
    for where, value in candidates.items():
        if value is not None and math.isfinite(value) and (best[0] is None or value > best[0]):
            best = (value, where)
    return best


def _both_tails(values: FloatArray) -> float | None:
    hi, lo = percentile(values, PERCENTILE_MAX), percentile(values, PERCENTILE_MIN)
    return None if hi is None or lo is None else max(abs(hi), abs(lo))


def _wheel_forces(out: _Builder, sig: _Signals, wheelsets: list[int], q0: float, section) -> None:
    low = {n: sig.low(n) for n in sig.raw if n.endswith("_Y_N") or n.endswith("_Q_N")}
    lo, hi = sig.window
    ratio, total, peak = {}, {}, {}
    for i in wheelsets:
        for s in SIDES:
            yq = y_over_q_values(low[f"ws{i}_{s}_Y_N"], low[f"ws{i}_{s}_Q_N"], s,
                                 MIN_LOAD_FRACTION * q0)  # fmt: skip
            ratio[f"ws{i}_{s}"] = percentile(
                window_means(sig.x, yq, SAFETY_WINDOW_M, SAFETY_STEP_M, lo, hi)[1], PERCENTILE_MAX
            )
            peak[f"ws{i}_{s}"] = percentile(sig.cut(low[f"ws{i}_{s}_Q_N"]), PERCENTILE_MAX)
        sum_y = low[f"ws{i}_left_Y_N"] + low[f"ws{i}_right_Y_N"]
        total[f"ws{i}"] = _both_tails(
            window_means(sig.x, sum_y, SAFETY_WINDOW_M, SAFETY_STEP_M, lo, hi)[1]
        )
    f20 = f"Butterworth low pass {LOWPASS_HZ:g} Hz (zero phase)"
    means = f"{SAFETY_WINDOW_M:g} m sliding means in {SAFETY_STEP_M:g} m steps"
    value, where = _largest(ratio)
    out.add("Y_over_Q_2m", value, "1", Processing(
        f20, means, f"{PERCENTILE_MAX:g} % value, flanging wheel positive, largest wheel",
        f"{STANDARD}, running safety: derailment quotient", where))  # fmt: skip
    value, where = _largest(total)
    out.add("sum_Y_2m", value, "N", Processing(
        f20, means, f"larger magnitude of the {PERCENTILE_MIN:g} % and {PERCENTILE_MAX:g} % "
        "values, largest axle", f"{STANDARD}, running safety: track-shifting force",
        where))  # fmt: skip
    value, where = _largest(peak)
    out.add("Q_max", value, "N", Processing(
        f20, "the section's samples", f"{PERCENTILE_MAX:g} % value, largest wheel",
        f"{STANDARD}, track loading: maximum wheel force", where))  # fmt: skip
    if section.direction is None:
        for name in ("Y_qst", "Q_qst"):
            out.skip(name, "N", "straight track: no quasi-static curving force")
        return
    inward = 1.0 if section.direction == "left" else -1.0
    outer = "right" if section.direction == "left" else "left"
    yq = {f"ws{i}_{outer}": percentile(sig.cut(inward * low[f"ws{i}_{outer}_Y_N"]),
                                       PERCENTILE_QUASI_STATIC) for i in wheelsets}  # fmt: skip
    qq = {f"ws{i}_{outer}": percentile(sig.cut(low[f"ws{i}_{outer}_Q_N"]),
                                       PERCENTILE_QUASI_STATIC) for i in wheelsets}  # fmt: skip
    for name, cand, what in (("Y_qst", yq, "guiding force Y towards the curve centre"),
                             ("Q_qst", qq, "wheel force Q")):  # fmt: skip
        value, where = _largest(cand)
        out.add(name, value, "N", Processing(
            f20, "the section's samples",
            f"{PERCENTILE_QUASI_STATIC:g} % value of the outer wheel's {what}, largest wheelset",
            f"{STANDARD}, track loading: quasi-static {what.split(' ')[0]} force",
            where))  # fmt: skip


def _sum_y_stability(out: _Builder, sig: _Signals, wheelsets: list[int]) -> None:
    """``sum_Y_rms``: EN 14363's instability criterion of the normal measuring method, the
    axle's sum Y (unfiltered but for the band) band-passed at ``f0 +- 2 Hz`` and its sliding rms
    (as :func:`railexu.assessment.en14363.running_stability_criterion`, but with f0 the band of
    the largest rms, the rule of the bogie frame's ``s(y+)``: no detected frequency needed)."""
    rms, bands = {}, {}
    for i in wheelsets:
        found = _worst_band_rms(sig, sig.raw[f"ws{i}_left_Y_N"] + sig.raw[f"ws{i}_right_Y_N"])
        if found is not None:
            rms[f"ws{i}"], bands[f"ws{i}"] = found
    value, where = _largest(rms)
    if value is None:
        out.skip("sum_Y_rms", "N", _NO_BAND)
        return
    out.add("sum_Y_rms", value, "N", Processing(
        _band_text(bands[where]), _SLIDING_RMS, "largest rms, largest axle",
        f"{STANDARD}, normal measuring method: running stability (instability criterion)",
        where))  # fmt: skip


_NO_BAND = (f"no band f0 +- 2 Hz with f0 in {BOGIE_F0_SEARCH_HZ[0]:g}-{BOGIE_F0_SEARCH_HZ[1]:g} "
            "Hz fits below the Nyquist frequency")  # fmt: skip
_SLIDING_RMS = (f"{STABILITY_WINDOW_M:g} m sliding rms in {STABILITY_STEP_M:g} m steps (the "
                "whole window if shorter: railexu)")  # fmt: skip


def _band_text(edges: tuple[float, float]) -> str:
    return (f"Butterworth band pass f0 +- {STABILITY_HALF_BAND_HZ:g} Hz, f0 the band of the "
            f"largest rms in {BOGIE_F0_SEARCH_HZ[0]:g}-{BOGIE_F0_SEARCH_HZ[1]:g} Hz "
            f"({BOGIE_F0_STEP_HZ:g} Hz steps, railexu): {edges[0]:.2f}-{edges[1]:.2f} Hz "
            "(zero phase)")  # fmt: skip


def _car_body(out: _Builder, sig: _Signals, points: list[str], section) -> None:
    names = [f"car_body_acc_{d}_{s}" for d in "yz" for s in ("max", "rms")]
    names.append("car_body_acc_y_qst")
    if not points:
        for n in names:
            out.skip(n, "m/s^2", "no acceleration recorded at a point on the car body")
        return
    band = f"Butterworth band pass {RIDE_BAND_HZ[0]:g}-{RIDE_BAND_HZ[1]:g} Hz (zero phase)"
    clause = f"{STANDARD}, normal measuring method: ride characteristics"
    for d in "yz":
        peaks, rms = {}, {}
        for p in points:
            name = f"{p}_acc_{d}_m_per_s2"
            if name not in sig.raw:
                continue
            a = sig.cut(bandpass(sig.raw[name], sig.fs_Hz, *RIDE_BAND_HZ))
            peaks[p] = _both_tails(a)
            rms[p] = _rms_over(sig.cut(sig.x), a)
        value, where = _largest(peaks)
        out.add(f"car_body_acc_{d}_max", value, "m/s^2", Processing(
            band, "the section's samples", f"larger magnitude of the {PERCENTILE_MIN:g} % and "
            f"{PERCENTILE_MAX:g} % values, largest car-body point", clause, where))  # fmt: skip
        value, where = _largest(rms)
        out.add(f"car_body_acc_{d}_rms", value, "m/s^2", Processing(
            band, "the section's samples", "rms, largest car-body point", clause,
            where))  # fmt: skip
    if section.direction is None:
        out.skip("car_body_acc_y_qst", "m/s^2", "straight track: no quasi-static acceleration")
        return
    # the accelerometer's specific force points to the curve's centre (to the left in a left
    # curve, docs/conventions.md): the uncompensated lateral acceleration, positive inwards
    inward = 1.0 if section.direction == "left" else -1.0
    qst = {p: percentile(sig.cut(inward * sig.low(f"{p}_acc_y_m_per_s2")),
                         PERCENTILE_QUASI_STATIC) for p in points}  # fmt: skip
    value, where = _largest(qst)
    out.add("car_body_acc_y_qst", value, "m/s^2", Processing(
        f"Butterworth low pass {LOWPASS_HZ:g} Hz (zero phase)", "the section's samples",
        f"{PERCENTILE_QUASI_STATIC:g} % value, positive towards the curve's centre "
        "(uncompensated), "
        "largest car-body point", clause, where))  # fmt: skip


def _bogie_frames(out: _Builder, sig: _Signals, points: list[str]) -> None:
    if not points:
        for n in ("bogie_frame_acc_y_max", "bogie_frame_acc_y_rms"):
            out.skip(n, "m/s^2", "no lateral acceleration recorded at a point on a bogie frame")
        return
    clause = f"{STANDARD}, simplified measuring method: bogie frame lateral acceleration"
    peaks, rms, bands = {}, {}, {}
    for p in points:
        raw = sig.raw[f"{p}_acc_y_m_per_s2"]
        peak = sig.cut(lowpass(raw, sig.fs_Hz, BOGIE_LOWPASS_HZ))
        peaks[p] = float(np.max(np.abs(peak))) if peak.size else None
        found = _worst_band_rms(sig, raw)
        if found is not None:
            rms[p], bands[p] = found
    value, where = _largest(peaks)
    out.add("bogie_frame_acc_y_max", value, "m/s^2", Processing(
        f"Butterworth low pass {BOGIE_LOWPASS_HZ:g} Hz (zero phase)", "the section's samples",
        "largest magnitude, largest bogie point", clause, where))  # fmt: skip
    value, where = _largest(rms)
    if value is None:
        out.skip("bogie_frame_acc_y_rms", "m/s^2", _NO_BAND)
        return
    out.add("bogie_frame_acc_y_rms", value, "m/s^2", Processing(
        _band_text(bands[where]), _SLIDING_RMS, "largest rms, largest bogie point", clause,
        where))  # fmt: skip


def _worst_band_rms(sig: _Signals, raw: FloatArray) -> tuple[float, tuple[float, float]] | None:
    """The largest rms of ``raw`` band-passed at ``f0 +- 2 Hz`` over the candidate ``f0`` of
    :data:`BOGIE_F0_SEARCH_HZ` (in :data:`BOGIE_F0_STEP_HZ` steps), and its band; None if no
    band fits below the Nyquist frequency. railexu's rule for f0: the frequency of the largest
    periodogram peak jumps between the bins of a flat spectrum (a stable bogie excited by
    irregularities: 9.5 Hz at one step, 2.8 Hz at half of it), the largest rms over the
    bands does not (a continuous function of the signal) and is the peak's band for an
    oscillating bogie."""
    lo, hi = sig.window
    best = None
    for f0 in np.arange(BOGIE_F0_SEARCH_HZ[0], BOGIE_F0_SEARCH_HZ[1] + 1e-9, BOGIE_F0_STEP_HZ):
        edges = (max(float(f0) - STABILITY_HALF_BAND_HZ, 0.5), float(f0) + STABILITY_HALF_BAND_HZ)
        if not sig.fs_Hz > 2.0 * edges[1]:
            break
        filtered = bandpass(raw, sig.fs_Hz, *edges)
        if hi - lo >= STABILITY_WINDOW_M:
            values = window_rms(sig.x, filtered, STABILITY_WINDOW_M, STABILITY_STEP_M, lo, hi)[1]
            value = float(np.nanmax(values)) if values.size else None
        else:
            value = _rms_over(sig.cut(sig.x), sig.cut(filtered))
        if value is not None and (best is None or value > best[0]):
            best = (value, edges)
    return best


def _rms_over(x: FloatArray, a: FloatArray) -> float | None:
    """Root mean square over the distance (trapezoid rule: the signal piecewise linear)."""
    span = float(x[-1] - x[0]) if x.size > 1 else 0.0
    if span <= 0.0:
        return None
    return math.sqrt(float(np.sum(0.5 * (a[1:] ** 2 + a[:-1] ** 2) * np.diff(x))) / span)


def _points(vehicle, ts) -> tuple[list[str], list[str]]:
    """Measurement points recorded in ``ts``: those on the car body and those on other bodies."""
    car = car_body_name(vehicle)
    recorded = set(ts.measurement_points())
    on_car = [p.name for p in vehicle.measurement_points if p.body == car and p.name in recorded]
    others = [p.name for p in vehicle.measurement_points if p.body != car and p.name in recorded]
    return on_car, others


def _conditions(ts, section, window: tuple[float, float]) -> dict[str, Any]:
    x = ts["distance_m"]
    inside = (x >= window[0]) & (x <= window[1])
    out: dict[str, Any] = {
        "radius_m": section.radius_m,
        "cant_m": section.cant_m,
        "cant_deficiency_m": section.cant_deficiency_m,
        "speed_m_per_s": section.speed_m_per_s,
        "speed_capped": section.speed_capped,  # at the zone's maximum test speed
        "transition_m": section.transition_m,  # the entry transition before the run-in
        "source": "programme",
    }
    if "cant_deficiency_m" in ts and np.any(inside):
        out["cant_deficiency_m"] = float(np.median(ts["cant_deficiency_m"][inside]))
        out["source"] = "recorded cant_deficiency_m (median over the window)"
    if "speed_m_per_s" in ts and np.any(inside):
        out["speed_m_per_s"] = float(np.median(ts["speed_m_per_s"][inside]))
    return out
