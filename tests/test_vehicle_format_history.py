"""Vehicle format 1: read exactly as format 1 meant it, or refused where a key changed meaning.

The reference is format 1 itself as documented when it was current (docs/vehicle-format.md
of format 1, ``git show 91f5b77^:docs/vehicle-format.md``): ``creep_model`` defaulted to
``polach`` (ContactParameters.creep_model = "polach" then), every vehicle was a locomotive, and
"where an element acts on a wheelset it acts on the axle, whatever height ... is given".
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from railexu.errors import InputError
from railexu.inputs import parse_yaml
from railexu.vehicle.vehicle import vehicle_from_dict

ROOT = Path(__file__).resolve().parent.parent
VEHICLES = ROOT / "vehicles"
BOGIE_2 = (VEHICLES / "eu07_bogie.yaml").read_text()
CONTACT_2 = """\
  creep: {model: polach}
  friction: 0.3
  shear_modulus: 82 GPa
  poisson: 0.28
  normal_damping: {model: hunt_crossley, coefficient: 3 s/m}
"""
#: The same contact the format-1 way, without creep_model (format 1's default: polach).
CONTACT_1 = """\
  friction: 0.3
  shear_modulus: 82 GPa
  poisson: 0.28
  damping_model: hunt_crossley
  normal_damping: 3 s/m
"""


def _bogie_1(text: str = BOGIE_2) -> str:
    """eu07_bogie.yaml written in format 1."""
    assert "format_version: 2" in text and text.count("creep: {model: polach}") == 1
    start = text.index("  creep: {model: polach}")
    end = text.index("normal_damping: {model: hunt_crossley", start)
    end = text.index("\n", end) + 1
    return text[:start].replace("format_version: 2", "format_version: 1") + CONTACT_1 + text[end:]


def _load(text: str, name: str = "v1.yaml"):
    data, lines = parse_yaml(text, name)
    return vehicle_from_dict(data, name, lines, VEHICLES)


def _error(text: str) -> str:
    with pytest.raises(InputError) as info:
        _load(text)
    return str(info.value)


def test_format_1_without_changed_keys_is_read_as_format_1_meant():
    one, two = _load(_bogie_1()), _load(BOGIE_2)
    assert one.contact.creep_model == "polach"  # format 1's default, not polach_fastsim
    assert one.contact == two.contact
    assert one.suspension == two.suspension and one.loads == two.loads
    assert one.bodies == two.bodies and one.wheelsets == two.wheelsets
    assert one.category == two.category == "locomotive"


def test_format_1_file_without_any_contact_section_takes_format_1s_creep_law():
    text = _bogie_1()
    start = text.index("contact:")
    end = text.index("bodies:")
    assert _load(text[:start] + text[end:]).contact.creep_model == "polach"
    # a format 2 file without contact takes today's default
    assert _load(BOGIE_2[: BOGIE_2.index("contact:")] + BOGIE_2[BOGIE_2.index("bodies:") :]
                 ).contact.creep_model == "polach_fastsim"  # fmt: skip


def test_format_1_element_above_the_axle_is_refused_with_what_to_write():
    text = _bogie_1().replace("position: [1.5, 1.05, 0.625]", "position: [1.5, 1.05, 0.9]")
    message = _error(text)
    line = 1 + text.splitlines().index("    position: [1.5, 1.05, 0.9]")
    assert message.startswith(f"v1.yaml:{line}: suspension.primary_ws1.position: format 1 ")
    assert "z = 0.625 m" in message and "z = 0.9 m" in message
    assert "format_version: 2" in message and "\n" not in message
    # the same height is read in format 2 (the axlebox carries the moment)
    two = _load(BOGIE_2.replace("position: [1.5, 1.05, 0.625]", "position: [1.5, 1.05, 0.9]"))
    assert two.suspension[0].position_m[2] == 0.9


def test_format_1_element_height_given_in_millimetres_at_the_axle_is_read():
    text = _bogie_1().replace("position: [1.5, 1.05, 0.625]", "position: [1.5, 1.05, 625 mm]")
    assert _load(text).suspension[0].position_m[2] == pytest.approx(0.625, abs=1e-12)


def test_format_1_element_on_two_bodies_not_wheelsets_keeps_its_height():
    """Only points on wheelsets changed meaning: a body-to-body element keeps its height."""
    text = _bogie_1().replace(
        "loads:",
        "  stop:\n    type: bump_stop\n    bodies: [bogie_1, ws1]\n    position: [1.5, 0, 0.625]\n"
        "    direction: y\n    clearance: 20 mm\n    stiffness: 1 MN/m\nloads:",
    )
    assert any(e.name == "stop" for e in _load(text).suspension)


def test_format_1_without_category_is_refused_with_format_1s_meaning():
    text = _bogie_1().replace("category: locomotive", "")
    message = _error(text)
    assert re.match(r"v1\.yaml(:\d+)?: missing key 'category': format 1 had none", message)
    assert "write 'category: locomotive' to keep that" in message


def test_format_1_refusal_through_the_command_line_is_one_line_exit_2(tmp_path):
    path = tmp_path / "old.yaml"
    path.write_text(
        _bogie_1().replace("position: [-1.5, 1.05, 0.625]", "position: [-1.5, 1.05, 0.3]")
    )
    done = subprocess.run(
        [sys.executable, "-m", "railexu.cli", "run", str(path), "--distance", "1 m",
         "--out", str(tmp_path / "out")],
        capture_output=True, text=True, timeout=120,
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in done.stderr
    assert f"{path}:" in lines[0] and "suspension.primary_ws2.position: format 1" in lines[0]
