"""The turnout runs table's tools (issue 29): ``benchmarks/turnout_vehicles.py`` names each
panel's rails and checks that they share the wheel's load; ``docs/turnout_run_figures.py``
takes the largest Q per rail past the crossing's wing rail end in the slices' ``s``, either
direction. Synthetic columns, no run."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _module(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def bench():
    return _module(ROOT / "benchmarks" / "turnout_vehicles.py")


@pytest.fixture(scope="module")
def figures():
    return _module(ROOT / "docs" / "turnout_run_figures.py")


def _columns(total_offset_n: float = 0.0) -> dict[str, np.ndarray]:
    """Two wheelsets over a panel at 10 .. 12 m (left side), Q per rail [N]; the wheel's total
    is the rails' sum plus ``total_offset_n`` at one sample inside the panel."""
    s = np.array([9.0, 10.5, 11.0, 11.5, 12.5])
    q1 = np.array([0.0, 20e3, 150e3, 90e3, 0.0])
    q2 = np.array([98e3, 80e3, 0.0, 10e3, 98e3])
    ts: dict[str, np.ndarray] = {}
    for i, shift in ((1, 0.0), (2, 0.2)):
        ts[f"ws{i}_s_m"] = s + shift
        ts[f"ws{i}_left_in_zone"] = np.ones_like(s)
        for r, q in ((1, q1 * (1.0 + 0.1 * (i - 1))), (2, q2)):
            ts[f"ws{i}_left_rail{r}_Q_N"] = q
            ts[f"ws{i}_left_rail{r}_Y_N"] = 0.1 * q
            ts[f"ws{i}_left_rail{r}_Tgamma_N"] = 1e-3 * q
            ts[f"ws{i}_left_rail{r}_contact_y_m"] = np.where(q > 0.0, 0.01 * r, 0.0)
        total = ts[f"ws{i}_left_rail1_Q_N"] + ts[f"ws{i}_left_rail2_Q_N"]
        ts[f"ws{i}_left_Q_N"] = total + np.array([0.0, 0.0, total_offset_n, 0.0, 0.0])
    return ts


def test_panel_quantities_under_the_rails_names_and_their_sum(bench):
    """Per rail under its name: the largest Q (the second wheelset's nose, 10 % more), |Y|,
    Tgamma; the rails' Q sum to the wheel's total (residual 0), and a total that differs
    inside the panel by 500 N shows as a residual of 500 N (outside the panel: ignored)."""
    out = bench.panel_quantities(_columns(), 2, "left", 10.0, 12.0, ["nose", "wing rail"])
    assert out["rails"] == ["nose", "wing rail"]
    nose, wing = out["by_rail"]["nose"], out["by_rail"]["wing rail"]
    assert nose["Q_max_N"] == pytest.approx(165e3) and nose["Q_max_ws"] == 2
    assert wing["Q_max_N"] == pytest.approx(80e3) and wing["Q_max_at_m"] == pytest.approx(10.5)
    assert nose["Y_absmax_N"] == pytest.approx(16.5e3)
    assert wing["Tgamma_max_N"] == pytest.approx(80.0)
    assert out["Q_max_N"] == [nose["Q_max_N"], wing["Q_max_N"]]
    assert out["Q_sum_residual_N"] == 0.0
    off = bench.panel_quantities(_columns(500.0), 2, "left", 10.0, 12.0, ["nose", "wing rail"])
    assert off["Q_sum_residual_N"] == pytest.approx(500.0)
    outside = bench.panel_quantities(_columns(500.0), 2, "left", 11.3, 12.0, ["a", "b"])
    assert outside["Q_sum_residual_N"] == 0.0


def _crossing_run(tmp_path: Path, route: str, s_slices: np.ndarray, q1, q2) -> tuple:
    """A run's line and columns: the crossing panel at 10 m .. 10 m + its slices' length, one
    wheelset at the slices' ``s_slices`` [m] (facing: increasing track distance)."""
    lo = 10.0
    hi = lo + 2.258 + 0.995
    facing = route.endswith("facing")
    s = lo + 0.995 + s_slices if facing else hi - 0.995 - s_slices
    line = {"vehicle": "v", "route": route,
            "panels": {"crossing": {"side": "left", "range_m": [lo, hi]}}}  # fmt: skip
    file = tmp_path / f"v_{route}.npz"
    np.savez(file, ws1_s_m=s, ws1_left_rail1_Q_N=np.asarray(q1, float),
             ws1_left_rail2_Q_N=np.asarray(q2, float))  # fmt: skip
    return file, line


@pytest.mark.parametrize("route", ["through_facing", "through_trailing"])
def test_past_the_wing_rail_end_per_rail(figures, tmp_path, route):
    """Past the wing rail's last slice (s = 1.0585 m): the nose's largest Q, the wing rail's up
    to 65 mm before the crossing's last slice, the rail-2 column within those 65 mm; a load
    before the wing rail's end counts in none; the same either direction."""
    s = np.array([0.5, 1.5, 2.0, 2.22, 2.30])
    q1 = [400e3, 200e3, 300e3, 50e3, 0.0]
    q2 = [90e3, 0.0, 7e3, 60e3, 99e3]  # the last one beyond the panel: not counted
    file, line = _crossing_run(tmp_path, route, s, q1, q2)
    assert figures.past_wing_end(file, line) == pytest.approx([300e3, 7e3, 60e3])


def test_sum_check_reports_the_largest_residual_per_panel(figures, tmp_path):
    """``--table``'s check line: per panel the largest ``|Q1 + Q2 - Q|`` over the runs [N] (a
    line saved before the check, the switch panel here, is left out)."""
    a = {"crossing": {"Q_sum_residual_N": 0.0, "Q_max_N": [300e3, 200e3]},
         "switch": {"Q_max_N": [1e5, 1e5]}}  # fmt: skip
    b = {"crossing": {"Q_sum_residual_N": 2e-11, "Q_max_N": [100e3, 0.0]}}
    lines = [
        {"vehicle": v, "route": "through_facing", "panels": p} for v, p in (("a", a), ("b", b))
    ]
    (tmp_path / "table.jsonl").write_text("\n".join(json.dumps(x) for x in lines))
    text = figures.sum_check(tmp_path)
    assert "crossing: largest |Q1 + Q2 - Q| 2e-11 N (largest rail Q 300 kN)" in text
    assert "switch" not in text
