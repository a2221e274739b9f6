"""The wear loop: run the route, accumulate the worn depth per wheel, step the mileage, update
the profiles, repeat (docs/wear.md, "The loop").

One step:

1. every case of the route (a section in one direction, :mod:`.route`) is run with the current
   profiles (``contact_outputs`` on) and worn by the chosen law over its evaluation window
   (:func:`railexu.results.wear.run_wear`): the depth per km across each wheel's profile;
   the step's cases are one study run by :func:`railexu.study.run_study` (local worker
   processes or a Dask distributed cluster, :mod:`.route_study`), resumable; a case that
   diverges is run again with half the integration step down to :data:`MIN_TIME_STEP_S`; a
   route that still does not complete at the profiles of the step just made makes that step
   again with half the depth (:data:`FAILURE_HALVINGS` times in a row at most), then stops;
   each case's wear is kept in ``step_NNN/cases/<case>.npz``, and a stopped loop resumes from
   the studies and these files;
2. the route's depth per km of each wheel is the share-weighted sum over the cases;
3. the depth per km is smoothed (:func:`~.profiles.smooth_normal_depth`: the depth normal to
   the current profile, spread by a Gaussian along ``y`` and turned back into the height change
   with the flank angle averaged by the same Gaussian; area kept);
4. the mileage step: rule ``max_depth`` (default): the largest smoothed depth taken off any
   wheel in the step is ``max_depth_m`` (0.1 mm by default), ``dL = max_depth_m / max(depth
   per km)``; rule ``fixed``: ``dL = step_km``; both end at the requested mileage; the depth
   times ``dL`` is added to the depth cumulated since the start, which is taken off each
   wheel's *new* profile (checked by :func:`~.profiles.profile_check`: a flange that is no
   longer monotone stops the loop); the profiles are written to
   ``step_NNN/profiles/`` and read back, so that the contact tables of the next step are built
   from those files;
5. per wheel: Sh, Sd, qR, the removed area and the conservation check (the area between the
   old and the new profile against the integral of the patches' volume rates times ``dL``);
   per wheelset: the equivalent conicity (EN 15302, amplitude 3 mm, nonlinear method) on the
   route's straight rails; from the route run that made the step (its ``folder``): per wheel
   the largest FI_surf and the WLRM damage per km, per rail the removed area and the WLRM
   damage per axle passage, share-weighted over the cases (:func:`_route_rcf`).

A step made again (the rate control or the failure rule) keeps its earlier attempts: each
attempt writes its profiles and runs its route in its own folders (``profiles``,
``profiles_again1``, ...; ``route``, ``route_again1``, ...), ``step_NNN/made_again.txt`` says
why, and a resumed loop reuses every finished run of every attempt.

The wheels wear, the rails do not (their wear per axle passage is reported per case).
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from railexu.contact.conicity import equivalent_conicity
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.wear.laws import DEFAULT_WEAR_LAW, wear_law_code
from railexu.errors import InputError
from railexu.model.assembly import wheelset_geometry
from railexu.operation.run_settings import RunSettings
from railexu.profiles import wheel_profile
from railexu.simulation.simulate import wheelset_order
from railexu.study.wear.profiles import (
    flange_measures,
    profile_check,
    profile_slope,
    removed_area,
    smooth_normal_depth,
    worn_profile,
)
from railexu.study.wear.route import Route, RouteCase, load_route
from railexu.study.wear.route_study import (
    MIN_TIME_STEP_S,
    attempt_name,
    profile_overrides,
    run_route_cases,
)
from railexu.vehicle.vehicle import Vehicle, load_vehicle

__all__ = ["MIN_TIME_STEP_S", "STEP_RULES", "WearLoopResult", "wear_loop"]

STEP_RULES = ("max_depth", "fixed")
#: rule max_depth: the largest change of the route's peak wear rate accepted over a step
RATE_TOLERANCE = 1.5
#: the smallest step depth the rate control halves to is max_depth / MAX_HALVINGS
MAX_HALVINGS = 64
#: rule max_depth: a route that does not complete at a step's profiles (a case diverged even at
#: :data:`MIN_TIME_STEP_S`) makes that step again with half the depth, at most this many times
#: in a row; then the loop stops (docs/wear.md, "Past a divergence")
FAILURE_HALVINGS = 2
#: the conicity amplitude (EN 15302: y = 3 mm) [m]
CONICITY_AMPLITUDE_M = 0.003
_SIDES = ("left", "right")


@dataclass
class WearLoopResult:
    """What :func:`wear_loop` did: one row per step (mileage at its end, per wheel and
    wheelset quantities) and where the files are."""

    out: Path
    steps: list[dict] = field(default_factory=list)
    complete: bool = False
    #: why the loop stopped before the mileage ("" when complete)
    reason: str = ""
    #: the cases that did not complete (even at :data:`MIN_TIME_STEP_S`) when the loop stopped
    #: for them, ``<section>_<direction>: <status>``; the profiles they ran with are the last
    #: step's, which is kept
    failed_cases: list[str] = field(default_factory=list)
    #: rule max_depth: the most times in a row a step is made again with half the depth because
    #: the route did not complete at its profiles
    failure_halvings: int = 0
    #: a non-monotone worn flange stops the loop when its radius rises again by at least this
    #: much [m] (0: any non-monotone flange)
    flank_rise_tolerance_m: float = 0.0

    def column(self, key: str) -> np.ndarray:
        """``key`` of every step's row, in order (NaN where missing)."""
        return np.array([row.get(key, math.nan) for row in self.steps], dtype=float)


def _wheel_keys(vehicle: Vehicle) -> list[tuple[str, int, str]]:
    """``(ws{k}_{side}, vehicle index, side)`` of every wheel, wheelsets from the front."""
    keys = []
    for k, i in enumerate(wheelset_order(vehicle), start=1):
        for side in _SIDES:
            keys.append((f"ws{k}_{side}", i, side))
    return keys


def _with_profiles(vehicle: Vehicle, profiles: dict[str, str]) -> Vehicle:
    """The vehicle with each wheel's profile file (``profiles[ws{k}_{side}]``)."""
    wheelsets = list(vehicle.wheelsets)
    for k, i in enumerate(wheelset_order(vehicle), start=1):
        ws = wheelsets[i]
        left, right = profiles[f"ws{k}_left"], profiles[f"ws{k}_right"]
        wheelsets[i] = dataclasses.replace(
            ws, wheel_profile=left, wheel_profile_right=right,
            nominal_radius_right_m=ws.radius_right_m,
        )  # fmt: skip
    return dataclasses.replace(vehicle, wheelsets=type(vehicle.wheelsets)(wheelsets))


def _vehicle_and_file(vehicle: Vehicle | str | Path) -> tuple[Vehicle, Path]:
    """The vehicle and the file a study's cases read it from (a vehicle object must be its
    file's, unchanged: the study's workers read the file)."""
    from railexu.inputs.catalog import find_input

    if isinstance(vehicle, str | Path):
        path = find_input("vehicle", vehicle).resolve()
        return load_vehicle(path), path
    path = Path(vehicle.source)
    if not path.is_file() or load_vehicle(path).raw != vehicle.raw:
        raise InputError(
            "the wear loop runs its cases as a study, whose workers read the vehicle file: give "
            "the vehicle file (or a vehicle loaded from it unchanged)",
            source=str(vehicle.source), key="vehicle",
        )  # fmt: skip
    return vehicle, path.resolve()


def _conicity(vehicle: Vehicle, track) -> dict:
    """Equivalent conicity of every wheelset (EN 15302, y = 3 mm, nonlinear method)."""
    out = {}
    for k, i in enumerate(wheelset_order(vehicle), start=1):
        geometry = wheelset_geometry(vehicle.wheelsets[i], track)
        model = WheelsetContactModel(geometry, vehicle.contact, 10.0)
        gamma = equivalent_conicity(model, [CONICITY_AMPLITUDE_M], out_of_range="nan")[0][0]
        out[f"ws{k}_conicity"] = float(gamma)
    return out


def _straight_track(route: Route, out: Path):
    from railexu.track.track import load_track

    case = RouteCase("conicity", 1.0, 10.0, 20.0, None, 0.0, "forward")
    return load_track(case.write_track(route, out / "tracks"))


def _sigterm_as_interrupt(func):
    """SIGTERM raises :class:`~railexu.errors.RunTerminated` (a ``KeyboardInterrupt``) while
    the loop runs, as in :func:`railexu.study.run_study`: the loop writes that it was
    interrupted and stops cleanly instead of being killed between two studies."""
    from railexu.study.runner import _sigterm_raises

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with _sigterm_raises():
            return func(*args, **kwargs)

    return wrapper


@_sigterm_as_interrupt
def wear_loop(
    vehicle: Vehicle | str | Path,
    route: Route | str | Path,
    mileage_km: float,
    out: str | Path,
    law: str = DEFAULT_WEAR_LAW,
    step_rule: str = "max_depth",
    max_depth_m: float = 1.0e-4,
    step_km: float | None = None,
    smoothing_m: float = 3.0e-3,
    workers: int | None = None,
    max_steps: int = 100,
    initial_lateral_m: float = 0.0,
    rate_tolerance: float | None = RATE_TOLERANCE,
    log=None,
    scheduler: Any = None,
    failure_halvings: int = FAILURE_HALVINGS,
    flank_rise_tolerance_m: float = 0.0,
) -> WearLoopResult:
    """Wear the vehicle's wheels over ``mileage_km`` of the route (module doc).

    Args:
        vehicle: a vehicle or its file; route: a route or its file (:mod:`.route`).
        mileage_km: the mileage to reach [km].
        out: the output folder (``steps.csv``, ``wear.json``, ``step_NNN/``, ``tracks/``).
        law: the wear law (:data:`~railexu.contact.wear.laws.WEAR_LAWS`).
        step_rule: ``max_depth`` (the largest depth per step is ``max_depth_m``) or ``fixed``
            (``step_km`` per step).
        smoothing_m: standard deviation of the Gaussian smoothing of the depth [m]; 3 mm by
            default (with 1 mm the wagon's curve cases diverged on the first worn profiles,
            docs/wear.md).
        workers: local worker processes for the cases of a step (as
            :func:`railexu.study.run_study`: default the number of CPUs, 0 in this process).
        scheduler: a Dask scheduler address (``tcp://host:port``) or a ``distributed.Client``:
            the cases run on that cluster (:func:`railexu.study.run_study`).
        max_steps: the most steps (the loop stops there and says so in ``wear.json``).
            A case that does not complete (derailed, diverged) is not worn: the step is made
            again (``failure_halvings``) or the loop stops, with the profiles so far and the
            reason in ``wear.json``.
        initial_lateral_m: the wheelsets' initial lateral offset in each case [m].
        rate_tolerance: rule ``max_depth``: a step over which the route's largest wear rate
            changes by more than this factor (up or down) is made again with half the depth
            (at most :data:`MAX_HALVINGS` times); the next step may double again up to
            ``max_depth_m``. None or 0: no control.
        log: a callable taking one line of progress (default: none).
        failure_halvings: rule ``max_depth``: when the route does not complete at the profiles
            of the step just made, that step is made again with half the depth, at most this
            many times in a row (and not below ``max_depth_m / MAX_HALVINGS``); 0: the loop
            stops at the first such route.
        flank_rise_tolerance_m: a worn flange that is not monotone stops the loop when the
            radius rises again by at least this much between the flange tip and the tape circle
            (:func:`~.profiles.profile_check`'s ``flank_rise_m``) [m]; 0 (default): any
            non-monotone flange stops it. A run on past such a flange relies on the contact
            coping with it (a route that does not complete stops the loop anyway:
            ``failure_halvings``); docs/wear.md, "Long loops on the shipped routes".

    Raises:
        InputError: bad arguments or input files.
    """
    log = log or (lambda line: None)
    wear_law_code(law)
    if step_rule not in STEP_RULES:
        raise InputError(f"{step_rule!r}: expected {' or '.join(STEP_RULES)}", key="step_rule")
    if not (math.isfinite(mileage_km) and 0.0 < mileage_km <= 1e7):
        raise InputError(f"{mileage_km!r}: expected 0 < mileage <= 1e7 km", key="mileage")
    if step_rule == "max_depth" and not (0.0 < max_depth_m <= 2e-3):
        raise InputError(f"{max_depth_m!r} m: expected 0 < max depth <= 2 mm", key="max_depth")
    if step_rule == "fixed" and not (step_km and math.isfinite(step_km) and step_km > 0.0):
        raise InputError(f"{step_km!r}: expected a step > 0 km", key="step_km")
    if isinstance(failure_halvings, bool) or not (
        isinstance(failure_halvings, int) and 0 <= failure_halvings <= 6
    ):
        raise InputError(f"{failure_halvings!r}: expected an integer 0 .. 6",
                         key="failure_halvings")  # fmt: skip
    if not (math.isfinite(flank_rise_tolerance_m) and 0.0 <= flank_rise_tolerance_m <= 1e-3):
        raise InputError(f"{flank_rise_tolerance_m!r} m: expected 0 .. 1 mm",
                         key="flank_rise_tolerance")  # fmt: skip
    if not (0.0 <= smoothing_m <= 0.01):
        raise InputError(f"{smoothing_m!r} m: expected 0 .. 10 mm", key="smoothing")
    vehicle, vehicle_file = _vehicle_and_file(vehicle)
    if isinstance(route, str | Path):
        route = load_route(route)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    keys = _wheel_keys(vehicle)
    profiles = {}
    for key, i, side in keys:
        ws = vehicle.wheelsets[i]
        profiles[key] = ws.wheel_profile if side == "left" else ws.profile_right
    straight = _straight_track(route, out)
    result = WearLoopResult(out=out, failure_halvings=failure_halvings,
                            flank_rise_tolerance_m=flank_rise_tolerance_m)  # fmt: skip
    mileage, step, rejected = 0.0, 0, 0
    current = {key: wheel_profile(profiles[key]) for key, _, _ in keys}
    # the new profiles and the depth removed since: every worn profile is the new one minus the
    # cumulated depth (the re-read points' errors do not accumulate over the steps)
    original = dict(current)
    total: dict[str, np.ndarray] = {}
    row0 = {"step": 0, "mileage_km": 0.0, "step_km": 0.0, "status": "new profiles",
            "folder": "", "profiles_folder": ""}  # fmt: skip
    row0.update(_measures(current, _conicity(_with_profiles(vehicle, profiles), straight)))
    result.steps.append(row0)
    _write_state(out, result, route, law, step_rule, max_depth_m, step_km, smoothing_m, False, "")
    reason = ""
    last = None  # the step just made: the profiles and rates it started from, its depth
    depth_limit = max_depth_m
    failures = 0  # steps made again in a row because the route did not complete
    note = ""  # why the next step is made again (its row's status)
    # each step's attempts: a step made again (rate control, failure rule) runs in new folders
    # (profiles_again1/, route_again1/, ...) and keeps its earlier attempts' files; why, in
    # step_NNN/made_again.txt
    attempts: dict[int, int] = {}
    notes: dict[int, list[str]] = {}
    control = step_rule == "max_depth" and bool(rate_tolerance)
    while True:
        reached = mileage >= mileage_km * (1.0 - 1e-9)
        if reached and (not control or last is None or last.get("checked")):
            break
        if step >= max_steps and not reached:
            reason = f"stopped after max_steps = {max_steps} steps at {mileage:.4g} km"
            break
        try:
            rates = _route_rates(vehicle, vehicle_file, profiles, route,
                                 out / f"step_{step:03d}", law, workers, scheduler,
                                 initial_lateral_m, keys, smoothing_m, log,
                                 attempts.get(step, 0), current)  # fmt: skip
        except KeyboardInterrupt:  # Ctrl-C, SIGTERM: the finished cases and steps are kept
            result.reason = (f"interrupted at {mileage:.6g} km (profiles of step {step}); run "
                             "the same loop again to resume")  # fmt: skip
            _write_state(out, result, route, law, step_rule, max_depth_m, step_km, smoothing_m,
                         False, result.reason)  # fmt: skip
            raise
        halve = (step_rule == "max_depth" and last is not None and failures < failure_halvings
                 and last["depth"] > max_depth_m / MAX_HALVINGS)  # fmt: skip
        if rates["bad"] and not halve:
            # a case that derailed, diverged or was stopped wears over part of its window only:
            # the loop stops here with the profiles so far and says why
            reason = (f"at {mileage:.6g} km (profiles of step {step}) cases did not complete "
                      f"(a diverged case was run again down to {MIN_TIME_STEP_S * 1e3:g} ms"
                      f"{_halvings_text(failures)}): {'; '.join(rates['bad'])}; the loop "
                      f"stopped, its {step} finished step(s) are kept")  # fmt: skip
            result.failed_cases = list(rates["bad"])
            result.steps[-1]["status"] += (
                f"; the route at this step's profiles did not complete "
                f"({'; '.join(rates['bad'])}): the loop stopped here"
            )
            log(reason)
            break
        if rates["bad"]:
            # the route did not complete at the last step's profiles: make it again with half
            # the depth (other profiles on the way to the same mileage)
            failures += 1
            note = (f"made again with half the depth: the route at the profiles of "
                    f"{result.steps[-1]['mileage_km']:.6g} km did not complete "
                    f"({'; '.join(rates['bad'])})")  # fmt: skip
            result.steps.pop()
            step -= 1
            profiles, current, mileage, total, rates, depth_limit = _state_before(last)
            rejected += 1
            _made_again(out, step + 1, attempts, notes, note, depth_limit)
            log(f"step {step + 1} {note}")
        elif last is not None and control:
            failures = 0
            ratio = rates["peak"] / last["rates"]["peak"]
            if not (1.0 / rate_tolerance <= ratio <= rate_tolerance) and (
                last["depth"] > max_depth_m / MAX_HALVINGS
            ):
                # the rate changed too much over the last step: make it again with half the depth
                result.steps.pop()
                step -= 1
                profiles, current, mileage, total, rates, depth_limit = _state_before(last)
                rejected += 1
                note = (f"made again with half the depth: the largest wear rate changed by a "
                        f"factor {ratio:.4g} over the step to "
                        f"{last['mileage'] + last['dl']:.6g} km (tolerance "
                        f"{rate_tolerance:.6g})")  # fmt: skip
                _made_again(out, step + 1, attempts, notes, note, depth_limit)
                log(f"step {step + 1} made again with half the depth "
                    f"({depth_limit * 1e3:.4g} mm): the largest wear rate changed by a factor "
                    f"{ratio:.3g} over it")  # fmt: skip
            else:
                last["checked"] = True
                depth_limit = min(max_depth_m, 2.0 * last["depth"])
                note = ""
                if reached:
                    break
        else:
            failures = 0
        if not rates["peak"] > 0.0:
            reason = "no wear on this route (every depth is zero)"
            break
        dl = depth_limit / rates["peak"] if step_rule == "max_depth" else float(step_km)
        dl = min(dl, mileage_km - mileage)
        last = {"profiles": dict(profiles), "current": dict(current), "mileage": mileage,
                "rates": rates, "depth": dl * rates["peak"], "total": dict(total),
                "dl": dl}  # fmt: skip
        step += 1
        profiles_dir = out / f"step_{step:03d}" / attempt_name("profiles", attempts.get(step, 0))
        row = {"step": step, "mileage_km": mileage + dl, "step_km": dl,
               "status": _step_status(rates["again"], note), "steps_made_again": rejected,
               "min_time_step_ms": rates["min_time_step_s"] * 1e3,
               "cases_run_again": "; ".join(rates["again"]), "folder": rates["folder"],
               "profiles_folder": profiles_dir.relative_to(out).as_posix(),
               **rates["rcf"]}  # fmt: skip
        note = ""
        new, total = {}, dict(total)
        for key, _, _ in keys:
            worn = rates["smooth"][key] * dl
            total[key] = total.get(key, 0.0) + worn
            path = profiles_dir / f"{key}.txt"
            new[key] = worn_profile(original[key], rates["y"], total[key], path,
                                    f"{key} after {mileage + dl:.6g} km ({law})")  # fmt: skip
            check = profile_check(new[key], original[key])
            row[f"{key}_flange_monotone"] = int(check["flange_monotone"])
            row[f"{key}_flank_rise_um"] = check["flank_rise_m"] * 1e6
            row[f"{key}_max_curvature_change_1_per_m"] = check["max_curvature_change_1_per_m"]
            area = removed_area(current[key], new[key])
            expected = rates["vol"][key] * dl
            row[f"{key}_area_mm2"] = area * 1e6
            row[f"{key}_area_integral_mm2"] = expected * 1e6
            row[f"{key}_conservation_error"] = area / expected - 1.0 if expected > 0 else 0.0
            row[f"{key}_max_depth_mm"] = float(worn.max() * 1e3)
            profiles[key] = str(path.resolve())
        current = new
        mileage += dl
        row.update(_measures(current, _conicity(_with_profiles(vehicle, profiles), straight)))
        result.steps.append(row)
        log(f"step {step}: {mileage:.5g} km (+{dl:.4g} km), largest depth "
            f"{max(row[f'{k}_max_depth_mm'] for k, _, _ in keys):.4f} mm")  # fmt: skip
        _write_state(out, result, route, law, step_rule, max_depth_m, step_km, smoothing_m,
                     False, "")  # fmt: skip
        folded = [k for k, _, _ in keys if not row[f"{k}_flange_monotone"]
                  and row[f"{k}_flank_rise_um"] >= flank_rise_tolerance_m * 1e6]  # fmt: skip
        if folded:
            rises = ", ".join(f"{row[f'{k}_flank_rise_um']:.3g}" for k in folded)
            reason = (
                f"at {mileage:.6g} km the worn flange of {', '.join(folded)} is no longer "
                "monotone (the radius does not fall from the flange tip to the tape circle: it "
                f"rises again by {rises} um"
                + (f", tolerance {flank_rise_tolerance_m * 1e6:g} um)" if flank_rise_tolerance_m
                   else ")")
            )  # fmt: skip
            log(reason)
            break
    result.complete = not reason
    result.reason = reason
    _write_state(out, result, route, law, step_rule, max_depth_m, step_km, smoothing_m,
                 result.complete, reason)  # fmt: skip
    return result


def _step_status(again: list[str], note: str = "") -> str:
    """A step's ``status`` in ``steps.csv``: ``completed``, which of the route's cases (run at
    the profiles the step started from) diverged at railexu's time step and completed at a
    smaller one (the rule of :func:`.route_study.run_route_cases`), and why the step was made
    again (``note``)."""
    text = "completed"
    if again:
        text += (f"; {len(again)} case(s) diverged and completed with a smaller time step: "
                 f"{'; '.join(again)}")  # fmt: skip
    return f"{text}; {note}" if note else text


def _halvings_text(failures: int) -> str:
    if not failures:
        return ""
    return f", and the step was made again with half the depth {failures} time(s)"


def _made_again(out: Path, step: int, attempts: dict, notes: dict, why: str,
                depth_m: float) -> None:  # fmt: skip
    """Step ``step`` is made again: its next attempt gets new folders; ``made_again.txt`` in
    its folder says which attempt was given up, why, and where the next one is."""
    a = attempts.get(step, 0)
    attempts[step] = a + 1
    old = f"{attempt_name('profiles', a)}/, {attempt_name('route', a)}/"
    new = f"{attempt_name('profiles', a + 1)}/, {attempt_name('route', a + 1)}/"
    notes.setdefault(step, []).append(
        f"attempt {a + 1} ({old}) given up, {why}; attempt {a + 2} with a largest depth of "
        f"{depth_m * 1e3:.6g} mm: {new}"
    )
    text = (
        f"step {step} was made again (docs/wear.md, 'A step made again'); every attempt's "
        "files are kept, steps.csv's row of the step names the accepted profiles "
        "(profiles_folder), the next row the route run its rates came from (folder)\n"
    )
    _atomic(out / f"step_{step:03d}" / "made_again.txt", text + "\n".join(notes[step]) + "\n")


def _route_rates(vehicle, vehicle_file, profiles, route, step_dir, law, workers, scheduler,
                 initial_lateral_m, keys, smoothing_m, log, attempt=0,
                 current=None) -> dict:  # fmt: skip
    """The route's smoothed depth per km of every wheel (share-weighted over the cases; smoothed
    as the depth normal to ``current[key]``, the profiles the route ran with), its
    volume rate per km, the largest depth per km and the cases that did not complete;
    ``folder``: the study folder of the route's run (``step_NNN/route_again1``)."""
    veh = _with_profiles(vehicle, profiles)
    items = profile_overrides(vehicle, wheelset_order(vehicle), profiles)
    cases = run_route_cases(veh, vehicle_file, items, route, step_dir, law, initial_lateral_m,
                            workers, scheduler, log, attempt)  # fmt: skip
    folder = f"{step_dir.name}/{attempt_name('route', attempt)}"
    bad = [f"{c.name}_{c.direction}: {r['status']}" for c, r in cases.items()
           if str(r["status"]) not in ("completed", "completed_with_exceedances")]  # fmt: skip
    if bad:
        return {"bad": bad, "folder": folder}
    steps = [float(r["time_step_s"]) for r in cases.values() if "time_step_s" in r]
    default_dt = RunSettings().time_step_s
    again = [f"{c.name}_{c.direction} ({float(r['time_step_s']) * 1e3:g} ms)"
             for c, r in cases.items()
             if float(r.get("time_step_s", default_dt)) < default_dt * (1 - 1e-9)]  # fmt: skip
    grid = np.asarray(next(iter(cases.values()))["grid"])
    depth = {k: sum(c.share * np.asarray(r[f"{k}_depth_per_km_m"]) for c, r in cases.items())
             for k, _, _ in keys}  # fmt: skip
    vol = {k: sum(c.share * float(r[f"{k}_volume_rate_per_km_m2"]) for c, r in cases.items())
           for k, _, _ in keys}  # fmt: skip
    y = grid[0] + grid[1] * np.arange(int(grid[2]))
    if current is None:
        current = {k: wheel_profile(profiles[k]) for k, _, _ in keys}
    smooth = {k: smooth_normal_depth(d, grid[1], smoothing_m, profile_slope(current[k], y))
              for k, d in depth.items()}  # fmt: skip
    return {
        "rcf": _route_rcf(cases, keys),
        "smooth": smooth,
        "vol": vol,
        "peak": max(float(d.max()) for d in smooth.values()),
        "bad": bad,
        "again": again,
        "min_time_step_s": min(steps) if steps else math.nan,
        "y": y,
        "folder": folder,
    }


def _route_rcf(cases: dict, keys: list) -> dict:
    """The route's RCF and rail wear of a step's rates (docs/wear.md, "RCF and rail wear per
    step"): per wheel the largest FI_surf of any case [-] and the WLRM damage per km
    (share-weighted over the cases, like the depth) [1/km]; per rail (the rail under the
    vehicle's left or right wheels) the removed area per axle passage [um^2] and the WLRM
    damage per axle passage [-], each share-weighted over the cases and averaged over the
    vehicle's axles."""
    from railexu.results.wear import RAIL_GRID

    row: dict[str, float] = {}
    for k, _, _ in keys:
        fi = [json.loads(str(r[f"{k}_summary"]))["fi_surf_max"] for r in cases.values()]
        fi = [float(v) for v in fi if v is not None]
        row[f"{k}_fi_surf_max_dimensionless"] = max(fi) if fi else math.nan
        row[f"{k}_wlrm_damage_per_km"] = sum(
            c.share * float(np.sum(r[f"{k}_wlrm_wheel_per_km"])) for c, r in cases.items()
        )
    for side in _SIDES:
        mine = [k for k, _, s in keys if s == side]
        area = [sum(c.share * float(np.sum(r[f"{k}_rail_depth_per_axle_m"])) * RAIL_GRID[1]
                    for c, r in cases.items()) for k in mine]  # fmt: skip
        dmg = [sum(c.share * float(np.sum(r[f"{k}_wlrm_rail_per_axle"])) for c, r in cases.items())
               for k in mine]  # fmt: skip
        row[f"rail_{side}_area_per_axle_um2"] = float(np.mean(area)) * 1e12
        row[f"rail_{side}_wlrm_damage_per_axle"] = float(np.mean(dmg))
    return row


def _measures(profiles: dict, conicity: dict) -> dict:
    row = dict(conicity)
    for key, p in profiles.items():
        for name, value in flange_measures(p).items():
            row[f"{key}_{name[:-2]}_mm"] = value * 1e3
    return row


def _write_state(out, result, route, law, rule, max_depth_m, step_km, smoothing_m, complete,
                 reason) -> None:  # fmt: skip
    """``steps.csv`` (one row per step) and ``wear.json`` (settings, rule, completion)."""
    keys: list[str] = []
    for row in result.steps:
        keys += [k for k in row if k not in keys]
    lines = [",".join(keys)]
    for row in result.steps:
        lines.append(",".join(_cell(row.get(k, "")) for k in keys))
    _atomic(out / "steps.csv", "\n".join(lines) + "\n")
    info = {
        "complete": complete,
        "reason": reason,
        "route": route.path or route.name,
        "law": law,
        "step_rule": rule,
        "rule_text": (
            f"each step's largest depth on any wheel is {max_depth_m * 1e3:g} mm"
            if rule == "max_depth"
            else f"fixed steps of {step_km} km"
        ),
        "smoothing_m": smoothing_m,
        "mileage_km": result.steps[-1]["mileage_km"] if result.steps else 0.0,
        "steps": len(result.steps) - 1,
        "conicity": "EN 15302, y = 3 mm, nonlinear method, on the route's straight rails",
        "time_step_rule": (
            "a case that diverges is run again with half the integration step, down to "
            f"{MIN_TIME_STEP_S * 1e3:g} ms; a case that still does not complete is not worn "
            "(failure_rule)"
        ),
        "failure_rule": (
            f"rule max_depth: when the route does not complete at a step's profiles, that step "
            f"is made again with half the depth, at most {result.failure_halvings} time(s) in a "
            "row; then the loop stops"
        ),
        "flange_rule": (
            "a worn flange that is not monotone (the radius does not fall from the flange tip "
            "to the tape circle) stops the loop"
            + (
                f" when the radius rises again by {result.flank_rise_tolerance_m * 1e6:g} um or "
                "more"
                if result.flank_rise_tolerance_m
                else ""
            )
        ),  # fmt: skip
        "failed_cases": list(result.failed_cases),
        "cases": [dataclasses.asdict(c) for c in route.cases],
        "pid": os.getpid(),
    }
    _atomic(out / "wear.json", json.dumps(info, indent=1) + "\n")


def _cell(v) -> str:
    if isinstance(v, float):
        return f"{v:.10g}"
    return str(v).replace(",", ";")


def _atomic(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)


def _state_before(last: dict) -> tuple:
    """The loop's state before its last step (profiles, current, mileage, total, rates) and
    half that step's depth [m]: the step made again."""
    return (last["profiles"], last["current"], last["mileage"], last["total"], last["rates"],
            0.5 * last["depth"])  # fmt: skip
