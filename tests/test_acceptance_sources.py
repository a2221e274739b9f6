"""The values railexu marks as its assumptions and the record of what was searched for them
(docs/acceptance.md, "What railexu searched for the values it marks as assumptions") stay
together: a flag in the code needs a "kept" row in that table, and a row needs its flag.

No physics here: this keeps the acceptance verdict honest about which limits and statistics a
public text confirmed (none of these, as of the search recorded there)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from railexu.assessment.acceptance.limits import CAR_BODY_NAMES, limits_for, zone_limits
from railexu.assessment.acceptance.programme import load_programme
from railexu.assessment.curve_transition import PCT_CONSTANTS, PctParameters
from railexu.vehicle.vehicle import load_vehicle

DOC = Path(__file__).resolve().parents[1] / "docs" / "acceptance.md"
HEADING = "### What railexu searched for the values it marks as assumptions"
PROGRAMMES = {"coach": "manchester_coach_extended", "locomotive": "eu07",
              "freight_wagon": "hbbins_loaded"}  # fmt: skip


def _kept_keys() -> set[str]:
    """The code names (in backticks) of the search table's rows that say "kept"."""
    text = DOC.read_text(encoding="utf-8")
    assert HEADING in text, "the search record is missing from docs/acceptance.md"
    section = text.split(HEADING, 1)[1].split("\n#", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    assert rows, "the search record has no table"
    keys: set[str] = set()
    for row in rows:
        first, *_, status = [cell.strip() for cell in row.strip("|").split("|")]
        if "kept" in status:
            keys.update(re.findall(r"`([A-Za-z_]+)`", first))
    return keys


def test_every_flagged_limit_has_a_kept_row():
    kept = _kept_keys()
    for category in ("locomotive", "coach", "multiple_unit", "wagon"):
        limits = limits_for(category, 60e3, speed_m_per_s=40.0, mean_radius_m=500.0,
                            bogie_mass_kg=5000.0)  # fmt: skip
        flagged = {name for name, lim in limits.items() if lim.assumption}
        assert flagged == set(CAR_BODY_NAMES), category  # only the car body's limits
        assert flagged <= kept, category


@pytest.mark.parametrize("programme", sorted(PROGRAMMES))
def test_shipped_programmes_flags_have_kept_rows(programme):
    kept = _kept_keys()
    prog = load_programme(programme)
    vehicle = load_vehicle(PROGRAMMES[programme])
    for zone in prog.zones:
        # the statistics: the flag set, and the values the record names
        assert zone.statistics_assumption, zone.name
        assert (zone.k_safety, zone.k_ride, zone.prediction_quantile) == (2.2, 3.0, 0.95)
        assert {"k_safety", "k_ride", "prediction_quantile"} <= kept
        limits = zone_limits(prog.category, zone, vehicle, prog.limits)
        flagged = {name for name, lim in limits.items() if lim.assumption}
        assert flagged <= kept, (programme, zone.name, flagged - kept)


def test_pct_constants_and_parameters_are_flagged_and_recorded():
    kept = _kept_keys()
    assert PctParameters().assumption is True
    assert {"PCT_CONSTANTS", "PctParameters"} <= kept
    # the doc's P_CT table carries the code's constants
    text = DOC.read_text(encoding="utf-8")
    for posture, constants in PCT_CONSTANTS.items():
        row = re.search(rf"^\| {posture} \|(.*)\|$", text, flags=re.MULTILINE)
        assert row, posture
        documented = [float(cell) for cell in row.group(1).split("|")]
        assert documented == pytest.approx(constants, rel=1e-12), posture
