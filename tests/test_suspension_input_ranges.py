"""Every numeric key of every suspension element: NaN, infinities, wrong units and values beyond
its physical range are refused with the file, the line and the key; so are tables that are not
monotonic, repeat an abscissa, hold NaN or rise steeper than a rigid stop (issue 26; the ranges
and their reasons: docs/vehicle-format.md, "Ranges of the suspension values and why").

The element under test is added as ``probe`` between the Manchester coach's car body and its
front bogie (docs/vehicles.md); its valid values are typical of real elements (yaw damper
12 kN at 0.05 m/s, a bag of 0.3 MN/m, UIC links of 0.16 m, ...).
"""

from __future__ import annotations

import copy
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from railexu.errors import InputError
from railexu.inputs import parse_yaml
from railexu.vehicle.schema import ELEMENTS
from railexu.vehicle.vehicle import vehicle_from_dict

ROOT = Path(__file__).resolve().parent.parent
VEHICLES = ROOT / "vehicles"
COACH = (VEHICLES / "manchester_coach_extended.yaml").read_text()
_AT = {"bodies": ["car_body", "bogie_1"], "position": [9.5, 1.0, 0.8275]}
#: A valid element of each type (SI values), the probe of the tests.
VALID = {
    "spring_damper": {"stiffness": [1e6, 1e6, 1e6], "damping": [0.0, 0.0, 1e4]},
    "torsion_spring": {"axis": "z", "stiffness": 1e5, "damping": 1e4},
    "bump_stop": {"direction": "y", "clearance": 0.03, "stiffness": 5e6, "damping": 2e4},
    "nonlinear_spring": {"direction": "y", "deflection": [0.0, 0.03, 0.05],
                         "force": [0.0, 0.0, 8e4], "symmetric": True, "damping": 0.0},
    "damper": {"direction": "x", "velocity": [0.0, 0.05, 0.2], "force": [0.0, 1.2e4, 1.6e4],
               "symmetric": True, "series_stiffness": 6e6},
    "friction": {"direction": "z", "friction_force": 4e3, "slip_velocity": 1e-3,
                 "stick_stiffness": 5e6},
    "uic_link": {"pendulum_length": [0.16, 0.2], "friction_coefficient": [0.2, 0.1],
                 "stick_stiffness": [8e6, 2e6], "vertical_load": 6e4, "slip_velocity": 1e-3},
    "air_spring": {"vertical_stiffness": 3e5, "reservoir_stiffness": 2.5e5,
                   "orifice_damping": 3e4, "lateral_stiffness": [1.5e5, 1.5e5],
                   "lateral_damping": [0.0, 0.0]},
    "anti_roll_bar": {"stiffness": 2.5e6, "damping": 0.0},
}  # fmt: skip
assert set(VALID) == set(ELEMENTS), "a new element type needs its probe here"


_COACH_DATA = parse_yaml(COACH, "coach.yaml")[0]


def _coach(kind: str, **changes) -> dict:
    data = copy.deepcopy(_COACH_DATA)
    data["suspension"]["probe"] = {"type": kind, **_AT, **VALID[kind], **changes}
    return data


def _load(data: dict):
    return vehicle_from_dict(data, "coach.yaml", None, VEHICLES)


def _refused(kind: str, key: str, value, words: str = "") -> str:
    with pytest.raises(InputError) as info:
        _load(_coach(kind, **{key: value}))
    message = str(info.value)
    assert re.match(rf"coach\.yaml(:\d+)?: suspension\.probe\.{key}(\.\w+)?: ", message), message
    assert words in message and "\n" not in message, message
    return message


@pytest.mark.parametrize("kind", sorted(VALID))
def test_each_probe_is_a_valid_element(kind):
    vehicle = _load(_coach(kind))
    assert any(e.name == "probe" for e in vehicle.suspension)


def _numeric_fields():
    for kind, schema in sorted(ELEMENTS.items()):
        for f in schema.fields:
            if f.unit and f.key != "position":
                yield kind, f


def _like(valid, value):
    """``value`` in the shape of ``valid`` (in the first component of a vector or table)."""
    if isinstance(valid, list):
        return [value, *valid[1:]]
    return value


def _refused_as(kind: str, key: str, value, words: str = "") -> None:
    """:func:`_refused`, for the damper's linear ``damping`` on a damper without a table."""
    if (kind, key) != ("damper", "damping"):
        _refused(kind, key, value, words)
        return
    data = _coach(kind, damping=value)
    del data["suspension"]["probe"]["velocity"], data["suspension"]["probe"]["force"]
    with pytest.raises(InputError) as info:
        _load(data)
    assert "suspension.probe.damping" in str(info.value) and words in str(info.value)


def _below(field) -> float | None:
    """A value below the field's lowest allowed one (None: no lower bound)."""
    if field.minimum is not None and field.minimum > 0.0:
        return 0.5 * field.minimum
    if field.positive:
        return 0.0
    if field.minimum is not None:
        return field.minimum - 1.0 if field.minimum <= 0.0 else None
    return None


@pytest.mark.parametrize(("kind", "field"), list(_numeric_fields()),
                         ids=lambda v: getattr(v, "key", v))  # fmt: skip
def test_every_numeric_key_refuses_nan_infinity_units_and_its_bounds(kind, field):
    valid = VALID[kind].get(field.key, 1.0e5)  # damper.damping: absent from the table probe
    for bad in (math.nan, math.inf, -math.inf, "nan", "inf"):
        _refused_as(kind, field.key, _like(valid, bad))
    _refused_as(kind, field.key, _like(valid, "1 kg"), "kg")
    below = _below(field)
    if below is not None:
        _refused_as(kind, field.key, _like(valid, below), "must be >")
    if field.maximum is not None:
        above = 2.0 * field.maximum if field.maximum > 0.0 else field.maximum + 1.0
        _refused_as(kind, field.key, _like(valid, above), f"<= {field.maximum:g}")


@pytest.mark.parametrize(
    ("kind", "changes", "key", "words"),
    [
        # repeated abscissa: a vertical jump
        ("nonlinear_spring", {"deflection": [0.0, 0.03, 0.03], "force": [0.0, 0.0, 8e4]},
         "deflection", "must increase"),
        ("damper", {"velocity": [0.0, 0.05, 0.05], "force": [0.0, 1.2e4, 1.6e4]},
         "velocity", "must increase"),
        # falling characteristic: negative stiffness or damping
        ("damper", {"velocity": [0.0, 0.05, 0.2], "force": [0.0, 1.6e4, 1.2e4]},
         "force", "must not decrease"),
        # NaN inside a table
        ("nonlinear_spring", {"force": [0.0, math.nan, 8e4]}, "force", "finite"),
        ("damper", {"velocity": [0.0, math.nan, 0.2]}, "velocity", "finite"),
        # 80 kN over 1 um: 8e10 N/m, steeper than a rigid stop (1e10 N/m)
        ("nonlinear_spring", {"deflection": [0.0, 0.03, 0.030001]}, "force", "slope"),
        # 12 kN at 1 um/s: 1.2e10 N s/m, above any damper (1e9 N s/m)
        ("damper", {"velocity": [0.0, 1e-6, 0.2]}, "force", "slope"),
        ("torsion_spring", {"stiffness": 0.0, "damping": 0.0}, "stiffness", "give a stiffness"),
    ],
)  # fmt: skip
def test_tables_and_element_rules(kind, changes, key, words):
    with pytest.raises(InputError) as info:
        _load(_coach(kind, **changes))
    message = str(info.value)
    assert f"suspension.probe.{key}" in message and words in message, message


def test_a_table_at_the_slope_limit_is_read():
    """80 kN over 8 um is 1e10 N/m, the limit itself: read."""
    _load(_coach("nonlinear_spring", deflection=[0.0, 0.03, 0.030008]))


_CLI_CASES = [
    # (text replaced in manchester_coach_extended.yaml, replacement, key in the message)
    ("orifice_damping: 58 kN s/m", "orifice_damping: .nan", "orifice_damping"),
    ("stiffness: 1.5 MN m/rad", "stiffness: .inf", "stiffness"),
    ("series_stiffness: 6 MN/m", "series_stiffness: 1 N/m", "series_stiffness"),
    ("vertical_stiffness: 430 kN/m", "vertical_stiffness: 430 kN", "vertical_stiffness"),
    ("velocity: [0, 0.04 m/s, 0.2 m/s]", "velocity: [0, 0.04 m/s, 0.04 m/s]", "velocity"),
]


@pytest.mark.parametrize(("old", "new", "key"), _CLI_CASES, ids=[c[2] for c in _CLI_CASES])
def test_refusals_through_railexu_run_are_one_located_line_and_exit_2(tmp_path, old, new, key):
    assert old in COACH, old
    path = tmp_path / "coach.yaml"
    text = COACH.replace(old, new, 1)
    path.write_text(text)
    line = 1 + next(i for i, t in enumerate(text.splitlines()) if new in t)
    done = subprocess.run(
        [sys.executable, "-m", "railexu.cli", "run", str(path), "--distance", "1 m",
         "--out", str(tmp_path / "out")],
        capture_output=True, text=True, timeout=120,
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert lines[0].startswith(f"railexu run: error: {path}:{line}: suspension."), lines[0]
    assert f".{key}" in lines[0]


_NASTY = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["nan", "-inf", "1e400", "-0", "1 kg", "2 MN/m", "1e-300", "", "[]", "{}"]),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
)
_KEYS = st.sampled_from(
    [(kind, f.key) for kind, schema in ELEMENTS.items() for f in schema.fields
     if f.key not in ("estimate", "notes")]
)  # fmt: skip


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_KEYS, _NASTY)
def test_any_value_of_any_element_loads_or_gives_an_input_error(key, value):
    kind, name = key
    try:
        vehicle = _load(_coach(kind, **{name: value}))
    except InputError as exc:
        assert str(exc).startswith("coach.yaml"), str(exc)
        assert "suspension.probe" in str(exc) or "bodies" in str(exc), str(exc)
    else:
        probe = [e for e in vehicle.suspension if e.name.startswith("probe")]
        for element in probe:
            for v in vars(element).values():
                if isinstance(v, float):
                    assert math.isfinite(v), (element, v)
