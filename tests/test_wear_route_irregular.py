"""Track irregularities in a wear route (docs/wear.md, "Wear spreading"): the block's checks,
the cases' tracks, the ideal routes unchanged, the mirrored case and conservation on irregular
track."""

from __future__ import annotations

import hashlib
import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from wear_checks import assert_steps_conserve_volume

from railexu.errors import InputError
from railexu.study.wear.route import RouteWarning, load_route
from railexu.study.wear.route_study import mirrored_parameters, route_study_data

ROOT = Path(__file__).resolve().parents[1]

ROUTE = """format_version: 1
name: irregular
irregularities:
  type: spectrum
  spectrum: german_low
  seed: 7
  wavelength_max: 40 m
sections:
  - {name: s, share: 2, speed: 20 m/s, length: 40 m, directions: both}
  - {name: R600, share: 1, speed: 20 m/s, length: 45 m, radius: 600 m, cant: 50 mm}
  - name: R300
    share: 1
    speed: 15 m/s
    length: 45 m
    radius: 300 m
    irregularities: {type: spectrum, spectrum: german_high, seed: 3, wavelength_max: 30 m}
  - {name: R400, share: 1, speed: 15 m/s, length: 45 m, radius: 400 m, irregularities: none}
"""


def _route(tmp_path, text: str) -> Path:
    path = tmp_path / "route.yaml"
    path.write_text(text)
    return path


def test_case_tracks_carry_the_irregularities(tmp_path):
    """Every case's track carries its section's block: the route's with seed + section index,
    a section's own as written (``none`` switches them off); a curve's reverse runs the same
    record mirrored, a straight's reverse (its mirrored case: the wheels exchanged) the record
    as it is. The mirrored track's rail offsets are the forward track's mirrored: left lateral
    = -right lateral, left vertical = right vertical (to the last bit)."""
    from railexu.track.track import load_track

    route = load_route(_route(tmp_path, ROUTE))
    blocks = {f"{c.name}_{c.direction}": c.track_data(route)["irregularities"]
              for c in route.cases}  # fmt: skip
    spec = {"type": "spectrum", "spectrum": "german_low", "wavelength_max": "40 m"}
    assert blocks["s_forward"] == {**spec, "seed": 7}
    assert blocks["s_reverse"] == {**spec, "seed": 7}  # the mirrored case: record as it is
    assert blocks["R600_forward"] == {**spec, "seed": 8}
    assert blocks["R600_reverse"] == {**spec, "seed": 8, "mirror": True}
    assert blocks["R300_forward"]["seed"] == 3 and blocks["R300_forward"]["spectrum"] == (
        "german_high")  # fmt: skip
    assert blocks["R300_reverse"]["mirror"] is True
    assert blocks["R400_forward"] == blocks["R400_reverse"] == {"type": "none"}
    # the written tracks are valid track files; the reverse curve's record is the mirror image
    fwd, rev = (load_track(c.write_track(route, tmp_path / "tracks"))
                for c in route.cases if c.name == "R600")  # fmt: skip
    x = np.linspace(0.0, 90.0, 301)
    a, b = fwd.irregularities(90.0), rev.irregularities(90.0)
    (ly, lz), (ry, rz) = a.left_rail_offsets(x), b.right_rail_offsets(x)
    assert np.abs(ly).max() > 1e-4
    assert np.array_equal(ly, -ry) and np.array_equal(lz, rz)
    # the step's study varies the block per case, zipped with the geometry
    _, study = route_study_data(route, list(route.cases), Path("v.yaml"), [], {}, "t")
    params = study["vary"]["parameters"]
    assert params["track.irregularities"] == list(blocks.values())


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        ("  seed: 7\n", "  seeed: 7\n", r"route.yaml:6: irregularities.seeed: unknown key. Did "
         r"you mean 'seed'"),
        ("spectrum: german_low", "spectrum: german_mid",
         r"route.yaml:5: irregularities.spectrum: .*german_mid"),
        ("  wavelength_max: 40 m\n", "  wavelength_max: 40 kg\n",
         r"route.yaml:7: irregularities.wavelength_max"),
        ("german_high, seed: 3", "german_high, seed: -3",
         r"route.yaml:16: sections.2.irregularities.seed"),
        ("irregularities: none}", "irregularities: wavy}",
         r"route.yaml:17: sections.3.irregularities.type: .*wavy"),
        ("  seed: 7\n", "  seed: 7\n  length: 60 m\n",
         r"route.yaml:7: irregularities.length: a record of 60 m does not cover the run of "
         r"section 'R600' \(75 m\)"),
        ("  seed: 7\n", "", r"route.yaml:\d+: irregularities: missing key 'seed'"),
    ],
)  # fmt: skip
def test_bad_irregularities_are_located_input_errors(tmp_path, old, new, match):
    """A bad key or value of the block, at the route's top level or in a section, is an
    InputError naming the route file, the line and the key (the track file's own checks)."""
    assert old in ROUTE
    with pytest.raises(InputError, match=match):
        load_route(_route(tmp_path, ROUTE.replace(old, new, 1)))


def test_a_window_shorter_than_the_longest_wavelength_warns(tmp_path):
    """A section whose evaluation window is shorter than ``wavelength_max`` runs, with a
    warning naming the file, its line and the section (docs/wear.md, "Wear spreading")."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RouteWarning)
        load_route(_route(tmp_path, ROUTE))  # every window is at least the wavelength_max
    text = ROUTE.replace("wavelength_max: 40 m", "wavelength_max: 150 m")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RouteWarning)
        load_route(_route(tmp_path, text))
    messages = [str(w.message) for w in caught if w.category is RouteWarning]
    assert len(messages) == 2  # the route's block: s and R600; R300 has its own (30 m)
    assert re.search(
        r"route.yaml:3: section 's': its evaluation window \(40 m\) is shorter "
        r"than the irregularities' wavelength_max \(150 m\)",
        messages[0],
    )
    assert "section 'R600': its evaluation window (40 m)" in messages[1]


def _digest(path: Path) -> str:
    route = load_route(path)
    cases = list(route.cases)
    mirror = None
    if any(c.mirrored for c in cases):
        from railexu.vehicle.vehicle import load_vehicle

        mirror = mirrored_parameters(load_vehicle("wheelset"), cases, 0.0)
    data = route_study_data(route, cases, Path("vehicle.yaml"), [], {}, "step", mirror)
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()


@pytest.mark.parametrize(
    ("name", "digest"),
    [
        ("curvy_10.yaml", "55e15c023d6360cda0a35a4dbc5c78c8b518e0860d720222799f29175c8c7ed0"),
        ("straight.yaml", "824b8f17d80095c7064c9888b0183925b82416b1acd796445f57a17c85de644d"),
    ],
)  # fmt: skip
def test_routes_without_irregularities_are_unchanged(name, digest):
    """The shipped routes (no ``irregularities:``) give the step's study exactly as before this
    change (the track and study mappings hashed; the digests computed with the code of
    e549783): the same case hashes, so a loop resumed across the change reuses its runs."""
    assert _digest(ROOT / "studies" / "wear" / name) == digest


STRAIGHT = """format_version: 1
name: s
irregularities: {type: spectrum, spectrum: german_low, seed: 1, wavelength_max: 20 m}
sections:
  - {name: s, share: 1, speed: 20 m/s, length: 20 m, directions: both}
"""
_SIDES = ("left", "right")


def test_irregular_mirrored_case_is_the_mirror_of_the_real_reverse_run(tmp_path):
    """A straight run both ways on irregular track (German low level, 3-20 m), free wheelset
    starting at +1 mm: the mirrored case (wheels exchanged, -1 mm, the record as it is) is the
    mirror image of the real reverse run, the vehicle as it is at +1 mm on the mirrored record
    (``mirror: true``, run here as a route of its own): its lateral displacement is minus that
    run's (to 1e-8 m; measured 1.7e-9 m of a 1 mm motion) and its wear, given back to the real
    wheels, equals that run's node by node (to 1e-4 of the peak depth; measured 2.0e-5) and in
    area (1e-5; measured 8.5e-7). The relation is exact but for the integration's round-off
    (5.5e-7 of the peak on ideal track, test_wear_loop.py), which the irregular motion
    amplifies; a sign error in the mirrored record would show at the level by which the
    forward run differs from the real reverse run (measured 27 % and 51 % of the peak depth of
    the left and right wheel: asserted above 10 %). The loop's conservation check holds on the
    irregular cases within 1 % (measured 2.9e-7)."""
    from railexu.simulation.timeseries import TimeSeries
    from railexu.study.wear.loop import wear_loop

    both = tmp_path / "both"
    both.mkdir()
    result = wear_loop("wheelset", _route(both, STRAIGHT), 1e5, both / "out", max_steps=1,
                       workers=0, rate_tolerance=None, initial_lateral_m=1e-3)  # fmt: skip
    one = tmp_path / "one"
    one.mkdir()
    text = STRAIGHT.replace("seed: 1,", "seed: 1, mirror: true,").replace("both}", "forward}")
    wear_loop("wheelset", _route(one, text), 1e5, one / "out", max_steps=1, workers=0,
              rate_tolerance=None, initial_lateral_m=1e-3)  # fmt: skip

    def lateral(out, case):
        ts = TimeSeries.from_csv(out / "step_000" / "route" / "cases" / case / "timeseries.csv")
        return np.asarray(ts.columns["ws1_lateral_m"])

    y_mirrored, y_real = lateral(both / "out", "case_0001"), lateral(one / "out", "case_0000")
    y_forward = lateral(both / "out", "case_0000")
    assert y_mirrored[0] == pytest.approx(-1e-3) and y_real[0] == pytest.approx(1e-3)
    assert np.abs(y_mirrored + y_real).max() < 1e-8
    assert np.abs(y_forward - y_real).max() > 1e-4  # the mirrored record moves it differently
    with (np.load(both / "out" / "step_000" / "cases" / "s_reverse.npz") as rev,
          np.load(one / "out" / "step_000" / "cases" / "s_forward.npz") as real,
          np.load(both / "out" / "step_000" / "cases" / "s_forward.npz") as fwd):  # fmt: skip
        for side in _SIDES:
            a, b = real[f"ws1_{side}_depth_per_km_m"], rev[f"ws1_{side}_depth_per_km_m"]
            assert a.max() > 0.0 and np.abs(a - b).max() < 1e-4 * a.max()
            va = float(real[f"ws1_{side}_volume_rate_per_km_m2"])
            assert float(rev[f"ws1_{side}_volume_rate_per_km_m2"]) == pytest.approx(va, rel=1e-5)
            c = fwd[f"ws1_{side}_depth_per_km_m"]
            assert np.abs(c - a).max() > 0.1 * a.max()
    assert_steps_conserve_volume(result.steps[1:])
    track = yaml.safe_load((both / "out" / "step_000" / "route" / "track.yaml").read_text())
    assert track["irregularities"]["spectrum"] == "german_low"


def test_measured_record_in_a_route_is_found_relative_to_the_route_file(tmp_path):
    """``type: measured`` names its CSV relative to the route file (as a track file does); the
    cases' tracks, written elsewhere, name it by its absolute path and load; a missing file is
    an InputError at the route's line and key."""
    from railexu.track.track import load_track

    x = np.arange(0.0, 120.0, 0.25)
    lines = ["distance_m,lateral_m,vertical_m,cross_level_m,gauge_m"]
    lines += [f"{v:g},{1e-3 * np.sin(v / 5):.9f},0,{5e-4 * np.cos(v / 7):.9f},0" for v in x]
    (tmp_path / "rec.csv").write_text("\n".join(lines) + "\n")
    text = STRAIGHT.replace(
        "{type: spectrum, spectrum: german_low, seed: 1, wavelength_max: 20 m}",
        "{type: measured, file: rec.csv}",
    )
    route = load_route(_route(tmp_path, text))
    fwd, rev = route.cases
    assert fwd.irregularities()["file"] == str(tmp_path / "rec.csv")
    track = load_track(fwd.write_track(route, tmp_path / "elsewhere"))
    assert track.irregularities(50.0).left_rail_offsets(30.0)[0] != 0.0
    assert rev.irregularities() == fwd.irregularities()  # the mirrored case: as it is
    with pytest.raises(InputError, match=r"route.yaml:3: irregularities.file: .*not found"):
        load_route(_route(tmp_path, text.replace("rec.csv", "missing.csv")))
