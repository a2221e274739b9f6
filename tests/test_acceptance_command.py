"""``railexu acceptance``: the programme run as studies, the verdict rule, acceptance.json, the
figures and the report page.

The end-to-end test runs a reduced programme (a straight zone of 2 sections and a curve zone of
4, each section 20 m after a 30 m run-in) of the loaded Hbbins wagon in this process; the
statistics, limits and quantities themselves are checked against hand calculations in
``test_acceptance_statistics.py`` and ``test_acceptance_quantities.py``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml

from railexu.assessment.acceptance.programme import load_programme
from railexu.inputs.catalog import shipped_path
from railexu.study import load_study
from railexu.study.acceptance.verdict import decide
from railexu.study.acceptance.zone_study import write_zone_files, zone_study, zone_track


def _small_programme(tmp_path: Path) -> Path:
    data = yaml.safe_load(shipped_path("programme", "freight_wagon").read_text())
    data["zones"] = {k: data["zones"][k] for k in ("straight", "curve_large_radius")}
    for zone, n in (("straight", 2), ("curve_large_radius", 4)):
        z = data["zones"][zone]
        z.update(n_sections=n, min_sections=n, quick_sections=n, section_length="20 m",
                 run_in="30 m")  # fmt: skip
    path = tmp_path / "small.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_zone_is_a_study_of_one_case_per_section(tmp_path):
    """The zone's study has one case per section, with the section's radius, direction, speed
    and irregularities (the conditions EN 14363's evaluation regresses on)."""
    programme = load_programme(_small_programme(tmp_path))
    zone = programme.zone("curve_large_radius")
    sections = zone.sections()
    vehicle = shipped_path("vehicle", "hbbins_loaded")
    study_file = write_zone_files(tmp_path / "z", zone_track(zone, sections),
                                  zone_study(zone, sections, vehicle))  # fmt: skip
    study = load_study(study_file)
    cases = study.cases()
    assert len(cases) == len(sections) == 4
    for case, s in zip(cases, sections, strict=True):
        si = case.si_values
        assert si["track.geometry.sections.1.radius"] == pytest.approx(s.radius_m, rel=1e-5)
        assert si["run.speed"] == pytest.approx(s.speed_m_per_s, rel=1e-5)
        assert case.values["track.geometry.sections.1.direction"] == s.direction
        assert case.values["track.irregularities.seed"] == s.irregularities["seed"]
        # V^2 = g R (I + D) / b with b = 1.5 m (EN 13803)
        v2 = 9.81 * s.radius_m * (s.cant_deficiency_m + s.cant_m) / 1.5
        assert si["run.speed"] ** 2 == pytest.approx(v2, rel=2e-3)


def _zone(criteria: dict, **extra) -> dict:
    return {"criteria": criteria, "reduced": False, **extra}


def _crit(value, limit, passed, assumption=False) -> dict:
    return {"value": value, "limit": limit, "pass": passed, "unit": "N", "clause": "c",
            "assumption": assumption}  # fmt: skip


@pytest.mark.parametrize(
    ("zones", "tests", "quick", "result"),
    [
        ({"a": _zone({"x": _crit(1.0, 2.0, True)})}, "completed", False, "pass"),
        ({"a": _zone({"x": _crit(3.0, 2.0, False)})}, "completed", False, "fail"),
        ({"a": _zone({"x": _crit(1.0, 2.0, True)})}, "completed", True, "incomplete"),
        ({"a": _zone({"x": _crit(1.0, 2.0, True)})}, "not_run", False, "incomplete"),
        ({"a": {"error": "too few sections"}}, "completed", False, "incomplete"),
        ({"a": _zone({"x": _crit(1.0, 2.0, True)}, reduced=True)}, "completed", False,
         "incomplete"),
        # a failure decides even when something else is missing
        ({"a": _zone({"x": _crit(3.0, 2.0, False)}), "b": {"error": "e"}}, "not_run", True,
         "fail"),
    ],
)  # fmt: skip
def test_the_verdict_rule(zones, tests, quick, result):
    data = {
        "zones": zones,
        "programme": {"quick": quick},
        "twist_test": {"status": tests, "pass": True},
        "yaw_resistance_test": {"status": tests, "pass": True},
    }
    verdict = decide(data)
    assert verdict["result"] == result
    if result == "fail":
        assert verdict["failed"]


def test_a_failed_quasi_static_test_fails_the_vehicle():
    data = {
        "zones": {"a": _zone({"x": _crit(1.0, 2.0, True, assumption=True)})},
        "programme": {"quick": False},
        "twist_test": {"status": "completed", "pass": True},
        "yaw_resistance_test": {"status": "completed", "pass": False, "value": 0.15,
                                "limit": 0.1},
    }  # fmt: skip
    verdict = decide(data)
    assert verdict["result"] == "fail" and "yaw_resistance_test" in verdict["failed"][0]
    assert verdict["assumptions"] == ["a: x"]


@pytest.mark.slow
def test_a_reduced_programme_end_to_end(tmp_path):
    """Every section runs, each zone is evaluated with its method, acceptance.json holds what
    the issue names (standard, vehicle with SHA-256, category, programme, zones with value,
    limit, pass, method, clause per criterion, the quasi-static tests, the verdict), the
    figures are drawn, the report page is written, and a second call resumes (runs nothing)."""
    from railexu.report.html_report import write_report
    from railexu.study.acceptance import run_acceptance

    out = tmp_path / "acc"
    lines: list[str] = []
    result = run_acceptance("hbbins_loaded", out, programme=_small_programme(tmp_path),
                            quick=True, workers=0, quasi_static=False,
                            progress=lines.append)  # fmt: skip
    data = json.loads((out / "acceptance.json").read_text())
    assert data["standard"] == "EN 14363:2016" and data["category"] == "wagon"
    assert len(data["vehicle"]["sha256"]) == 64
    assert data["programme"]["quick"] is True
    # never a pass: the quick programme and the missing quasi-static tests are listed (20 m
    # sections of a two-axle wagon may also fail a limit: a trend, not a verdict)
    assert data["verdict"]["result"] in ("incomplete", "fail")
    assert "quick" in data["verdict"]["missing"][0]
    assert any("twist_test" in m for m in data["verdict"]["missing"])
    straight, curve = data["zones"]["straight"], data["zones"]["curve_large_radius"]
    assert straight["sections_run"] == 2 and curve["sections_run"] == 4
    assert straight["method"] == "one_dimensional" and curve["method"] == "two_dimensional"
    for zone in (straight, curve):
        for name in ("Y_over_Q_2m", "sum_Y_2m", "Q_max"):
            c = zone["criteria"][name]
            assert {"value", "limit", "pass", "method", "clause"} <= set(c)
            assert c["value"] is not None and math.isfinite(c["value"]) and c["limit"] > 0
    # quasi-static track loading only in curves (on straight track: evaluated as not applicable)
    assert curve["criteria"]["Y_qst"]["value"] > 0 and curve["criteria"]["Y_qst"]["limit"] > 0
    assert straight["criteria"].get("Y_qst", {}).get("value") is None
    # the loaded wagon's quasi-static wheel force in the curve: about its static wheel load
    q0 = 22.4e3 * 9.81 / 2  # 22.4 t axle load
    assert 0.8 * q0 < curve["criteria"]["Q_qst"]["value"] < 1.5 * q0
    assert data["figures"] and all((out / f).is_file() for f in data["figures"])
    page = write_report(out)[0]
    assert f"Verdict: {data['verdict']['result']}" in page.read_text()
    again = run_acceptance("hbbins_loaded", out, programme=_small_programme(tmp_path),
                           quick=True, workers=0, quasi_static=False,
                           progress=lines.append)  # fmt: skip
    for zone in ("straight", "curve_large_radius"):
        assert again.data["zones"][zone]["study"]["ran"] == 0
    assert result.verdict == again.verdict
