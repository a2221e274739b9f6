"""``railexu acceptance``: a vehicle taken through an EN 14363:2016 running-behaviour programme.

:func:`run_acceptance` reads the programme (``programmes/`` ships one per category; a user's copy
works the same), runs every section of every test zone as a case of a study (parallel local
workers or a Dask cluster, resumable: :mod:`railexu.study.acceptance.zone_study`), evaluates each
section's EN 14363 quantities (:func:`railexu.assessment.acceptance.quantities.section_values`),
combines them per zone with the zone's statistical method against the category's limits
(:func:`railexu.assessment.acceptance.statistics.evaluate_zone`), runs the quasi-static tests,
and writes ``acceptance.json`` (:mod:`railexu.study.acceptance.verdict`) and its figures.

Output folder ``DIR``:

- ``acceptance.json``: the programme, the vehicle (file and SHA-256), per zone its conditions,
  sections and criteria, the quasi-static tests and the verdict, written last (atomically): a
  folder without it holds no verdict;
- ``zones/<zone>/``: each zone's study (``study.yaml``, ``track.yaml``, ``results.csv``,
  ``cases/<case>/`` with each section's time series and summary);
- ``figures/``: per zone and quantity, the section values against the zone's regressor with the
  regression and the limit (:mod:`railexu.report.acceptance_figures`).

Running the same command into the same folder resumes it: finished sections are not run again.
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from railexu.errors import InputError

ACCEPTANCE_JSON = "acceptance.json"
ZONES_DIR = "zones"
FIGURES_DIR = "figures"


@dataclass
class AcceptanceResult:
    """Outcome of :func:`run_acceptance`.

    Attributes:
        out_dir: the output folder.
        data: the content of ``acceptance.json`` (a JSON-ready mapping).
        zone_results: per zone, its :class:`~railexu.assessment.acceptance.statistics.ZoneResult`
            (absent for a zone that could not be evaluated: see ``data``).
        section_values: per zone, the sections'
            :class:`~railexu.assessment.acceptance.quantities.SectionValues`.
    """

    out_dir: Path
    data: dict
    zone_results: dict[str, Any] = field(default_factory=dict)
    section_values: dict[str, list] = field(default_factory=dict)

    @property
    def verdict(self) -> str:
        """``pass``, ``fail`` or ``incomplete``."""
        return str(self.data["verdict"]["result"])


def run_acceptance(
    vehicle: str | Path,
    out_dir: str | Path,
    programme: str | Path | None = None,
    quick: bool = False,
    workers: int | None = None,
    scheduler: Any = None,
    vehicle_overrides: Iterable[str] = (),
    programme_overrides: Iterable[str] = (),
    quasi_static: bool = True,
    progress: Callable[[str], None] | None = None,
    run_settings: dict[str, str] | None = None,
    admissible_speed_m_per_s: float | None = None,
    admissible_cant_deficiency_m: float | None = None,
) -> AcceptanceResult:
    """Take ``vehicle`` through an EN 14363 running-behaviour programme.

    Args:
        vehicle: a vehicle file or a shipped name.
        out_dir: the output folder (created; an earlier acceptance there is resumed).
        programme: a programme file or shipped name; default: the shipped programme of the
            vehicle's category (``programmes/``).
        quick: the reduced programme (few sections): a trend, marked as such on every output,
            never an acceptance verdict.
        workers, scheduler: as :func:`railexu.run_study` (local worker processes, or a Dask
            scheduler address).
        vehicle_overrides: ``dotted.key=value`` changes of the vehicle (``--set``).
        programme_overrides: ``dotted.key=value`` changes of the programme.
        quasi_static: also run the quasi-static tests (twist, bogie yaw resistance).
        progress: called with one line of text per step (default: print to standard error).
        run_settings: keys of the run file's ``run:`` section for every section's run (e.g.
            ``{"time_step": "1 ms"}``: the step-size study of ``docs/acceptance.md``).
        admissible_speed_m_per_s, admissible_cant_deficiency_m: the vehicle's admissible speed
            [m/s] and cant deficiency [m]; each one not given is the vehicle file's
            (``admissible_speed``, ``admissible_cant_deficiency``) if it has one: the straight
            zones run at 1.1 times the speed and no curve section faster (``speed_max``), the
            curve zones' sections reach the cant deficiency and are evaluated at it
            (:func:`railexu.assessment.acceptance.admissible.admissible_overrides`; applied
            before ``programme_overrides``, which win). ``acceptance.json`` records each value
            and where it came from (``programme.admissible.source``).

    Raises:
        InputError: bad vehicle, programme or folder (naming the file, line and key).
    """
    from railexu.assessment.acceptance.programme import load_programme
    from railexu.inputs.catalog import find_input
    from railexu.study.acceptance.verdict import build_acceptance, write_acceptance
    from railexu.vehicle.vehicle import load_vehicle

    say = progress or _print_line
    overrides = tuple(vehicle_overrides)
    vehicle_file = find_input("vehicle", vehicle).resolve()
    vehicle_obj = load_vehicle(vehicle_file, overrides)
    if programme is None:
        programme = default_programme(vehicle_obj.category)
    prog = load_programme(programme, quick=quick, overrides=tuple(programme_overrides))
    admissible = admissible_values(vehicle_obj, admissible_speed_m_per_s,
                                   admissible_cant_deficiency_m)  # fmt: skip
    speed, cant = admissible["speed_m_per_s"], admissible["cant_deficiency_m"]
    if speed is not None or cant is not None:
        from railexu.assessment.acceptance.admissible import admissible_overrides

        admissible["overrides"] = admissible_overrides(prog, speed, cant)
        overrides_all = (*admissible["overrides"], *programme_overrides)
        prog = load_programme(programme, quick=quick, overrides=overrides_all)
    if prog.category != vehicle_obj.category:
        raise InputError(
            f"programme {prog.name!r} is for category {prog.category!r}, the vehicle "
            f"{vehicle_obj.name!r} is a {vehicle_obj.category!r}: choose the programme of its "
            "category (railexu list) or give one with --programme",
            source=prog.source, key="category",
        )  # fmt: skip
    out = Path(out_dir)
    _check_folder(out)
    say(
        f"railexu acceptance: {vehicle_obj.name} ({vehicle_obj.category}), programme "
        f"{prog.name}{' (quick: a trend, not an acceptance verdict)' if quick else ''}, "
        f"{sum(z.n_sections for z in prog.zones)} sections in {len(prog.zones)} zones"
    )
    zone_results, section_values, zone_errors, studies = {}, {}, {}, {}
    for zone in prog.zones:
        outcome = _run_zone(zone, prog, vehicle_file, vehicle_obj, overrides, out, workers,
                            scheduler, say, run_settings)  # fmt: skip
        studies[zone.name] = outcome["study"]
        if "error" in outcome:
            zone_errors[zone.name] = outcome["error"]
        else:
            zone_results[zone.name] = outcome["result"]
            section_values[zone.name] = outcome["sections"]
    tests = _quasi_static_tests(vehicle_obj, say) if quasi_static else {}
    data = build_acceptance(
        prog, vehicle_file, _sha256(vehicle_file), overrides, vehicle_obj, zone_results,
        section_values, zone_errors, studies, tests,
    )  # fmt: skip
    # the admissible values, where each came from and what they changed in the programme
    changed = list(admissible.get("overrides", ()))
    data["programme"]["admissible"] = {**admissible, "overrides": changed}
    result = AcceptanceResult(out, data, zone_results, section_values)
    _draw_figures(result, say)
    write_acceptance(out / ACCEPTANCE_JSON, data)
    say(f"verdict: {data['verdict']['result']} ({data['verdict']['reason']})")
    return result


def admissible_values(
    vehicle, speed_m_per_s: float | None, cant_deficiency_m: float | None
) -> dict[str, Any]:
    """The admissible speed [m/s] and cant deficiency [m] an acceptance runs with: each given
    value (the command line's, or the Python argument's) wins over the vehicle file's; ``source``
    says per value where it came from (``command line``, ``vehicle file <path>`` or ``none``:
    the programme's own conditions)."""
    out: dict[str, Any] = {"source": {}}
    for key, given, own in (
        ("speed_m_per_s", speed_m_per_s, vehicle.admissible_speed_m_per_s),
        ("cant_deficiency_m", cant_deficiency_m, vehicle.admissible_cant_deficiency_m),
    ):
        if given is not None:
            out[key], out["source"][key] = given, "command line"
        elif own is not None:
            out[key], out["source"][key] = own, f"vehicle file {vehicle.source}"
        else:
            out[key], out["source"][key] = None, "none (the programme's conditions)"
    return out


def default_programme(category: str) -> str:
    """The shipped programme of a vehicle category (``programmes/<category>.yaml``)."""
    from railexu.inputs.catalog import shipped_names

    names = {"wagon": "freight_wagon", "locomotive": "locomotive", "coach": "coach"}
    name = names.get(category, category)
    if name not in shipped_names("programme"):
        raise InputError(
            f"railexu ships no acceptance programme for category {category!r} (shipped: "
            f"{', '.join(shipped_names('programme'))}); give one with --programme"
        )
    return name


def _run_zone(
    zone, prog, vehicle_file, vehicle, overrides, out, workers, scheduler, say, run_settings=None
):
    from railexu.study import load_study, print_study_progress, run_study
    from railexu.study.acceptance.zone_study import (
        start_lead_m,
        write_zone_files,
        zone_study,
        zone_track,
    )

    sections = zone.sections()
    folder = out / ZONES_DIR / zone.name
    lead = start_lead_m(vehicle) if zone.kind == "curve" else 0.0
    name = zone_study_name(prog, zone)
    study_file = write_zone_files(
        folder,
        zone_track(zone, sections, lead),
        zone_study(zone, sections, vehicle_file, overrides, name, run_settings, lead),
    )
    say(f"zone {zone.name}: {len(sections)} sections ({zone.kind}, {zone.method})")
    study = load_study(study_file)
    stream = sys.stderr
    done = run_study(study, folder, workers=workers, scheduler=scheduler,
                     progress=print_study_progress(stream))  # fmt: skip
    outcome: dict[str, Any] = {"study": _study_summary(done, folder)}
    pct = _transition_comfort(done, folder)
    if pct["sections"]:
        outcome["study"]["curve_transition_comfort"] = pct
    try:
        svs = _section_values(done, folder, sections, vehicle)
        outcome["sections"] = svs
        outcome["result"] = _evaluate(zone, prog, svs, vehicle)
    except InputError as exc:
        outcome["error"] = str(exc)
        say(f"zone {zone.name}: not evaluated: {exc}")
    return outcome


def zone_study_name(prog, zone) -> str:
    """The name of a zone's study (its study page's and figures' title): the programme and the
    zone, and for the quick programme that it is a trend, not a verdict (issue 27: "saying so
    on every output")."""
    quick = " (quick programme: a trend, not an acceptance verdict)" if prog.quick else ""
    return f"{prog.name}: {zone.name}{quick}"


def _section_values(done, folder: Path, sections, vehicle) -> list:
    """The section values of every finished case (a failed or derailed case has none: the
    zone's evaluation then has fewer sections and says so)."""
    from railexu.assessment.acceptance.quantities import section_values
    from railexu.simulation.timeseries import TimeSeries
    from railexu.study.folder import CASES_DIR

    out = []
    for case, section in zip(done.study.cases(), sections, strict=True):
        row = next((r for r in done.rows if r.get("case_id") == case.case_id), None)
        if row is None or row.get("status") not in ("completed", "completed_with_exceedances"):
            continue
        ts_file = folder / CASES_DIR / case.case_id / "timeseries.csv"
        if not ts_file.is_file():
            continue
        out.append(section_values(TimeSeries.from_csv(ts_file), vehicle, section))
    return out


def _transition_comfort(done, folder: Path) -> dict:
    """EN 12299 P_CT of the sections' transitions (each finished case's summary,
    ``curve_transitions``): per section the largest over its points, and the zone's largest
    (railexu's rule: P_CT is reported, EN 14363 sets no limit on it)."""
    import json

    from railexu.study.folder import CASES_DIR

    sections: dict[str, dict] = {}
    clause = assumption = None
    for row in done.rows:
        if row.get("status") not in ("completed", "completed_with_exceedances"):
            continue
        path = folder / CASES_DIR / str(row.get("case_id")) / "summary.json"
        try:
            ct = json.loads(path.read_text()).get("curve_transitions") or {}
        except (OSError, ValueError):
            continue
        clause, assumption = ct.get("clause", clause), ct.get("assumption", assumption)
        for tr in ct.get("transitions", []):
            sections[str(row["case_id"])] = {
                k: tr[k] for k in ("start_m", "end_m", "P_CT_standing_percent",
                                   "P_CT_seated_percent")
            }  # fmt: skip
    out: dict[str, Any] = {"sections": sections, "clause": clause, "assumption": assumption}
    for key in ("P_CT_standing_percent", "P_CT_seated_percent"):
        values = [v[key] for v in sections.values()]
        out[f"max_{key}"] = max(values) if values else None
    return out


def _evaluate(zone, prog, svs, vehicle):
    from railexu.assessment.acceptance.limits import (
        limits_for,
        with_y_qst_radius_rule,
        y_qst_limit_radius_m,
    )
    from railexu.assessment.acceptance.quantities import bogie_mass_kg, static_wheel_load_N
    from railexu.assessment.acceptance.statistics import evaluate_zone

    sections = [sv.section for sv in svs] or zone.sections()
    radii = [s.radius_m for s in sections if s.radius_m]
    limits = limits_for(
        prog.category if prog.category else vehicle.category,
        static_wheel_load_N(vehicle),
        speed_m_per_s=max(s.speed_m_per_s for s in sections),
        mean_radius_m=y_qst_limit_radius_m(zone, radii),
        bogie_mass_kg=bogie_mass_kg(vehicle),
        overrides=prog.limits,
    )
    return evaluate_zone(zone, svs, with_y_qst_radius_rule(limits, zone))


def _quasi_static_tests(vehicle, say) -> dict:
    """The twist test and the bogie yaw-resistance test, or why they were not run."""
    tests: dict[str, Any] = {}
    try:
        from railexu.assessment.acceptance import twist
    except ImportError:  # pragma: no cover - the module ships with railexu
        twist = None
    if twist is None:
        tests["twist_test"] = {"status": "not_run", "reason": "not available"}
    else:
        say("twist test (safety against derailment on twisted track) ...")
        tests["twist_test"] = _guarded(lambda: twist.twist_test(vehicle).to_dict())
    try:
        from railexu.assessment.acceptance import yaw_resistance
    except ImportError:  # pragma: no cover
        yaw_resistance = None
    if yaw_resistance is None:
        tests["yaw_resistance_test"] = {"status": "not_run", "reason": "not available"}
    else:
        say("bogie yaw-resistance test ...")
        tests["yaw_resistance_test"] = _guarded(
            lambda: yaw_resistance.yaw_resistance_test(vehicle).to_dict()
        )
        if vehicle.category not in YAW_TEST_CATEGORIES:
            tests["yaw_resistance_test"] = _informative(tests["yaw_resistance_test"])
    return tests


#: The vehicle categories whose bogie yaw resistance is judged by the X factor: the limit
#: X <= 0.1 is UIC 530-2's, a leaflet for freight wagons (railexu's reading of EN 14363:2016
#: 6.2: for other categories the running tests in small-radius curves (Y/Q, Y_qst) judge the
#: yaw resistance; railexu's assumption until checked against the standard).
YAW_TEST_CATEGORIES = ("wagon",)


def _informative(entry: dict) -> dict:
    """A yaw-resistance result of a vehicle outside :data:`YAW_TEST_CATEGORIES`: not
    applicable, its X factor kept for information and not judged."""
    if entry.get("status") != "completed":
        return entry
    return {
        "status": "not_applicable",
        "reason": (
            "the X factor limit (0.1) is UIC 530-2's for freight wagons; for this category the "
            "running tests in small-radius curves judge the yaw resistance (railexu's reading "
            "of EN 14363:2016 6.2, an assumption)"
        ),
        "assumption": True,
        "informative": {k: v for k, v in entry.items() if k != "status"},
    }


def _guarded(compute: Callable[[], dict]) -> dict:
    try:
        result = compute()
        result["run_status"] = result.pop("status", None)  # the test's own run
        return {"status": "completed", **result}
    except InputError as exc:
        return {"status": "not_applicable", "reason": str(exc)}


def _study_summary(done, folder: Path) -> dict:
    return {
        "folder": str(folder),
        "cases": len(done.study.cases()),
        "counts": done.counts,
        "ran": done.ran,
        "resumed": done.skipped,
        "elapsed_s": done.elapsed_s,
    }


def _draw_figures(result: AcceptanceResult, say) -> None:
    from railexu.report.acceptance_figures import draw_acceptance_figures

    files = draw_acceptance_figures(result.data, result.out_dir / FIGURES_DIR)
    result.data["figures"] = [str(Path(FIGURES_DIR) / f.name) for f in files]
    say(f"figures: {len(files)} in {result.out_dir / FIGURES_DIR}")


def _check_folder(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise InputError(f"{out} is a file; --out must be a folder")
    foreign = [p.name for p in out.glob("*") if p.name in ("summary.json", "results.csv")]
    if foreign:
        raise InputError(
            f"{out} holds another kind of output ({', '.join(foreign)}): choose another --out"
        )


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _print_line(text: str) -> None:
    print(text, file=sys.stderr, flush=True)
