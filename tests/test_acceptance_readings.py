"""Readings of EN 14363 that railexu makes explicit (docs/acceptance.md, "Readings"): the radius
of the Y_qst limit, and the yaw-resistance X factor outside the freight-wagon category."""

from __future__ import annotations

from pathlib import Path

import pytest

from railexu.assessment.acceptance.limits import y_qst_limit_radius_m, zone_limits
from railexu.assessment.acceptance.programme import load_programme
from railexu.errors import InputError
from railexu.study.acceptance.runner import YAW_TEST_CATEGORIES, _informative
from railexu.study.acceptance.verdict import decide
from railexu.vehicle.vehicle import load_vehicle

KN = 1000.0
ROOT_VEHICLE = Path(__file__).resolve().parents[1] / "vehicles" / "manchester_coach_extended.yaml"


@pytest.mark.parametrize(
    ("choice", "radius_m"),
    [("mean", 325.0), ("evaluation", 250.0)],
)
def test_the_y_qst_limit_at_the_mean_or_the_evaluation_radius(choice, radius_m):
    """The coach's very-small-radius zone: 50 sections with radii evenly from 250 m to 400 m
    (mean 325 m), its estimate taken at 250 m. `mean` (the shipped choice) gives the limit
    30 + 10500/325 = 62.31 kN, `evaluation` 30 + 10500/250 = 72 kN; the rule says which."""
    programme = load_programme("coach", overrides=(f"statistics.y_qst_limit_radius={choice}",))
    zone = programme.zone("curve_very_small_radius")
    radii = [s.radius_m for s in zone.sections()]
    assert y_qst_limit_radius_m(zone, radii) == pytest.approx(radius_m, rel=1e-9)
    limits = zone_limits(programme.category, zone, load_vehicle("manchester_coach_extended"))
    y = limits["Y_qst"]
    assert y.value == pytest.approx((30.0 + 10500.0 / radius_m) * KN, rel=1e-9)
    assert f"y_qst_limit_radius: {choice}" in y.rule and y.assumption


def test_the_shipped_programmes_take_the_mean_radius():
    for name in ("freight_wagon", "locomotive", "coach"):
        for zone in load_programme(name).zones:
            assert zone.y_qst_limit_radius == "mean"


def test_a_bad_y_qst_radius_choice_is_refused():
    with pytest.raises(InputError, match="y_qst_limit_radius"):
        load_programme("coach", overrides=("statistics.y_qst_limit_radius=smallest",))


def _data(yaw: dict) -> dict:
    return {"zones": {}, "programme": {"quick": False},
            "twist_test": {"status": "completed", "pass": True},
            "yaw_resistance_test": yaw}  # fmt: skip


def test_the_yaw_resistance_of_a_non_wagon_is_informative():
    """UIC 530-2's X <= 0.1 is a freight-wagon limit: for a locomotive or coach the X factor is
    kept for information, the test is not applicable and does not decide the verdict."""
    assert YAW_TEST_CATEGORIES == ("wagon",)
    completed = {"status": "completed", "x_factor": 0.37, "limit": 0.1, "pass": False,
                 "clause": "EN 14363:2016, 6.2"}  # fmt: skip
    assert decide(_data(completed))["result"] == "fail"
    entry = _informative(completed)
    assert entry["status"] == "not_applicable" and entry["assumption"] is True
    assert entry["informative"]["x_factor"] == 0.37 and "UIC 530-2" in entry["reason"]
    assert decide(_data(entry))["result"] == "pass"
    not_run = {"status": "not_run", "reason": "x"}
    assert _informative(not_run) is not_run


def test_a_curve_section_starts_on_straight_track():
    """With the lead of the vehicle's wheelbase + 1 m, the whole vehicle starts on straight
    track (a run puts its rearmost wheelset 1 m past the track's start) and the leading
    wheelset reaches the transition at distance 0; the study varies the curve piece after it."""
    from railexu.study.acceptance.zone_study import curve_key, start_lead_m, zone_study
    from railexu.study.acceptance.zone_study import zone_track as track_of

    coach = load_vehicle("manchester_coach_extended")
    lead = start_lead_m(coach)
    assert lead == pytest.approx(2 * 10.78 + 1.0)  # wheelsets at +-10.78 m
    zone = load_programme("coach").zone("curve_small_radius")
    sections = zone.sections()
    pieces = track_of(zone, sections, lead)["geometry"]["sections"]
    assert [p["type"] for p in pieces] == ["straight", "transition", "curve"]
    assert pieces[0]["length"] == f"{lead:.3f} m"
    study = zone_study(zone, sections, ROOT_VEHICLE, lead_m=lead)
    assert f"{curve_key(lead)}.radius" == "track.geometry.sections.2.radius"
    assert f"{curve_key(lead)}.radius" in study["vary"]["parameters"]
    assert curve_key(0.0) == "track.geometry.sections.1"
