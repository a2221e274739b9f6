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

Two brackets are refined. The **fold**: where the branch followed from the top speed ends, a
plateau below it either at rest or no longer on it (its amplitude dropped below
:data:`~railexu.stability.nonlinear.JUMP_FRACTION` of the plateau above: the motion fell onto
another cycle). The **lowest cycle**: the highest speed without any sustained or growing
oscillation below the lowest speed with one (the critical speed, whatever the cycle's
amplitude). For each, the next stage runs down quickly from the top speed to the bracket's
upper speed (on the branch: the cycle follows a deceleration of ``2 m/s^2``, checked by that
plateau's own classification and, for the fold, by its amplitude) and steps down from it in
quarter steps. The stages stop when both brackets are at most ``tolerance_m_per_s``
(``converged``) or when the next stage would exceed ``max_runs`` plateaus in all (``budget
exhausted``)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.operation.speed_profile import SpeedProfile
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.stability.nonlinear import _judgement, _run_text, classify_window, same_branch
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

    Returns ``critical_speed_m_per_s`` (the lowest speed with a sustained cycle or a growing
    oscillation, whatever its amplitude), ``critical_amplitude_m`` (its fitted amplitude),
    ``bracket_m_per_s`` ([highest speed without, lowest with]), ``resolution_m_per_s``, ``fold``
    (where the branch followed from the top speed ends: :func:`_fold_section`), ``branches``
    (each branch's speeds and amplitudes, :func:`branches_of`), ``branch``: every plateau of
    every stage (speed, stage, classification, fitted amplitude of the deciding wheelset, growth
    rate, frequency, ``branch`` index), ``stages`` (the speeds of each stage), ``status``
    (``converged`` or ``budget exhausted``), ``converged``, ``note``, ``plateaus_run``,
    ``distance_run_m``, the disturbance and the judgement."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    v_max, v_min = settings.speed_max_m_per_s, settings.speed_min_m_per_s
    step = settings.branch_step_m_per_s
    points: list[dict] = []
    out: dict = {
        "critical_speed_m_per_s": None,
        "critical_amplitude_m": None,
        "bracket_m_per_s": None,
        "resolution_m_per_s": step,
        "fold": None,
        "branch": points,
        "branches": [],
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
        "branch_rule": BRANCH_RULE,
        "max_runs": settings.max_runs,
        "plateaus_run": 0,
        "distance_run_m": 0.0,
    }
    speeds = list(np.arange(v_max, v_min - 1e-9, -step)) or [v_max]
    if speeds[-1] > v_min + 1e-9:
        speeds.append(v_min)
    speeds = [float(v) for v in speeds][: settings.max_runs]

    def stage(speeds: list[float], first: int) -> list[dict] | None:
        """Runs one stage, records its plateaus; None when the branch must end there."""
        k = len(out["stages"])
        out["stages"].append(speeds)
        found = run_stage(vehicle, track, speeds, settings)
        out["plateaus_run"] += len(speeds)
        out["distance_run_m"] += staircase(speeds, settings.distance_m)[1][-1][2]
        label_branches(found)
        for p in found:
            p["stage"] = k
            points.append(p)
            if progress:
                progress(f"branch stage {k}: {p['speed_m_per_s']:.2f} m/s -> {_run_text(p)}")
        return None if _stage_end(found, k, first, out) else found

    found = stage(speeds, 0)
    if found is None:
        return _finish(out, settings)
    fold = _follow(found, 0, None)
    loss = _bracket_of(found, 0, None)
    fold_is_loss = fold[1] is not None and fold[1] == loss[1]
    for target in ("fold", "loss"):
        while True:
            on, off = fold if target == "fold" else loss
            if off is None or on - off <= settings.tolerance_m_per_s + 1e-9:
                break
            if target == "loss" and fold_is_loss:
                loss = fold
                break
            step = (on - off) * REFINEMENT
            first = 1 if on < v_max else 0
            speeds = [v_max] * first + [on]
            speeds += [on - j * step for j in range(1, round(1.0 / REFINEMENT))]
            if out["plateaus_run"] + len(speeds) > settings.max_runs:
                out["note"] = (
                    f"budget exhausted: {out['plateaus_run']} plateaus run, refining the "
                    f"{'fold' if target == 'fold' else 'lowest cycle'} ({off:g} to {on:g} m/s) "
                    f"needs {len(speeds)} more than the {settings.max_runs} allowed"
                )
                out["budget_exhausted"] = True
                return _finish(out, settings, fold, loss)
            above = [p for p in points if p["speed_m_per_s"] == on and p.get("branch") == 0]
            found = stage(speeds, first)
            if found is None:
                return _finish(out, settings, fold, loss)
            if target == "fold" and above and not same_branch(above[0], found[first]):
                out["note"] = (
                    f"stage {len(out['stages']) - 1}: at its restart speed {on:g} m/s the motion "
                    "is not on the branch followed from the top speed (after the deceleration "
                    "from the top); the fold's bracket is that of the stage before"
                )
                out["restart_lost_branch"] = True
                return _finish(out, settings, fold, loss)
            if target == "fold":
                fold = _follow(found, first, off)
            else:
                loss = _bracket_of(found, first, off)
        if fold_is_loss:
            loss = fold
    return _finish(out, settings, fold, loss)


BRANCH_RULE = (
    "a plateau is on the branch of the plateau above it when it is not stable (growing or "
    "sustained) and its fitted amplitude is at least half the amplitude above (railexu's "
    "assumption: a larger drop within one speed step is a jump to another branch at a fold); "
    "the fold of the branch followed from the top speed is bracketed between its lowest plateau "
    "and the next one below"
)


def label_branches(found: list[dict]) -> None:
    """Numbers the branches down one stage (``p["branch"]``): 0 from the top plateau down to
    its first jump (:func:`~railexu.stability.nonlinear.same_branch`: the fold), then one more
    after that jump and after every stable plateau; stable plateaus get None. Below the fold a
    drop is not split further: the fold reported is that of the branch followed from the top."""
    k, above = -1, None
    for p in found:
        if p.get("stable") is not False:
            p["branch"], above = None, p
            continue
        if above is None or above.get("stable") is not False:
            k += 1
        elif k == 0 and not same_branch(above, p):
            k = 1
        p["branch"], above = k, p


def _follow(found: list[dict], first: int, off: float | None) -> tuple:
    """``(lowest speed on the branch followed from plateau first, the next speed below it)``;
    ``off`` (the bracket's lower end so far) where the stage kept the branch to its end."""
    on = found[first]
    for p in found[first + 1 :]:
        if not same_branch(on, p):
            return on["speed_m_per_s"], p["speed_m_per_s"]
        on = p
    return on["speed_m_per_s"], off


def branches_of(points: list[dict]) -> list[dict]:
    """Every branch found (the plateaus of all stages with the same ``branch`` index): its
    ``index``, ``speeds_m_per_s`` (falling), ``amplitude_m``, ``classification`` and lowest
    speed."""
    out = []
    for k in sorted({p["branch"] for p in points if p.get("branch") is not None}):
        ps = sorted((p for p in points if p.get("branch") == k),
                    key=lambda p: -p["speed_m_per_s"])  # fmt: skip
        out.append({"index": k, "speeds_m_per_s": [p["speed_m_per_s"] for p in ps],
                    "amplitude_m": [p.get("amplitude_m") for p in ps],
                    "classification": [p["classification"] for p in ps],
                    "lowest_speed_m_per_s": ps[-1]["speed_m_per_s"]})  # fmt: skip
    return out


def _fold_section(points: list[dict], fold: tuple | None, settings) -> dict | None:
    """Where the branch followed from the top speed ends: ``bracket_m_per_s`` ([the speed below
    which it is lost, the lowest speed on it]), ``speed_m_per_s`` (the lowest on it),
    ``amplitude_m`` there, ``resolution_m_per_s``, ``converged`` (within ``tolerance``) and what
    the motion does below it (``below``: classification and amplitude). None when the branch
    holds down to the lowest speed, or there was none."""
    if not fold or fold[1] is None:
        return None
    on, off = fold
    at = [p for p in points if p["speed_m_per_s"] == on and p.get("branch") == 0]
    below = [p for p in points if p["speed_m_per_s"] == off]
    out = {"bracket_m_per_s": [off, on], "speed_m_per_s": on,
           "amplitude_m": at[-1].get("amplitude_m") if at else None,
           "resolution_m_per_s": on - off,
           "converged": on - off <= settings.tolerance_m_per_s + 1e-9}  # fmt: skip
    if below:
        b = below[-1]
        out["below"] = {"classification": b["classification"], "amplitude_m": b.get("amplitude_m"),
                        "branch": b.get("branch")}  # fmt: skip
    return out


def _finish(out: dict, settings, fold: tuple | None = None, loss: tuple | None = None) -> dict:
    """Fills the result from the fold and loss brackets; a status that :func:`_stage_end` set
    (``run stopped``, ``restart lost the cycle``) stays, unconverged."""
    ended = out["status"] in ("run stopped", "restart lost the cycle", "no verdict")
    ended_status = out["status"]
    points = out["branch"]
    out["branches"] = branches_of(points)
    out["fold"] = _fold_section(points, fold, settings)
    if loss is None:
        return out
    hunting, lost = loss
    at = [p for p in points if p["speed_m_per_s"] == hunting and p.get("stable") is False]
    amp = at[-1].get("amplitude_m") if at else None
    if lost is None:
        low = hunting
        out["lowest_cycle"] = {"speed_m_per_s": low, "amplitude_m": amp}
        if low <= settings.speed_min_m_per_s + 1e-9:
            out.update(converged=not out.get("budget_exhausted"), unstable_in_range=True,
                       note=out.get("note") or (
                           f"a sustained cycle down to the lowest speed, {low:g} m/s "
                           f"({(amp or 0.0) * 1e3:.2f} mm): the critical speed lies below the "
                           "range"))  # fmt: skip
        else:
            out["note"] = out.get("note") or (
                f"budget exhausted: {settings.max_runs} plateaus, still hunting at {low:g} m/s"
            )
            out["converged"] = False
    else:
        out.update(bracket_m_per_s=[lost, hunting], critical_speed_m_per_s=hunting,
                   critical_amplitude_m=amp, resolution_m_per_s=hunting - lost)  # fmt: skip
        out["converged"] = not out.get("budget_exhausted") and (
            hunting - lost <= settings.tolerance_m_per_s + 1e-9
        )
    if out["fold"] is not None and not out["fold"]["converged"]:
        out["converged"] = False
    out["status"] = "converged" if out["converged"] else "budget exhausted"
    if ended or out.pop("restart_lost_branch", False):
        out["converged"] = False
        out["status"] = ended_status if ended else "restart lost the branch"
    out.pop("budget_exhausted", None)
    return out


def _bracket_of(found: list[dict], first: int, lost: float | None) -> tuple:
    """``(lowest speed with a cycle, highest speed without one)`` of one stage, from its plateau
    ``first`` on (a refining stage's plateau 0 is the settling at the top speed); ``lost`` (the
    bracket's lower end so far) where the stage kept a cycle to its lowest speed."""
    hunting = found[first]["speed_m_per_s"]
    for p in found[first + 1 :]:
        if p["stable"]:
            return hunting, p["speed_m_per_s"]
        hunting = p["speed_m_per_s"]
    return hunting, lost


def _stage_end(found: list[dict], stage: int, first: int, out: dict) -> bool:
    """Ends the branch (True, with the status and note set in ``out``) when a stage's run
    stopped, when a plateau is too short to classify, when there is no cycle at the top speed,
    or when a refining stage does not find the cycle again at its restart speed."""
    stopped = [p for p in found if p["classification"] == "not reached"]
    if stopped:
        why = next((p.get("reason") for p in found if p.get("reason")), "")
        out.update(status="run stopped", note=f"stage {stage}'s run stopped: {why}")
        return True
    short = [p for p in found if p.get("classification") == "too short"]
    if short:
        out.update(status="no verdict", note=(
            f"stage {stage}: the plateau at {short[0]['speed_m_per_s']:g} m/s is too short to "
            "classify (its fit window holds fewer than four periods): use a longer distance "
            "or fit_fraction"))  # fmt: skip
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
