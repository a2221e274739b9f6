"""``railexu report``: the self-contained report.html of a run and of a study.

The page is checked as text (no network reference, the file hashes, the tables) and, as a person
would see it, in a real headless Chromium (Debian's ``chromium`` package; skipped with the
reason when it is absent): it loads without console errors, its images decode, its tables are
there, the case table sorts when a heading is clicked, and a screenshot is taken.
"""

from __future__ import annotations

import hashlib
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from railexu.cli import main
from railexu.report.animate import AnimationSettings, animate_run
from railexu.report.html_report import write_report
from railexu.report.run_files import write_run
from railexu.results.run import RunSettings, run
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory):
    """A short run of the EU07 bogie at 45 m/s with its animations."""
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07_bogie.yaml")
    result = run(vehicle, None, RunSettings(speed_m_per_s=45.0, distance_m=45.0))
    out = tmp_path_factory.mktemp("run")
    write_run(result, out)
    animate_run(out, settings=AnimationSettings(fps=8, dpi=50))
    write_report(out)
    return out


@pytest.fixture(scope="module")
def study_folder(tmp_path_factory):
    """A study of three speeds, run in this process, with its reports."""
    from railexu.study import run_study

    tmp = tmp_path_factory.mktemp("study")
    spec = tmp / "speeds.yaml"
    spec.write_text(
        "format_version: 1\nname: bogie speeds\nanalysis: run\n"
        f"base:\n  vehicle: {ROOT / 'vehicles' / 'eu07_bogie.yaml'}\n"
        "  run: {distance: 8 m, initial_lateral: 2 mm}\n"
        "vary:\n  parameters:\n    run.speed: [10 m/s, 30 m/s, 20 m/s]\n"
        "collect:\n  - max_abs_lateral_force_N\n  - wheelsets.0.max_abs_lateral_m\n",
        encoding="utf-8",
    )
    out = tmp / "out"
    run_study(spec, out, workers=0)
    assert main(["report", str(out), "--quiet"]) == 0
    return out


class _Page(HTMLParser):
    """Tags, attributes and table cells of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict]] = []
        self.cells: list[str] = []
        self._cell: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.cells.append("".join(self._cell).strip())
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _parse(text: str) -> _Page:
    page = _Page()
    page.feed(text)
    return page


def _no_network(page: _Page) -> None:
    for tag, attrs in page.tags:
        for key in ("src", "href"):
            value = attrs.get(key) or ""
            assert not re.match(r"^(https?:)?//", value), f"<{tag} {key}={value[:60]}>"
            if tag in ("img", "video", "script", "link") and key in attrs:
                assert value.startswith("data:"), f"<{tag}> refers to a file: {value[:60]}"


def test_run_report_is_self_contained(run_folder):
    text = (run_folder / "report.html").read_text(encoding="utf-8")
    page = _parse(text)
    _no_network(page)
    images = [a["src"] for t, a in page.tags if t == "img"]
    assert sum(s.startswith("data:image/gif;base64,") for s in images) == 2  # contact, plan
    assert sum(s.startswith("data:image/png;base64,") for s in images) >= 3  # the figures
    digest = hashlib.sha256((ROOT / "vehicles" / "eu07_bogie.yaml").read_bytes()).hexdigest()
    assert digest in page.cells
    assert "completed" in text and "max Y/Q (EN 14363) [-]" in page.cells
    # inputs, settings, results, the solver's step facts, the assessment's criteria, ride
    # comfort at the body points
    assert sum(t == "table" for t, _ in page.tags) == 6
    assert "<h2>Assessment</h2>" in text and "<h2>Ride comfort</h2>" in text


def test_study_report_links_its_cases(study_folder):
    text = (study_folder / "report.html").read_text(encoding="utf-8")
    page = _parse(text)
    _no_network(page)
    links = [a["href"] for t, a in page.tags if t == "a"]
    assert len(links) == 3
    for link in links:
        assert (study_folder / link).is_file()
    tables = [a for t, a in page.tags if t == "table"]
    assert tables == [{"class": "sortable"}]
    assert "run.speed" in page.cells and "max_abs_lateral_force_N" in page.cells
    assert any(t == "img" for t, _ in page.tags)  # the study figure


def test_report_refuses_other_folders(tmp_path, capsys):
    assert main(["report", str(tmp_path)]) == 2
    assert "neither a run's output" in capsys.readouterr().err


# ----------------------------------------------------------------------------------------------
# in a real browser
# ----------------------------------------------------------------------------------------------

needs_chromium = pytest.mark.skipif(
    CHROMIUM is None,
    reason="Chromium is not installed (Debian: apt-get install chromium); .ci/run installs it",
)
_PROBE = """<script>
window.addEventListener("load", function () {
  var imgs = Array.prototype.slice.call(document.images);
  document.body.dataset.images = imgs.length;
  document.body.dataset.decoded = imgs.filter(function (i) { return i.naturalWidth > 0; }).length;
  %s
});
</script></body>"""


def _chromium(page: Path, tmp: Path, *extra: str) -> subprocess.CompletedProcess:
    args = [
        CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--no-first-run", "--disable-component-update", "--disable-sync",
        f"--user-data-dir={tmp / 'profile'}", "--enable-logging=stderr", "--v=0",
        "--virtual-time-budget=5000", *extra, page.resolve().as_uri(),
    ]  # fmt: skip
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


def _console_errors(stderr: str) -> list[str]:
    """Console messages of the page (Chromium logs them as CONSOLE lines), and JavaScript
    errors; the browser's own complaints (no D-Bus in a container) are not the page's."""
    return [
        line
        for line in stderr.splitlines()
        if "CONSOLE" in line or "Uncaught" in line or "SyntaxError" in line
    ]


def _probe_copy(report: Path, tmp: Path, action: str = "") -> Path:
    text = report.read_text(encoding="utf-8").replace("</body>", _PROBE % action, 1)
    copy = report.with_name("probe.html")
    copy.write_text(text, encoding="utf-8")
    return copy


def _dom(report: Path, tmp: Path, action: str = "") -> tuple[str, str]:
    done = _chromium(_probe_copy(report, tmp, action), tmp, "--dump-dom")
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout, done.stderr


@needs_chromium
def test_run_report_in_chromium(run_folder, tmp_path):
    dom, stderr = _dom(run_folder / "report.html", tmp_path)
    assert _console_errors(stderr) == []
    images = int(re.search(r'data-images="(\d+)"', dom).group(1))
    decoded = int(re.search(r'data-decoded="(\d+)"', dom).group(1))
    assert images >= 5 and decoded == images  # two animations and the figures, all decoded
    # inputs, settings, results, the solver's step facts, the assessment, ride comfort
    assert dom.count("<table") == 6 and "Results" in dom and "Assessment" in dom
    assert "Solver" in dom
    shot = tmp_path / "run_report.png"
    done = _chromium(run_folder / "report.html", tmp_path, f"--screenshot={shot}",
                     "--window-size=1200,1800")  # fmt: skip
    assert done.returncode == 0 and shot.stat().st_size > 10_000
    from PIL import Image

    with Image.open(shot) as img:
        pixels = np.asarray(img.convert("L"))
    assert pixels.shape == (1800, 1200) and pixels.std() > 10  # not a blank page


@needs_chromium
def test_study_report_sorts_in_chromium(study_folder, tmp_path):
    dom, stderr = _dom(study_folder / "report.html", tmp_path)
    assert _console_errors(stderr) == []
    assert 'data-decoded="1"' in dom and 'data-images="1"' in dom
    speeds = re.findall(r"<td>(\d+) m/s</td>", dom)
    assert speeds == ["10", "30", "20"]  # case order
    # a person clicks the speed heading twice: ascending, then descending (numeric, not text)
    column = "var th = document.querySelectorAll('table.sortable th')[1];"
    dom, stderr = _dom(study_folder / "report.html", tmp_path, column + "th.click();")
    assert re.findall(r"<td>(\d+) m/s</td>", dom) == ["10", "20", "30"]
    dom, _ = _dom(study_folder / "report.html", tmp_path, column + "th.click(); th.click();")
    assert re.findall(r"<td>(\d+) m/s</td>", dom) == ["30", "20", "10"]
    assert _console_errors(stderr) == []
    shot = tmp_path / "study_report.png"
    done = _chromium(study_folder / "report.html", tmp_path, f"--screenshot={shot}",
                     "--window-size=1200,1400")  # fmt: skip
    assert done.returncode == 0 and shot.stat().st_size > 10_000


@needs_chromium
def test_console_errors_are_seen(tmp_path):
    """The console check is not blind: a page that throws is caught."""
    bad = tmp_path / "bad.html"
    bad.write_text("<html><body><script>undefinedFunction();</script></body></html>")
    done = _chromium(bad, tmp_path, "--dump-dom")
    assert any("undefinedFunction" in line for line in _console_errors(done.stderr))


def test_assessment_table(run_folder, tmp_path):
    """The summary's assessment (criteria with value, limit and pass) becomes a table with a
    verdict per criterion, and the exceeded ones are named."""
    import json

    from railexu.report.html_report import run_report_html

    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    summary = json.loads((folder / "summary.json").read_text())
    criterion = {"unit": "-", "where": "ws1 right", "distance_m": 40.0, "window": "2 m",
                 "rule": "EN 14363"}  # fmt: skip
    summary["assessment"] = {
        "category": "safety",
        "exceedances": ["sum_y"],
        "criteria": {
            "y_over_q": {"value": 0.5, "limit": 0.8, "pass": True, **criterion},
            "sum_y": {"value": 9e4, "limit": 7.5e4, "pass": False, **criterion},
        },
    }
    (folder / "summary.json").write_text(json.dumps(summary))
    text = run_report_html(folder, figures=False)
    page = _parse(text)
    assert "y_over_q" in page.cells and "sum_y" in page.cells
    i = page.cells.index("y_over_q")
    row = page.cells[i : i + 9]
    assert row[1] == "0.5" and row[2] == "0.8" and row[-1] == "pass"
    j = page.cells.index("sum_y")
    assert page.cells[j + 8] == "fail"
    assert "exceeded: sum_y" in text


def test_settings_are_shown_with_their_units_not_as_json():
    """A report page shows ``speed 10 m/s``, ``default (not set)`` and ``generalized-alpha``,
    never ``null`` or a quoted ``"generalized_alpha"`` (issue 27)."""
    from railexu.report.html_report import _setting_row

    assert _setting_row("speed_m_per_s", 10.0) == ("speed", "10 m/s")
    assert _setting_row("deceleration_m_per_s2", 0.5) == ("deceleration", "0.5 m/s²")
    assert _setting_row("time_step_s", 0.002) == ("time step", "0.002 s")
    assert _setting_row("evaluate_from_m", None) == ("evaluate from", "default (not set)")
    assert _setting_row("solver", "generalized_alpha") == ("solver", "generalized-alpha")
    assert _setting_row("contact_outputs", False) == ("contact outputs", "no")
    assert "null" not in _setting_row("traction", {"torque_N_m": None})[1]


def test_run_report_shows_the_solver_facts_and_warnings(run_folder):
    """The solver's step facts (docs/performance.md) are on the page with their units, so a
    run whose step the solver cut says so where a reader looks."""
    text = (run_folder / "report.html").read_text(encoding="utf-8")
    assert "<h2>Solver</h2>" in text and "step cuts" in text and "smallest step" in text
    assert "0.002 s" in text  # the time step, with its unit


def test_run_report_shows_the_wear_block():
    """A run asked for its wear (``--wear``) gets a table per wheel and per rail with units;
    a block that could not be computed says why."""
    from railexu.report.html_report import _setting_row, _wear_html

    block = {
        "law": "archard_jendel", "coefficients_file": "railexu/data/wear_rcf.yaml (shipped)",
        "computed": True, "window_m": [35.0, 40.0], "window_rule": "from 35 m",
        "wheels": [{"wheelset": 1, "side": "right", "removed_area_per_km_mm2": 0.227,
                    "max_depth_per_km_um": 159.0, "max_depth_at_mm": -31.2, "fi_surf_max": 0.131,
                    "fi_surf_max_at_mm": -30.0, "wlrm_damage_per_km": 1.29e-3}],
        "rails": [{"wheelset": 1, "side": "right", "removed_area_per_axle_um2": 893.0,
                   "max_depth_per_axle_nm": 40.0, "max_depth_at_mm": None, "fi_surf_max": 0.1,
                   "wlrm_damage_per_axle": 2e-6}],
    }  # fmt: skip
    html = _wear_html(block)
    assert "removed area [mm²/km]" in html and "ws1 right" in html and "0.227" in html
    assert "removed area [µm²/axle]" in html and "893" in html and "null" not in html
    assert "not computed: no loaded contact" in _wear_html(
        {"law": "archard_jendel", "computed": False, "reason": "no loaded contact"}
    )
    assert _setting_row("wear_law", None) == ("wear law", "none")
