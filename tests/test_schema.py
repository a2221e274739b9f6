"""The schemas: one declaration per key feeds the loaders, the defaults, the --set paths and the
generated tables of docs/*-format.md."""

from __future__ import annotations

import pytest

from railexu import schema as docs_schema
from railexu.inputs import OPTIONAL, REQUIRED, Field, InputError, Schema, Section
from railexu.inputs.docs import markdown_table, region_is_current, update_region
from railexu.operation.run_settings import RUN_SCHEMA, RunSettings
from railexu.track.schema import TRACK
from railexu.track.track import Track
from railexu.vehicle.schema import CONTACT, VEHICLE, WHEELSET

SMALL = Schema(
    "small",
    (
        Field("length", "a length", unit="m", default=2.0, positive=True, maximum=10.0),
        Field("mode", "a choice", "text", default="a", choices=("a", "b")),
        Field("count", "a count", "integer", default=OPTIONAL, minimum=0),
        Field("name", "required text", "text"),
        Field("side", "one or two", "sided", unit="m", default=REQUIRED, minimum=0.0),
        Field("law", "a model", "model", default={"model": "x"}, models={
            "x": Schema("x", ()),
            "y": Schema("y", (Field("k", "a stiffness", unit="N/m", default=1.0),)),
        }),
    ),
)  # fmt: skip


def _read(data: dict, key: str):
    lines = {(k,): i + 1 for i, k in enumerate(data)}
    return SMALL.read(SMALL.wrap(data, "f.yaml", lines), key)


def test_a_field_reads_converts_and_checks():
    assert _read({"length": "300 mm"}, "length") == pytest.approx(0.3)
    assert _read({}, "length") == 2.0  # the declared default
    assert _read({}, "count") is None
    assert _read({"side": "1 m"}, "side") == (1.0, 1.0)
    assert _read({"side": {"left": 1, "right": "2 m"}}, "side") == (1.0, 2.0)
    assert _read({}, "law") == ("x", {})
    assert _read({"law": "y"}, "law") == ("y", {"k": 1.0})
    assert _read({"law": {"model": "y", "k": "2 kN/m"}}, "law") == ("y", {"k": 2000.0})


@pytest.mark.parametrize(
    "data, key, message",
    [
        ({"length": "11 m"}, "length", "f.yaml:1: length: must be <= 10 m, got '11 m'"),
        ({"length": -1}, "length", "must be > 0 m"),
        ({"length": "2 s"}, "length", "wrong dimension"),
        ({"mode": "c"}, "mode", "'c' is not one of a, b"),
        ({"count": -1}, "count", "must be >= 0"),
        ({}, "name", "missing key 'name'"),
        ({"law": {"model": "z"}}, "law", "'z' is not one of x, y"),
        ({"law": {"model": "x", "k": 1}}, "law", "unknown key"),
        ({"side": {"left": 1}}, "side", "missing key 'right'"),
    ],
)
def test_a_field_reports_file_line_and_key(data, key, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _read(data, key)


def test_unknown_keys_are_refused_with_did_you_mean():
    with pytest.raises(InputError, match="unknown key. Did you mean 'length'"):
        SMALL.wrap({"lenght": 1}, "f.yaml", {})


def test_defaults_live_in_the_schemas():
    """The dataclasses take their defaults from the schemas (one declaration each)."""
    assert Track("t").gauge_m == TRACK.default("gauge") == 1.435
    assert Track("t").inclination == TRACK.default("inclination") == "1:40"
    settings = RunSettings()
    assert settings.speed_m_per_s == RUN_SCHEMA.default("speed")
    assert settings.time_step_s == RUN_SCHEMA.default("time_step")
    assert WHEELSET.default("flange_back_distance") == 1.360
    assert CONTACT.default("friction") == 0.3


def test_override_paths_find_their_units():
    assert VEHICLE.field_at(["suspension", "primary_ws*", "stiffness", "x"])[1] == "N/m"
    assert VEHICLE.field_at(["bodies", "car_body", "mass"])[1] == "kg"
    assert VEHICLE.field_at(["contact", "normal_damping", "coefficient"])[1] == "s/m"
    assert VEHICLE.field_at(["wheelsets", "ws1", "nominal_radius", "right"])[1] == "m"
    assert TRACK.field_at(["irregularities", "wavelength_min"])[1] == "m"
    assert VEHICLE.field_at(["bodies", "car_body", "colour"]) == (None, "")


def test_markdown_table_lists_every_key_once():
    table = markdown_table(SMALL)
    rows = table.splitlines()[2:]
    assert [r.split("|")[1].strip() for r in rows] == [f"`{f.key}`" for f in SMALL.fields]
    assert "| `length` | m | 2 | > 0; <= 10 | a length |" in rows


def test_generated_regions_replace_only_their_content():
    text = "intro\n<!-- schema:x begin (generated: python -m railexu.schema --write-docs) -->\n"
    text += "old\n<!-- schema:x end -->\noutro\n"
    new = update_region(text, "x", "table\n")
    assert new.startswith("intro\n") and new.endswith("outro\n") and "old" not in new
    assert region_is_current(new, "x", "table\n") and not region_is_current(text, "x", "table\n")
    with pytest.raises(ValueError):
        update_region("no region", "x", "t")


def test_docs_are_current():
    """docs/*-format.md hold the tables the schemas generate: run
    ``python -m railexu.schema --write-docs`` after changing a schema."""
    assert docs_schema.stale_docs() == []
    assert docs_schema.main(["--check-docs"]) == 0


def test_section_fail_names_the_override_that_set_a_value():
    from railexu.inputs import LineMap

    lines = LineMap({("a",): 3})
    lines.origins[("a",)] = ("study.yaml", 12)
    with pytest.raises(InputError, match=r"^study.yaml:12: a: bad$"):
        Section({"a": 1}, "vehicle.yaml", lines).fail("bad", key="a")
