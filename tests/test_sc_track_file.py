"""The track file's ``variable_rails:`` section (issue 29): a switch-and-crossing zone read from a
track file, with its slices files relative to it, and located refusals.

Checks against something outside the reader: the shipped facing and trailing tracks give the
same rail surface met in opposite directions (the trailing surface at ``s`` is the facing one at
``-s``, to the last bit: the same points, the same interpolation), and the zone lies where the
file says (the first and the last slice of CONTACT's ``uk_interrupt_v2.slcs``: -85.20 mm and
178.81 mm, read from the file's text in the test).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from railexu.errors import InputError
from railexu.track.track import load_track

TRACKS = Path(__file__).resolve().parents[1] / "tracks"

TRACK = """\
format_version: 1
name: zone test
rail_profile: MBench_UIC60
geometry:
{geometry}
variable_rails:
{zone}
"""
STRAIGHT = "  type: straight"
ZONE = """\
  type: slices
  start: 30 m
  left: uk_crossing/uk_interrupt_v2.slcs
  text_unit: m
  rail_origin: [0.75 m, 0 m]"""


def _write(tmp_path: Path, zone: str = ZONE, geometry: str = STRAIGHT) -> Path:
    if not (tmp_path / "uk_crossing").exists():
        shutil.copytree(TRACKS / "uk_crossing", tmp_path / "uk_crossing")
    path = tmp_path / "track.yaml"
    path.write_text(TRACK.format(zone=zone, geometry=geometry))
    return path


def _slcs_positions_m() -> list[float]:
    """The slice positions as CONTACT's file writes them (usr = m, U_OFFSET 0)."""
    lines = (TRACKS / "uk_crossing" / "uk_interrupt_v2.slcs").read_text().splitlines()
    return [float(line.split()[0]) for line in lines if "'uk_crossing/" in line]


def test_zone_read_relative_to_the_track_file(tmp_path):
    track = load_track(_write(tmp_path))
    rails = track.variable_rails
    assert rails.right is None
    assert rails.rail_origin_m == (0.75, 0.0)
    assert rails.station_step_m == pytest.approx(0.01)
    first, last = _slcs_positions_m()[0], _slcs_positions_m()[-1]
    assert rails.zone_m() == pytest.approx((30.0 + first, 30.0 + last), abs=1e-9)
    assert first == pytest.approx(-0.0852) and last == pytest.approx(0.17881)


def test_no_zone_and_type_none(tmp_path):
    assert load_track(TRACKS / "straight.yaml").variable_rails is None
    assert load_track(_write(tmp_path, zone="  type: none")).variable_rails is None


def test_shipped_facing_and_trailing_are_one_crossing_in_two_directions():
    facing = load_track("uk_crossing_facing").variable_rails
    trailing = load_track("uk_crossing_trailing").variable_rails
    lo, hi = facing.left.s_range_m
    assert trailing.left.s_range_m == pytest.approx((-hi, -lo))
    y = np.linspace(-0.045, 0.1, 300)
    s = np.array([-0.08, 0.0, 0.05, 0.1139, 0.12, 0.15, 0.175])
    a = facing.left.heights_on_grid(s, y)
    b = trailing.left.heights_on_grid(-s, y)
    assert np.array_equal(np.isfinite(a), np.isfinite(b))  # no rail: +inf (z down)
    finite = np.isfinite(a)
    assert np.max(np.abs(a[finite] - b[finite])) < 1e-12
    # the nose exists only after its start (s = 118.94 mm): left of the flangeway at y < -20 mm
    # nothing before it, the nose's top after it
    assert not np.any(np.isfinite(a[:3, y < -0.03]))
    assert np.any(np.isfinite(a[4:, (y > -0.03) & (y < -0.02)]))


@pytest.mark.parametrize(
    ("zone", "geometry", "key", "words"),
    [
        (ZONE + "\n  lefft: x.slcs", STRAIGHT, "variable_rails.lefft", "unknown key"),
        (ZONE.replace("uk_interrupt_v2", "missing"), STRAIGHT, "variable_rails.left",
         "not found"),
        (ZONE.replace("uk_interrupt_v2.slcs", "uk_crossing/Crossing_41.txt"), STRAIGHT,
         "variable_rails.left", "expected a CONTACT .slcs file"),
        (ZONE.replace("30 m", "0.5 m"), STRAIGHT, "variable_rails.start", "run's start"),
        (ZONE, "  type: sections\n  sections:\n    - {type: straight, length: 20 m}",
         "variable_rails.start", "overlaps the track's end at 20 m"),
        ("  type: slices\n  start: 30 m", STRAIGHT, "variable_rails", "left or the right"),
        (ZONE.replace("30 m", "nan m"), STRAIGHT, "variable_rails.start", "got 'nan m'"),
        (ZONE + "\n  direction: backwards", STRAIGHT, "variable_rails.direction", "facing"),
        (ZONE + "\n  station_step: 10 m", STRAIGHT, "variable_rails.station_step", "<="),
        ("  type: crossing", STRAIGHT, "variable_rails.type", "slices"),
    ],
)  # fmt: skip
def test_bad_zone_is_refused_with_file_line_and_key(tmp_path, zone, geometry, key, words):
    path = _write(tmp_path, zone, geometry)
    with pytest.raises(InputError) as err:
        load_track(path)
    assert words in str(err.value)
    assert err.value.key == key
    assert err.value.source == str(path)
    assert err.value.line is not None and err.value.line >= 6


def test_bad_slices_file_is_refused_naming_both_files(tmp_path):
    path = _write(tmp_path)
    slcs = tmp_path / "uk_crossing" / "uk_interrupt_v2.slcs"
    text = slcs.read_text().replace("0.11894   'uk_crossing/Crossing_48.txt'",
                                    "0.11000   'uk_crossing/Crossing_48.txt'")  # fmt: skip
    slcs.write_text(text)
    with pytest.raises(InputError) as err:
        load_track(path)
    message = str(err.value)
    assert err.value.key == "variable_rails.left" and err.value.source == str(path)
    # the slices file's own place: its line 46 holds the moved slice's features
    assert "uk_interrupt_v2.slcs, line 46" in message and "0.11894" in message
