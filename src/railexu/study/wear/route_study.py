"""One wear step's route run as a study (docs/wear.md, "One step").

The cases of a route (:mod:`.route`) with the current wheel profiles become one study
(docs/study-format.md) run by :func:`railexu.study.run_study`: on local worker processes or a
Dask distributed cluster, resumable (a case in the study's ``results.csv`` with the same hash is
not run again; a worn profile file whose content changed changes every hash), its folder
complete or saying it is not (the study's own contract). The study has one base track (the
route's first case) and varies, zipped, the track's ``geometry.sections``, ``run.speed``,
``run.distance`` and ``run.evaluate_from`` (and ``irregularities`` when a case has any:
:mod:`.route`, their two directions); the worn profiles are base overrides of the vehicle
(``wheelsets.<name>.wheel_profile={left: file, right: file}``), the run records the contact
points (``contact_outputs: true``).

A straight's ``reverse`` case is its mirrored case (:attr:`.route.RouteCase.mirrored`): in
a study that has one, the profiles and the initial lateral offset are varied per case (zipped
with the track): each wheelset's ``{left: R, right: L}`` and ``-initial_lateral``; its wear is
mapped back to the real wheels (the simulated left wheel's and the rail under it are the real
right wheel's; the wheel and rail grids are each in their own outward frame, so they are not
flipped).

A case that diverges is run again with half the integration step, down to
:data:`MIN_TIME_STEP_S`, as a study of the diverged cases alone in the folder of that step
(``route_dt1ms``, ...). Each case's wear (:func:`railexu.results.wear.run_wear` of its recorded
``timeseries.csv``, in this process) is kept in ``cases/<section>_<direction>.npz`` with the
case's hash, the law and the coefficient file's digest, so that a resumed loop does not compute
it again.
"""

from __future__ import annotations

import hashlib
import json
import math
import shutil
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from railexu.study.wear.route import Route, RouteCase
from railexu.vehicle.vehicle import Vehicle

__all__ = [
    "MIN_TIME_STEP_S",
    "attempt_name",
    "mirrored_parameters",
    "route_study_data",
    "run_route_cases",
]

#: a case that diverges is run again with half the integration step, down to this step [s]
#: (docs/wear.md, "Worn profiles that diverge": the contact sweeping across a worn flange root
#: needed 0.5 ms where the new profiles run with railexu's 2 ms)
MIN_TIME_STEP_S = 2.5e-4
#: the layout of the cases' .npz files (a file of another layout is computed again)
_NPZ_VERSION = 2
#: statuses whose case wore over its whole window
_DONE = ("completed", "completed_with_exceedances")


def attempt_name(kind: str, attempt: int) -> str:
    """The folder of attempt ``attempt`` (0: the first) of a step's ``kind`` (``route``,
    ``profiles``, ``cases``): ``route``, ``route_again1``, ... (docs/wear.md, "A step made
    again")."""
    return kind if attempt == 0 else f"{kind}_again{attempt}"


def _dt_name(route_name: str, dt_s: float) -> str:
    return f"{route_name}_dt{dt_s * 1e3:g}ms".replace(".", "p")


def profile_overrides(vehicle: Vehicle, order: list[int], profiles: dict[str, str]) -> list[str]:
    """Base ``set`` items of the study: each wheelset's worn profile files (absolute paths),
    ``vehicle.wheelsets.<name>.wheel_profile={left: ..., right: ...}``; none for a wheel that
    still has its vehicle file's profile."""
    items = []
    for k, i in enumerate(order, start=1):
        ws = vehicle.wheelsets[i]
        left, right = profiles[f"ws{k}_left"], profiles[f"ws{k}_right"]
        if left == ws.wheel_profile and right == ws.profile_right:
            continue
        value = yaml.safe_dump({"left": left, "right": right}, default_flow_style=True,
                               width=10**9).strip()  # fmt: skip
        items.append(f"vehicle.wheelsets.{ws.name}.wheel_profile={value}")
    return items


def mirrored_parameters(
    vehicle: Vehicle, cases: list[RouteCase], initial_lateral_m: float
) -> dict[str, list[Any]]:
    """The per-case parameters of a study with a mirrored case (module doc): every wheelset's
    profiles (``{left, right}``, swapped in a mirrored case) and ``run.initial_lateral``
    (negated in a mirrored case) [m].

    Raises:
        InputError: a wheelset whose two wheels have different nominal radii (its mirrored
            case would need the radii swapped too).
    """
    from railexu.errors import InputError

    params: dict[str, list[Any]] = {}
    for ws in vehicle.wheelsets:
        if abs(ws.nominal_radius_m - ws.radius_right_m) > 1e-12:
            raise InputError(
                f"wheelset {ws.name}: the left and right nominal radii differ "
                f"({ws.nominal_radius_m} and {ws.radius_right_m} m); a straight run 'reverse' "
                "(its mirrored case) needs equal radii: use directions: forward",
                source=str(vehicle.source), key=f"wheelsets.{ws.name}.nominal_radius",
            )  # fmt: skip
        left, right = ws.wheel_profile, ws.profile_right
        params[f"vehicle.wheelsets.{ws.name}.wheel_profile"] = [
            {"left": right, "right": left} if c.mirrored else {"left": left, "right": right}
            for c in cases
        ]
    y0 = float(initial_lateral_m)
    params["run.initial_lateral"] = [f"{(-y0 if c.mirrored and y0 else y0):.12g} m" for c in cases]
    return params


def route_study_data(
    route: Route,
    cases: list[RouteCase],
    vehicle_file: Path,
    set_items: list[str],
    run: dict[str, str],
    name: str,
    mirrored: dict[str, list[Any]] | None = None,
) -> tuple[dict, dict]:
    """``(track, study)`` mappings of the study of ``cases`` (module doc); ``run`` adds base
    run settings (time step, initial lateral offset); ``mirrored``: the per-case parameters of
    :func:`mirrored_parameters` (they replace the profiles' base overrides and the base
    ``initial_lateral``)."""
    tracks = [c.track_data(route) for c in cases]
    params: dict[str, list[Any]] = {
        "track.geometry.sections": [t["geometry"]["sections"] for t in tracks],
        "run.speed": [f"{c.speed_m_per_s:.12g} m/s" for c in cases],
        "run.distance": [f"{c.distance_m:.12g} m" for c in cases],
        "run.evaluate_from": [f"{c.evaluate_from_m:.12g} m" for c in cases],
    }
    if any(t["irregularities"].get("type") != "none" for t in tracks):
        params["track.irregularities"] = [t["irregularities"] for t in tracks]
    if mirrored:
        params.update(mirrored)
        varied = tuple(f"{k}=" for k in mirrored if k.startswith("vehicle."))
        set_items = [s for s in set_items if not s.startswith(varied)]
        run = {k: v for k, v in run.items() if k != "initial_lateral"}
    base: dict[str, Any] = {
        "vehicle": str(vehicle_file),
        "track": "track.yaml",
        "run": {"contact_outputs": True, **run},
    }
    if set_items:
        base["set"] = list(set_items)
    study = {
        "format_version": 1,
        "name": name,
        "description": "the route's cases of one wear step (railexu wear, docs/wear.md): "
        + ", ".join(f"{c.name} {c.direction}{' (mirrored)' if c.mirrored else ''}" for c in cases),
        "analysis": "run",
        "base": base,
        "vary": {"combine": "zip", "parameters": params},
        "collect": ["max_Y_over_Q.value", "max_abs_lateral_force_N"],
    }
    return tracks[0], study


def _write_study(folder: Path, track: dict, study: dict) -> Path:
    """Write ``track.yaml`` and ``study.yaml``; a folder holding another study's files (another
    set of cases) is emptied first (its results belong to other cases). Returns the study
    file."""
    texts = {n: yaml.safe_dump(d, sort_keys=False, allow_unicode=True)
             for n, d in (("track.yaml", track), ("study.yaml", study))}  # fmt: skip
    old = folder / "study.yaml"
    if old.is_file() and old.read_text(encoding="utf-8") != texts["study.yaml"]:
        shutil.rmtree(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for n, text in texts.items():
        path = folder / n
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            tmp = path.with_name(f".{n}.tmp")
            tmp.write_text(text, encoding="utf-8")
            tmp.replace(path)
    return folder / "study.yaml"


def run_route_cases(
    vehicle: Vehicle,
    vehicle_file: Path,
    set_items: list[str],
    route: Route,
    step_dir: Path,
    law: str,
    initial_lateral_m: float,
    workers: int | None,
    scheduler: Any,
    log,
    attempt: int = 0,
) -> dict[RouteCase, dict]:
    """Every case's result of one step (module doc): status, the time step it completed with,
    and per wheel the depth per km, the volume rate per km, the rail's depth per axle and the
    summary of :func:`~railexu.results.wear.run_wear`.

    ``attempt``: the how-manieth attempt of the step this is (0: the first; a step made again
    by the rate control or the failure rule, docs/wear.md): each attempt runs in its own
    folders (``route``, ``route_again1``, ...; the cases' wear in ``cases``, ``cases_again1``,
    ...), so that every attempt's finished runs stay and a resumed loop reuses them."""
    from railexu.operation.run_settings import RunSettings
    from railexu.study import StudyWarning, load_study, run_study

    dt = RunSettings().time_step_s
    todo = list(route.cases)
    final: dict[RouteCase, tuple[Path, dict, float]] = {}
    first = True
    name = attempt_name("route", attempt)
    while todo:
        folder = step_dir / (name if first else _dt_name(name, dt))
        run = {"initial_lateral": f"{initial_lateral_m:.12g} m"}
        if not first:
            run["time_step"] = f"{dt:.12g} s"
        title = (f"{route.name}: wear step {step_dir.name}"
                 + (f", made again ({attempt})" if attempt else "")
                 + ("" if first else f", {dt * 1e3:g} ms"))  # fmt: skip
        mirror = (mirrored_parameters(vehicle, todo, initial_lateral_m)
                  if any(c.mirrored for c in todo) else None)  # fmt: skip
        track, data = route_study_data(route, todo, vehicle_file, set_items, run, title, mirror)
        study = load_study(_write_study(folder, track, data))
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", StudyWarning)
            done = run_study(study, folder, workers=workers, scheduler=scheduler)
        for w in caught:
            log(f"{step_dir.name}: {w.message}")
        if done.ran:
            log(f"{step_dir.name}: {done.ran} case(s) run ({done.skipped} from before) in "
                f"{time.perf_counter() - t0:.1f} s, {folder.name}")  # fmt: skip
        rows = {r["case_id"]: r for r in done.rows}
        diverged = []
        for case, c in zip(todo, study.cases(), strict=True):
            row = rows[c.case_id]
            final[case] = (folder / "cases" / c.case_id, row, dt)
            if row["status"] == "diverged":
                diverged.append(case)
        first = False
        if not diverged or dt <= MIN_TIME_STEP_S * (1 + 1e-9):
            break
        dt = max(MIN_TIME_STEP_S, 0.5 * dt)
        todo = diverged
        log(f"{step_dir.name}: {len(diverged)} case(s) diverged, run again with {dt * 1e3:g} ms")
    cases_dir = step_dir / attempt_name("cases", attempt)
    return {
        case: _case_wear(vehicle, route, case, *final[case], law, cases_dir) for case in route.cases
    }


def _case_file(cases_dir: Path, case: RouteCase) -> Path:
    return cases_dir / f"{case.name}_{case.direction}.npz"


def _case_wear(vehicle, route, case, case_dir: Path, row: dict, dt: float, law: str,
               cases_dir: Path) -> dict:  # fmt: skip
    """The wear of one finished case, from its ``.npz`` when it was computed for the same case
    hash, law and coefficient file, else from its ``timeseries.csv``."""
    from railexu.contact.wear.coefficients import COEFFICIENTS_FILE
    from railexu.results.wear import WHEEL_GRID, run_wear
    from railexu.simulation.timeseries import TimeSeries

    status = row["status"]
    coefficients = hashlib.sha256(COEFFICIENTS_FILE.read_bytes()).hexdigest()
    stamp = json.dumps([_NPZ_VERSION, row["case_hash"], status, law, coefficients,
                        str(case_dir), case.mirrored])  # fmt: skip
    path = _case_file(cases_dir, case)
    if path.is_file():
        with np.load(path, allow_pickle=False) as data:
            if str(data["stamp"]) == stamp:
                return {k: data[k] for k in data.files}
    out: dict[str, Any] = {
        "status": status if status != "failed" else f"failed ({row.get('error', '')})",
        "wall_s": float(row["run_time_s"] or math.nan),
        "time_step_s": dt,
        "grid": np.array(WHEEL_GRID),
    }
    ts_file = case_dir / "timeseries.csv"
    if status in _DONE:  # a case that did not complete stops the loop: nothing to wear
        wears = run_wear(TimeSeries.from_csv(ts_file), vehicle, law,
                         evaluate_from_m=case.evaluate_from_m, gauge_m=route.gauge_m)  # fmt: skip
        out["rail_grid"] = wears[0].rail_lateral_m
        for w in wears:
            side = w.side
            if case.mirrored:  # the simulated left wheel (and rail) is the real right one
                side = "right" if w.side == "left" else "left"
                w.side = side
            key = f"{w.wheelset}_{side}"
            out[f"{key}_depth_per_km_m"] = w.depth_per_km_m
            out[f"{key}_volume_rate_per_km_m2"] = np.array(w.volume_rate_per_km_m2)
            out[f"{key}_rail_depth_per_axle_m"] = w.rail_depth_per_axle_m
            out[f"{key}_wlrm_wheel_per_km"] = w.wlrm_wheel_per_km
            out[f"{key}_wlrm_rail_per_axle"] = w.wlrm_rail_per_axle
            summary = w.summary()
            if case.mirrored:
                summary["mirrored_case"] = True
            out[f"{key}_summary"] = json.dumps(summary)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.tmp.npz")
    np.savez(tmp, stamp=np.array(stamp), **{k: np.asarray(v) for k, v in out.items()})
    tmp.replace(path)
    return out
