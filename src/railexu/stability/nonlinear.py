"""Nonlinear critical speed: bisection between a stable and an unstable run after a lateral
disturbance, and the ramp method (the speed at which a hunting limit cycle vanishes on a slow
deceleration). Amplitudes are half the peak-to-peak range (:func:`railexu.assessment.signals.
amplitude`)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.assessment.signals import amplitude
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.stability.settings import CriticalSpeedSettings
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle


def _lateral_amplitude(ts, fraction: float = 0.1) -> tuple[float, float, bool]:
    """Largest half peak-to-peak lateral motion of any wheelset over the last ``fraction`` of the
    distance, the same over the ``fraction`` before it, and whether the motion grows."""
    x = ts.distance_m
    end = x[-1]
    span = fraction * (end - x[0])
    last = x >= end - span
    before = (x >= end - 2 * span) & ~last
    a_last = a_before = 0.0
    for i in ts.wheelset_indices():
        y = ts[f"ws{i}_lateral_m"]
        a_last = max(a_last, amplitude(y[last]))
        a_before = max(a_before, amplitude(y[before]))
    return a_last, a_before, a_last > 1.05 * a_before


def nonlinear_run_is_stable(
    vehicle: Vehicle, track: Track, speed: float, settings: CriticalSpeedSettings
) -> dict:
    """One run after the lateral disturbance; stable when the lateral motion over the last
    10 % of the distance stays below the threshold and does not grow."""
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_m_per_s=speed,
            distance_m=settings.distance_m,
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
        ),
    )
    state = result.status["state"]
    if state not in COMPLETED_STATES:
        return {"speed_m_per_s": speed, "stable": False, "amplitude_m": None, "state": state,
                "reason": result.status["reason"]}  # fmt: skip
    amp, before, growing = _lateral_amplitude(result.timeseries)
    stable = amp < settings.threshold_m and not (growing and amp > 0.25 * settings.threshold_m)
    return {
        "speed_m_per_s": speed,
        "stable": bool(stable),
        "amplitude_m": amp,
        "previous_amplitude_m": before,
        "growing": bool(growing),
        "state": state,
    }


def bisection_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed by bisection between a stable and an unstable run."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    runs = []

    def test(v: float) -> bool:
        r = nonlinear_run_is_stable(vehicle, track, v, settings)
        runs.append(r)
        if progress:
            amp = r["amplitude_m"]
            amp_text = f"{amp * 1e3:.2f} mm" if amp is not None else r["state"]
            progress(f"bisection: {v:.2f} m/s -> {'stable' if r['stable'] else 'unstable'} "
                     f"({amp_text})")  # fmt: skip
        return r["stable"]

    lo, hi = settings.speed_min_m_per_s, settings.speed_max_m_per_s
    out = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "runs": runs,
        "threshold_m": settings.threshold_m,
        "initial_lateral_m": settings.initial_lateral_m,
    }
    if test(hi):
        out["stable_in_range"] = True
        out["note"] = f"stable up to the highest speed tested, {hi:g} m/s"
        return out
    if not test(lo):
        out["unstable_in_range"] = True
        out["note"] = f"unstable at every speed tested, down to {lo:g} m/s"
        return out
    while hi - lo > settings.tolerance_m_per_s:
        mid = 0.5 * (lo + hi)
        if test(mid):
            lo = mid
        else:
            hi = mid
    out["critical_speed_m_per_s"] = 0.5 * (lo + hi)
    out["bracket_m_per_s"] = [lo, hi]
    return out


def ramp_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed by the ramp method: settle into hunting at the top speed, then
    decelerate slowly; report the speed at which the limit cycle vanishes.

    The amplitude is taken per half period of the leading wheelset's lateral motion (between
    zero crossings); the critical speed is the speed at the end of the last half period whose
    amplitude exceeds the threshold.
    """
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    v0, v1 = settings.speed_max_m_per_s, settings.speed_min_m_per_s
    a = settings.ramp_deceleration_m_per_s2
    # settle at v0, then decelerate: one run, the deceleration starting after ramp_settle_m is
    # approximated by starting the ramp a little higher (same settle time at v0 + a t/2)
    t_settle = settings.ramp_settle_m / v0
    v_start = v0 + a * t_settle
    distance = (v_start**2 - v1**2) / (2.0 * a)
    if progress:
        progress(f"ramp: {v_start:.1f} -> {v1:.1f} m/s over {distance:.0f} m")
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_m_per_s=v_start,
            distance_m=distance,
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
            deceleration_m_per_s2=a,
        ),
    )
    ts = result.timeseries
    speed = ts["speed_m_per_s"]
    y = ts["ws1_lateral_m"]
    amplitude, at_speed = _half_period_amplitudes(y, speed)
    out = {
        "critical_speed_m_per_s": None,
        "start_speed_m_per_s": v_start,
        "end_speed_m_per_s": v1,
        "deceleration_m_per_s2": a,
        "state": result.status["state"],
        "threshold_m": settings.threshold_m,
        "speeds_m_per_s": at_speed.tolist(),
        "amplitude_m": amplitude.tolist(),
    }
    if result.status["state"] not in COMPLETED_STATES:
        out["note"] = f"the ramp run stopped: {result.status['reason']}"
        return out
    above = amplitude > settings.threshold_m
    if not np.any(above):
        out["note"] = f"no hunting at the start speed {v_start:g} m/s"
        return out
    if above[-1]:
        out["note"] = f"still hunting at the end of the ramp, {v1:g} m/s"
        out["unstable_in_range"] = True
        return out
    last = int(np.nonzero(above)[0][-1])
    out["critical_speed_m_per_s"] = float(at_speed[last])
    return out


def _half_period_amplitudes(y: np.ndarray, speed: np.ndarray):
    """The amplitude (:func:`~railexu.assessment.signals.amplitude`, half peak to peak) of each
    full period that ends at a sign change of ``y - mean``, and the speed at its end: one value
    per half period, each over the last full period."""
    centred = y - np.mean(y)
    sign = np.signbit(centred)
    cuts = np.nonzero(sign[1:] != sign[:-1])[0] + 1
    edges = np.concatenate([[0], cuts, [len(y)]])
    amps, speeds = [], []
    for i0, i1 in zip(edges[:-2], edges[2:], strict=True):
        if i1 - i0 < 3:
            continue
        amps.append(amplitude(y[i0:i1]))
        speeds.append(float(speed[i1 - 1]))
    return np.asarray(amps), np.asarray(speeds)
