"""`railexu plot` redraws every figure a run writes, those of a curved track included (the track
plan with curvature and cant, and the curving figure), from the run folder alone."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from railexu.cli import main
from railexu.track.alignment import alignment_from_record
from railexu.track.track import track_from_dict

ROOT = Path(__file__).resolve().parents[1]

TRACK = """\
format_version: 1
name: short curve
rail_profile: UIC60
inclination: "1:40"
geometry:
  type: sections
  sections:
    - {type: straight, length: 40 m}
    - {type: transition, length: 10 m, shape: bloss}
    - {type: curve, length: 30 m, radius: 800 m, cant: 40 mm, direction: right}
"""


def test_the_geometry_record_rebuilds_the_alignment_exactly():
    """The summary's geometry record gives back the same centre line, heading, curvature and
    cant (to rounding: the record holds the same floating-point numbers)."""
    import yaml

    alignment = track_from_dict(yaml.safe_load(TRACK)).alignment
    again = alignment_from_record(json.loads(json.dumps(alignment.to_dict())))
    s = np.linspace(-5.0, 95.0, 301)
    for what in ("curvature", "cant", "heading"):
        assert np.array_equal(getattr(again, what)(s), getattr(alignment, what)(s))
    assert np.array_equal(np.array(again.position(s)), np.array(alignment.position(s)))
    assert again.sections == alignment.sections


def test_plot_redraws_the_track_and_curving_figures(tmp_path, capsys):
    track = tmp_path / "curve.yaml"
    track.write_text(TRACK)
    out = tmp_path / "run"
    status = main(["run", str(ROOT / "vehicles" / "wheelset.yaml"), "--track", str(track),
                   "--distance", "10", "--out", str(out), "--quiet"])  # fmt: skip
    assert status == 0
    written = {p.name for p in out.glob("*.png")}
    assert {"track.png", "curving.png"} <= written
    for p in out.glob("*.png"):
        p.unlink()
    track.unlink()  # the folder alone must suffice
    assert main(["plot", str(out)]) == 0
    assert {p.name for p in out.glob("*.png")} == written


def test_plot_refuses_a_broken_geometry_record(tmp_path, capsys):
    track = tmp_path / "curve.yaml"
    track.write_text(TRACK)
    out = tmp_path / "run"
    assert main(["run", str(ROOT / "vehicles" / "wheelset.yaml"), "--track", str(track),
                 "--distance", "5", "--out", str(out), "--quiet", "--no-plots"]) == 0  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    del summary["curving"]["geometry"]["pieces"]["dk"]
    (out / "summary.json").write_text(json.dumps(summary))
    assert main(["plot", str(out)]) == 2
    assert "geometry record" in capsys.readouterr().err


@pytest.mark.parametrize("bad", [{"pieces": {}}, {"cant_base_m": 1.5}])
def test_geometry_record_errors_are_input_errors(bad):
    from railexu.errors import InputError

    with pytest.raises(InputError):
        alignment_from_record(bad)
