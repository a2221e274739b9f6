"""The shipped S&C tracks carry the converged setting the docs state (issue 29).

docs/switches-and-crossings.md ("In the dynamic model", the turnout's "Runs" and "Cost"): with
the 12 mm contact filter and crossing stations of 10 mm or less the crossing's peaks converge
with the station step (the loaded Hbbins' wing rail 221.3 / 224.8 / 223.9 kN at 10 / 5 / 2.5
mm), unfiltered 20 mm stations do not (243 / 224 / 246 kN at 20 / 10 / 5 mm). The shipped
turnouts and crossing tracks therefore set ``contact_filter: 12 mm`` and 10 mm crossing
stations (the switch panel and the plain rail keep the design's 50 mm), and a track file's
zone or turnout that does not set them gets the same (railexu's assumption,
``railexu.track.variable_rails.FILE_CONTACT_FILTER_M``, ``FILE_CROSSING_STATION_STEP_M``); a
zone built from Python states its own filter (default 0). Cheap: the files are read, no table
is built.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from railexu.inputs import load_yaml
from railexu.inputs.catalog import find_input
from railexu.track.track import load_track, track_from_dict
from railexu.track.variable_rails import (
    DEFAULT_CONTACT_FILTER_M,
    FILE_CONTACT_FILTER_M,
    FILE_CROSSING_STATION_STEP_M,
)

TURNOUTS = [f"turnout_uk_r245_{r}_{d}" for r in ("through", "diverging")
            for d in ("facing", "trailing")]  # fmt: skip
CROSSINGS = ["uk_crossing_facing", "uk_crossing_trailing"]


def test_the_file_defaults_are_the_documented_ones():
    assert FILE_CONTACT_FILTER_M == 0.012  # the Hertz patch's box: L^2 / 12 = a^2 / 5, a 7.7 mm
    assert FILE_CROSSING_STATION_STEP_M == 0.010  # finer than the filter (docs: where converged)
    assert DEFAULT_CONTACT_FILTER_M == 0.0  # a zone built in code states its filter


@pytest.mark.parametrize("name", TURNOUTS)
def test_shipped_turnout_sets_the_filter_and_10_mm_crossing_stations(name):
    raw = load_yaml(find_input("track", name))[0]["turnout"]
    assert raw["contact_filter"] == "12 mm" and raw["crossing_station_step"] == "10 mm"
    assert "station_step" not in raw and "switch_station_step" not in raw  # the design's 50 mm


@pytest.mark.parametrize("name", CROSSINGS)
def test_shipped_crossing_has_the_filter_and_10_mm_stations(name):
    raw = load_yaml(find_input("track", name))[0]["variable_rails"]
    assert raw["contact_filter"] == "12 mm" and raw["station_step"] == "10 mm"
    zone = load_track(name).variable_rails
    assert zone.contact_filter_m == pytest.approx(0.012)
    assert zone.station_step_m == pytest.approx(0.010) and zone.uniform


def _without(name: str, section: str, keys: tuple[str, ...]):
    path = find_input("track", name)
    data, lines = load_yaml(path)
    for key in keys:
        del data[section][key]
    return track_from_dict(data, str(path), lines, path.parent).variable_rails


def test_a_turnout_with_and_without_the_keys_gets_the_shipped_setting():
    shipped = load_track(TURNOUTS[2]).variable_rails  # diverging facing: the station study's
    assert shipped.contact_filter_m == pytest.approx(0.012)
    assert shipped.station_step_m == pytest.approx(0.05)  # the switch panel, the plain rail
    (part,) = shipped.station_steps_m  # the crossing panel only
    assert part[2] == pytest.approx(0.010)
    assert part[1] - part[0] == pytest.approx(5.69, abs=0.01)  # the check rail's 5.69 m
    zone = _without(TURNOUTS[2], "turnout", ("contact_filter", "crossing_station_step"))
    assert zone.contact_filter_m == FILE_CONTACT_FILTER_M
    assert zone.stations_m().tolist() == shipped.stations_m().tolist()


def test_a_zone_without_the_key_gets_the_filter():
    zone = _without(CROSSINGS[0], "variable_rails", ("contact_filter",))
    assert zone.contact_filter_m == FILE_CONTACT_FILTER_M


def test_the_docs_state_the_shipped_setting():
    """The runs table's text names the stations and the filter the shipped tracks carry."""
    docs = Path(__file__).resolve().parents[1] / "docs" / "switches-and-crossings.md"
    text = " ".join(docs.read_text().split())
    assert "**10 mm over the crossing panel, with the 12 mm contact filter**" in text
    assert "a track file's zone and a turnout: 12 mm unless set" in text
