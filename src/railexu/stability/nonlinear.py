"""Nonlinear critical speed by bisection between a stable and an unstable run after a lateral
disturbance, and the growth-rate classification that it, the limit-cycle branch
(:mod:`railexu.stability.branch`) and the ramp (:mod:`railexu.stability.ramp`) share.

Every run is judged by the growth rate of its oscillation (:func:`classify_run`: the fitted
envelope of :func:`railexu.assessment.oscillation.fit_oscillation` over the last part of the
run), not by whether an amplitude threshold is reached within the run: a slowly growing
oscillation is unstable however small it still is at the end, a sustained one (a limit cycle) is
unstable whatever its amplitude above the noise floor ``floor_m``, a decaying one is stable. No
verdict depends on ``limit_cycle_floor_m``: it only labels a cycle smaller than it ``small limit
cycle`` (below the run summary's hunting threshold), and the bisection says where such a bounded
small cycle exists instead of reporting where it crosses a threshold."""

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
#: or it neither grows nor decays (a limit cycle, of any amplitude above the floor).
UNSTABLE_CLASSES = ("growing", "limit cycle", "small limit cycle")
#: The classifications of a sustained oscillation (a limit cycle).
SUSTAINED_CLASSES = ("limit cycle", "small limit cycle")


def classify_run(ts, settings: CriticalSpeedSettings) -> dict:
    """Classify a run by the growth rate of its wheelsets' lateral oscillation.

    Each wheelset's lateral displacement over the last ``settings.fit_fraction`` of the run's
    time is fitted (:func:`~railexu.assessment.oscillation.fit_oscillation`, floor
    ``settings.floor_m``); the wheelset with the largest fitted amplitude decides:
    ``growing`` (more than 1 % amplitude growth per period), ``limit cycle`` (sustained: less
    than 1 % change per period), ``small limit cycle`` (sustained, but smaller than
    ``settings.limit_cycle_floor_m``: a label only, e.g. the small oscillation of a profile pair
    near its centre; unstable like every sustained cycle, so that no verdict moves with that
    floor), ``decaying``, ``below floor`` or, for a motion that is not one oscillation
    (``broad-band``), ``large broad-band`` above ``settings.threshold_m`` (an unstable,
    irregular motion) else ``broad-band``. Returns the classification, whether it is stable,
    the fitted ``amplitude_m`` (envelope at the end), ``growth_rate_per_s``,
    ``growth_per_period``, ``frequency_Hz``, the deciding ``wheelset`` and the fit's window."""
    t = ts.time_s
    start = t[0] + (1.0 - settings.fit_fraction) * (t[-1] - t[0])
    inside = t >= start
    signals = {f"ws{i}": ts[f"ws{i}_lateral_m"][inside] for i in ts.wheelset_indices()}
    return classify_window(t[inside], signals, settings)


def classify_window(t_s: np.ndarray, lateral_m: dict, settings: CriticalSpeedSettings) -> dict:
    """Classify the wheelsets' lateral displacements ``lateral_m`` (name -> values at the times
    ``t_s``, s) over their whole window by the growth rate of the fitted envelope; the rules
    and the returned entries are those of :func:`classify_run` (which calls this on the last
    ``fit_fraction`` of a run; the branch and ramp methods on windows of one run)."""
    best = None
    for name, y in lateral_m.items():
        fit = fit_oscillation(t_s, y, settings.floor_m)
        if best is None or fit.amplitude > best[1].amplitude:
            best = (name, fit)
    if best is None:
        return {"classification": "no wheelsets", "stable": True}
    name, fit = best
    status = {"sustained": "limit cycle"}.get(fit.status, fit.status)
    if status == "limit cycle" and fit.amplitude < settings.limit_cycle_floor_m:
        status = "small limit cycle"
    if status == "broad-band" and fit.amplitude > settings.threshold_m:
        status = "large broad-band"
    unstable = status in (*UNSTABLE_CLASSES, "large broad-band")
    if status == "too short":  # fewer than four periods: no verdict (module docstring)
        return {"classification": status, "stable": None, "amplitude_m": fit.amplitude,
                "growth_rate_per_s": None, "growth_per_period": None,
                "frequency_Hz": fit.frequency_Hz, "fit_periods": None, "wheelset": name,
                "fit_window_s": None}  # fmt: skip
    return {
        "classification": status,
        "stable": not unstable,
        "amplitude_m": fit.amplitude,
        "growth_rate_per_s": fit.growth_rate_per_s,
        "growth_per_period": fit.growth_per_period,
        "frequency_Hz": fit.frequency_Hz,
        "fit_periods": (t_s[-1] - t_s[0]) * fit.frequency_Hz if fit.frequency_Hz else None,
        "wheelset": name,
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
    base = {"speed_m_per_s": speed, "initial_lateral_m": offset, "state": state,
            "distance_m": settings.distance_m,
            "duration_s": settings.distance_m / speed}  # fmt: skip
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
        f"{settings.fit_fraction:.0%} of the run's time (growing, or sustained: a limit cycle "
        f"of any amplitude above the {settings.floor_m * 1e3:g} mm floor: unstable; decaying or "
        f"below {settings.floor_m * 1e3:g} mm: stable; cycles below "
        f"{settings.limit_cycle_floor_m * 1e3:g} mm are labelled small, the verdict does not "
        "depend on that label; +-1 % per period "
        "counts as a limit cycle; the fit resolves the growth to about 0.13 / N per period over "
        "N periods (fit_periods): at least 16 periods are needed for the 1 % band); the floors "
        "and the 1 % band are railexu's assumptions"
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
        if r["stable"] is None:
            raise _NoVerdictError(v)
        return r["stable"]

    out = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "runs": runs,
        "threshold_m": settings.threshold_m,
        "initial_lateral_m": settings.initial_lateral_m,
        "disturbance": f"initial lateral offset of the whole vehicle, "
        f"{settings.initial_lateral_m * 1e3:g} mm",
        "run_distance_m": settings.distance_m,
        "run_duration": f"{settings.distance_m:g} m per run, "
        f"{settings.distance_m / settings.speed_max_m_per_s:.2f} s at the highest speed to "
        f"{settings.distance_m / settings.speed_min_m_per_s:.2f} s at the lowest",
        "judged_by": _judgement(settings),
    }
    try:
        return _bisect(test, out, settings)
    except _NoVerdictError as exc:
        out["status"] = "no verdict"
        out["note"] = (
            f"the run at {exc.args[0]:.2f} m/s is too short to classify (its fit window holds "
            f"fewer than four periods): use a longer distance than {settings.distance_m:g} m"
        )
        return _with_cycles(out)


class _NoVerdictError(Exception):
    """A run too short for the classification (stops the bisection, which says so)."""


def _bisect(test: Callable[[float], bool], out: dict, settings: CriticalSpeedSettings) -> dict:
    """The bisection proper (:func:`bisection_critical_speed`)."""
    lo, hi = settings.speed_min_m_per_s, settings.speed_max_m_per_s
    if test(hi):
        out["stable_in_range"] = True
        out["note"] = f"stable up to the highest speed tested, {hi:g} m/s"
        return _with_cycles(out)
    if not test(lo):
        out["unstable_in_range"] = True
        out["note"] = f"unstable at every speed tested, down to {lo:g} m/s"
        return _with_cycles(out)
    while hi - lo > settings.tolerance_m_per_s:
        mid = 0.5 * (lo + hi)
        if test(mid):
            lo = mid
        else:
            hi = mid
    out["critical_speed_m_per_s"] = 0.5 * (lo + hi)
    out["bracket_m_per_s"] = [lo, hi]
    return _with_cycles(out)


def _with_cycles(out: dict) -> dict:
    """Adds what the runs at the verdict's edge ended on: ``sustained_cycles`` (every run that
    ended on a limit cycle: speed, amplitude, growth per period), ``critical_run`` (the lowest
    unstable run: its classification and amplitude) and, where the lowest unstable run is a
    sustained cycle, a sentence saying so: the verdict is the lowest speed at which a cycle is
    sustained (judged by its growth rate, not by a threshold crossing)."""
    runs = out["runs"]
    cycles = [
        {k: r.get(k) for k in ("speed_m_per_s", "amplitude_m", "growth_per_period", "frequency_Hz")}
        for r in runs
        if r.get("classification") in SUSTAINED_CLASSES
    ]
    out["sustained_cycles"] = sorted(cycles, key=lambda c: c["speed_m_per_s"])
    unstable = [r for r in runs if r.get("stable") is False]
    if not unstable:
        return out
    low = min(unstable, key=lambda r: r["speed_m_per_s"])
    out["critical_run"] = {k: low.get(k) for k in ("speed_m_per_s", "classification",
                                                   "amplitude_m", "growth_per_period")}  # fmt: skip
    if low.get("classification") in SUSTAINED_CLASSES and low.get("amplitude_m"):
        words = (
            f"the lowest unstable run ({low['speed_m_per_s']:.2f} m/s) ends on a sustained "
            f"cycle of {low['amplitude_m'] * 1e3:.2f} mm (growth "
            f"{low['growth_per_period']:+.3f}/period): a bounded cycle exists there; the verdict "
            "is where a cycle is sustained at all, whatever its amplitude"
        )
        out["note"] = f"{out['note']}; {words}" if out.get("note") else words
    return out


def _run_text(r: dict) -> str:
    """``unstable (limit cycle, 2.10 mm, growth +0.001 /period, 3.1 Hz)``."""
    verdict = {True: "stable", False: "unstable"}.get(r["stable"], "no verdict")
    if r.get("amplitude_m") is None:
        return f"{verdict} ({r['classification']})"
    text = f"{verdict} ({r['classification']}, {r['amplitude_m'] * 1e3:.2f} mm"
    if r.get("growth_per_period") is not None:
        text += f", growth {r['growth_per_period']:+.3f}/period, {r['frequency_Hz']:.2f} Hz"
    return text + ")"
