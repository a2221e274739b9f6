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

Two brackets are refined. The **fold**: where the branch followed from the top speed ends,
found without a chosen factor (:mod:`railexu.stability.fold`): the first stage's largest fall of
the attractor's amplitude (down to its first stable plateau, which counts 0) is the candidate;
each refining stage steps its bracket again in sub-steps, and the bracket is a jump (a fold)
where the largest fall across one sub-step exceeds the changes across all the others together,
continuous otherwise (then there is no fold there: ``fold`` None, ``fold_search`` says why).
The **lowest cycle**: the highest speed without any sustained or growing oscillation below the
lowest speed with one (the critical speed, whatever the cycle's amplitude). For each, the next
stage runs down quickly from the top speed to the bracket's upper speed (on the branch: the
cycle follows a deceleration of ``2 m/s^2``, checked by that plateau's own classification and,
for the fold, by its amplitude being nearer to the branch's than to the attractor's below) and
steps down from it in sub-steps of :data:`REFINEMENT` of the bracket. The stages stop when both
brackets are at most ``tolerance_m_per_s`` (``converged``) or when the next stage would exceed
``max_runs`` plateaus in all (``budget exhausted``)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from railexu.operation.speed_profile import SpeedProfile
from railexu.results.run import RunSettings, run
from railexu.simulation.simulate import COMPLETED_STATES
from railexu.stability.fold import (
    attractor_amplitude,
    concentrated,
    largest_fall,
    nearer_to_upper,
)
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
        entry = inside & (t < start)
        first = {f"ws{i}": ts[f"ws{i}_lateral_m"][entry] for i in ts.wheelset_indices()}
        early = classify_window(t[entry], first, settings) if np.count_nonzero(entry) > 1 else {}
        out.append({**base, **classify_window(t[window], signals, settings),
                    "entry_classification": early.get("classification"),
                    "entry_growth_per_period": early.get("growth_per_period")})  # fmt: skip
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
    (where the branch followed from the top speed ends: :func:`_fold_section`), ``fold_search``
    (the candidate, each refinement and the verdict: ``jump``, ``continuous`` or ``not
    refined``; :mod:`railexu.stability.fold`), ``branches``
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
        for p in found:
            p["stage"] = k
            points.append(p)
            if progress:
                progress(f"branch stage {k}: {p['speed_m_per_s']:.2f} m/s -> {_run_text(p)}")
        return None if _stage_end(found, k, first, out) else found

    found = stage(speeds, 0)
    if found is None:
        return _finish(out, settings)
    loss = _bracket_of(found, 0, None)
    fold = _fold_candidate(found, 0)
    search: dict = {"candidate_m_per_s": list(fold[::-1]) if fold else None, "levels": [],
                    "discontinuity": "not refined" if fold else None}  # fmt: skip
    out["fold_search"] = search
    while fold is not None and fold[0] - fold[1] > settings.tolerance_m_per_s + 1e-9:
        on, off = fold
        fold_is_loss = fold == loss  # a fold to rest: this stage refines the loss as well
        speeds, first = _refining_speeds(on, off, v_max)
        if _over_budget(out, settings, speeds, "fold", on, off):
            return _finish(out, settings, fold, loss)
        upper, lower = _amplitude_at(points, on), _amplitude_at(points, off)
        found = stage(speeds, first)
        if found is None:
            return _finish(out, settings, fold, loss)
        restart = found[first]
        if not nearer_to_upper(attractor_amplitude(restart), upper, lower):
            out["note"] = (
                f"stage {len(out['stages']) - 1}: at its restart speed {on:g} m/s the motion "
                f"({(restart.get('amplitude_m') or 0.0) * 1e3:.2f} mm) is nearer to the "
                f"attractor below the fold ({lower * 1e3:.2f} mm) than to the branch followed "
                f"from the top ({upper * 1e3:.2f} mm); the fold's bracket is that of the stage "
                "before"
            )
            out["restart_lost_branch"] = True
            return _finish(out, settings, fold, loss)
        fold, level = _refine_fold(found[first:], off, lower)
        search["levels"].append(level)
        search["discontinuity"] = "jump" if level["jump"] else "continuous"
        if fold_is_loss:
            loss = _bracket_of(found, first, loss[1])
        if not level["jump"]:
            fold = None
    while loss[1] is not None:
        on, off = loss
        if on - off <= settings.tolerance_m_per_s + 1e-9:
            break
        speeds, first = _refining_speeds(on, off, v_max)
        if _over_budget(out, settings, speeds, "lowest cycle", on, off):
            return _finish(out, settings, fold, loss)
        found = stage(speeds, first)
        if found is None:
            return _finish(out, settings, fold, loss)
        loss = _bracket_of(found, first, off)
    return _finish(out, settings, fold, loss)


def _refining_speeds(on: float, off: float, v_max: float) -> tuple[list[float], int]:
    """A refining stage's speeds: the top speed (when below it), the bracket's upper end and
    its sub-steps of :data:`REFINEMENT` of the bracket down to (not including) its lower end;
    and the index of the upper end."""
    step = (on - off) * REFINEMENT
    first = 1 if on < v_max else 0
    speeds = [v_max] * first + [on]
    speeds += [on - j * step for j in range(1, round(1.0 / REFINEMENT))]
    return speeds, first


def _over_budget(out: dict, settings, speeds: list, target: str, on: float, off: float) -> bool:
    """True (with the note set) when the next stage would pass ``max_runs`` plateaus."""
    if out["plateaus_run"] + len(speeds) <= settings.max_runs:
        return False
    out["note"] = (
        f"budget exhausted: {out['plateaus_run']} plateaus run, refining the {target} "
        f"({off:g} to {on:g} m/s) needs {len(speeds)} more than the {settings.max_runs} allowed"
    )
    out["budget_exhausted"] = True
    return True


def _amplitude_at(points: list[dict], speed: float) -> float:
    """The attractor's amplitude of the latest plateau run at ``speed`` [m]."""
    at = [p for p in points if p["speed_m_per_s"] == speed]
    return (attractor_amplitude(at[-1]) or 0.0) if at else 0.0


def _fold_candidate(found: list[dict], first: int) -> tuple | None:
    """``(upper, lower)`` speeds of the largest fall of the attractor's amplitude
    (:func:`~railexu.stability.fold.largest_fall`) from plateau ``first`` down to the first
    stable plateau (included: the motion at rest, amplitude 0); None where it never falls."""
    seq = []
    for p in found[first:]:
        seq.append(p)
        if p.get("stable") is not False:
            break
    amps = [attractor_amplitude(p) for p in seq]
    if any(a is None for a in amps):
        return None
    j = largest_fall(amps)
    return None if j is None else (seq[j]["speed_m_per_s"], seq[j + 1]["speed_m_per_s"])


def _refine_fold(found: list[dict], off: float, lower_m: float) -> tuple[tuple, dict]:
    """One refinement of the fold's bracket: ``found`` the refining stage's plateaus from the
    bracket's upper end down, ``off`` the bracket's lower end and ``lower_m`` the attractor's
    amplitude there. Returns the new bracket (the sub-step of the largest fall) and the level's
    record (:func:`~railexu.stability.fold.concentrated`)."""
    speeds = [p["speed_m_per_s"] for p in found] + [off]
    amps = [attractor_amplitude(p) or 0.0 for p in found] + [lower_m]
    c = concentrated(amps)
    j = c["index"] if c["index"] is not None else len(found) - 1
    level = {"bracket_m_per_s": [off, speeds[0]], "speeds_m_per_s": speeds,
             "attractor_amplitude_m": amps, **{k: c[k] for k in (
                 "largest_fall_m", "other_change_m", "jump")}}  # fmt: skip
    return (speeds[j], speeds[j + 1]), level


BRANCH_RULE = (
    "a plateau is on a cycle when it is not stable (growing or sustained); the branch followed "
    "from the top speed ends at a fold where its amplitude is discontinuous in speed: the "
    "largest fall of the attractor's amplitude (a stable plateau counts 0) within the first "
    "stage is refined, each refining stage stepping its bracket in equal sub-steps from the "
    "settled cycle above, and it is a jump when the largest fall across one sub-step exceeds the "
    "changes across all the other sub-steps together (on a continuous branch the change spreads "
    "over the sub-steps and shrinks with them; across a fold it stays the whole jump); no factor "
    "is chosen"
)


def label_branches(found: list[dict], fold_speed_m_per_s: float | None = None) -> None:
    """Numbers the branches down one stage (``p["branch"]``): 0 from the top plateau down to
    the fold (the plateaus at or above ``fold_speed_m_per_s``, the lowest speed on the branch
    followed from the top), then one more after the fold and after every stable plateau; stable
    plateaus get None. Below the fold a change is not split further: the fold reported is that
    of the branch followed from the top."""
    k, above = -1, None
    for p in found:
        if p.get("stable") is not False:
            p["branch"], above = None, p
            continue
        if above is None or above.get("stable") is not False:
            k += 1
        elif (
            k == 0
            and fold_speed_m_per_s is not None
            and (p["speed_m_per_s"] < fold_speed_m_per_s - 1e-9)
        ):
            k = 1
        p["branch"], above = k, p


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


def _fold_section(points: list[dict], fold: tuple | None, settings, search: dict) -> dict | None:
    """Where the branch followed from the top speed ends: ``bracket_m_per_s`` ([the speed below
    which it is lost, the lowest speed on it]), ``speed_m_per_s`` (the lowest on it),
    ``amplitude_m`` there, ``resolution_m_per_s``, ``converged`` (within ``tolerance``),
    ``discontinuity`` (``jump``: every refinement found the change in one sub-step; ``not
    refined``: the first stage's largest fall, its steps within the tolerance), ``levels`` (each
    refinement's record, :func:`_refine_fold`) and what the motion does below it (``below``:
    classification, amplitude and the envelope's growth over the plateau's first part, where it
    leaves the cycle above). None when the branch holds down to the lowest speed, or the
    largest fall was found continuous (``fold_search``)."""
    if not fold or fold[1] is None:
        return None
    on, off = fold
    at = [p for p in points if p["speed_m_per_s"] == on and p.get("branch") == 0]
    below = [p for p in points if p["speed_m_per_s"] == off]
    out = {"bracket_m_per_s": [off, on], "speed_m_per_s": on,
           "amplitude_m": at[-1].get("amplitude_m") if at else None,
           "resolution_m_per_s": on - off,
           "converged": on - off <= settings.tolerance_m_per_s + 1e-9,
           "discontinuity": search.get("discontinuity"),
           "levels": search.get("levels", [])}  # fmt: skip
    if below:
        b = below[-1]
        out["below"] = {k: b.get(k) for k in ("classification", "amplitude_m", "branch",
                                              "entry_classification",
                                              "entry_growth_per_period")}  # fmt: skip
    return out


def _label(points: list[dict], fold: tuple | None) -> None:
    """Branch labels of every stage's plateaus (:func:`label_branches`) from the fold found."""
    speed = fold[0] if fold and fold[1] is not None else None
    for k in sorted({p["stage"] for p in points}):
        label_branches([p for p in points if p["stage"] == k], speed)


def _finish(out: dict, settings, fold: tuple | None = None, loss: tuple | None = None) -> dict:
    """Fills the result from the fold and loss brackets; a status that :func:`_stage_end` set
    (``run stopped``, ``restart lost the cycle``) stays, unconverged."""
    ended = out["status"] in ("run stopped", "restart lost the cycle", "no verdict")
    ended_status = out["status"]
    points = out["branch"]
    _label(points, fold)
    out["branches"] = branches_of(points)
    out["fold"] = _fold_section(points, fold, settings, out.get("fold_search") or {})
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
        top = found[0]
        if any(p["stable"] is False for p in found[1:]):
            # a lower plateau, started from the top one's state, holds a cycle: the top one
            # was still on its way (e.g. onto its cycle from a larger disturbance), not at rest
            out.update(status="no verdict", note=(
                f"the plateau at the highest speed, {top['speed_m_per_s']:g} m/s, is "
                f"{top['classification']} ({(top.get('amplitude_m') or 0.0) * 1e3:.2f} mm, "
                f"{(top.get('growth_per_period') or 0.0):+.1%} per period) while lower plateaus "
                "started from its state hold a cycle: it had not settled; use a longer "
                "distance"))  # fmt: skip
            return True
        out.update(converged=True, status="converged", note=(
            f"no limit cycle at the highest speed, {top['speed_m_per_s']:g} m/s, from "
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
