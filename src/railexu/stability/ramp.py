"""The ramp method of the nonlinear critical speed, judged by growth rate and shown at two rates
(:func:`ramp_critical_speed`).

One run settles into hunting at the top speed (``ramp_settle_m`` after the disturbance
``initial_lateral_m``) and then decelerates at a constant rate; the run is cut into windows of
:data:`WINDOW_PERIODS` hunting periods (the frequency measured on the plateau), half a window
apart, and each window is classified by the growth rate of the wheelsets' fitted envelope
(:func:`~railexu.stability.nonlinear.classify_window`: the same rules as every run of the
bisection and branch methods, no fixed amplitude threshold). The critical speed of one ramp is
the speed at the end of the last window that is not stable (a limit cycle of at least
``limit_cycle_floor_m`` or a growing oscillation) with only stable windows after it: where the
limit cycle vanishes for good. Its resolution is the speed lost over one window
(deceleration x window length).

A ramp that is too fast lags behind the branch: on a ramp the cycle's amplitude follows the
branch, which shrinks as speed falls, and a window is "sustained" only while that drift is below
the classification's 1 % per period. The drift per period is ``(d ln A / dV) a / f`` (A the
amplitude, f the frequency, a the deceleration), so the default deceleration
(:data:`DEFAULT_DECELERATION_M_PER_S2`, 0.2 m/s^2) follows from the rule ``a <= 0.01 f / (d ln
A / dV)`` with f >= 3 Hz and a branch slope d ln A / dV up to 0.15 per m/s (the EU07 bogie's
large cycle, docs/validation.md): the speed lost over one window of 16 periods is then at most
16 a / f = 1.07 m/s. Each ramp measures its branch's local slope from its windows and reports
the largest drift per period (``drift_per_period`` at ``drift_speed_m_per_s``,
``drift_within_band``) with the largest deceleration that keeps it in the band there
(``max_deceleration_m_per_s2``).

The method runs the ramp at ``ramp_deceleration`` and, to show the result rate-independent, at
:data:`FASTER` times it (or at it divided by :data:`FASTER` where twice would pass the steepest
deceleration allowed, 5 m/s^2). Each ramp reports where its last sustained window ends and
where the cycle it follows from the plateau ends (``fold_m_per_s``: the end of the window above
the steepest fall of the amplitude, :func:`_steepest_fall`; whether that fall is a
discontinuity is the branch method's verdict, :mod:`railexu.stability.fold`). The method's
results are those speeds where the two ramps agree within the sum of their resolutions (the
slower ramp's value); where they do not, the result is ``rate-dependent``: no verdict, with
both values (:func:`rate_verdicts`). Every ramp has a distance
budget (``ramp_budget``): a ramp that would run further is cut at its budget and says so
(``budget exhausted``), it never runs on."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.operation.speed_profile import SpeedProfile
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.stability.fold import largest_fall
from railexu.stability.nonlinear import _judgement, classify_window
from railexu.stability.settings import MAX_DECELERATION_M_PER_S2, CriticalSpeedSettings
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle

#: Length of a classification window in hunting periods (railexu's choice, from the fit's own
#: error on steady sines sampled at 100 Hz: +-1.6 % per period over 8 periods, depending on the
#: phase, 0.3 % over 16; the classification's tolerance is 1 % per period).
WINDOW_PERIODS = 16.0
#: The second ramp's deceleration as a multiple of the first's (the check of rate
#: independence).
FASTER = 2.0
#: The default deceleration [m/s^2] (module docstring: the 1 % per period drift rule).
DEFAULT_DECELERATION_M_PER_S2 = 0.2
#: The largest drift of the branch's amplitude per period within the classification's band.
MAX_DRIFT_PER_PERIOD = 0.01
#: Window length when the plateau shows no oscillation to measure a frequency on [s].
DEFAULT_WINDOW_S = 2.0


def ramp_profile(v_max: float, v_min: float, a: float, settle_m: float, budget_m: float):
    """``(profile, distance_m, end_speed_m_per_s, cut)``: ``settle_m`` at ``v_max``, then a
    deceleration ``a`` to ``v_min``, cut at ``budget_m`` in all (``cut`` True)."""
    full = settle_m + (v_max**2 - v_min**2) / (2.0 * a)
    distance = min(full, budget_m)
    cut = full > budget_m + 1e-9
    v_end = float(np.sqrt(max(v_max**2 - 2.0 * a * (distance - settle_m), 0.0))) if cut else v_min
    if distance <= settle_m:
        return SpeedProfile(((0.0, v_max),)), distance, v_max, True
    points = ((0.0, v_max), (settle_m, v_max), (distance, v_end)) if settle_m > 0 else (
        (0.0, v_max), (distance, v_end))  # fmt: skip
    return SpeedProfile(points), distance, v_end, cut


def classify_ramp(ts, settle_m: float, a: float, settings: CriticalSpeedSettings) -> dict:
    """Classify a ramp run's windows (module docstring); returns the plateau's classification,
    the window length, per window its end speed, fitted amplitude, growth per period and
    classification, and the critical speed with its resolution (None where the cycle did not
    vanish within the run, or there was none at the start)."""
    t, x = ts.time_s, ts.distance_m
    names = [f"ws{i}" for i in ts.wheelset_indices()]
    lateral = {n: ts[f"{n}_lateral_m"] for n in names}
    speed = ts["speed_m_per_s"]
    on_plateau = x <= settle_m + 1e-9
    t_settle = t[on_plateau][-1] if np.any(on_plateau) else t[0]
    start = t[0] + (1.0 - settings.fit_fraction) * (t_settle - t[0])
    sel = (t >= start) & (t <= t_settle)
    plateau = classify_window(t[sel], {n: y[sel] for n, y in lateral.items()}, settings)
    if plateau.get("frequency_Hz") is None:  # too short for the fit: the whole plateau
        sel = t <= t_settle
        plateau = classify_window(t[sel], {n: y[sel] for n, y in lateral.items()}, settings)
    f = plateau.get("frequency_Hz")
    window = WINDOW_PERIODS / f if f else DEFAULT_WINDOW_S
    out = {"plateau": plateau, "window_s": window, "resolution_m_per_s": a * window,
           "windows": [], "critical_speed_m_per_s": None}  # fmt: skip
    t0 = t_settle
    while t0 + window <= t[-1] + 1e-9:
        sel = (t >= t0) & (t <= t0 + window)
        c = classify_window(t[sel], {n: y[sel] for n, y in lateral.items()}, settings)
        end = int(np.nonzero(sel)[0][-1])
        out["windows"].append({"speed_m_per_s": float(speed[end]), **c})
        t0 += 0.5 * window
    out.update(_drift(out["windows"], plateau, a))
    unstable = [k for k, w in enumerate(out["windows"]) if not w["stable"]]
    if not out["windows"]:
        out["note"] = (f"the ramp is shorter than one window ({window:.2f} s, "
                       f"{WINDOW_PERIODS:g} periods): nothing to classify")  # fmt: skip
    elif plateau["stable"] and not unstable:
        out["note"] = "no hunting at the start speed"
    elif unstable and unstable[-1] == len(out["windows"]) - 1:
        out["note"] = "still hunting at the end of the ramp"
    elif unstable:
        out["critical_speed_m_per_s"] = out["windows"][unstable[-1]]["speed_m_per_s"]
    else:
        out["note"] = "the cycle vanished before the ramp's first window"
        out["critical_speed_m_per_s"] = float(speed[np.searchsorted(t, t_settle)])
    return out


def _window_amplitude(w: dict) -> float:
    """A window's fitted amplitude [m] where it holds one oscillation, else 0 (below the floor,
    broad-band): the classification does not matter (a ramp too fast for its branch calls its
    windows decaying, and their amplitudes still show the branch)."""
    fitted = bool(w.get("amplitude_m") and w.get("frequency_Hz")) and w.get(
        "classification") not in ("below floor", "broad-band", "large broad-band")  # fmt: skip
    return float(w["amplitude_m"]) if fitted else 0.0


def _steepest_fall(windows: list[dict]) -> int | None:
    """Index of the window above the largest fall of the amplitude from one window to the next
    (:func:`~railexu.stability.fold.largest_fall`): where the cycle followed from the plateau
    ends on this ramp; None where it never falls."""
    return largest_fall([_window_amplitude(w) for w in windows])


def _segments(windows: list[dict]) -> list[list[dict]]:
    """The ramp's windows split into runs of continuous amplitude: a run breaks at the steepest
    fall (:func:`_steepest_fall`, the fold) and where no oscillation is fitted. Above the fall
    every fitted window counts (the branch followed from the plateau: a ramp too fast for it
    calls its windows decaying); below it only windows on a cycle (not stable: the decay
    after the fold is the motion's way to another attractor, not a branch). A ramp too short
    to leave two windows on a side of its steepest fall is not split (its one fall is the
    branch's slope or the fold: the drift it gives is an upper bound)."""
    split = _split(windows, _steepest_fall(windows))
    return split or _split(windows, None)


def _split(windows: list[dict], fall: int | None) -> list[list[dict]]:
    out: list[list[dict]] = [[]]
    for k, w in enumerate(windows):
        below = fall is not None and k > fall
        ok = _window_amplitude(w) > 0.0 and (not below or w.get("stable") is False)
        if not ok or (fall is not None and k == fall + 1):
            out.append([])
        if ok:
            out[-1].append(w)
    return [seg for seg in out if len(seg) > 1]


#: The local slope of the branch is the running median of this many window-to-window slopes
#: (robust against the one or two windows that overlap a fold).
LOCAL_SLOPES = 5


def _drift(windows: list[dict], plateau: dict, a: float) -> dict:
    """``fold_m_per_s`` (the end speed of the window above the steepest fall of the amplitude,
    :func:`_steepest_fall`; None when it never falls or no cycle is sustained above it: the
    plateau, or a window down to the fall, not stable) and the drift of the branch's amplitude
    on this ramp: within each run of continuous amplitude (:func:`_segments`) the
    local slope d ln A / dV is the running median of :data:`LOCAL_SLOPES` window-to-window
    slopes; where it is steepest the ramp reports ``branch_slope_per_m_per_s``,
    ``drift_speed_m_per_s``, ``drift_per_period`` (|slope| x a / f: the relative change of the
    branch's amplitude per period), ``drift_within_band`` (at most
    :data:`MAX_DRIFT_PER_PERIOD`) and ``max_deceleration_m_per_s2`` (the rate that keeps it
    there)."""
    out: dict = {"fold_m_per_s": None, "drift_per_period": None}
    fall = _steepest_fall(windows)
    cycle_above = fall is not None and (
        plateau.get("stable") is False or any(w["stable"] is False for w in windows[: fall + 1])
    )
    if cycle_above:
        out["fold_m_per_s"] = windows[fall]["speed_m_per_s"]
    worst = None
    for seg in _segments(windows):
        v = np.array([w["speed_m_per_s"] for w in seg])
        ln_a = np.log([w["amplitude_m"] for w in seg])
        f = np.array([w["frequency_Hz"] for w in seg])
        dv = np.diff(v)
        slopes = np.where(dv != 0.0, np.diff(ln_a) / np.where(dv != 0.0, dv, 1.0), 0.0)
        n = min(LOCAL_SLOPES, slopes.size)
        for k in range(slopes.size - n + 1):
            slope = float(np.median(slopes[k : k + n]))
            drift = abs(slope) * a / float(np.mean(f[k : k + n + 1]))
            if worst is None or drift > worst[0]:
                worst = (drift, slope, float(v[k + n]), float(np.mean(f[k : k + n + 1])))
    if worst is None:
        return out
    drift, slope, speed, f_mean = worst
    out.update(branch_slope_per_m_per_s=slope, drift_per_period=drift, drift_speed_m_per_s=speed,
               drift_within_band=drift <= MAX_DRIFT_PER_PERIOD,
               max_deceleration_m_per_s2=(MAX_DRIFT_PER_PERIOD * f_mean / abs(slope)
                                          if slope else None))  # fmt: skip
    return out


def _agree(slow: dict, fast: dict, key: str) -> tuple[float | None, bool | None, str]:
    """The slower ramp's ``key`` where both ramps found one within the sum of their resolutions
    (and whether they agree); None and False where they differ or only one found it; None and
    None where neither did."""
    v_slow, v_fast = slow.get(key), fast.get(key)
    if v_slow is None and v_fast is None:
        return None, None, ""
    both = (
        f"{_text(v_slow)} at {slow['deceleration_m_per_s2']:g} m/s^2, {_text(v_fast)} at "
        f"{fast['deceleration_m_per_s2']:g} m/s^2"
    )
    if v_slow is None or v_fast is None:
        return None, False, both
    tolerance = (slow.get("resolution_m_per_s") or 0.0) + (fast.get("resolution_m_per_s") or 0.0)
    agree = abs(v_slow - v_fast) <= tolerance + 1e-9
    return (v_slow if agree else None), agree, both + f" (tolerance {tolerance:.2f} m/s)"


def _text(v: float | None) -> str:
    return f"{v:.2f} m/s" if v is not None else "none"


def rate_verdicts(slow: dict, fast: dict) -> dict:
    """The ramp method's results from its two ramps: ``critical_speed_m_per_s`` (where the last
    sustained window ends) and ``fold_m_per_s`` (where the cycle followed from the plateau
    falls most steeply), each the slower ramp's value where the two ramps agree within the sum
    of their stated resolutions (deceleration x window), None where they do not (a
    rate-dependent result is no verdict: slower ramps are needed); ``rate_independent`` and
    ``fold_rate_independent`` (None where neither ramp found one), both ramps' values
    (``..._by_rate``, slower first), ``rate_difference_m_per_s`` and a ``rate_note`` saying
    which result depends on the rate."""
    v, same, v_text = _agree(slow, fast, "critical_speed_m_per_s")
    f, fold_same, f_text = _agree(slow, fast, "fold_m_per_s")
    out = {"critical_speed_m_per_s": v, "rate_independent": same, "fold_m_per_s": f,
           "fold_rate_independent": fold_same,
           "critical_speed_m_per_s_by_rate": [slow.get("critical_speed_m_per_s"),
                                              fast.get("critical_speed_m_per_s")],
           "fold_m_per_s_by_rate": [slow.get("fold_m_per_s"),
                                    fast.get("fold_m_per_s")]}  # fmt: skip
    if None not in out["critical_speed_m_per_s_by_rate"]:
        out["rate_difference_m_per_s"] = abs(
            slow["critical_speed_m_per_s"] - fast["critical_speed_m_per_s"]
        )
    words = []
    if same is False:
        words.append(f"rate-dependent, no verdict: the last sustained window ends at {v_text}")
    if fold_same is False:
        words.append(f"the steepest fall (fold) is rate-dependent: {f_text}")
    out["rate_note"] = "; ".join(words) + ("; slower ramps are needed" if words else "")
    return out


def one_ramp(vehicle, track, a: float, settings: CriticalSpeedSettings) -> dict:
    """One ramp at deceleration ``a`` (m/s^2) within the budget, classified by windows."""
    v_max, v_min = settings.speed_max_m_per_s, settings.speed_min_m_per_s
    profile, distance, v_end, cut = ramp_profile(
        v_max, v_min, a, settings.ramp_settle_m, settings.ramp_budget_m
    )
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_profile=profile,
            distance_m=distance,
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
        ),
    )
    out = {"deceleration_m_per_s2": a, "start_speed_m_per_s": v_max, "end_speed_m_per_s": v_end,
           "distance_m": distance, "duration_s": profile.times_s[-1] if cut else
           float(result.timeseries.time_s[-1]), "budget_m": settings.ramp_budget_m,
           "state": result.status["state"], "cut": cut}  # fmt: skip
    if result.status["state"] not in COMPLETED_STATES:
        out.update(status="run stopped", note=f"the ramp run stopped: {result.status['reason']}",
                   critical_speed_m_per_s=None)  # fmt: skip
        return out
    out.update(classify_ramp(result.timeseries, settings.ramp_settle_m, a, settings))
    if out["critical_speed_m_per_s"] is not None:
        out["status"] = "converged"
    elif cut and out.get("note") == "still hunting at the end of the ramp":
        out["status"] = "budget exhausted"
        out["note"] = (f"budget exhausted: {distance:g} m run, still hunting at {v_end:.1f} m/s "
                       f"(the ramp to {v_min:g} m/s needs more)")  # fmt: skip
    else:
        out["status"] = "converged" if "no hunting" in out.get("note", "") else "not found"
    return out


def check_deceleration(settings: CriticalSpeedSettings) -> float:
    """The second ramp's deceleration [m/s^2]: :data:`FASTER` times the requested one, or, where
    that would pass the steepest deceleration allowed (``MAX_DECELERATION_M_PER_S2``), the
    requested one divided by :data:`FASTER`."""
    a = settings.ramp_deceleration_m_per_s2
    return FASTER * a if FASTER * a <= MAX_DECELERATION_M_PER_S2 else a / FASTER


def ramp_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed by the ramp method at two rates (module docstring).

    Returns ``critical_speed_m_per_s`` and ``fold_m_per_s`` (where the last sustained window
    ends, and where the cycle followed from the plateau falls most steeply: the slower ramp's
    value where the two ramps agree within the sum of their resolutions, None where they do
    not, :func:`rate_verdicts`), ``resolution_m_per_s`` (the slower ramp's), ``drift_per_period``,
    ``drift_within_band``, ``max_deceleration_m_per_s2``, ``rate_independent``,
    ``fold_rate_independent``, both ramps' values, ``rate_difference_m_per_s``, ``status``
    (``converged``, ``rate-dependent``: the two rates disagree, no verdict; ``budget
    exhausted``, ``run stopped`` or ``not found``), ``ramps`` (both, each with its windows),
    ``speeds_m_per_s`` and ``amplitude_m`` (the slower ramp's windows, for the figure), the
    disturbance and the judgement."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    ramps = []
    for a in (settings.ramp_deceleration_m_per_s2, check_deceleration(settings)):
        if progress:
            progress(f"ramp: {settings.speed_max_m_per_s:g} -> {settings.speed_min_m_per_s:g} "
                     f"m/s at {a:g} m/s^2 (budget {settings.ramp_budget_m:g} m)")  # fmt: skip
        r = one_ramp(vehicle, track, a, settings)
        ramps.append(r)
        if progress:
            v = r.get("critical_speed_m_per_s")
            progress(f"ramp at {a:g} m/s^2: {r['status']}, " + (
                f"cycle vanishes at {v:.2f} m/s (+-{r['resolution_m_per_s']:.2f})" if v else
                r.get("note", "")))  # fmt: skip
    slow, fast = sorted(ramps, key=lambda r: r["deceleration_m_per_s2"])
    out = {
        "critical_speed_m_per_s": slow.get("critical_speed_m_per_s"),
        "resolution_m_per_s": slow.get("resolution_m_per_s"),
        "status": slow["status"],
        "ramps": ramps,
        "speeds_m_per_s": [w["speed_m_per_s"] for w in slow.get("windows", [])],
        "amplitude_m": [w.get("amplitude_m") or 0.0 for w in slow.get("windows", [])],
        "deceleration_m_per_s2": [slow["deceleration_m_per_s2"], fast["deceleration_m_per_s2"]],
        "fold_m_per_s": slow.get("fold_m_per_s"),
        "drift_per_period": slow.get("drift_per_period"),
        "drift_speed_m_per_s": slow.get("drift_speed_m_per_s"),
        "drift_within_band": slow.get("drift_within_band"),
        "max_deceleration_m_per_s2": slow.get("max_deceleration_m_per_s2"),
        "threshold_m": settings.threshold_m,
        "disturbance": f"initial lateral offset {settings.initial_lateral_m * 1e3:g} mm, "
        f"{settings.ramp_settle_m:g} m at {settings.speed_max_m_per_s:g} m/s before the ramp",
        "judged_by": _judgement(settings)
        .replace(f"each run {settings.distance_m:g} m", f"windows of {WINDOW_PERIODS:g} periods")
        .replace(f" over the last {settings.fit_fraction:.0%} of the run's time", ""),
    }
    if slow.get("note"):
        out["note"] = slow["note"]
    if fast.get("note") and "budget" in fast["note"] and "note" not in out:
        out["note"] = f"faster ramp: {fast['note']}"
    out.update(rate_verdicts(slow, fast))
    cut_short = {slow["status"], fast["status"]} & {"budget exhausted", "run stopped"}
    if out["rate_independent"] is False and not cut_short:  # (else that status says why)
        out["status"] = "rate-dependent"
    if out["rate_note"]:
        out["note"] = out["rate_note"]
    if slow.get("note") == "still hunting at the end of the ramp":
        out["unstable_in_range"] = True
    if slow.get("drift_within_band") is False:
        words = (f"at {slow['deceleration_m_per_s2']:g} m/s^2 the branch's amplitude drifts by "
                 f"{slow['drift_per_period']:.1%} per period near "
                 f"{slow['drift_speed_m_per_s']:.1f} m/s (more than the 1 % band): use at most "
                 f"{slow['max_deceleration_m_per_s2']:.2g} m/s^2 there")  # fmt: skip
        out["note"] = f"{out['note']}; {words}" if out.get("note") else words
    return out
