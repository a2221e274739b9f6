"""Parameter studies: study files, wildcard overrides, local and Dask execution, resume, plots.

The runs use the single wheelset over 5 m (a fraction of a second each); the process pools and
the Dask cluster dominate the time of this file.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import sys
import textwrap
from pathlib import Path

import pytest
import yaml

from railexu import study as S
from railexu.cli.study import add_parser as add_study_parser
from railexu.inputs import InputError, apply_overrides, load_yaml
from railexu.study import (
    StudyError,
    StudyProgress,
    StudyWarning,
    load_study,
    read_results,
    run_study,
)
from railexu.study.plots import plot_study
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
VEHICLES = ROOT / "vehicles"
TRACKS = ROOT / "tracks"
STUDIES = ROOT / "studies"

COLLECT = [
    "max_abs_lateral_force_N",
    "hunting.detected",
    "hunting.wavelength_m",
    "wheelsets.0.max_abs_lateral_m",
    "max_Y_over_Q.value",
]


def write_study(folder: Path, body: str, name: str = "study.yaml", collect=COLLECT) -> Path:
    """A study of the single wheelset over 5 m with ``body`` (the vary section and more)."""
    head = f"""\
        format_version: 1
        name: wheelset test
        base:
          vehicle: {VEHICLES / "wheelset.yaml"}
          run: {{distance: 5 m, initial_lateral: 2 mm}}
        """
    text = textwrap.dedent(head) + textwrap.dedent(body)
    if collect is not None:
        text += f"collect: {json.dumps(list(collect))}\n"
    path = folder / name
    path.write_text(text)
    return path


def parse(tmp_path: Path, text: str):
    path = tmp_path / "s.yaml"
    path.write_text(textwrap.dedent(text))
    return load_study(path)


def study_error(tmp_path: Path, text: str) -> str:
    with pytest.raises(InputError) as info:
        parse(tmp_path, text)
    return str(info.value)


HEAD = f"""\
format_version: 1
name: t
base:
  vehicle: {VEHICLES / "wheelset.yaml"}
"""


# ----------------------------------------------------------------------------------------------
# Wildcard overrides (railexu.inputs.apply_overrides)
# ----------------------------------------------------------------------------------------------


def test_wildcard_override_sets_every_matching_entry():
    data, _ = load_yaml(VEHICLES / "eu07.yaml")
    out = apply_overrides(data, ["suspension.primary_ws*.stiffness.x=4 MN/m"])
    for i in range(1, 5):
        assert out["suspension"][f"primary_ws{i}"]["stiffness"]["x"] == "4 MN/m"
        assert out["suspension"][f"primary_ws{i}"]["stiffness"]["y"] == "2.5 MN/m"
    assert out["suspension"]["secondary_1"]["stiffness"]["x"] == "2 MN/m"
    assert data["suspension"]["primary_ws1"]["stiffness"]["x"] == "8 MN/m"  # input unchanged
    # '?' matches one character; list items by index pattern
    out = apply_overrides(data, ["wheelsets.ws?.mass=4.5 t", "sources.*=none"])
    assert {ws["mass"] for ws in out["wheelsets"].values()} == {"4.5 t"}
    assert out["sources"] == ["none", "none"]
    # the vehicle reader sees all eight mirrored primary elements changed
    vehicle = load_vehicle(VEHICLES / "eu07.yaml", ["suspension.primary_ws*.stiffness.x=16e6"])
    primary = [e for e in vehicle.suspension if e.name.startswith("primary_ws")]
    assert len(primary) == 8
    assert all(e.stiffness_N_per_m == (16e6, 2.5e6, 1.1e6) for e in primary)
    others = [e for e in vehicle.suspension if e.name.startswith("secondary")]
    assert all(e.stiffness_N_per_m[0] == 2e6 for e in others)


def test_wildcard_override_errors():
    data, _ = load_yaml(VEHICLES / "eu07.yaml")
    with pytest.raises(
        InputError,
        match=r"suspension\.tertiary_\*: pattern 'tertiary_\*' "
        r"matches no key here \(there are: primary_ws1, ",
    ):
        apply_overrides(data, ["suspension.tertiary_*.stiffness.x=1"])
    # a matched entry without the rest of the path is an error, not silently skipped
    with pytest.raises(
        InputError,
        match=r"suspension\.pivot_yaw_1\.stiffness\.x: suspension"
        r"\.pivot_yaw_1\.stiffness is a value",
    ):
        apply_overrides(data, ["suspension.*.stiffness.x=1"])
    with pytest.raises(InputError, match="matches no list index"):
        apply_overrides(data, ["sources.7*=x"])


def test_override_behaviour_without_wildcards_is_unchanged():
    data, _ = load_yaml(VEHICLES / "wheelset.yaml")
    out = apply_overrides(data, ["wheelsets.ws1.mass=4.5 t", "wheelsets.ws1.notes=new key"])
    assert out["wheelsets"]["ws1"]["mass"] == "4.5 t" and out["wheelsets"]["ws1"]["notes"]
    with pytest.raises(InputError, match="no key 'wheelset' here. Did you mean 'wheelsets'"):
        apply_overrides(data, ["wheelset.ws1.mass=1"])
    with pytest.raises(InputError, match=r"no list item '5' \(the list has 1 items\)"):
        apply_overrides(data, ["sources.5=x"])


# ----------------------------------------------------------------------------------------------
# Study files
# ----------------------------------------------------------------------------------------------


def test_ranges_lists_units_and_case_order(tmp_path):
    study = parse(
        tmp_path,
        HEAD
        + """\
vary:
  parameters:
    run.speed: {from: 36 km/h, to: 108 km/h, step: 18 km/h}
    vehicle.wheelsets.ws1.mass: [4 t, 4500 kg, 4600]
""",
    )
    speed, mass = study.parameters
    assert speed.values == ("36 km/h", "54 km/h", "72 km/h", "90 km/h", "108 km/h")
    assert speed.si_values == pytest.approx((10.0, 15.0, 20.0, 25.0, 30.0), rel=1e-12)
    assert speed.quantity and speed.unit == "m/s"
    assert mass.values == ("4 t", "4500 kg", 4600)
    assert mass.si_values == (4000.0, 4500.0, 4600.0)
    assert mass.quantity and mass.unit == "kg"
    cases = study.cases()
    assert len(cases) == 15
    assert [c.case_id for c in cases[:2]] == ["case_0000", "case_0001"]
    # product: the last parameter varies fastest
    assert cases[1].values == {"run.speed": "36 km/h", "vehicle.wheelsets.ws1.mass": "4500 kg"}
    assert cases[3].values["run.speed"] == "54 km/h"
    assert len({c.hash for c in cases}) == 15
    assert [c.hash for c in load_study(tmp_path / "s.yaml").cases()] == [c.hash for c in cases]
    assert study.vehicle_overrides(cases[1]) == ["wheelsets.ws1.mass=4500 kg"]
    assert study.settings_data(cases[3])["speed"] == "54 km/h"
    assert study.columns()[:5] == [
        "case_id",
        "run.speed",
        "run.speed_si",
        "vehicle.wheelsets.ws1.mass",
        "vehicle.wheelsets.ws1.mass_si",
    ]
    assert study.columns()[-4:] == ["status", "error", "run_time_s", "case_hash"]


def test_range_includes_to_within_half_a_step_and_plain_numbers(tmp_path):
    study = parse(
        tmp_path,
        HEAD
        + """\
vary:
  parameters:
    run.speed: {from: 10, to: 24.9, step: 5}
    run.initial_lateral: {from: 0 mm, to: 0.3 mm, step: 0.1 mm}
""",
    )
    speed, lateral = study.parameters
    assert speed.values == (10, 15, 20, 25) and not speed.quantity and speed.unit == "m/s"
    assert lateral.values == ("0 mm", "0.1 mm", "0.2 mm", "0.3 mm")
    assert lateral.si_values == pytest.approx((0.0, 1e-4, 2e-4, 3e-4), abs=1e-15)


def test_zip_combines_element_wise_and_needs_equal_lengths(tmp_path):
    text = (
        HEAD
        + """\
vary:
  combine: zip
  parameters:
    run.speed: [10 m/s, 20 m/s, 30 m/s]
    run.distance: [5 m, 6 m, 7 m]
"""
    )
    cases = parse(tmp_path, text).cases()
    assert [(c.values["run.speed"], c.values["run.distance"]) for c in cases] == [
        ("10 m/s", "5 m"),
        ("20 m/s", "6 m"),
        ("30 m/s", "7 m"),
    ]
    message = study_error(tmp_path, text.replace("[5 m, 6 m, 7 m]", "[5 m, 6 m]"))
    assert message.startswith(f"{tmp_path / 's.yaml'}:6: vary.combine: zip needs lists")
    assert "run.speed has 3 (line 8), run.distance has 2 (line 9)" in message


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ("colect: [a]\n", r"s.yaml:5: colect: unknown key. Did you mean 'collect'\?"),
        (
            "vary:\n  parameters:\n    run.sped: [10 m/s]\n",
            r"s.yaml:7: vary.parameters.run.sped: unknown run key 'sped'. Did you mean 'speed'\?",
        ),
        (
            "vary:\n  parameters:\n    vehicel.wheelsets.ws1.mass: [1 t]\n",
            r"s.yaml:7: vary.parameters.vehicel.wheelsets.ws1.mass: unknown parameter path: "
            r"it must start with vehicle., track., run. followed by a key. Did you mean "
            r"'vehicle'\?",
        ),
        (
            "vary:\n  parameters:\n    vehicle.wheelset.ws1.mass: [1 t]\n",
            r"s.yaml:7: vary.parameters.vehicle.wheelset.ws1.mass: .*wheelset.yaml: wheelset: "
            r"no key 'wheelset' here. Did you mean 'wheelsets'\?",
        ),
        (
            "vary:\n  parameters:\n    vehicle.wheelsets.ws1.mas: [1 t]\n",
            r"s.yaml:7: vary.parameters.vehicle.wheelsets.ws1.mas: .*wheelset.yaml:\d+: "
            r"wheelsets.ws1.mas: unknown key. Did you mean 'mass'\?",
        ),
        (
            "vary:\n  parameters:\n    vehicle.wheelsets.w*.mass: []\n",
            r"s.yaml:7: vary.parameters.vehicle.wheelsets.w\*.mass: empty list",
        ),
        (
            "vary:\n  parameters:\n    vehicle.wheelsets.x*.mass: [1 t]\n",
            r"s.yaml:7: .*pattern 'x\*' matches no key here \(there are: ws1\)",
        ),
        (
            "vary:\n  parameters:\n    run.speed: 10 m/s\n",
            r"s.yaml:7: vary.parameters.run.speed: expected a list of values",
        ),
        (
            "vary:\n  parameters:\n    run.speed: {from: 10 m/s, to: 40 m/s, step: 0 m/s}\n",
            r"s.yaml:7: vary.parameters.run.speed.step: step must be > 0",
        ),
        (
            "vary:\n  parameters:\n    run.speed: {from: 10 m/s, to: 4 m/s, step: 1 m/s}\n",
            r"s.yaml:7: vary.parameters.run.speed.to: to \('4 m/s'\) must be >= from",
        ),
        (
            "vary:\n  parameters:\n    run.speed: {from: 10 m/s, to: 40 m/s, stp: 1 m/s}\n",
            r"s.yaml:7: vary.parameters.run.speed.stp: unknown key. Did you mean 'step'\?",
        ),
        (
            "vary:\n  parameters:\n    run.speed: {from: 10 m/s, to: 40 m, step: 1 m/s}\n",
            r"s.yaml:7: vary.parameters.run.speed: from, to and step must all carry units of "
            r"the same kind",
        ),
        (
            "vary:\n  parameters:\n    track.gauge: [1.435 m]\n",
            r"s.yaml:7: vary.parameters.track.gauge: track.\* parameters need a track file",
        ),
        (
            "vary:\n  parameters:\n    critical_speed.speed_min: [1 m/s]\n",
            r"s.yaml:7: .*critical_speed.\* parameters need 'analysis: critical_speed'",
        ),
        (
            "vary:\n  parameters:\n    run.speed: [1 m/s]\ncollect: [hunting detected]\n",
            r"s.yaml:8: collect.0: expected a dotted path",
        ),
        (
            "vary:\n  parameters:\n    run.speed: [1 m/s]\ncollect: [status]\n",
            r"s.yaml:8: collect.0: 'status' is also the name of another column",
        ),
        (
            "vary:\n  parameters:\n    run.speed: [1 m/s]\ncollect: []\n",
            r"s.yaml:8: collect: expected a non-empty list",
        ),
        ("vary:\n  parameters: {}\n", r"s.yaml:6: vary.parameters: no parameters"),
        ("analysis: crit\n", r"s.yaml:5: analysis: 'crit' is not one of run, critical_speed"),
    ],
)
def test_study_errors_name_file_line_and_key(tmp_path, body, expected):
    assert pytest.raises(InputError, parse, tmp_path, HEAD + body).match(expected)


def test_base_errors(tmp_path):
    message = study_error(tmp_path, HEAD.replace("wheelset.yaml", "whelset.yaml"))
    assert "s.yaml:4: base.vehicle: file not found" in message
    assert "(paths are relative to the study file)" in message
    body = "  run: {speed: 10 m/s, distanse: 5 m}\nvary: {parameters: {run.speed: [1]}}\n"
    assert "s.yaml:5: base.run.distanse: unknown key. Did you mean 'distance'?" in study_error(
        tmp_path, HEAD + body
    )
    body = "  set: [wheelsets.ws1.mas=5 t]\nvary: {parameters: {run.speed: [1]}}\n"
    message = study_error(tmp_path, HEAD + body)
    assert message.startswith(f"{tmp_path / 's.yaml'}:5: base.set.0: ")
    assert "wheelset.yaml:" in message and "wheelsets.ws1.mas: unknown key" in message
    body = "  set: ['wheelsets.ws1.mass=-1 t']\nvary: {parameters: {run.speed: [1]}}\n"
    assert "s.yaml:5: base.set.0: " in study_error(tmp_path, HEAD + body)
    body = "  set: [track.gauge=1.4 m]\nvary: {parameters: {run.speed: [1]}}\n"
    assert "s.yaml:5: base.set.0: track overrides need a track file" in study_error(
        tmp_path, HEAD + body
    )


def test_relative_paths_base_set_and_track_parameters(tmp_path):
    folder = tmp_path / "studies"
    folder.mkdir()
    shutil.copy(VEHICLES / "wheelset.yaml", tmp_path / "wheelset.yaml")
    shutil.copy(TRACKS / "straight.yaml", tmp_path / "straight.yaml")
    path = folder / "s.yaml"
    path.write_text(
        textwrap.dedent(
            """\
            format_version: 1
            name: t
            base:
              vehicle: ../wheelset.yaml
              track: ../straight.yaml
              set: ["wheelsets.ws1.mass=4.3 t", "vehicle.speed_body=ws1",
                    "track.gauge=1.437 m"]
            vary:
              parameters:
                track.gauge: [1.433 m, 1.435 m]
            """
        )
    )
    study = load_study(path)
    assert study.vehicle == (tmp_path / "wheelset.yaml").resolve()
    case = study.cases()[0]
    assert study.vehicle_overrides(case) == ["wheelsets.ws1.mass=4.3 t", "speed_body=ws1"]
    assert study.track_overrides(case) == ["gauge=1.437 m", "gauge=1.433 m"]
    assert study.collect == S.DEFAULT_COLLECT["run"]


def test_example_studies_load():
    counts = {
        "eu07_lateral_force_vs_speed": 7,
        "eu07_primary_stiffness_vs_speed": 16,
        "eu07_critical_speed_vs_primary_stiffness": 4,
        "eu07_curve_r300_cant_deficiency": 5,
        "eu07_traction_adhesion": 5,
    }
    assert {p.stem for p in STUDIES.glob("*.yaml")} == set(counts)
    for name, n in counts.items():
        study = load_study(STUDIES / f"{name}.yaml")
        assert len(study.cases()) == n, name
    study = load_study(STUDIES / "eu07_lateral_force_vs_speed.yaml")
    assert study.parameters[0].si_values == (10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0)
    study = load_study(STUDIES / "eu07_primary_stiffness_vs_speed.yaml")
    assert [len(p.values) for p in study.parameters] == [4, 4]
    case = study.cases()[-1]
    vehicle = load_vehicle(study.vehicle, study.vehicle_overrides(case))
    primary = [e for e in vehicle.suspension if e.name.startswith("primary_ws")]
    assert len(primary) == 8 and {e.stiffness_N_per_m[0] for e in primary} == {32e6}
    study = load_study(STUDIES / "eu07_critical_speed_vs_primary_stiffness.yaml")
    assert study.analysis == "critical_speed"
    assert study.settings_data(study.cases()[0])["methods"] == ["linear", "bisection"]


# ----------------------------------------------------------------------------------------------
# Running studies
# ----------------------------------------------------------------------------------------------

TWO_SPEEDS = """\
vary:
  parameters:
    run.speed: [8 m/s, 12 m/s]
"""


@pytest.fixture(scope="module")
def local_study(tmp_path_factory):
    """The 2-case study run on 2 local worker processes."""
    folder = tmp_path_factory.mktemp("local")
    path = write_study(folder, TWO_SPEEDS)
    calls: list[StudyProgress] = []
    result = run_study(path, folder / "out", workers=2, progress=calls.append)
    return path, folder / "out", result, calls


def test_local_study_writes_rows_and_case_folders(local_study):
    path, out, result, calls = local_study
    assert result.ran == 2 and result.skipped == 0 and result.ok
    assert result.counts["completed"] == 2
    rows = read_results(out / "results.csv")
    assert len(rows) == 2
    header = (out / "results.csv").read_text().splitlines()[0].split(",")
    assert header == [
        "case_id",
        "run.speed",
        "run.speed_si",
        *COLLECT,
        "status",
        "error",
        "run_time_s",
        "case_hash",
    ]
    by_id = {r["case_id"]: r for r in rows}
    assert by_id["case_0000"]["run.speed"] == "8 m/s"
    assert by_id["case_0000"]["run.speed_si"] == "8.0"
    assert by_id["case_0001"]["run.speed_si"] == "12.0"
    for r in rows:
        case = out / "cases" / r["case_id"]
        assert (case / "timeseries.csv").is_file() and (case / "summary.json").is_file()
        assert not list(case.glob("*.png"))  # plots are off by default
        summary = json.loads((case / "summary.json").read_text())
        assert r["max_abs_lateral_force_N"] == repr(summary["max_abs_lateral_force_N"])
        assert r["wheelsets.0.max_abs_lateral_m"] == repr(
            summary["wheelsets"][0]["max_abs_lateral_m"]
        )
        assert r["hunting.detected"] in ("true", "false")
        assert summary["settings"]["speed_m_per_s"] == float(r["run.speed_si"])
        assert summary["settings"]["distance_m"] == 5.0
        assert r["status"] == "completed" and r["error"] == "" and float(r["run_time_s"]) > 0
        case_json = json.loads((case / "case.json").read_text())
        assert case_json["hash"] == r["case_hash"]
    # study.json: the study and its cases
    stored = json.loads((out / "study.json").read_text())
    assert [c["case_id"] for c in stored["cases"]] == ["case_0000", "case_0001"]
    assert stored["parameters"][0]["si_values"] == [8.0, 12.0]
    assert stored["collect"] == COLLECT
    # progress: a first call, then one per case; the last one has nothing left
    assert [p.done for p in calls] == [0, 1, 2] and calls[0].case_id is None
    assert all(p.total == 2 and p.failed == 0 for p in calls)
    assert calls[-1].eta_s == 0.0 and calls[-1].elapsed_s > 0


def test_resume_skips_finished_cases_and_refuses_another_study(local_study, tmp_path):
    path, out, first, _ = local_study
    out2 = tmp_path / "out"
    shutil.copytree(out, out2)
    again = run_study(path, out2, workers=2)
    assert again.ran == 0 and again.skipped == 2
    assert again.rows == first.rows
    # delete one row: only that case runs again
    lines = (out2 / "results.csv").read_text().splitlines(keepends=True)
    kept = [ln for ln in lines if not ln.startswith("case_0001,")]
    (out2 / "results.csv").write_text("".join(kept))
    stamp = (out2 / "cases" / "case_0000" / "summary.json").stat().st_mtime_ns
    third = run_study(path, out2, workers=2)
    assert third.ran == 1 and third.skipped == 1
    assert [r["case_id"] for r in third.rows] == ["case_0000", "case_0001"]
    assert (out2 / "cases" / "case_0000" / "summary.json").stat().st_mtime_ns == stamp
    # deterministic: the re-run case gives the same results
    for c in COLLECT:
        assert third.rows[1][c] == first.rows[1][c]
    # a different study into the same folder is refused
    other = write_study(tmp_path, TWO_SPEEDS.replace("12 m/s", "13 m/s"), name="other.yaml")
    with pytest.raises(
        StudyError,
        match=r"holds the results of a different study: case_0001 "
        r"there is run.speed=12 m/s; here it is run.speed=13 m/s",
    ):
        run_study(other, out2, workers=2)
    changed = write_study(tmp_path, TWO_SPEEDS.replace("run.speed", "run.speed"), name="d.yaml")
    changed.write_text(changed.read_text().replace("distance: 5 m", "distance: 6 m"))
    with pytest.raises(StudyError, match="different study: base.run differ"):
        run_study(changed, out2, workers=2)
    # collecting other results re-reads them from the case folders
    extra = [*COLLECT, "flange_contact.occurred", "hunting.nonsense"]
    more = write_study(tmp_path, TWO_SPEEDS, name="more.yaml", collect=extra)
    with pytest.warns(
        StudyWarning,
        match=r"more.yaml:\d+: collect.6 'hunting.nonsense': not "
        r"found in summary.json of case_0000",
    ):
        resumed = run_study(more, out2, workers=2)
    assert resumed.ran == 0
    assert [r["flange_contact.occurred"] for r in resumed.rows] == ["false", "false"]
    assert [r["hunting.nonsense"] for r in resumed.rows] == ["", ""]
    assert resumed.rows[0]["run_time_s"] == first.rows[0]["run_time_s"]


def test_dask_cluster_gives_the_same_results(local_study, tmp_path):
    distributed = pytest.importorskip("distributed")
    path, _, local, _ = local_study
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        result = run_study(path, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert result.ran == 2 and result.ok
    for a, b in zip(local.rows, result.rows, strict=True):
        assert a["case_id"] == b["case_id"] and a["case_hash"] == b["case_hash"]
        for c in COLLECT:
            assert a[c] == b[c], c  # deterministic runs: identical to the last digit
    for r in result.rows:
        case = tmp_path / "dask" / "cases" / r["case_id"]
        assert (case / "timeseries.csv").is_file() and (case / "summary.json").is_file()


def test_missing_dask_names_the_extra(tmp_path, monkeypatch):
    path = write_study(tmp_path, TWO_SPEEDS)
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ImportError, match=r"pip install railexu\[dask\]"):
        run_study(path, tmp_path / "out", scheduler="tcp://127.0.0.1:1")


def test_failing_case_is_recorded_and_the_others_complete(tmp_path):
    body = """\
        vary:
          combine: zip
          parameters:
            vehicle.wheelsets.ws1.mass: [4.25 t, -1 t]
            run.speed: [10 m/s, 10 m/s]
        """
    path = write_study(tmp_path, body)
    result = run_study(path, tmp_path / "out", workers=2)
    assert not result.ok
    ok, bad = result.rows
    assert ok["status"] == "completed" and ok["max_abs_lateral_force_N"] != ""
    assert bad["status"] == "failed"
    assert bad["error"].endswith("wheelsets.ws1.mass: must be > 0 kg, got '-1 t'")
    assert bad["max_abs_lateral_force_N"] == ""
    assert bad["vehicle.wheelsets.ws1.mass_si"] == "-1000.0"
    assert "Traceback" in (tmp_path / "out" / "cases" / "case_0001" / "error.txt").read_text()
    # failed cases are kept on resume, and run again only when asked
    assert run_study(path, tmp_path / "out", workers=0).ran == 0
    retried = run_study(path, tmp_path / "out", workers=0, retry_failed=True)
    assert retried.ran == 1 and retried.counts == {
        "completed": 1,
        "completed_with_exceedances": 0,
        "derailed": 0,
        "diverged": 0,
        "failed": 1,
    }
    assert len(read_results(tmp_path / "out" / "results.csv")) == 2


def test_a_crashing_worker_fails_only_its_case(tmp_path):
    """In a process of its own: the test hook's environment variable must reach the workers,
    which a fork server started earlier in this session would not pass on."""
    import os
    import subprocess
    import sys

    path = write_study(tmp_path, "vary:\n  parameters:\n    run.speed: [8 m/s, 9 m/s, 10 m/s]\n")
    code = (
        "from railexu.study import run_study\n"
        f"run_study({str(path)!r}, {str(tmp_path / 'out')!r}, workers=2)\n"
    )
    env = dict(os.environ, **{S._CRASH_ENV: "case_0001"})
    subprocess.run([sys.executable, "-c", code], env=env, check=True, timeout=300)
    result = run_study(path, tmp_path / "out", workers=0)  # resumes: reads the recorded rows
    assert [r["status"] for r in result.rows] == ["completed", "failed", "completed"]
    assert "the worker process died" in result.rows[1]["error"]


def test_interrupted_study_keeps_finished_rows_and_resumes(tmp_path):
    path = write_study(tmp_path, "vary:\n  parameters:\n    run.speed: [8 m/s, 9 m/s, 10 m/s]\n")
    out = tmp_path / "out"

    def interrupt(p: StudyProgress) -> None:
        if p.case_id is not None:
            raise KeyboardInterrupt

    # 2 workers: when the first case finishes, the second is running and must be stopped
    with pytest.raises(KeyboardInterrupt):
        run_study(path, out, workers=2, progress=interrupt)
    rows = read_results(out / "results.csv")
    assert len(rows) == 1 and rows[0]["status"] == "completed"
    result = run_study(path, out, workers=2)
    assert result.ran == 2 and result.skipped == 1
    assert [r["case_id"] for r in result.rows] == ["case_0000", "case_0001", "case_0002"]
    assert all(r["status"] == "completed" for r in result.rows)


def test_incomplete_last_line_is_dropped_and_rerun(local_study, tmp_path):
    path, out, first, _ = local_study
    out2 = tmp_path / "out"
    shutil.copytree(out, out2)
    text = (out2 / "results.csv").read_text()
    (out2 / "results.csv").write_text(text[: len(text) - 25])  # a write cut short
    result = run_study(path, out2, workers=0)
    assert result.ran == 1 and len(result.rows) == 2
    assert [r["max_abs_lateral_force_N"] for r in result.rows] == [
        r["max_abs_lateral_force_N"] for r in first.rows
    ]


@pytest.mark.parametrize("cut", [1, 5, 15])
def test_a_last_row_cut_inside_its_case_hash_is_dropped_and_rerun(local_study, tmp_path, cut):
    """A power cut inside the last field (the case hash): the row has all its fields but a
    short hash and no line end. It is dropped and its case runs again, with no talk of
    another study."""
    path, out, first, _ = local_study
    out2 = tmp_path / "out"
    shutil.copytree(out, out2)
    text = (out2 / "results.csv").read_text()
    assert text.endswith("\n")
    (out2 / "results.csv").write_text(text[: len(text) - 1 - cut])  # the line end and `cut` hex
    result = run_study(path, out2, workers=0)
    assert result.ran == 1 and len(result.rows) == 2
    assert [r["case_hash"] for r in result.rows] == [r["case_hash"] for r in first.rows]


def test_workers_end_when_the_study_process_is_killed(tmp_path):
    """kill -9 of a study's main process: its worker processes notice and end (they would
    otherwise stay blocked forever, some 200 MB each)."""
    import signal
    import subprocess
    import sys
    import time

    path = write_study(
        tmp_path,
        """\
        vary:
          parameters:
            run.speed: [10, 11, 12, 13, 14, 15]
        """,
    )
    slow = path.read_text().replace("distance: 5 m", "distance: 400 m")
    path.write_text(slow)
    code = (
        "from railexu.study import run_study\n"
        f"run_study({str(path)!r}, {str(tmp_path / 'out')!r}, workers=2)\n"
    )
    main = subprocess.Popen([sys.executable, "-c", code])

    def children(pid: int) -> list[int]:
        found = []
        for task in Path(f"/proc/{pid}/task").glob("*"):
            with contextlib.suppress(OSError):
                found += [int(c) for c in (task / "children").read_text().split()]
        return found

    def cmdline(pid: int) -> str:
        with contextlib.suppress(OSError):
            return Path(f"/proc/{pid}/cmdline").read_text()
        return ""

    try:
        deadline = time.monotonic() + 120
        workers: list[int] = []
        servers: list[int] = []
        while time.monotonic() < deadline and len(workers) < 2:
            time.sleep(0.5)
            starters = [c for c in children(main.pid) if "resource_tracker" not in cmdline(c)]
            servers = [c for c in starters if "forkserver" in cmdline(c)]
            # spawn workers are the study's children, forkserver workers the fork server's
            workers = [w for c in servers for w in children(c)] or starters
        assert len(workers) >= 2, "the study did not start its workers"
        workers += servers  # the fork server must end too
    finally:
        main.send_signal(signal.SIGKILL)
        main.wait(timeout=30)
    deadline = time.monotonic() + 30
    alive = list(workers)
    while alive and time.monotonic() < deadline:
        time.sleep(0.2)
        alive = [w for w in alive if Path(f"/proc/{w}").exists() and
                 "Z" not in Path(f"/proc/{w}/stat").read_text().split(")")[-1][:3]]  # fmt: skip
    assert not alive, f"workers still alive after their parent was killed: {alive}"


def test_critical_speed_analysis_with_a_fake_critical_speed(tmp_path, monkeypatch):
    stability = pytest.importorskip("railexu.stability")
    seen = []

    def fake_critical_speed(vehicle, track=None, settings=None, progress=None):
        seen.append(settings)
        mass = vehicle.wheelsets[0].mass_kg
        return {
            "vehicle": vehicle.name,
            "linear_m_per_s": mass / 100.0,
            "nonlinear_bisection_m_per_s": None,
            "nonlinear_ramp_m_per_s": None,
            "settings": {"speed_min_m_per_s": settings.speed_min_m_per_s},
        }

    monkeypatch.setattr(stability, "critical_speed", fake_critical_speed)
    path = tmp_path / "cs.yaml"
    path.write_text(
        textwrap.dedent(
            f"""\
            format_version: 1
            name: critical speed
            analysis: critical_speed
            base:
              vehicle: {VEHICLES / "wheelset.yaml"}
              critical_speed: {{methods: [linear], speed_min: 20 m/s, speed_max: 80 m/s}}
            vary:
              parameters:
                vehicle.wheelsets.ws1.mass: [4 t, 5 t]
                critical_speed.tolerance: [1 m/s]
            collect: [linear_m_per_s, nonlinear_bisection_m_per_s, linear.critical_speed_m_per_s]
            """
        )
    )
    with pytest.warns(StudyWarning, match="linear.critical_speed_m_per_s") as record:
        result = run_study(path, tmp_path / "out", workers=0)
    assert len([w for w in record if issubclass(w.category, StudyWarning)]) == 1  # warned once
    assert [r["linear_m_per_s"] for r in result.rows] == ["40.0", "50.0"]
    assert [r["nonlinear_bisection_m_per_s"] for r in result.rows] == ["", ""]
    assert all(r["status"] == "completed" for r in result.rows)
    assert seen[0].speed_min_m_per_s == 20.0 and seen[0].tolerance_m_per_s == 1.0
    assert (tmp_path / "out" / "cases" / "case_0001" / "critical_speed.json").is_file()
    assert "run.speed" in study_error(
        tmp_path, path.read_text().replace("critical_speed.tolerance", "run.speed")
    )
    with pytest.raises(InputError, match=r"base.run: not used by 'analysis: critical_speed'"):
        parse(
            tmp_path,
            path.read_text().replace(
                "  critical_speed: {", "  run: {speed: 1}\n  critical_speed: {"
            ),
        )


def test_cli_study_command(tmp_path, capsys):
    body = """\
        vary:
          parameters:
            vehicle.wheelsets.ws1.mass: [4.25 t, -1 t]
        """
    path = write_study(tmp_path, body)
    parser = argparse.ArgumentParser(prog="railexu")
    add_study_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["study", str(path), "--out", str(tmp_path / "out"), "--workers", "0"])
    assert args.func(args) == 1  # one case failed
    captured = capsys.readouterr()
    assert "2 of 2 cases (1 completed, 1 failed)" in captured.out
    assert "case_0001 failed:" in captured.out
    assert "2/2 cases, 1 failed" in captured.err
    assert (tmp_path / "out" / "plots" / "study_vs_vehicle_wheelsets_ws1_mass.png").is_file()


# ----------------------------------------------------------------------------------------------
# Plots
# ----------------------------------------------------------------------------------------------


def test_plot_study_one_parameter(local_study):
    _, out, _, _ = local_study
    written = plot_study(out)
    names = {p.name for p in written}
    assert names == {"study_vs_run_speed.png", "study_vs_run_speed.svg"}
    assert all(p.stat().st_size > 1000 for p in written)
    with pytest.raises(StudyError, match="not an output folder of a study"):
        plot_study(out / "cases")


def test_study_figures_two_parameters_map_and_scatter(tmp_path):
    from railexu.report.figures import save_figure
    from railexu.report.study_figures import result_unit, study_figures

    assert result_unit("hunting.wavelength_m") == "m"
    assert result_unit("linear_m_per_s") == "m/s"
    assert result_unit("max_abs_lateral_force_N") == "N"
    assert result_unit("max_Y_over_Q.value") == ""
    params = [
        {
            "path": "run.speed",
            "values": ["10 m/s", "20 m/s", "30 m/s"],
            "quantity": True,
            "unit": "m/s",
        },
        {
            "path": "vehicle.suspension.primary_ws*.stiffness.x",
            "values": ["4 MN/m", "8 MN/m"],
            "quantity": True,
            "unit": "N/m",
        },
    ]
    rows = []
    for i, (v, k) in enumerate((v, k) for v in (10, 20, 30) for k in (4, 8)):
        status = "failed" if i == 3 else ("derailed" if i == 5 else "completed")
        rows.append(
            {
                "case_id": f"case_{i:04d}",
                "run.speed": f"{v} m/s",
                "run.speed_si": repr(float(v)),
                "vehicle.suspension.primary_ws*.stiffness.x": f"{k} MN/m",
                "vehicle.suspension.primary_ws*.stiffness.x_si": repr(k * 1e6),
                "max_abs_lateral_force_N": "" if status == "failed" else repr(1000.0 * v + k),
                "hunting.detected": "" if status == "failed" else ("true" if v > 15 else "false"),
                "max_Y_over_Q.wheel": "ws1_left",
                "status": status,
            }
        )
    collect = ["max_abs_lateral_force_N", "hunting.detected", "max_Y_over_Q.wheel"]
    figs = study_figures(rows, {"name": "grid", "parameters": params, "collect": collect})
    assert set(figs) == {
        "study_vs_run_speed",
        "study_vs_vehicle_suspension_primary_ws_stiffness_x",
        "study_map_max_abs_lateral_force_N",
        "study_map_hunting_detected",
    }
    # engineering units: km/h, MN/m, kN; each cell's value written on the map (5 with a value)
    ax = figs["study_map_max_abs_lateral_force_N"].axes[0]
    assert ax.get_xlabel() == "run speed [km/h]"
    assert ax.get_ylabel() == "vehicle suspension primary ws* stiffness x [MN/m]"
    assert figs["study_map_max_abs_lateral_force_N"].axes[1].get_ylabel() == (
        "max abs lateral force [kN]"
    )
    assert sorted(t.get_text() for t in ax.texts) == ["10", "10", "20", "30", "30"]
    # a boolean result: markers (filled = true, open = false), no colour bar
    assert len(figs["study_map_hunting_detected"].axes) == 1
    vs = figs["study_vs_run_speed"].axes
    assert [a.get_title(loc="left") for a in vs] == [
        "max abs lateral force",
        "hunting detected (true / false)",
    ]
    assert [a.get_ylabel() for a in vs] == ["[kN]", ""]
    assert [t.get_text() for t in vs[1].get_yticklabels()] == ["false", "true"]
    assert all(ln.get_linestyle() == "None" for ln in vs[1].get_lines())
    written = []
    for name, fig in figs.items():
        written += save_figure(fig, tmp_path / name)
    assert len(written) == 8 and all(p.stat().st_size > 1000 for p in written)
    assert {p.suffix for p in written} == {".png", ".svg"}
    # zip-like cases (not a grid) and a text-valued parameter: coloured points
    params[1] = {
        "path": "vehicle.contact.creep_model",
        "values": ["polach", "fastsim"],
        "quantity": False,
        "unit": "",
    }
    zipped = [
        {
            "case_id": "case_0000",
            "run.speed": "10 m/s",
            "run.speed_si": "10.0",
            "vehicle.contact.creep_model": "polach",
            "max_abs_lateral_force_N": "1.0",
            "status": "completed",
        },
        {
            "case_id": "case_0001",
            "run.speed": "20 m/s",
            "run.speed_si": "20.0",
            "vehicle.contact.creep_model": "fastsim",
            "max_abs_lateral_force_N": "2.0",
            "status": "completed",
        },
    ]
    figs = study_figures(zipped, {"name": "zip", "parameters": params, "collect": collect[:1]})
    assert set(figs) == {
        "study_vs_run_speed",
        "study_vs_vehicle_contact_creep_model",
        "study_map_max_abs_lateral_force_N",
    }
    labels = [
        t.get_text()
        for t in figs["study_vs_vehicle_contact_creep_model"].axes[-1].get_xticklabels()
    ]
    assert labels == ["polach", "fastsim"]
    for name, fig in figs.items():
        assert len(save_figure(fig, tmp_path / "zip" / name)) == 2
    assert study_figures([], {"parameters": params, "collect": collect}) == {}


def test_yaml_text_round_trips_override_values():
    for value in ["8 MN/m", "1:40", "yes", 8e6, 1e20, 5, True, [1, 2.5], {"x": "1 m"}, "polach"]:
        text = S._yaml_text(value)
        assert yaml.safe_load(text) == value, (value, text)
    assert S._cell(True) == "true" and S._cell(None) == "" and S._cell(0.1) == "0.1"


def test_a_changed_input_file_reruns_the_cases_and_keeps_the_old_results(tmp_path):
    """Resuming after the vehicle file (or a file it names) changed must not reuse the old
    results: they are set aside, a warning names the file, and every case runs again."""
    vehicle = tmp_path / "wheelset.yaml"
    vehicle.write_text((VEHICLES / "wheelset.yaml").read_text())
    path = write_study(
        tmp_path,
        """\
        vary:
          parameters:
            run.speed: [10, 12]
        """,
    )
    path.write_text(path.read_text().replace(str(VEHICLES / "wheelset.yaml"), str(vehicle)))
    out = tmp_path / "out"
    first = run_study(path, out, workers=0)
    assert first.ran == 2
    assert run_study(path, out, workers=0).ran == 0  # nothing changed: all reused
    # a change that does not alter the parsed data (a comment) still changes the file
    vehicle.write_text(vehicle.read_text() + "\n# edited\n")
    with pytest.warns(StudyWarning, match="input files changed .*wheelset.yaml"):
        again = run_study(path, out, workers=0)
    assert again.ran == 2 and again.skipped == 0
    assert (out / "results.before-input-change.csv").exists()
    # a change of a value: the same
    vehicle.write_text(vehicle.read_text().replace("4.25 t", "4.5 t", 1))
    with pytest.warns(StudyWarning, match="input files changed"):
        assert run_study(path, out, workers=0).ran == 2


def test_the_files_a_vehicle_names_are_part_of_the_study_inputs(tmp_path):
    from railexu.study.input_files import input_file_digests

    (tmp_path / "worn.txt").write_text("0 0\n1 1\n")
    (tmp_path / "v.yaml").write_text("wheelsets:\n  ws1: {wheel_profile: worn.txt}\n")
    (tmp_path / "alt.txt").write_text("0 0\n")
    digests = input_file_digests(tmp_path / "v.yaml", None, ["alt.txt", 10.0], tmp_path)
    names = sorted(Path(p).name for p in digests)
    assert names == ["alt.txt", "v.yaml", "worn.txt"]


def test_what_a_worker_preloads_loads_without_error():
    """The workers' preload swallows its errors (a case reports them): it must not fail in a
    working installation, or every worker's first case pays for the loading."""
    from railexu.study import worker

    worker.load_case_needs()


def test_local_workers_come_from_a_fork_server_that_preloads_the_cases_needs():
    import importlib.util
    import multiprocessing

    from railexu.runtime import fork_server

    ctx = fork_server.pool_context()
    if "forkserver" in multiprocessing.get_all_start_methods():
        assert ctx.get_start_method() == "forkserver"
    else:
        assert ctx.get_start_method() == "spawn"
    assert fork_server.PRELOAD[0] == "railexu.runtime.blas_threads"  # before the preload's numpy
    for name in fork_server.PRELOAD:
        assert importlib.util.find_spec(name) is not None


def test_the_fork_server_starts_ahead_of_the_pool():
    """`railexu study` starts the fork server before it reads the study (its preload then runs
    on another core); a pool made afterwards uses that server."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from railexu.runtime import fork_server

    if "forkserver" not in multiprocessing.get_all_start_methods():
        assert fork_server.start() is False
        return
    assert fork_server.start() is True
    assert fork_server.start() is True  # running already: nothing new
    with ProcessPoolExecutor(1, mp_context=fork_server.pool_context()) as pool:
        assert pool.submit(os.getpid).result() != os.getpid()


@pytest.mark.parametrize(
    ("options", "starts"),
    [
        (["--workers", "0"], False),
        (["--workers", "2"], True),
        ([], True),
        (["--scheduler", "tcp://127.0.0.1:1"], False),  # a Dask cluster: no local workers
    ],
)
def test_the_study_command_starts_the_fork_server_only_for_local_workers(
    tmp_path, monkeypatch, options, starts
):
    from railexu.cli import study as study_cli
    from railexu.runtime import fork_server

    calls = []
    monkeypatch.setattr(fork_server, "start", lambda: calls.append(1) or True)
    parser = argparse.ArgumentParser(prog="railexu")
    add_study_parser(parser.add_subparsers(dest="command"))
    path = write_study(tmp_path, "vary:\n  parameters:\n    run.speed: [10 m/s]\n")
    args = parser.parse_args(["study", str(path), "--out", str(tmp_path / "out"), *options])
    study_cli.start_workers_early(args)
    assert bool(calls) is starts
    missing = parser.parse_args(["study", str(tmp_path / "missing.yaml"), "--out", "x"])
    calls.clear()
    study_cli.start_workers_early(missing)  # no study file: the command fails at once
    assert not calls


def test_a_studys_workers_run_blas_on_one_thread():
    """The fork server imports railexu.runtime.blas_threads before its preload loads numpy, so the
    workers have no BLAS threads busy-waiting beside the other workers' cases."""
    import multiprocessing

    from railexu.runtime import fork_server

    if "forkserver" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork server here (the spawn workers keep the study's setting)")
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(1, mp_context=fork_server.pool_context()) as pool:
        value, threads = pool.submit(_blas_setting).result()
    assert value == os.environ.get("OPENBLAS_NUM_THREADS", "1")
    assert threads == 1 or value != "1"


def test_a_studys_workers_inherit_the_preload_frozen():
    """The fork server freezes what it preloaded (gc.freeze): a worker's collections do not
    scan those objects again."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from railexu.runtime import fork_server

    if "forkserver" not in multiprocessing.get_all_start_methods():
        pytest.skip("no fork server here")
    with ProcessPoolExecutor(1, mp_context=fork_server.pool_context()) as pool:
        frozen, enabled = pool.submit(_gc_state).result()
    assert frozen > 10_000
    assert enabled  # frozen, not switched off: a case's own garbage is collected


def _gc_state() -> tuple[int, bool]:
    import gc

    return gc.get_freeze_count(), gc.isenabled()


def _blas_setting() -> tuple[str, int]:
    """In a worker: OPENBLAS_NUM_THREADS and the number of threads of the process."""
    return os.environ["OPENBLAS_NUM_THREADS"], len(os.listdir("/proc/self/task"))
