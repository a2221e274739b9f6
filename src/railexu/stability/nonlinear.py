"""Nonlinear critical speed: the limit-cycle branch followed as speed falls (:func:`branch_
critical_speed`), bisection between a stable and an unstable run after a lateral disturbance,
and the ramp method (the speed at which a hunting limit cycle vanishes on a slow deceleration).

Every run is judged by the growth rate of its oscillation (:func:`classify_run`: the fitted
envelope of :func:`railexu.assessment.oscillation.fit_oscillation` over the last part of the
run), not by whether an amplitude threshold is reached within the run: a slowly growing
oscillation is unstable however small it still is at the end, a limit cycle of at least
``limit_cycle_floor_m`` is hunting, a decaying one is stable."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.assessment.oscillation import fit_oscillation
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


#: The classifications of :func:`classify_run` that mean "not stable": the oscillation grows,
#: or it neither grows nor decays (a limit cycle: hunting).
UNSTABLE_CLASSES = ("growing", "limit cycle")


def classify_run(ts, settings: CriticalSpeedSettings) -> dict:
    """Classify a run by the growth rate of its wheelsets' lateral oscillation.

    Each wheelset's lateral displacement over the last ``settings.fit_fraction`` of the run's
    time is fitted (:func:`~railexu.assessment.oscillation.fit_oscillation`, floor
    ``settings.floor_m``); the wheelset with the largest fitted amplitude decides:
    ``growing`` (more than 1 % amplitude growth per period), ``limit cycle`` (sustained: less
    than 1 % change per period), ``small limit cycle`` (sustained, but smaller than
    ``settings.limit_cycle_floor_m``: the small oscillation of a profile pair near its centre,
    not hunting; stable for the critical speed, railexu's assumption), ``decaying``, ``below
    floor`` or, for a motion that is not one oscillation (``broad-band``), ``large broad-band``
    above ``settings.threshold_m`` (an unstable, irregular motion) else ``broad-band``. Returns
    the classification, whether it is stable, the fitted ``amplitude_m`` (envelope at the
    end), ``growth_rate_per_s``, ``growth_per_period``, ``frequency_Hz``, the deciding
    ``wheelset`` and the fit's window."""
    t = ts.time_s
    start = t[0] + (1.0 - settings.fit_fraction) * (t[-1] - t[0])
    inside = t >= start
    best = None
    for i in ts.wheelset_indices():
        fit = fit_oscillation(t[inside], ts[f"ws{i}_lateral_m"][inside], settings.floor_m)
        if best is None or fit.amplitude > best[1].amplitude:
            best = (i, fit)
    if best is None:
        return {"classification": "no wheelsets", "stable": True}
    i, fit = best
    status = {"sustained": "limit cycle"}.get(fit.status, fit.status)
    if status == "limit cycle" and fit.amplitude < settings.limit_cycle_floor_m:
        status = "small limit cycle"
    if status == "broad-band" and fit.amplitude > settings.threshold_m:
        status = "large broad-band"
    unstable = status in (*UNSTABLE_CLASSES, "large broad-band")
    return {
        "classification": status,
        "stable": not unstable,
        "amplitude_m": fit.amplitude,
        "growth_rate_per_s": fit.growth_rate_per_s,
        "growth_per_period": fit.growth_per_period,
        "frequency_Hz": fit.frequency_Hz,
        "wheelset": f"ws{i}",
        "fit_window_s": list(fit.window_s) if fit.window_s else None,
    }


def _run_at(vehicle, track, speed: float, settings: CriticalSpeedSettings, offset_m: float):
    return run(
        vehicle,
        track,
        RunSettings(
            speed_m_per_s=speed,
            distance_m=settings.distance_m,
            initial_lateral_m=offset_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
        ),
    )


def nonlinear_run_is_stable(
    vehicle: Vehicle,
    track: Track,
    speed: float,
    settings: CriticalSpeedSettings,
    offset_m: float | None = None,
) -> dict:
    """One run of ``settings.distance_m`` after a lateral offset of the whole vehicle
    (``offset_m``, default ``settings.initial_lateral_m``), classified by :func:`classify_run`.
    A run that stops (derails, diverges) is unstable and says why."""
    offset = settings.initial_lateral_m if offset_m is None else offset_m
    result = _run_at(vehicle, track, speed, settings, offset)
    state = result.status["state"]
    base = {"speed_m_per_s": speed, "initial_lateral_m": offset, "state": state}
    if state not in COMPLETED_STATES:
        return {**base, "stable": False, "classification": state, "amplitude_m": None,
                "reason": result.status["reason"]}  # fmt: skip
    amp, before, growing = _lateral_amplitude(result.timeseries)
    return {
        **base,
        **classify_run(result.timeseries, settings),
        "final_half_peak_to_peak_m": amp,
        "previous_half_peak_to_peak_m": before,
    }


def _judgement(settings: CriticalSpeedSettings) -> str:
    return (
        f"each run {settings.distance_m:g} m; classified by the growth rate of the fitted "
        f"envelope of the wheelsets' lateral displacement over the last "
        f"{settings.fit_fraction:.0%} of the run's time (growing above "
        f"{settings.floor_m * 1e3:g} mm, or a limit cycle of at least "
        f"{settings.limit_cycle_floor_m * 1e3:g} mm: unstable; decaying, below "
        f"{settings.floor_m * 1e3:g} mm or a smaller limit cycle: stable; +-1 % per period "
        "counts as a limit cycle)"
    )


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
            progress(f"bisection: {v:.2f} m/s -> {_run_text(r)}")
        return r["stable"]

    lo, hi = settings.speed_min_m_per_s, settings.speed_max_m_per_s
    out = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "runs": runs,
        "threshold_m": settings.threshold_m,
        "initial_lateral_m": settings.initial_lateral_m,
        "disturbance": f"initial lateral offset of the whole vehicle, "
        f"{settings.initial_lateral_m * 1e3:g} mm",
        "judged_by": _judgement(settings),
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


def _run_text(r: dict) -> str:
    """``unstable (limit cycle, 2.10 mm, growth +0.001 /period, 3.1 Hz)``."""
    verdict = "stable" if r["stable"] else "unstable"
    if r.get("amplitude_m") is None:
        return f"{verdict} ({r['classification']})"
    text = f"{verdict} ({r['classification']}, {r['amplitude_m'] * 1e3:.2f} mm"
    if r.get("growth_per_period") is not None:
        text += f", growth {r['growth_per_period']:+.3f}/period, {r['frequency_Hz']:.2f} Hz"
    return text + ")"


def branch_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed from the limit-cycle branch, followed as speed falls.

    Stepwise continuation: at ``speed_max`` a run from the disturbance ``initial_lateral_m``
    settles; each lower speed (steps of ``branch_step_m_per_s``) starts from a lateral offset
    of the whole vehicle equal to the amplitude found at the speed above (at least
    ``initial_lateral_m / 4``), runs ``distance_m`` and is classified by the growth rate of its
    fitted envelope (:func:`classify_run`). Where the limit cycle is lost (the oscillation
    decays), the step is halved between the last speed with a limit cycle and the first without
    it, down to ``tolerance_m_per_s``. The nonlinear critical speed is the lowest speed with a
    limit cycle (or a growing oscillation). At most ``max_runs`` runs: a branch not closed
    within them says so (``converged`` False).

    Returns ``critical_speed_m_per_s``, ``bracket_m_per_s`` ([highest speed without, lowest
    with a limit cycle]), ``branch``: per run speed, classification, amplitude (fitted, of the
    deciding wheelset), growth rate, frequency and the offset it started from, ``converged``,
    ``note``, the disturbance and the judgement used. A restart from an offset of the whole
    vehicle is not the limit cycle's state itself: where a limit cycle exists, the run settles
    onto it within the distance run (checked by its growth rate)."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    points: list[dict] = []
    out = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "branch": points,
        "converged": False,
        "disturbance": f"initial lateral offset {settings.initial_lateral_m * 1e3:g} mm at "
        f"{settings.speed_max_m_per_s:g} m/s; each lower speed restarts from the amplitude found "
        "at the speed above",
        "judged_by": _judgement(settings),
        "max_runs": settings.max_runs,
    }

    def at(v: float, offset: float) -> dict:
        r = nonlinear_run_is_stable(vehicle, track, v, settings, offset)
        points.append(r)
        if progress:
            progress(f"branch: {v:.2f} m/s from {offset * 1e3:.2f} mm -> {_run_text(r)}")
        return r

    def next_offset(r: dict) -> float:
        amp = r.get("amplitude_m") or 0.0
        return max(amp, 0.25 * settings.initial_lateral_m)

    first = at(settings.speed_max_m_per_s, settings.initial_lateral_m)
    if first["stable"]:
        out["converged"] = True
        out["note"] = (f"no limit cycle at the highest speed, {settings.speed_max_m_per_s:g} m/s, "
                       "from this disturbance")  # fmt: skip
        return out
    hunting, offset = first, next_offset(first)
    v = settings.speed_max_m_per_s
    lost = None
    while len(points) < settings.max_runs:
        v_next = max(v - settings.branch_step_m_per_s, settings.speed_min_m_per_s)
        if v_next >= v:
            break
        r = at(v_next, offset)
        if r["stable"]:
            lost = r
            break
        hunting, offset, v = r, next_offset(r), v_next
    if lost is None:
        if v <= settings.speed_min_m_per_s:
            out["converged"] = True
            out["unstable_in_range"] = True
            out["note"] = f"a limit cycle down to the lowest speed, {v:g} m/s"
        else:
            out["note"] = (
                f"not converged: {settings.max_runs} runs used, still hunting at {v:g} m/s"
            )
        return out
    lo, hi = lost["speed_m_per_s"], hunting["speed_m_per_s"]
    while hi - lo > settings.tolerance_m_per_s and len(points) < settings.max_runs:
        r = at(0.5 * (lo + hi), offset)
        if r["stable"]:
            lo = r["speed_m_per_s"]
        else:
            hi, offset = r["speed_m_per_s"], next_offset(r)
    out["bracket_m_per_s"] = [lo, hi]
    out["critical_speed_m_per_s"] = hi
    out["converged"] = hi - lo <= settings.tolerance_m_per_s
    if not out["converged"]:
        out["note"] = (f"not converged: {settings.max_runs} runs used, bracket {lo:g} to "
                       f"{hi:g} m/s")  # fmt: skip
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
