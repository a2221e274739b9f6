"""Threshold-free stability verdicts, the fold of the followed branch and the ramp's drift rule
(issue 28), on synthetic runs whose branches are known: each plateau (or run) is a sine whose
envelope is set by the test and classified by railexu's own growth-rate classification
(``classify_window``), so that only the method's logic is replaced.

The test vehicle's branches (a subcritical pair as measured on the EU07 bogie,
docs/validation.md): a large cycle of 7 mm that exists down to :data:`FOLD` and a small cycle of
``0.1 mm (v - 18 m/s)`` that exists down to :data:`SMALL_END` (0.4 mm there: below the 1 mm
label floor, as the bogie's 0.4 mm at 20 m/s); below both every motion decays."""

from __future__ import annotations

import numpy as np
import pytest

from railexu.stability import CriticalSpeedSettings, bisection_critical_speed
from railexu.stability.nonlinear import classify_window

FOLD = 32.0
SMALL_END = 22.0
FREQUENCY_HZ = 3.0
T = np.arange(0.0, 8.0, 0.01)  # a plateau's fit window: 24 periods at 100 Hz


def _small(v: float) -> float:
    return 1e-4 * (v - 18.0)


def _plateau(amplitude_m: float, growth_per_s: float, settings) -> dict:
    """A plateau's classification by railexu's rules from a sine of the given envelope."""
    y = amplitude_m * np.exp(growth_per_s * T) * np.sin(2 * np.pi * FREQUENCY_HZ * T + 0.4)
    return classify_window(T, {"ws1": y, "ws2": 0.5 * y}, settings)


def _fake_stages(monkeypatch):
    """Each stage's run replaced: the motion stays on the large cycle while the speed is at least
    FOLD, then falls onto the small cycle (above SMALL_END) or decays."""
    import railexu.stability.branch as br

    stages = []

    def fake(vehicle, track, speeds, settings):
        stages.append(list(speeds))
        out, large = [], True
        for v in speeds:
            large = large and v >= FOLD
            if large:
                c = _plateau(7e-3, 0.0, settings)
            elif v >= SMALL_END:
                c = _plateau(_small(v), 0.0, settings)
            else:
                c = _plateau(_small(SMALL_END), -1.0, settings)
            out.append({"speed_m_per_s": v, **c})
        return out

    monkeypatch.setattr(br, "run_stage", fake)
    return stages


def _settings(**kw) -> CriticalSpeedSettings:
    base = dict(methods=("branch",), speed_min_m_per_s=15.0, speed_max_m_per_s=45.0,
                tolerance_m_per_s=1.0, branch_step_m_per_s=5.0, max_runs=30)  # fmt: skip
    return CriticalSpeedSettings(**{**base, **kw})


def test_the_branch_reports_its_fold_and_the_lowest_sustained_cycle(monkeypatch):
    """The large cycle's fold (32 m/s) is bracketed within the 1 m/s tolerance, with the large
    cycle's amplitude and what the motion does below it (the small cycle, another branch); the
    critical speed is the lowest speed with a sustained cycle (22 m/s, the small cycle: 0.4 mm,
    reported), not where a cycle crosses 1 mm (28 m/s); two branches are listed."""
    from railexu.stability import branch_critical_speed

    stages = _fake_stages(monkeypatch)
    result = branch_critical_speed(None, None, _settings())
    assert result["status"] == "converged", result.get("note")
    fold = result["fold"]
    lo, hi = fold["bracket_m_per_s"]
    assert lo < FOLD <= hi and hi - lo <= 1.0 and fold["converged"]
    assert fold["amplitude_m"] == pytest.approx(7e-3, rel=0.02)
    assert fold["below"]["branch"] == 1 and fold["below"]["amplitude_m"] < 2e-3
    lo, hi = result["bracket_m_per_s"]
    assert lo < SMALL_END <= hi and hi - lo <= 1.0
    assert result["critical_speed_m_per_s"] == hi
    assert result["critical_amplitude_m"] == pytest.approx(_small(hi), rel=0.02)
    assert [b["index"] for b in result["branches"]] == [0, 1]
    large, small = result["branches"]
    assert min(large["speeds_m_per_s"]) == fold["speed_m_per_s"]
    assert min(small["speeds_m_per_s"]) == hi
    # stage 0 down the whole range, then the fold refined from the top, then the lowest cycle
    assert stages[0] == [45.0, 40.0, 35.0, 30.0, 25.0, 20.0, 15.0]
    assert stages[1][:2] == [45.0, 35.0]
    assert result["plateaus_run"] == sum(len(s) for s in stages) <= 30
    assert "no factor" in result["branch_rule"]
    assert fold["discontinuity"] == "jump" and all(lv["jump"] for lv in fold["levels"])


@pytest.mark.parametrize("floor_mm", [0.3, 3.0])
def test_the_verdicts_do_not_move_with_the_limit_cycle_floor(monkeypatch, floor_mm):
    """The branch's critical speed, bracket, fold and every plateau's stable/unstable verdict, and
    the bisection's speed, are the same with the 1 mm label floor (``limit_cycle_floor``) set to
    0.3 or 3 mm: only the labels (``small limit cycle``) change. Before issue 28's change the
    verdict was where the small cycle crossed that floor (28 m/s at 1 mm)."""
    from railexu.stability import branch_critical_speed

    _fake_stages(monkeypatch)
    ref = branch_critical_speed(None, None, _settings())
    other = branch_critical_speed(None, None, _settings(limit_cycle_floor_m=floor_mm * 1e-3))
    for key in ("critical_speed_m_per_s", "bracket_m_per_s", "stages"):
        assert other[key] == ref[key], key
    for key in ("bracket_m_per_s", "speed_m_per_s", "amplitude_m"):
        assert other["fold"][key] == ref["fold"][key], key
    assert [p["stable"] for p in other["branch"]] == [p["stable"] for p in ref["branch"]]
    labels = {p["classification"] for p in other["branch"]} | {
        p["classification"] for p in ref["branch"]
    }
    assert "small limit cycle" in labels  # the label moves, the verdict does not

    import railexu.stability.nonlinear as nl

    def fake_run(vehicle, track, speed, settings, offset_m=None):
        amp, growth = (_small(speed), 0.0) if speed >= SMALL_END else (2e-4, -1.0)
        return {"speed_m_per_s": speed, **_plateau(amp, growth, settings)}

    monkeypatch.setattr(nl, "nonlinear_run_is_stable", fake_run)
    bis = [
        bisection_critical_speed(None, None, _settings(methods=("bisection",), **kw))
        for kw in ({}, {"limit_cycle_floor_m": floor_mm * 1e-3})
    ]
    assert bis[0]["critical_speed_m_per_s"] == bis[1]["critical_speed_m_per_s"]
    lo, hi = bis[0]["bracket_m_per_s"]
    assert lo < SMALL_END <= hi
    # the bisection says that its unstable edge is a bounded cycle, with its amplitude
    assert "sustained cycle of 0.4" in bis[0]["note"]
    assert bis[0]["critical_run"]["amplitude_m"] == pytest.approx(_small(hi), rel=0.02)


def test_a_budget_too_small_for_the_fold_says_so(monkeypatch):
    """With 10 plateaus the first stage (7) is run and the fold's refinement (5 more) is not:
    the status says so and the fold keeps the first stage's 5 m/s bracket."""
    from railexu.stability import branch_critical_speed

    _fake_stages(monkeypatch)
    result = branch_critical_speed(None, None, _settings(max_runs=10))
    assert result["status"] == "budget exhausted" and not result["converged"]
    assert "refining the fold" in result["note"]
    assert result["fold"]["bracket_m_per_s"] == [30.0, 35.0] and not result["fold"]["converged"]


def _fake_continuous(monkeypatch):
    """Each stage's run replaced by a branch that is steep but continuous: 7 mm down to 34 m/s,
    falling linearly to 1.2 mm at 30 m/s and on along the small cycle (1.2 mm at 30 m/s) down
    to SMALL_END. With 5 m/s steps it falls from 7 to 1.2 mm in one step, as across the fold
    of :func:`_fake_stages`."""
    import railexu.stability.branch as br

    def amplitude(v):
        if v >= 34.0:
            return 7e-3
        if v >= 30.0:
            return 1.2e-3 + (7e-3 - 1.2e-3) * (v - 30.0) / 4.0
        return _small(v)

    def fake(vehicle, track, speeds, settings):
        out = []
        for v in speeds:
            if v >= SMALL_END:
                c = _plateau(amplitude(v), 0.0, settings)
            else:
                c = _plateau(_small(SMALL_END), -1.0, settings)
            out.append({"speed_m_per_s": v, **c})
        return out

    monkeypatch.setattr(br, "run_stage", fake)


@pytest.mark.parametrize("refinement", [0.25, 1.0 / 3.0])
def test_the_fold_is_a_discontinuity_found_by_refinement(monkeypatch, refinement):
    """No factor decides the fold (railexu.stability.fold): a jump of 7 -> 1.3 mm at 32 m/s and
    a continuous fall of 7 -> 1.2 mm over 34-30 m/s look alike with 5 m/s steps (the old rule,
    a drop below half the amplitude above, called both a fold). Refined, the jump stays in one
    sub-step (its fall exceeds all other changes together) and is bracketed within the 1 m/s
    tolerance; the continuous fall spreads over the sub-steps (each carries 1/n of it) and no
    fold is reported. The verdicts are the same with the bracket refined in quarters and in
    thirds (the one constant of the search, ``REFINEMENT``)."""
    import railexu.stability.branch as br
    from railexu.stability import branch_critical_speed

    monkeypatch.setattr(br, "REFINEMENT", refinement)
    _fake_stages(monkeypatch)
    jump = branch_critical_speed(None, None, _settings())
    assert jump["status"] == "converged", jump.get("note")
    lo, hi = jump["fold"]["bracket_m_per_s"]
    assert lo < FOLD <= hi and hi - lo <= 1.0
    assert jump["fold"]["discontinuity"] == "jump"
    for level in jump["fold"]["levels"]:
        assert level["largest_fall_m"] > 5e-3 > level["other_change_m"]
    assert [b["index"] for b in jump["branches"]] == [0, 1]

    _fake_continuous(monkeypatch)
    smooth = branch_critical_speed(None, None, _settings())
    assert smooth["fold"] is None and smooth["status"] == "converged", smooth.get("note")
    search = smooth["fold_search"]
    assert search["candidate_m_per_s"] == [30.0, 35.0]
    assert search["discontinuity"] == "continuous" and len(search["levels"]) == 1
    level = search["levels"][0]
    # a linear fall over n sub-steps: the largest carries about 1/n of 5.8 mm, the rest more
    assert level["largest_fall_m"] < level["other_change_m"]
    assert [b["index"] for b in smooth["branches"]] == [0]  # one branch down to the loss
    lo, hi = smooth["bracket_m_per_s"]
    assert lo < SMALL_END <= hi and hi - lo <= 1.0


def test_the_concentration_rule_on_measured_amplitudes():
    """:func:`~railexu.stability.fold.concentrated` on amplitudes as measured with the
    patch-centroid kernel (docs/validation.md, the methods table): the folds of the EU07 bogie
    (refined in quarters from 35 m/s: 6.62, 6.33 mm on the large cycle, 0.45 mm below) and of
    the EU07 (from 45 m/s: 6.51 ... 5.92 mm, then 0.48 mm) are jumps; a linear fall is not, nor
    a square-root end of a branch at rest (a supercritical Hopf bifurcation: 1, 0.87, 0.71,
    0.5, 0 mm); a stable plateau counts as 0 and a plateau without a verdict as unknown."""
    from railexu.stability.fold import attractor_amplitude, concentrated, nearer_to_upper

    bogie = concentrated([6.62e-3, 6.33e-3, 0.454e-3, 0.446e-3, 0.450e-3])  # 35 -> 30 m/s
    assert bogie["jump"] and bogie["index"] == 1
    eu07 = concentrated([6.51e-3, 6.39e-3, 6.10e-3, 5.92e-3, 0.483e-3])  # 45 -> 40 m/s
    assert eu07["jump"] and eu07["index"] == 3
    assert not concentrated([4e-3, 3e-3, 2e-3, 1e-3, 0.0])["jump"]
    assert not concentrated([1e-3, 0.87e-3, 0.71e-3, 0.5e-3, 0.0])["jump"]
    assert not concentrated([1e-3, 1.1e-3, 1.2e-3])["jump"]  # never falls
    assert attractor_amplitude({"stable": True, "amplitude_m": 2e-3}) == 0.0
    assert attractor_amplitude({"stable": False, "amplitude_m": 2e-3}) == 2e-3
    assert attractor_amplitude({"stable": None}) is None
    assert nearer_to_upper(5.9e-3, 6.1e-3, 1.8e-3) and not nearer_to_upper(2.2e-3, 6.1e-3, 1.8e-3)


class _Ramp:
    """A ramp's time series: 12 s at ``v0``, then a deceleration ``a``; a 3 Hz cycle whose
    amplitude follows the branch ``2 mm exp(slope (v - 40))`` (d ln A / dV = slope)."""

    def __init__(self, v0: float, a: float, slope: float, v_end: float):
        dt, t_settle = 0.01, 12.0
        self.time_s = t = np.arange(0.0, t_settle + (v0 - v_end) / a, dt)
        speed = np.where(t < t_settle, v0, v0 - a * (t - t_settle))
        self.distance_m = np.cumsum(speed) * dt - speed[0] * dt
        y = 2e-3 * np.exp(slope * (speed - 40.0)) * np.sin(2 * np.pi * FREQUENCY_HZ * t)
        self.columns = {"speed_m_per_s": speed, "ws1_lateral_m": y}
        self.settle_m = float(v0 * t_settle)

    def wheelset_indices(self):
        return [1]

    def __getitem__(self, name):
        return self.columns[name]


@pytest.mark.parametrize("a, within", [(0.1, True), (0.6, False)])
def test_the_ramp_measures_its_drift_against_the_1_percent_band(a, within):
    """A branch with d ln A / dV = 0.15 per m/s at 3 Hz drifts by 0.15 a / 3 per period on a
    ramp: 0.5 % at 0.1 m/s^2 (within the 1 % band), 3 % at 0.6 m/s^2 (outside: the windows are
    called decaying and the ramp says to use at most 0.01 x 3 / 0.15 = 0.2 m/s^2, the default).
    The measured slope within 10 % (the fitted envelope's amplitude at each window's end)."""
    from railexu.stability.ramp import DEFAULT_DECELERATION_M_PER_S2, classify_ramp

    ts = _Ramp(40.0, a, 0.15, 34.0)
    out = classify_ramp(ts, ts.settle_m, a, CriticalSpeedSettings(methods=("ramp",)))
    assert out["branch_slope_per_m_per_s"] == pytest.approx(0.15, rel=0.1)
    assert out["drift_per_period"] == pytest.approx(0.15 * a / FREQUENCY_HZ, rel=0.1)
    assert out["drift_within_band"] is within
    assert out["max_deceleration_m_per_s2"] == pytest.approx(0.2, rel=0.1)
    assert DEFAULT_DECELERATION_M_PER_S2 == 0.2
    assert CriticalSpeedSettings().ramp_deceleration_m_per_s2 == DEFAULT_DECELERATION_M_PER_S2


def test_the_check_ramp_stays_within_the_steepest_deceleration():
    """The second ramp runs at twice the requested deceleration, or at half of it where twice
    would pass the 5 m/s^2 that a speed profile allows (beyond the adhesion of dry rail)."""
    from railexu.stability.ramp import check_deceleration

    assert check_deceleration(CriticalSpeedSettings()) == pytest.approx(0.4)
    assert check_deceleration(CriticalSpeedSettings(ramp_deceleration_m_per_s2=2.5)) == 5.0
    assert check_deceleration(CriticalSpeedSettings(ramp_deceleration_m_per_s2=4.0)) == 2.0


def test_a_run_too_short_to_classify_gives_no_verdict(monkeypatch):
    """Fewer than four periods in the fit window: no verdict (not "stable"); the bisection and
    the branch stop and say so, and the command exits with 1 (not converged)."""
    import railexu.stability.nonlinear as nl
    from railexu.cli.critical_speed import unfinished_methods
    from railexu.stability import branch_critical_speed

    settings = _settings(methods=("bisection",))
    t = np.arange(0.0, 1.0, 0.01)  # 3 periods at 3 Hz
    short = classify_window(t, {"ws1": 2e-3 * np.sin(2 * np.pi * FREQUENCY_HZ * t)}, settings)
    assert short["classification"] == "too short" and short["stable"] is None

    def fake_run(vehicle, track, speed, settings, offset_m=None):
        return {"speed_m_per_s": speed, **short}

    monkeypatch.setattr(nl, "nonlinear_run_is_stable", fake_run)
    bis = bisection_critical_speed(None, None, settings)
    assert bis["status"] == "no verdict" and "too short to classify" in bis["note"]
    assert len(bis["runs"]) == 1 and bis["critical_speed_m_per_s"] is None

    import railexu.stability.branch as br

    monkeypatch.setattr(br, "run_stage", lambda v, tr, speeds, s: [
        {"speed_m_per_s": x, **short} for x in speeds])  # fmt: skip
    branch = branch_critical_speed(None, None, _settings())
    assert branch["status"] == "no verdict" and not branch["converged"]
    result = {"bisection": bis, "branch": branch, "ramp": {"status": "not found"}}
    assert unfinished_methods(result) == ["branch (no verdict)", "bisection (no verdict)"]


class _FoldRamp:
    """A ramp's time series over a fold: 12 s of a 3 Hz, 3 mm cycle at ``v0``, then a
    deceleration ``a``; the cycle holds down to ``fold`` m/s and then decays at 1.5 /s to rest."""

    def __init__(self, v0: float, a: float, fold: float, v_end: float):
        dt, t_settle = 0.01, 12.0
        self.time_s = t = np.arange(0.0, t_settle + (v0 - v_end) / a, dt)
        speed = np.where(t < t_settle, v0, v0 - a * (t - t_settle))
        self.distance_m = np.cumsum(speed) * dt - speed[0] * dt
        t_fold = t_settle + (v0 - fold) / a
        y = 3e-3 * np.exp(-1.5 * np.clip(t - t_fold, 0.0, None)) * np.sin(2 * np.pi * 3.0 * t)
        self.columns = {"speed_m_per_s": speed, "ws1_lateral_m": y}
        self.settle_m = float(v0 * t_settle)

    def wheelset_indices(self):
        return [1]

    def __getitem__(self, name):
        return self.columns[name]


@pytest.mark.parametrize("fast_fold, agree", [(33.0, True), (22.0, False)])
def test_the_ramp_gives_a_verdict_only_where_its_two_rates_agree(monkeypatch, fast_fold, agree):
    """The ramp's two runs at 0.5 and 1 m/s^2 (windows of 16 periods of 3 Hz: resolutions 2.67
    and 5.33 m/s). Where the cycle vanishes at 33 m/s on both, the speeds agree within the sum
    of the resolutions and the method's critical speed and fold are the slower ramp's. Where on
    the faster ramp the cycle outlives the speed down to 22 m/s (a motion that lags the ramp),
    the two differ by 11 m/s, more than 8 m/s: the result is "rate-dependent", no verdict (the
    command then exits unconverged), with both speeds."""
    import railexu.stability.ramp as rp
    from railexu.cli.critical_speed import unfinished_methods

    def fake(vehicle, track, a, settings):
        ts = _FoldRamp(45.0, a, 33.0 if a == 0.5 else fast_fold, 15.0)
        out = {"deceleration_m_per_s2": a, "distance_m": float(ts.distance_m[-1])}
        out.update(rp.classify_ramp(ts, ts.settle_m, a, settings))
        out["status"] = "converged" if out["critical_speed_m_per_s"] else "not found"
        return out

    monkeypatch.setattr(rp, "one_ramp", fake)
    settings = CriticalSpeedSettings(methods=("ramp",), ramp_deceleration_m_per_s2=0.5,
                                     speed_min_m_per_s=15.0, speed_max_m_per_s=45.0)  # fmt: skip
    result = rp.ramp_critical_speed(None, None, settings)
    slow, fast = result["critical_speed_m_per_s_by_rate"]
    assert 33.0 - 2.67 <= slow <= 33.0 + 2.67
    assert fast_fold - 5.33 <= fast <= fast_fold + 5.33
    assert result["rate_independent"] is agree
    assert result["fold_rate_independent"] is agree
    if agree:
        assert result["status"] == "converged"
        assert result["critical_speed_m_per_s"] == slow
        assert result["fold_m_per_s"] == result["fold_m_per_s_by_rate"][0]
        assert 33.0 - 2.67 <= result["fold_m_per_s"] <= 33.0 + 2.67
    else:
        assert result["status"] == "rate-dependent"
        assert result["critical_speed_m_per_s"] is None and result["fold_m_per_s"] is None
        assert "rate-dependent, no verdict" in result["note"]
        assert unfinished_methods({"ramp": result}) == ["ramp (rate-dependent)"]


def test_a_fold_to_rest_is_the_critical_speed(monkeypatch):
    """The classical subcritical case (True 1999): the 7 mm cycle holds down to 32 m/s and below
    it every motion decays to rest. The fold (a jump to rest: 7 mm to 0 in one sub-step) and the
    lowest cycle are one bracket, refined within the 1 m/s tolerance, and the critical speed is
    its upper end; one branch is listed."""
    import railexu.stability.branch as br
    from railexu.stability import branch_critical_speed

    def fake(vehicle, track, speeds, settings):
        out, large = [], True
        for v in speeds:
            large = large and v >= FOLD
            c = _plateau(7e-3, 0.0, settings) if large else _plateau(2e-4, -1.0, settings)
            out.append({"speed_m_per_s": v, **c})
        return out

    monkeypatch.setattr(br, "run_stage", fake)
    result = branch_critical_speed(None, None, _settings())
    assert result["status"] == "converged", result.get("note")
    fold = result["fold"]
    lo, hi = fold["bracket_m_per_s"]
    assert lo < FOLD <= hi and hi - lo <= 1.0 and fold["discontinuity"] == "jump"
    assert result["bracket_m_per_s"] == fold["bracket_m_per_s"]
    assert result["critical_speed_m_per_s"] == hi
    assert fold["below"]["classification"] in ("decaying", "below floor")
    assert [b["index"] for b in result["branches"]] == [0]


def test_an_unsettled_top_plateau_gives_no_verdict(monkeypatch):
    """A top plateau still decaying onto its cycle from a larger disturbance is classified
    "decaying" (stable); the plateaus below it, started from its state, hold the cycle. That is
    not "no limit cycle at the highest speed" (as measured on the EU07 bogie at 45 m/s after
    150 m: 6.89 mm, -1.4 % per period, then 7.08 mm sustained at 40 m/s): the branch says it
    has no verdict and asks for a longer distance; where every plateau decays, no cycle."""
    import railexu.stability.branch as br
    from railexu.stability import branch_critical_speed

    def fake(vehicle, track, speeds, settings):
        out = []
        for k, v in enumerate(speeds):
            c = _plateau(7e-3, -0.05 if k == 0 else 0.0, settings) if v >= FOLD else (
                _plateau(2e-4, -1.0, settings))  # fmt: skip
            out.append({"speed_m_per_s": v, **c})
        return out

    monkeypatch.setattr(br, "run_stage", fake)
    result = branch_critical_speed(None, None, _settings())
    assert result["branch"][0]["classification"] == "decaying"
    assert result["status"] == "no verdict" and not result["converged"]
    assert "had not settled" in result["note"] and "longer" in result["note"]

    monkeypatch.setattr(br, "run_stage", lambda v, tr, speeds, s: [
        {"speed_m_per_s": x, **_plateau(2e-4, -1.0, s)} for x in speeds])  # fmt: skip
    rest = branch_critical_speed(None, None, _settings())
    assert rest["status"] == "converged" and "no limit cycle" in rest["note"]
