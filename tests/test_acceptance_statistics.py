"""EN 14363 statistical evaluation and limits (railexu.assessment.acceptance), checked against the
standard's formulas evaluated by hand in the test: no simulation.

Hand calculations: one-dimensional ``mean + k s`` with ``s`` over ``N - 1``; the simple
regression in closed form (``b1 = Sxy / Sxx``, ``b0 = mean y - b1 mean x``,
``s^2 = RSS / (N - 2)``, leverage ``1/N + (x0 - mean x)^2 / Sxx``) with Student's t from a
printed table (one-sided 95 %, 3 degrees of freedom: 2.3534; e.g. NIST/SEMATECH e-Handbook of
Statistical Methods, table 1.3.6.7.2). Tolerances: the numbers are exact up to rounding, so
1e-9 relative, 1e-4 where the t value is the table's (4 digits).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from railexu.assessment.acceptance.limits import limits_for
from railexu.assessment.acceptance.programme import TrackQuality, Zone
from railexu.assessment.acceptance.statistics import (
    AcceptanceError,
    evaluate_zone,
    one_dimensional,
    two_dimensional,
)
from railexu.errors import InputError

T_3DOF_95 = 2.3534  # Student's t, one-sided 95 %, 3 degrees of freedom (printed table)


def test_one_dimensional_is_mean_plus_k_standard_deviations():
    values = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]
    # mean 5.5; sum of squared deviations 82.5; s = sqrt(82.5 / 9) = 3.0276504
    s = math.sqrt(82.5 / 9.0)
    est = one_dimensional(values, k=2.2)
    assert est.mean == pytest.approx(5.5, rel=1e-12)
    assert est.std == pytest.approx(s, rel=1e-12)
    assert est.estimate == pytest.approx(5.5 + 2.2 * 3.0276504, rel=1e-7)
    assert est.n == 10


def test_one_dimensional_ignores_sections_without_a_value_and_refuses_too_few():
    assert one_dimensional([1.0, math.nan, 3.0], k=1.0).mean == 2.0
    with pytest.raises(AcceptanceError, match="at least 10 sections"):
        one_dimensional([1.0, 2.0, 3.0], k=2.2, minimum=10)
    with pytest.raises(AcceptanceError, match="at least 2 sections"):
        one_dimensional([1.0], k=2.2)


def test_simple_regression_with_prediction_bound_matches_the_closed_form():
    x = [0.0, 1.0, 2.0, 3.0, 4.0]
    y = [1.0, 3.0, 2.0, 5.0, 4.0]
    # mean x = 2, mean y = 3, Sxx = 10, Sxy = 8 -> b1 = 0.8, b0 = 3 - 0.8 * 2 = 1.4
    # residuals -0.4, 0.8, -1.0, 1.2, -0.6 -> RSS = 3.6, s^2 = 3.6 / 3 = 1.2
    # at x0 = 5: fitted 1.4 + 0.8 * 5 = 5.4, leverage 1/5 + (5 - 2)^2 / 10 = 1.1
    expected = 5.4 + T_3DOF_95 * math.sqrt(1.2) * math.sqrt(1.0 + 1.1)
    reg = two_dimensional(y, x, at=[5.0], quantile=0.95)
    assert reg.coefficients == pytest.approx((1.4, 0.8), rel=1e-12)
    assert reg.fitted == pytest.approx(5.4, rel=1e-12)
    assert reg.residual_std == pytest.approx(math.sqrt(1.2), rel=1e-12)
    assert reg.leverage == pytest.approx(1.1, rel=1e-12)
    assert reg.t == pytest.approx(T_3DOF_95, abs=1e-4)
    assert reg.estimate == pytest.approx(expected, rel=1e-4)
    # quasi-static quantities: the regression's value alone
    assert two_dimensional(y, x, [5.0], 0.95, dispersion=False).estimate == pytest.approx(5.4)


def test_regression_over_cant_deficiency_and_curvature_recovers_an_exact_plane():
    # y = 10 kN + 200 kN/m * I + 3e6 N m * (1/R): no scatter, so the estimate is the plane at x0
    conditions = [(0.06, 1 / 250), (0.13, 1 / 300), (0.09, 1 / 350), (0.11, 1 / 400),
                  (0.07, 1 / 320), (0.12, 1 / 270)]  # fmt: skip
    y = [10e3 + 200e3 * i + 3e6 * c for i, c in conditions]
    reg = two_dimensional(y, conditions, at=[0.13, 1 / 250], quantile=0.95)
    assert reg.estimate == pytest.approx(10e3 + 200e3 * 0.13 + 3e6 / 250, rel=1e-9)
    assert reg.residual_std == pytest.approx(0.0, abs=1e-6)


def test_regression_refuses_too_few_sections_and_regressors_without_spread():
    with pytest.raises(AcceptanceError, match="at least 4 sections"):
        two_dimensional([1, 2, 3], [[0, 1], [1, 0], [1, 1]], [1, 1], 0.95)
    with pytest.raises(AcceptanceError, match="do not vary independently"):
        two_dimensional([1, 2, 3, 4], [[0.1, 1], [0.1, 1], [0.1, 1], [0.1, 1]], [0.1, 1], 0.95)


def _zone(method: str, min_sections: int, **kw) -> Zone:
    quality = TrackQuality("QN1", "german_low", (3.0, 25.0), (7e-4, 1.2e-3), (1e-3, 1.6e-3))
    base = dict(name="z", kind="curve", n_sections=min_sections, section_length_m=100.0,
                run_in_m=50.0, method=method, min_sections=min_sections, track_quality=quality,
                radius_m=(250.0, 400.0), cant_m=0.15, cant_deficiency_m=(0.06, 0.13))  # fmt: skip
    base.update(kw)
    return Zone(**base)


def _section_values(values: dict[str, float], i: int, cd: float, radius: float):
    return SimpleNamespace(
        section=SimpleNamespace(name=f"s{i}"), values=values,
        units={k: "N" for k in values},
        conditions={"cant_deficiency_m": cd, "radius_m": radius},
        regressors=lambda names, cd=cd, r=radius: [cd if n == "cant_deficiency" else 1 / r
                                                   for n in names],
    )  # fmt: skip


def test_evaluate_zone_one_dimensional_against_the_hand_value_and_the_limit():
    sums = [40e3, 42e3, 44e3, 46e3, 48e3]  # mean 44 kN, s = sqrt(40e6 / 4) = 3162.28 N
    svs = [_section_values({"sum_Y_2m": v, "Q_qst": 100e3 + v}, i, 0.1, 300.0)
           for i, v in enumerate(sums)]  # fmt: skip
    limits = limits_for("wagon", 100e3, mean_radius_m=300.0)
    result = evaluate_zone(_zone("one_dimensional", 5), svs, limits)
    c = result.criteria["sum_Y_2m"]
    assert c.value == pytest.approx(44e3 + 2.2 * math.sqrt(40e6 / 4.0), rel=1e-12)
    # limit 0.85 (10 kN + 2 x 100 kN / 3) = 65.17 kN
    assert c.limit == pytest.approx(0.85 * (10e3 + 200e3 / 3.0), rel=1e-12)
    assert c.passed is True and c.method == "one_dimensional"
    assert "EN 14363:2016" in c.clause and c.sections == ("s0", "s1", "s2", "s3", "s4")
    assert c.assumption  # k of the shipped statistics is railexu's assumption
    q = result.criteria["Q_qst"]  # quasi-static: the mean, no k s
    assert q.value == pytest.approx(144e3, rel=1e-12) and q.passed is True
    assert result.passed is True


def test_evaluate_zone_refuses_too_few_sections_naming_the_minimum():
    svs = [_section_values({"sum_Y_2m": 40e3}, i, 0.1, 300.0) for i in range(3)]
    with pytest.raises(AcceptanceError, match="needs at least 25 sections"):
        evaluate_zone(_zone("one_dimensional", 25), svs, limits_for("coach", 80e3))


def test_evaluate_zone_two_dimensional_fails_a_quantity_over_its_limit():
    pts = [(0.06, 250.0), (0.13, 300.0), (0.09, 350.0), (0.11, 400.0), (0.07, 320.0)]
    svs = [_section_values({"Y_qst": 40e3 + 300e3 * cd}, i, cd, r)
           for i, (cd, r) in enumerate(pts)]  # fmt: skip
    zone = _zone("two_dimensional", 5, regressors=("cant_deficiency",), evaluate_at=(0.13,))
    result = evaluate_zone(zone, svs, limits_for("locomotive", 100e3, mean_radius_m=300.0))
    c = result.criteria["Y_qst"]
    # exact line: 40 kN + 300 kN/m x 0.13 m = 79 kN against 30 + 10500 / 300 = 65 kN
    assert c.value == pytest.approx(79e3, rel=1e-9)
    assert c.limit == pytest.approx(65e3, rel=1e-12)
    assert c.passed is False and result.passed is False


def test_limits_by_category_against_the_formulas():
    q0 = 100e3  # N
    wagon, loco = limits_for("wagon", q0, 120 / 3.6, 350.0, 5000.0), limits_for("locomotive", q0)
    assert wagon["sum_Y_2m"].value == pytest.approx(0.85 * (10e3 + 2 * q0 / 3), rel=1e-12)
    assert loco["sum_Y_2m"].value == pytest.approx(10e3 + 2 * q0 / 3, rel=1e-12)
    assert wagon["Y_over_Q_2m"].value == 0.8
    assert wagon["Y_qst"].value == pytest.approx(60e3, rel=1e-12)  # 30 + 10500 / 350
    assert wagon["Q_qst"].value == 145e3
    assert wagon["Q_max"].value == pytest.approx(190e3)  # 90 + 100 kN, below the 200 kN cap
    assert limits_for("coach", q0, 230 / 3.6)["Q_max"].value == pytest.approx(180e3)  # capped
    assert wagon["bogie_frame_acc_y_max"].value == pytest.approx(11.0)  # 12 - 5 t / 5
    assert wagon["bogie_frame_acc_y_rms"].value == pytest.approx(5.5)
    assert "Y_qst" not in loco and "Q_max" not in loco  # straight track, no speed given
    assert wagon["car_body_acc_y_max"].assumption and not wagon["sum_Y_2m"].assumption
    for limit in wagon.values():
        assert limit.clause and limit.rule


def test_limits_refuse_bad_input_and_mark_overrides_as_assumptions():
    with pytest.raises(InputError, match="unknown vehicle category"):
        limits_for("tram", 100e3)
    with pytest.raises(InputError, match="static_wheel_load"):
        limits_for("coach", math.nan)
    with pytest.raises(InputError, match="mean_radius"):
        limits_for("coach", 80e3, mean_radius_m=-300.0)
    limits = limits_for("coach", 80e3, overrides={"Y_over_Q_2m": (0.7, "national rule")})
    assert limits["Y_over_Q_2m"].value == 0.7 and limits["Y_over_Q_2m"].assumption
    with pytest.raises(InputError, match="no limit named"):
        limits_for("coach", 80e3, overrides={"Y_qst": (60e3, "")})


def test_results_have_a_json_form():
    import json

    svs = [_section_values({"sum_Y_2m": 40e3 + i}, i, 0.1, 300.0) for i in range(3)]
    result = evaluate_zone(_zone("one_dimensional", 3), svs, limits_for("coach", 80e3))
    data = json.loads(json.dumps(result.to_dict()))
    assert data["criteria"]["sum_Y_2m"]["pass"] is True and data["pass"] is True
    assert data["criteria"]["sum_Y_2m"]["sections"] == ["s0", "s1", "s2"]


def test_a_quantity_no_section_has_is_reported_with_the_sections_reason():
    svs = [_section_values({"sum_Y_2m": 40e3 + i, "Y_qst": math.nan}, i, 0.1, 300.0)
           for i in range(3)]  # fmt: skip
    for sv in svs:
        sv.notes = {"Y_qst": "straight track: no quasi-static curving force"}
    result = evaluate_zone(_zone("one_dimensional", 3), svs, limits_for("coach", 80e3))
    c = result.criteria["Y_qst"]
    assert c.value is None and c.passed is None and "straight track" in c.note
    assert result.passed is True  # judged on the criteria that could be evaluated


def test_zone_limits_take_the_zone_conditions_and_flag_y_over_q_below_250_m():
    from railexu.assessment.acceptance.limits import zone_limits

    ws = SimpleNamespace(axle_load_N=200e3, mass_kg=1.5e3)
    body = SimpleNamespace(name="body", mass_kg=40e3)
    vehicle = SimpleNamespace(wheelsets=(ws,) * 4, bodies=(body,), total_mass_kg=80e3,
                              gravity_m_per_s2=9.81)  # fmt: skip
    zone = _zone("one_dimensional", 4, radius_m=(200.0, 400.0))
    limits = zone_limits("coach", zone, vehicle)
    # mean of the radii 200, 266.7, 333.3, 400 m is 300 m: 30 + 10500 / 300 = 65 kN
    assert limits["Y_qst"].value == pytest.approx(65e3)
    assert limits["Y_over_Q_2m"].assumption and "below 250 m" in limits["Y_over_Q_2m"].rule
    assert "bogie_frame_acc_y_max" not in limits  # one body only: no bogie frame


def test_running_stability_takes_the_largest_section_and_the_other_method_informs():
    """The instability criteria are judged in every section (the largest section value, no
    mean + k s); with ``stability_method: normal`` the simplified method's bogie-frame values
    are reported with their limit but do not decide (and the reverse)."""
    rms = [12e3, 29e3, 10e3, 23e3, 15e3]  # N; limit (sum Y_2m)_lim / 2 = (10 + 200/3) / 2 kN
    frame = [2.0, 4.5, 1.8, 3.0, 2.2]  # m/s^2; limit (12 - 16.8 / 5) / 2 = 4.32 m/s^2
    svs = [_section_values({"sum_Y_rms": r, "bogie_frame_acc_y_rms": f}, i, 0.0, 1e4)
           for i, (r, f) in enumerate(zip(rms, frame, strict=True))]  # fmt: skip
    limits = limits_for("locomotive", 100e3, bogie_mass_kg=16.8e3)
    assert limits["sum_Y_rms"].value == pytest.approx(0.5 * (10e3 + 200e3 / 3.0), rel=1e-12)
    normal = evaluate_zone(_zone("one_dimensional", 5, kind="straight"), svs, limits)
    c = normal.criteria["sum_Y_rms"]
    assert c.value == 29e3 and c.method == "largest_section_value"
    assert c.details["section"] == "s1" and c.passed is True
    b = normal.criteria["bogie_frame_acc_y_rms"]
    assert b.value == 4.5 and b.passed is None and b.details["within_limit"] is False
    assert "informative" in b.note and normal.passed is True
    simplified = evaluate_zone(
        _zone("one_dimensional", 5, kind="straight", stability_method="simplified"), svs, limits
    )
    assert simplified.criteria["bogie_frame_acc_y_rms"].passed is False
    assert simplified.criteria["sum_Y_rms"].passed is None and simplified.passed is False
    both = evaluate_zone(
        _zone("one_dimensional", 5, kind="straight", stability_method="both"), svs, limits
    )
    assert both.criteria["sum_Y_rms"].passed is True
    assert both.criteria["bogie_frame_acc_y_rms"].passed is False
