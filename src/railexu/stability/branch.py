"""The limit-cycle branch followed as speed falls, each speed step restarting from the last state
of the step above: one run per stage down a staircase of speeds (:func:`branch_critical_speed`).

A stage is one run of the full model with a prescribed speed profile: a plateau at the top speed
after the lateral disturbance, then, down a staircase, a short deceleration
(:data:`TRANSITION_DECELERATION_M_PER_S2`) and a plateau of ``distance_m`` at each lower speed.
So every plateau starts from the state in which the plateau above ended: the settled limit
cycle, not a fresh offset of the vehicle (Knudsen, Feldberg and True 1992; True 1999, "On the
theory of nonlinear dynamics and its applications in vehicle systems dynamics", Vehicle System
Dynamics 31: the branch of periodic solutions followed by continuation in speed). Each plateau is
classified by the growth rate of its wheelsets' fitted envelope over the last ``fit_fraction`` of
its time (:func:`~railexu.stability.nonlinear.classify_window`) and its amplitude recorded.

Where the cycle is lost between two plateaus (a limit cycle above, a decaying motion below), the
next stage runs down quickly from the top speed to the last speed with a limit cycle (on the
branch: the cycle follows a deceleration of ``2 m/s^2``, checked by that plateau's own
classification) and steps down from it in quarter steps. The stages stop when the step is at
most ``tolerance_m_per_s`` (``converged``) or when the next stage would exceed ``max_runs``
plateaus in all (``budget exhausted``)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.operation.speed_profile import SpeedProfile
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.stability.nonlinear import _judgement, _run_text, classify_window
from railexu.stability.settings import CriticalSpeedSettings
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle

#: Deceleration between two plateaus of a stage [m/s^2] (railexu's choice: short against a
#: plateau, slow against the hunting period, well within adhesion).
TRANSITION_DECELERATION_M_PER_S2 = 2.0
#: Each refining stage steps down in this fraction of the step of the stage before.
REFINEMENT = 0.25


def staircase(speeds: list[float], plateau_m: float) -> tuple[SpeedProfile, list[tuple]]:
    """The speed profile of one stage: ``plateau_m`` at ``speeds[0]``, then for each lower speed a
    deceleration of :data:`TRANSITION_DECELERATION_M_PER_S2` and ``plateau_m`` at that speed.
    Returns the profile and each plateau's ``(speed, start_m, end_m)``."""
    points = [(0.0, speeds[0]), (plateau_m, speeds[0])]
    plateaus = [(speeds[0], 0.0, plateau_m)]
    s = plateau_m
    for v_above, v in zip(speeds[:-1], speeds[1:], strict=True):
        s += (v_above**2 - v**2) / (2.0 * TRANSITION_DECELERATION_M_PER_S2)
        points.append((s, v))
        plateaus.append((v, s, s + plateau_m))
        s += plateau_m
        points.append((s, v))
    return SpeedProfile(tuple(points)), plateaus


def run_stage(
    vehicle: Vehicle,
    track: Track,
    speeds: list[float],
    settings: CriticalSpeedSettings,
) -> list[dict]:
    """One stage down the staircase ``speeds`` from the disturbance ``initial_lateral_m``: each
    plateau classified over the last ``fit_fraction`` of its time. A run that stops (derails,
    diverges) marks the plateau it stopped in as unstable with the reason, and those below as
    not reached."""
    profile, plateaus = staircase(speeds, settings.distance_m)
    result = run(
        vehicle,
        track,
        RunSettings(
            speed_profile=profile,
            distance_m=plateaus[-1][2],
            initial_lateral_m=settings.initial_lateral_m,
            time_step_s=settings.time_step_s,
            output_interval_s=max(settings.time_step_s, 0.01),
        ),
    )
    ts = result.timeseries
    state = result.status["state"]
    x, t = ts.distance_m, ts.time_s
    out = []
    for v, s0, s1 in plateaus:
        base = {"speed_m_per_s": v, "plateau_m": [s0, s1], "state": state}
        reached = x[-1] >= s1 - 1e-6
        if not reached:
            if state not in COMPLETED_STATES and x[-1] >= s0:
                out.append({**base, "stable": False, "classification": state,
                            "amplitude_m": None, "reason": result.status["reason"]})  # fmt: skip
            else:
                out.append({**base, "stable": None, "classification": "not reached",
                            "amplitude_m": None})  # fmt: skip
            continue
        inside = (x >= s0) & (x <= s1)
        t_in = t[inside]
        start = t_in[0] + (1.0 - settings.fit_fraction) * (t_in[-1] - t_in[0])
        window = inside & (t >= start)
        signals = {f"ws{i}": ts[f"ws{i}_lateral_m"][window] for i in ts.wheelset_indices()}
        out.append({**base, **classify_window(t[window], signals, settings)})
    return out


#: Fewer periods than this in a plateau's fit window resolve the growth rate more coarsely than
#: the classification's 1 % per period (:mod:`railexu.stability.ramp`, ``WINDOW_PERIODS``).
MIN_FIT_PERIODS = 16.0


def branch_critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """The branch (:func:`_branch`) with a warning where a plateau's fit window held fewer than
    :data:`MIN_FIT_PERIODS` periods (a longer ``distance`` or ``fit_fraction`` resolves it)."""
    out = _branch(vehicle, track, settings, progress)
    periods = [p["fit_periods"] for p in out["branch"] if p.get("fit_periods")]
    if periods and min(periods) < MIN_FIT_PERIODS:
        out["warning"] = (
            f"the shortest fit window held {min(periods):.1f} periods (fewer than "
            f"{MIN_FIT_PERIODS:g}): its growth rate is resolved to about "
            f"{0.13 / min(periods):.1%} per period, against the 1 % band of the classification"
        )
    return out


def _branch(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Nonlinear critical speed from the limit-cycle branch, followed down in speed with every
    step restarting from the settled cycle of the step above (module docstring).

    Returns ``critical_speed_m_per_s`` (the lowest speed with a limit cycle or a growing
    oscillation), ``bracket_m_per_s`` ([highest speed without, lowest with]), ``resolution_m_
    per_s`` (the last stage's step), ``branch``: every plateau of every stage (speed, stage,
    classification, fitted amplitude of the deciding wheelset, growth rate, frequency),
    ``stages`` (the speeds of each stage), ``status`` (``converged`` or ``budget exhausted``),
    ``converged``, ``note``, ``plateaus_run``, ``distance_run_m``, the disturbance and the
    judgement."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    v_max, v_min = settings.speed_max_m_per_s, settings.speed_min_m_per_s
    step = settings.branch_step_m_per_s
    points: list[dict] = []
    out: dict = {
        "critical_speed_m_per_s": None,
        "bracket_m_per_s": None,
        "resolution_m_per_s": step,
        "branch": points,
        "stages": [],
        "converged": False,
        "status": "budget exhausted",
        "disturbance": (
            f"initial lateral offset {settings.initial_lateral_m * 1e3:g} mm at {v_max:g} m/s; "
            "each lower speed starts from the last state of the speed above (one run per stage, "
            f"{TRANSITION_DECELERATION_M_PER_S2:g} m/s^2 between plateaus of "
            f"{settings.distance_m:g} m)"
        ),
        "judged_by": _judgement(settings).replace("each run", "each plateau"),
        "max_runs": settings.max_runs,
        "plateaus_run": 0,
        "distance_run_m": 0.0,
    }
    speeds = list(np.arange(v_max, v_min - 1e-9, -step)) or [v_max]
    if speeds[-1] > v_min + 1e-9:
        speeds.append(v_min)
    speeds = [float(v) for v in speeds][: settings.max_runs]
    lost: float | None = None
    first = 0  # the plateau a stage restarts from (a refining stage settles at the top first)
    for stage in range(settings.max_runs):
        out["stages"].append(speeds)
        found = run_stage(vehicle, track, speeds, settings)
        out["plateaus_run"] += len(speeds)
        out["distance_run_m"] += staircase(speeds, settings.distance_m)[1][-1][2]
        for p in found:
            p["stage"] = stage
            points.append(p)
            if progress:
                progress(f"branch stage {stage}: {p['speed_m_per_s']:.2f} m/s -> {_run_text(p)}")
        end = _stage_end(found, stage, first, out)
        if end:
            return out
        hunting, lost = _bracket_of(found, first, lost)
        if lost is None:  # hunting down to the stage's lowest speed, no loss yet
            low = found[-1]["speed_m_per_s"]
            if low <= v_min + 1e-9:
                out.update(converged=True, status="converged", unstable_in_range=True,
                           note=f"a limit cycle down to the lowest speed, {low:g} m/s")  # fmt: skip
            else:
                out["note"] = (f"budget exhausted: {settings.max_runs} plateaus, still hunting "
                               f"at {low:g} m/s")  # fmt: skip
            return out
        out.update(bracket_m_per_s=[lost, hunting], critical_speed_m_per_s=hunting,
                   resolution_m_per_s=hunting - lost)  # fmt: skip
        if hunting - lost <= settings.tolerance_m_per_s + 1e-9:
            out["converged"], out["status"] = True, "converged"
            return out
        step = (hunting - lost) * REFINEMENT
        first = 1 if hunting < v_max else 0
        speeds = [v_max] * first + [hunting]
        speeds += [hunting - j * step for j in range(1, round(1.0 / REFINEMENT))]
        if out["plateaus_run"] + len(speeds) > settings.max_runs:
            out["note"] = (
                f"budget exhausted: {out['plateaus_run']} plateaus run, the next stage needs "
                f"{len(speeds)} more than the {settings.max_runs} allowed; bracket {lost:g} to "
                f"{hunting:g} m/s"
            )
            return out
    return out


def _bracket_of(found: list[dict], first: int, lost: float | None) -> tuple:
    """``(lowest speed with the cycle, highest speed without it)`` of one stage, from its plateau
    ``first`` on (a refining stage's plateau 0 is the settling at the top speed); ``lost`` (the
    bracket's lower end so far) where the stage kept the cycle to its lowest speed."""
    hunting = found[first]["speed_m_per_s"]
    for p in found[first + 1 :]:
        if p["stable"]:
            return hunting, p["speed_m_per_s"]
        hunting = p["speed_m_per_s"]
    return hunting, lost


def _stage_end(found: list[dict], stage: int, first: int, out: dict) -> bool:
    """Ends the branch (True, with the status and note set in ``out``) when a stage's run
    stopped, when there is no cycle at the top speed, or when a refining stage does not find the
    cycle again at its restart speed."""
    stopped = [p for p in found if p["classification"] == "not reached"]
    if stopped:
        why = next((p.get("reason") for p in found if p.get("reason")), "")
        out.update(status="run stopped", note=f"stage {stage}'s run stopped: {why}")
        return True
    if stage == 0 and found[0]["stable"]:
        out.update(converged=True, status="converged", note=(
            f"no limit cycle at the highest speed, {found[0]['speed_m_per_s']:g} m/s, from "
            "this disturbance"))  # fmt: skip
        return True
    restart = found[first]
    if stage > 0 and restart["stable"]:
        out.update(status="restart lost the cycle", note=(
            f"stage {stage}: no limit cycle at its restart speed {restart['speed_m_per_s']:g} "
            "m/s after the deceleration from the top speed; the bracket is that of the stage "
            "before"))  # fmt: skip
        return True
    return False
