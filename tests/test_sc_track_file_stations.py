"""Parts of a track file's ``variable_rails:`` zone with their own station step
(``station_steps:``, issue 29).

Checked against the same zone built from Python (:class:`VariableRails` with
``station_steps_m`` in track distances): the stations are equal to the last bit, facing and
trailing; a facing and a trailing zone with the same parts (in the slices' own ``s``) give
stations that are each other's mirror image at the same ``s`` (to 1e-12 m: ``start + s`` and
``start - s`` rounded apart); every refusal names the track file, the part's line and key.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from railexu.errors import InputError
from railexu.model.assembly import wheelset_geometry
from railexu.model.sc_tables import sc_kernel_fields
from railexu.track.track import load_track
from railexu.track.variable_rails import VariableRails
from railexu.vehicle.vehicle import load_vehicle

TRACKS = Path(__file__).resolve().parents[1] / "tracks"
START_M = 30.0

TRACK = """\
format_version: 1
name: zone test
rail_profile: MBench_UIC60
geometry:
  type: straight
variable_rails:
  type: slices
  start: 30 m
  direction: {direction}
  left: uk_crossing/uk_interrupt_v2.slcs
  text_unit: m
  rail_origin: [0.75 m, 0 m]
  station_step: 0.02 m
{steps}
"""
# CONTACT's uk_interrupt_v2.slcs runs from s = -85.20 mm to 178.81 mm; the second part's
# 53 mm is no whole number of its 2 mm steps (its last interval 1 mm): the mirror image is by
# construction, not by a lucky length
STEPS = """\
  station_steps:
    - {from: -0.05 m, to: 0.0 m, step: 0.005 m}
    - {from: 0.1 m, to: 0.153 m, step: 0.002 m}"""
PARTS_S = ((-0.05, 0.0, 0.005), (0.1, 0.153, 0.002))


def _write(tmp_path: Path, steps: str = STEPS, direction: str = "facing") -> Path:
    if not (tmp_path / "uk_crossing").exists():
        shutil.copytree(TRACKS / "uk_crossing", tmp_path / "uk_crossing")
    path = tmp_path / f"track_{direction}.yaml"
    path.write_text(TRACK.format(direction=direction, steps=steps))
    return path


def _from_python(rails: VariableRails, trailing: bool) -> VariableRails:
    """The same zone built from Python: the parts in track distances."""
    if trailing:
        parts = tuple((START_M - b, START_M - a, h) for a, b, h in PARTS_S)
    else:
        parts = tuple((START_M + a, START_M + b, h) for a, b, h in PARTS_S)
    return VariableRails(
        left=rails.left, start_m=START_M, station_step_m=0.02, rail_origin_m=(0.75, 0.0),
        x_max_m=rails.x_max_m, station_steps_m=parts, grids_from_end=trailing,
    )  # fmt: skip


@pytest.mark.parametrize("direction", ["facing", "trailing"])
def test_file_parts_give_the_stations_of_the_python_zone(tmp_path, direction):
    rails = load_track(_write(tmp_path, direction=direction)).variable_rails
    trailing = direction == "trailing"
    assert rails.grids_from_end == trailing and not rails.uniform
    x = rails.stations_m()
    np.testing.assert_array_equal(x, _from_python(rails, trailing).stations_m())
    # each part's ends are stations, and inside a part the stations are its step apart but
    # for one shorter interval where its length is no whole number of steps (the 53 mm part's:
    # 1 mm, at s = 0.152 .. 0.153 m in both directions)
    shorter = []
    for a, b, h in rails.station_steps_m:
        assert a in x and b in x
        inside = np.diff(x[(x >= a) & (x <= b)])
        assert np.all(inside <= h + 1e-12)
        shorter.append(inside[np.abs(inside - h) > 1e-12])
    assert sorted(s.size for s in shorter) == [0, 1]
    assert np.concatenate(shorter) == pytest.approx([1e-3], abs=1e-12)


def test_facing_and_trailing_parts_give_mirrored_stations(tmp_path):
    facing = load_track(_write(tmp_path)).variable_rails
    trailing = load_track(_write(tmp_path, direction="trailing")).variable_rails
    s_facing = facing.stations_m() - START_M
    s_trailing = START_M - trailing.stations_m()  # the slices' s of each station, decreasing
    assert s_facing.size == s_trailing.size
    np.testing.assert_allclose(s_trailing[::-1], s_facing, rtol=0.0, atol=1e-12)
    # the 53 mm part's grid runs from s = 0.1 m both ways (facing: its first slice met;
    # trailing: its last), so 0.152 m is a station in both and 0.151 m in neither
    for s in (s_facing, s_trailing):
        assert np.any(np.abs(s - 0.152) < 1e-12) and not np.any(np.abs(s - 0.151) < 1e-12)


def test_no_parts_and_an_empty_list_keep_the_uniform_zone(tmp_path):
    for steps in ("", "  station_steps: []", "  station_steps:"):
        rails = load_track(_write(tmp_path, steps=steps)).variable_rails
        assert rails.uniform and not rails.grids_from_end


def test_grids_from_end_without_parts_refused(tmp_path):
    rails = load_track(_write(tmp_path, steps="")).variable_rails
    with pytest.raises(InputError, match="needs parts"):
        VariableRails(left=rails.left, start_m=START_M, grids_from_end=True)


def _part(text: str, second: str | None = None) -> str:
    lines = ["  station_steps:", f"    - {text}"] + ([f"    - {second}"] if second else [])
    return "\n".join(lines)


OK = "{from: 0.0 m, to: 0.05 m, step: 0.005 m}"


@pytest.mark.parametrize(
    ("steps", "key", "words"),
    [
        (_part("{from: 0 m, to: 0.05 m, stepp: 5 mm}"), "station_steps.0.stepp", "unknown key"),
        (_part("{from: 0 m, to: 0.05 m}"), "station_steps.0", "missing key 'step'"),
        (_part("5 mm"), "station_steps.0", "expected a mapping"),
        ("  station_steps: {from: 0 m, to: 0.05 m, step: 5 mm}", "station_steps",
         "expected a list"),
        (_part("{from: 0.05 m, to: 0.0 m, step: 5 mm}"), "station_steps.0.to", "from < to"),
        (_part("{from: 0.0 m, to: 0.0 m, step: 5 mm}"), "station_steps.0.to", "from < to"),
        (_part(OK, "{from: 0.04 m, to: 0.1 m, step: 5 mm}"), "station_steps.1.from",
         "overlaps"),
        (_part(OK, "{from: -0.08 m, to: -0.06 m, step: 5 mm}"), "station_steps.1.from",
         "comes before"),
        (_part("{from: 0.1 m, to: 0.2 m, step: 5 mm}"), "station_steps.0.to",
         "outside the zone's slices (-0.0852 .. 0.17881 m"),
        (_part("{from: -0.1 m, to: 0.1 m, step: 5 mm}"), "station_steps.0.from",
         "outside the zone's slices"),
        (_part("{from: 0 m, to: 0.05 m, step: nan m}"), "station_steps.0.step", "got 'nan m'"),
        (_part("{from: 0 m, to: 0.05 m, step: .nan}"), "station_steps.0.step", "finite"),
        (_part("{from: 0 m, to: 0.05 m, step: .inf}"), "station_steps.0.step", "finite"),
        (_part("{from: 0 m, to: 0.05 m, step: inf m}"), "station_steps.0.step", "got 'inf m'"),
        (_part("{from: .nan, to: 0.05 m, step: 5 mm}"), "station_steps.0.from", "finite"),
        (_part("{from: 0 m, to: -.inf, step: 5 mm}"), "station_steps.0.to", "finite"),
        (_part("{from: 0 m, to: 0.05 m, step: -5 mm}"), "station_steps.0.step", ">= 0.0001"),
        (_part("{from: 0 m, to: 0.05 m, step: 0 m}"), "station_steps.0.step", ">= 0.0001"),
        (_part("{from: 0 m, to: 0.05 m, step: 5 m}"), "station_steps.0.step", "<= 1"),
        (_part("{from: 0 m, to: 0.05 m, step: 5 kg}"), "station_steps.0.step", "kg"),
    ],
)  # fmt: skip
@pytest.mark.parametrize("direction", ["facing", "trailing"])
def test_bad_part_refused_with_file_line_and_key(tmp_path, steps, key, words, direction):
    path = _write(tmp_path, steps=steps, direction=direction)
    with pytest.raises(InputError) as err:
        load_track(path)
    assert words in str(err.value)
    assert err.value.key == f"variable_rails.{key}"
    assert err.value.source == str(path)
    # the parts are written from line 14 on (the list's own key: line 14)
    assert err.value.line is not None and err.value.line >= 14, err.value
    assert str(path) in str(err.value) and f"variable_rails.{key}" in str(err.value)


def test_mirrored_stations_carry_the_same_tables(tmp_path):
    """The dynamics' station tables (:func:`sc_kernel_fields`) of the facing and the trailing
    zone with the same parts: the stations as :meth:`VariableRails.stations_m` gives them (not
    uniform: ``sc_step = 0``), and station ``i`` of the facing zone carries the table of
    station ``n - 1 - i`` of the trailing one (the same slices' ``s``; the effective section's
    envelope over +-60 mm is symmetric in ``x``): heights within 1e-12 m (measured 1.1e-14 m:
    the surface read at ``start + s + x`` and ``start - s - x``, rounded apart; neighbouring
    stations' tables differ by up to 44 mm here, where the nose begins)."""
    tables = []
    for direction in ("facing", "trailing"):
        track = load_track(_write(tmp_path, direction=direction))
        geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
        fields = sc_kernel_fields(track.variable_rails, geometry, 5.0e-4)
        assert fields["sc_step"] == 0.0
        np.testing.assert_array_equal(fields["sc_stations"], track.variable_rails.stations_m())
        side = int(np.flatnonzero(fields["sc_side"] >= 0)[0])
        rows = fields["sc_index"][:, side]
        tables.append(fields["sc_base"][rows][:, :, 0])  # the heights' column
    facing, trailing = tables
    assert facing.shape == trailing.shape
    finite = np.isfinite(facing)
    assert np.array_equal(finite, np.isfinite(trailing[::-1]))
    assert np.max(np.abs(facing[finite] - trailing[::-1][finite])) < 1e-12


def test_too_many_stations_refused_before_any_table_is_built():
    """0.1 mm stations (the smallest step) over the shipped crossing's 5.7 m zone: about
    57 000 stations, refused naming the file and the key before the tables (about 0.7 MB per
    station and side) are built; its 20 mm stations pass the bound (5000)."""
    assert load_track("uk_crossing_facing").variable_rails.too_many_stations() is None
    with pytest.raises(InputError) as err:
        load_track("uk_crossing_facing", ["variable_rails.station_step=0.1 mm"])
    message = str(err.value)
    assert "variable_rails.station_step" in message and "at most 5000" in message
    assert "uk_crossing_facing.yaml" in message
