"""What an acceptance folder shows a reader (issue 27): the quasi-static tests' values with
their own limits in the verdict, the twist test's ``limit`` key of acceptance.json, the
yaw-resistance X factor that is kept for information (not judged) on the report page, and the
zone figures' titles inside the figure. Synthetic acceptance mappings: no simulation."""

from __future__ import annotations

import pytest

from railexu.assessment.acceptance.twist import TwistTestResult
from railexu.study.acceptance.verdict import decide, write_acceptance


def _twist(y_over_q: float, unloading: float) -> dict:
    """A completed twist test's mapping as ``TwistTestResult.to_dict`` writes it (limits of
    EN 14363:2016, 6.1: Y/Q 1.2, unloading 0.6), after the runner's ``_guarded``."""
    result = TwistTestResult(
        y_over_q=y_over_q, y_over_q_limit=1.2, wheel="ws1_right", unloading=unloading,
        unloading_limit=0.6, unloading_wheel="ws1_right",
        passed=y_over_q <= 1.2 and unloading <= 0.6, twist_per_mille=3.05, twist_base_m=19.0,
        radius_m=150.0, direction="left", max_cant_m=0.15, speed_m_per_s=1.5,
        window_m=(5.0, 9.0), status={"state": "completed"},
    )  # fmt: skip
    entry = result.to_dict()
    entry["run_status"] = entry.pop("status")
    return {"status": "completed", **entry}


def _data(twist: dict, yaw: dict) -> dict:
    return {
        "standard": "EN 14363:2016",
        "category": "coach",
        "vehicle": {"name": "a coach", "file": "coach.yaml", "sha256": "0" * 64},
        "programme": {"name": "p", "file": "p.yaml", "quick": False},
        "zones": {},
        "twist_test": twist,
        "yaw_resistance_test": yaw,
    }


def test_the_twist_test_names_its_deciding_limit():
    """acceptance.json's ``twist_test`` has the keys issue 27 names: ``y_over_q``, ``limit``
    (the flange-climbing limit 1.2 of EN 14363:2016, 6.1), ``pass``, the twist and the radius."""
    entry = _twist(0.88, 0.30)
    assert entry["y_over_q"] == 0.88 and entry["limit"] == 1.2 and entry["pass"] is True
    assert entry["twist_per_mille"] == 3.05 and entry["radius_m"] == 150.0


@pytest.mark.parametrize(
    ("y_over_q", "unloading", "expected"),
    [
        (1.35, 0.30, ["y_over_q 1.35 > 1.2"]),
        (0.80, 0.72, ["unloading 0.72 > 0.6"]),
        (1.35, 0.72, ["y_over_q 1.35 > 1.2", "unloading 0.72 > 0.6"]),
    ],
)
def test_a_failed_twist_test_names_each_quantity_against_its_own_limit(
    y_over_q, unloading, expected
):
    """A twist test that fails by Y/Q, by the wheel unloading or by both says which, each with
    its own limit (before: the Y/Q against ``None`` whichever had failed)."""
    data = _data(_twist(y_over_q, unloading), {"status": "not_applicable", "reason": "coach"})
    verdict = decide(data)
    assert verdict["result"] == "fail"
    (line,) = verdict["failed"]
    assert line.startswith("twist_test: ") and "None" not in line
    for text in expected:
        assert text in line
    assert "EN 14363:2016, 6.1" in line
    if len(expected) == 1:
        other = "unloading" if "y_over_q" in expected[0] else "y_over_q"
        assert other not in line


def test_a_twist_run_that_stopped_numerically_leaves_the_verdict_incomplete():
    """The EU07's twist test on the patch-centroid contact diverged at 30.6 m, before its
    window (docs/acceptance.md): no value was measured, so the verdict is incomplete (as for a
    test not run), not fail; a derailment on the twist is a physical failure and fails."""
    stopped = {"state": "diverged", "distance_m": 30.56,
               "reason": "the solver failed at t = 20.374 s: SolveDynamic terminated"}  # fmt: skip
    entry = _twist(0.5, 0.2) | {"pass": False, "y_over_q": None, "unloading": None,
                                "run_status": stopped}  # fmt: skip
    verdict = decide(_data(entry, {"status": "not_applicable"}))
    assert verdict["result"] == "incomplete" and verdict["failed"] == []
    assert verdict["missing"][0].startswith("twist_test: its run diverged at 30.6 m")
    derailed = entry | {"run_status": {"state": "derailed", "reason": "left wheel rose 21 mm"}}
    verdict = decide(_data(derailed, {"status": "not_applicable"}))
    assert verdict["result"] == "fail"
    assert "did not pass (run: derailed)" in verdict["failed"][0]
    # a value above its limit fails whatever stopped the run afterwards
    exceeded = entry | {"y_over_q": 1.3}
    assert decide(_data(exceeded, {"status": "not_applicable"}))["result"] == "fail"


def test_the_report_page_shows_the_quasi_static_values_that_are_not_judged(tmp_path):
    """A coach's yaw-resistance test is not judged (X <= 0.1 is UIC 530-2's freight-wagon
    limit); its X factor is kept under ``informative`` and the page shows it, as it shows the
    twist test's run state and evaluation window."""
    from railexu.report.html_report import write_report

    yaw = {
        "status": "not_applicable",
        "reason": "the X factor limit (0.1) is UIC 530-2's for freight wagons",
        "assumption": True,
        "informative": {"x_factor": 0.157, "limit": 0.1, "max_moment_N_m": 21.9e3},
    }
    data = _data(_twist(0.634, 0.295), yaw)
    data["verdict"] = decide(data)
    write_acceptance(tmp_path / "acceptance.json", data)
    text = write_report(tmp_path)[0].read_text()
    assert "informative: x factor" in text and "0.157" in text
    assert "informative: max moment" in text and "21.9 kN m" in text
    assert "run status: state" in text and "window" in text and "5, 9 m" in text
    assert "y over q" in text and "0.634" in text
    # words and units, not raw JSON (issue 27): radius 150 m, twist 3.05 per mille, pass yes
    assert "150 m" in text and "3.05 ‰" in text and "1.5 m/s" in text
    assert ">yes<" in text and "True" not in text and "null" not in text


def _figure_data(vehicle_name: str) -> dict:
    """A quick acceptance's mapping with one two-dimensional curve zone of 4 sections."""
    sections, values = [], [0.40, 0.45, 0.52, 0.48]
    for i, (y, d, r) in enumerate(zip(values, (0.06, 0.15, 0.10, 0.12),
                                      (250.0, 300.0, 350.0, 400.0), strict=True)):  # fmt: skip
        sections.append({"section": i, "values": {"Y_over_Q_2m": y},
                         "conditions": {"cant_deficiency_m": d, "radius_m": r}})  # fmt: skip
    criterion = {
        "value": 0.62, "limit": 0.8, "pass": True, "unit": "1", "method": "two_dimensional",
        "sections": [0, 1, 2, 3],
        "details": {"coefficients": [0.2, 1.5, 20.0], "at": [0.15, 1 / 250.0]},
    }  # fmt: skip
    zone = {
        "method": "two_dimensional",
        "conditions": {"regressors": ["cant_deficiency", "curvature"]},
        "sections": sections,
        "criteria": {"Y_over_Q_2m": criterion},
    }
    return {
        "vehicle": {"name": vehicle_name},
        "programme": {"quick": True},
        "zones": {"curve_very_small_radius": zone},
    }


@pytest.mark.parametrize("name", ["Manchester coach extended", "x" * 40 + " " + "y" * 60])
def test_the_zone_figures_titles_stay_inside_the_figure(name):
    """Every title of a zone figure, the quick programme's notice included, lies inside the
    figure (issue 27: titles were cut at both edges); a long vehicle name is wrapped."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from railexu.report.acceptance_figures import _zone_figure

    data = _figure_data(name)
    zone = data["zones"]["curve_very_small_radius"]
    fig = _zone_figure("curve_very_small_radius", zone, zone["criteria"], data)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    width, height = fig.bbox.width, fig.bbox.height
    titles = list(fig.texts) + [ax.title for ax in fig.axes if ax.get_visible()]
    assert any("quick programme" in t.get_text() for t in titles)
    for text in titles:
        if not text.get_text():
            continue
        box = text.get_window_extent(renderer)
        assert box.x0 >= 0.0 and box.x1 <= width, text.get_text()
        assert box.y0 >= 0.0 and box.y1 <= height, text.get_text()


def _texts_outside(fig) -> list[str]:
    """The titles (the figure's and every axes') that reach beyond the figure's edges."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    out = []
    for text in list(fig.texts) + [ax.title for ax in fig.axes]:
        if text.get_text():
            box = text.get_window_extent(renderer)
            if box.x0 < 0.0 or box.x1 > fig.bbox.width or box.y0 < 0.0 or (
                box.y1 > fig.bbox.height
            ):  # fmt: skip
                out.append(text.get_text())
    return out


@pytest.mark.parametrize(
    "title",
    ["EU07 at 30 m/s", "Manchester coach extended at 20.2462 m/s",
     "Hbbins loaded at 36.6667 m/s",
     "Hbbins wagon, loaded to 22.4 t per axle, with worn S1002 wheels at 36.6667 m/s"],
)  # fmt: skip
def test_the_run_figures_titles_stay_inside_the_figure(title):
    """A section's run figures (a shipped vehicle's name and the section's speed as the run
    writes them) keep every title inside the figure; the lateral displacement's title with the
    hunting verdict ran over both edges for the coach (-14 to 1074 px of 1000) and is wrapped;
    a figure's title set in smaller type when a long vehicle name needs it (down to 8 pt).
    Synthetic series of tests/test_results.py (a 20 m hunting wave)."""
    import math

    import numpy as np
    from test_results import WHEEL_LOAD_N, make_ts, summary_of

    from railexu.report.run_figures import run_figures

    x = np.arange(0.0, 120.0, 0.1)
    y = 6e-3 * np.sin(2 * np.pi * x / 20.0)
    forces = {(1, "left"): (np.where(y > 5e-3, -30e3, 2e3), WHEEL_LOAD_N)}
    angles = {(1, "left"): np.where(y > 5e-3, math.radians(68), 0.02)}
    ts = make_ts(x, [y, 0.8 * y], forces=forces, angles=angles,
                 bodies={"bogie_1": 0.5 * y, "car_body": 0.1 * y})  # fmt: skip
    summary = summary_of(ts)
    assert summary["hunting"]["detected"]  # the long title: the verdict is in it
    for name, fig in run_figures(ts, summary, title=title).items():
        assert _texts_outside(fig) == [], name


def test_a_quick_zone_study_says_it_is_a_trend():
    """The quick programme's zone studies (their study pages and figures) carry the notice, as
    acceptance.json, the zone figures and the report page do; the full programme's do not."""
    from railexu.assessment.acceptance.programme import load_programme
    from railexu.study.acceptance.runner import zone_study_name

    for quick in (True, False):
        prog = load_programme("coach", quick=quick)
        name = zone_study_name(prog, prog.zone("straight"))
        assert name.startswith("EN 14363 coach: straight")
        assert ("quick programme: a trend, not an acceptance verdict" in name) is quick
