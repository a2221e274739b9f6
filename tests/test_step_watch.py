"""The solver's step facts of every run (issue 29, reliability): ``summary.json``'s ``solver``
block counts the steps, the steps Exudyn's adaptive step control cut, the first cut's time and
the smallest step taken (:mod:`railexu.simulation.step_watch`), and ``railexu run`` warns when
the step was cut."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import railexu.simulation.simulate as sim
from railexu.cli import main
from railexu.operation.run_settings import RunSettings
from railexu.simulation.step_watch import StepWatch
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]
H = 2e-3  # the default step [s]


def test_watch_counts_rejected_attempts_and_short_steps():
    """The call sequence Exudyn makes (measured with a mass falling onto a Hertz spring,
    Newton limited to 3 iterations): pre-step before every attempt, post-step after every
    accepted step and once with the initial state."""
    w = StepWatch(H, 10 * H)
    w.accepted(0.0)
    for k in (1, 2):
        w.attempt(k * H)
        w.accepted(k * H)
    w.attempt(3 * H)  # rejected, retried at h/2, rejected, retried at h/4: accepted
    w.attempt(2.5 * H)
    w.attempt(2.25 * H)
    w.accepted(2.25 * H)
    facts = w.facts()
    assert facts["steps"] == 3 and facts["step_attempts"] == 5
    assert facts["step_cuts"] == 2 and facts["steps_below_time_step"] == 1
    assert facts["first_cut_time_s"] == pytest.approx(2 * H)
    assert facts["smallest_step_s"] == pytest.approx(0.25 * H)
    assert "cut the step 2 times" in w.warning()


def test_watch_failed_run_and_stopped_run():
    """The attempt the solver gave up on counts as a cut; a step the pre-step function
    refused (a free run's end) is no attempt."""
    w = StepWatch(H, 10 * H)
    w.accepted(0.0)
    w.attempt(H)
    w.attempt(0.5 * H)
    w.finish(failed=True)
    assert w.facts()["step_cuts"] == 2 and w.facts()["steps"] == 0
    assert w.facts()["smallest_step_s"] is None
    ok = StepWatch(H, 10 * H)
    ok.accepted(0.0)
    ok.attempt(H)
    ok.accepted(H)
    ok.attempt(2 * H)
    ok.not_attempted()
    ok.finish(failed=False)
    assert ok.facts()["step_cuts"] == 0 and ok.facts()["step_attempts"] == 1
    assert ok.warning() is None


def _wheelset_run(**kw):
    vehicle = load_vehicle(ROOT / "vehicles" / "wheelset.yaml")
    settings = RunSettings(speed_m_per_s=10.0, distance_m=2.0, initial_lateral_m=0.002, **kw)
    return sim.simulate(vehicle, None, settings)


def test_normal_run_reports_no_cut():
    """0.2 s at the 2 ms step: 100 steps, none cut, the smallest step the step."""
    result = _wheelset_run()
    solver = result.summary["solver"]
    assert result.status["state"] == "completed"
    assert solver["steps"] == solver["step_attempts"] == 100
    assert solver["step_cuts"] == 0 and solver["steps_below_time_step"] == 0
    assert solver["first_cut_time_s"] is None
    assert solver["smallest_step_s"] == H and solver["time_step_s"] == H
    assert not any("cut the step" in w for w in result.summary.get("warnings", []))


@pytest.fixture
def newton_limited(monkeypatch):
    """Newton limited to 3 iterations (2 modified): the wheelset's start from 2 mm needs more
    at a few steps, which the solver then halves (deterministic: one thread, fixed inputs)."""
    build = sim._solver_settings

    def limited(settings):
        ss, n_steps = build(settings)
        ss.timeIntegration.newton.maxIterations = 3
        ss.timeIntegration.newton.maxModifiedNewtonIterations = 2
        return ss, n_steps

    monkeypatch.setattr(sim, "_solver_settings", limited)


def test_cut_run_reports_cuts_and_warns(newton_limited, tmp_path, capsys):
    """The same run with Newton's iterations limited: the cuts, the first cut's time, the
    smallest step in summary.json, and the warning line on the console."""
    out = tmp_path / "run"
    status = main(["run", "wheelset", "--distance", "2", "--initial-lateral", "0.002",
                   "--out", str(out), "--quiet", "--no-plots"])  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    solver = summary["solver"]
    assert status == 0 and summary["status"]["state"] == "completed"
    assert solver["step_cuts"] > 0 and solver["steps_below_time_step"] > 0
    assert solver["step_attempts"] == solver["steps"] + solver["step_cuts"]
    assert 0.0 < solver["first_cut_time_s"] < 0.2
    # a cut halves the step (adaptiveStepDecrease 0.5): the smallest is h / 2^k
    ratio = H / solver["smallest_step_s"]
    assert ratio >= 2.0 and math.log2(ratio) == pytest.approx(round(math.log2(ratio)))
    assert solver["steps"] > 100  # more steps than 0.2 s / 2 ms
    err = capsys.readouterr().err
    assert "railexu run: warning: the solver cut the step" in err
    assert any("cut the step" in w for w in summary["warnings"])
