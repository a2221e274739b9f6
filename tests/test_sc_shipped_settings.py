"""The shipped S&C tracks carry the converged setting the docs state (issue 29).

docs/switches-and-crossings.md ("In the dynamic model", the turnout's "Runs" and "Cost"): with
the 12 mm contact filter applied at the wheelset's position and crossing stations of 5 mm the
crossing's named windows are within 1 % of their 2.5 mm values (the diverging route trailing's
0-1 m window: the empty Hbbins 218.4 / 224.2 / 226.2 kN at 10 / 5 / 2.5 mm, 0.2 ms); the
filter's first form, filtered stations blended linearly, left them 9 % low at 10 mm and 2.4 %
at 5 mm; unfiltered 20 mm stations do not converge (243 / 224 / 246 kN at 20 / 10 / 5 mm, the
loaded Hbbins' wing rail). The shipped turnouts and crossing tracks therefore set
``contact_filter: 12 mm`` and 5 mm crossing stations (the switch panel and the plain rail keep
the design's 50 mm), a track file's zone or turnout that does not set them gets the same
(railexu's assumption, ``railexu.track.variable_rails.FILE_CONTACT_FILTER_M``,
``FILE_CROSSING_STATION_STEP_M``), and the kernel fields apply the filter at the wheelset
unless asked for the first form; a zone built from Python states its own filter (default 0).
Cheap: the files are read, no table is built.
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
    assert FILE_CROSSING_STATION_STEP_M == 0.005  # L / 2 (docs: where converged, within 1 %)
    assert DEFAULT_CONTACT_FILTER_M == 0.0  # a zone built in code states its filter


@pytest.mark.parametrize("name", TURNOUTS)
def test_shipped_turnout_sets_the_filter_and_5_mm_crossing_stations(name):
    raw = load_yaml(find_input("track", name))[0]["turnout"]
    assert raw["contact_filter"] == "12 mm" and raw["crossing_station_step"] == "5 mm"
    assert "station_step" not in raw and "switch_station_step" not in raw  # the design's 50 mm


@pytest.mark.parametrize("name", CROSSINGS)
def test_shipped_crossing_has_the_filter_and_5_mm_stations(name):
    raw = load_yaml(find_input("track", name))[0]["variable_rails"]
    assert raw["contact_filter"] == "12 mm" and raw["station_step"] == "5 mm"
    zone = load_track(name).variable_rails
    assert zone.contact_filter_m == pytest.approx(0.012)
    assert zone.station_step_m == pytest.approx(0.005) and zone.uniform


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
    assert part[2] == pytest.approx(0.005)
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
    assert "**5 mm over the crossing panel, with the 12 mm contact filter at the wheelset**" in text
    assert "**0.2 ms step with every step recorded**" in text
    assert "a track file's zone and a turnout: 12 mm unless set" in text


def test_the_kernel_applies_the_filter_at_the_wheelset_by_default():
    """The kernel fields' default is the filter at the wheelset's position (``sc_filter``, the
    C1 box average, :func:`railexu.model.forces.filter_weight`), not its first form."""
    import inspect

    from railexu.model.sc_tables import sc_kernel_fields

    default = inspect.signature(sc_kernel_fields).parameters["filter_at_stations"].default
    assert default is False
