"""The wear of a single run asked for by its settings (``wear:`` in the run settings, ``railexu
run --wear LAW``; docs/wear.md, "Per run"): the option's checks, the files and the summary's
``wear`` block, equal to :func:`railexu.results.wear.run_wear` of the same run, and a run that
did not complete saying so."""

from __future__ import annotations

import json
import os
import signal
from pathlib import Path

import numpy as np
import pytest

from railexu.cli import main
from railexu.contact.wear import laws
from railexu.contact.wear.coefficients import COEFFICIENTS_FILE
from railexu.errors import InputError, RunInterrupted
from railexu.operation.run_settings import (
    WEAR_LAWS,
    RunSettings,
    RunSettingsError,
    run_settings_from_dict,
)
from railexu.report.run_files import write_run
from railexu.report.run_folder import read_run_summary
from railexu.results import TimeSeries
from railexu.results.run import run
from railexu.results.run_wear import wear_block
from railexu.results.wear import WHEEL_GRID, run_wear
from railexu.study.spec import load_study
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]

#: the shortest curve run of the wear tests (test_wear_run.py's R 200 m case): the free
#: wheelset, 10 m straight, a 20 m clothoid, the curve; 15 m/s without cant (1.1 m/s^2
#: uncompensated), run for 40 m and evaluated from 35 m (5 m into the curve)
TRACK = """\
format_version: 1
name: R200 left
rail_profile: UIC60
inclination: '1:40'
gauge: 1.435 m
geometry:
  type: sections
  sections:
  - {type: straight, length: 10 m}
  - {type: transition, length: 20 m}
  - {type: curve, length: 60 m, radius: 200 m, cant: 0 mm, direction: left}
irregularities: {type: none}
"""
RUN = dict(speed_m_per_s=15.0, distance_m=40.0, evaluate_from_m=35.0)

#: floats of the summary against run_wear of the folder's timeseries.csv: the CSV holds 9
#: significant digits (5e-10 relative); a contact point moved by that much splits its strips
#: differently between the 0.2 mm nodes, which moves a node's peak by up to 1.2e-7 (measured)
CSV_ROUND_OFF = 1e-6


def test_the_run_settings_know_the_wear_laws():
    """The names written in the run settings (numpy-free) are those of the wear laws."""
    assert tuple(laws.WEAR_LAWS) == WEAR_LAWS


def test_wear_turns_the_contact_outputs_on():
    assert RunSettings(wear_law="energy_usfd").contact_outputs
    assert run_settings_from_dict({"wear": "archard_jendel"}).wear_law == "archard_jendel"
    assert run_settings_from_dict({"wear": {"law": "energy_usfd"}}).wear_law == "energy_usfd"
    assert run_settings_from_dict({}).wear_law is None
    with pytest.raises(RunSettingsError, match="wear must be one of archard_jendel") as info:
        RunSettings(wear_law="archard")
    assert info.value.field == "wear"


STUDY = """\
format_version: 1
name: worn
base:
  vehicle: {vehicle}
  run:
    distance: 5 m
    {line}
"""


@pytest.mark.parametrize(
    "line, key, message",
    [
        ("wear: archard", "base.run.wear.law", "'archard' is not one of archard_jendel, "
         "energy_usfd. Did you mean 'archard_jendel'?"),
        ("wear: {law: usfd}", "base.run.wear.law", "'usfd' is not one of"),
        ("wear: {law: energy_usfd, k1: 0.1}", "base.run.wear.k1", "unknown key"),
        ("wear: {lwa: energy_usfd}", "base.run.wear.lwa", "missing key 'law'"),
        ("wear: 3", "base.run.wear", "expected a wear law, one of archard_jendel, energy_usfd "
         "(or {law: NAME}), got 3"),
        ("wear:", "base.run.wear", "expected a wear law"),
        ("wear: archard_jendel\n    contact_outputs: false", "base.run.contact_outputs",
         "wear needs the contact points"),
        ("waer: archard_jendel", "base.run.waer", "unknown key"),
    ],
)  # fmt: skip
def test_bad_wear_settings_name_file_line_and_key(tmp_path, line, key, message):
    path = tmp_path / "study.yaml"
    path.write_text(STUDY.format(vehicle=ROOT / "vehicles" / "wheelset.yaml", line=line))
    with pytest.raises(InputError) as info:
        load_study(path)
    text = str(info.value)
    line = 8 if "contact" in key else 7
    assert text.startswith(f"{path}:{line}: {key}: "), text
    assert message in text


def test_bad_wear_option_fails_before_the_folder(tmp_path, capsys):
    out = tmp_path / "run"
    status = main(["run", "wheelset", "--wear", "jendel", "--out", str(out), "--quiet"])
    assert status == 2
    err = capsys.readouterr().err
    assert "--wear 'jendel': unknown wear law" in err and "archard_jendel, energy_usfd" in err
    assert not out.exists()


@pytest.fixture(scope="module")
def worn_folder(tmp_path_factory):
    """``railexu run wheelset --track R200 --wear archard_jendel`` (40 m, no figures but the
    wear's: plots on)."""
    tmp = tmp_path_factory.mktemp("worn_run")
    track = tmp / "r200.yaml"
    track.write_text(TRACK)
    out = tmp / "run"
    status = main([
        "run", "wheelset", "--track", str(track), "--speed", "15 m/s", "--distance", "40 m",
        "--evaluate-from", "35 m", "--wear", "archard_jendel", "--out", str(out), "--quiet",
    ])  # fmt: skip
    assert status == 0
    return out, track


def test_the_run_writes_the_wear_files_figure_and_summary_block(worn_folder, capsys):
    out, _ = worn_folder
    for name in ("wear.csv", "wear.json", "wear.png", "timeseries.csv"):
        assert (out / name).is_file(), name
    summary = read_run_summary(out, ("summary.json", "wear.csv", "wear.json"))  # manifest
    manifest = json.loads((out / ".railexu-files.json").read_text())
    assert manifest["complete"] and {"wear.csv", "wear.json", "wear.png"} <= set(manifest["files"])
    wear = summary["wear"]
    assert summary["settings"]["contact_outputs"] and summary["settings"]["wear_law"]
    assert wear["law"] == "archard_jendel" and wear["computed"] and wear["complete"]
    assert wear["coefficients_file"] == "railexu/data/wear_rcf.yaml (shipped)"
    assert "Jendel" in wear["sources"]["archard_jendel"] and "Ekberg" in wear["sources"]["fi_surf"]
    assert "Burstow" in wear["sources"]["wlrm"]
    assert wear["window_rule"] == "evaluate_from" and wear["window_m"][0] == 35.0
    assert [(w["wheelset"], w["side"]) for w in wear["wheels"]] == [("ws1", "left"),
                                                                   ("ws1", "right")]  # fmt: skip
    left, right = wear["wheels"]
    # the outer (right) wheel of the left curve wears at its flange root, the inner on its tread
    assert right["removed_area_per_km_mm2"] > 10.0 * left["removed_area_per_km_mm2"]
    assert right["max_depth_at_mm"] < -20.0 < -15.0 < left["max_depth_at_mm"]
    assert right["fi_surf_max"] > left["fi_surf_max"]
    assert (
        wear["rails"][1]["removed_area_per_axle_um2"]
        > wear["rails"][0]["removed_area_per_axle_um2"]
    )
    from railexu.cli.run import format_summary

    assert "ws1 right: wheel" in format_summary(summary)


def test_the_run_writes_what_run_wear_gives(worn_folder):
    """The summary's block and wear.json equal run_wear of the folder's own timeseries.csv
    (to the CSV's round-off, CSV_ROUND_OFF)."""
    out, _ = worn_folder
    wear = json.loads((out / "summary.json").read_text())["wear"]
    ts = TimeSeries.from_csv(out / "timeseries.csv")
    wears = run_wear(ts, load_vehicle("wheelset"), "archard_jendel", evaluate_from_m=35.0)
    expected = wear_block(wears, "archard_jendel", str(COEFFICIENTS_FILE))
    assert expected.keys() == wear.keys()
    for part in ("wheels", "rails"):
        for got, want in zip(wear[part], expected[part], strict=True):
            assert got.keys() == want.keys()
            for key, value in want.items():
                if isinstance(value, float):
                    assert got[key] == pytest.approx(value, rel=CSV_ROUND_OFF, abs=1e-12), key
                else:
                    assert got[key] == value, key
    per_wheel = json.loads((out / "wear.json").read_text())["wheels"]
    for got, w in zip(per_wheel, wears, strict=True):
        assert got["wheel_area_per_km_mm2"] == pytest.approx(
            w.area_per_km_m2 * 1e6, rel=CSV_ROUND_OFF
        )


def test_the_written_area_is_the_integrated_volume_rate(worn_folder):
    """Conservation (as the wear tests): the area of wear.csv's depth across each wheel's
    profile equals the integral of the patches' volume rates (the summary's
    ``patch_volume_rate_per_km_mm2``) within 1 %, and is the summary's removed area."""
    out, _ = worn_folder
    wear = json.loads((out / "summary.json").read_text())["wear"]
    header = (out / "wear.csv").read_text().splitlines()[0].split(",")
    data = np.genfromtxt(out / "wear.csv", delimiter=",", skip_header=1)
    for w in wear["wheels"]:
        depth = data[:, header.index(f"{w['wheelset']}_{w['side']}_wheel_depth_per_km_m")]
        area_mm2 = np.nansum(depth) * WHEEL_GRID[1] * 1e6
        assert w["patch_volume_rate_per_km_mm2"] > 0.0
        assert area_mm2 == pytest.approx(w["patch_volume_rate_per_km_mm2"], rel=0.01)
        assert area_mm2 == pytest.approx(w["removed_area_per_km_mm2"], rel=1e-6)


def test_the_python_run_carries_run_wear_exactly(worn_folder):
    """railexu.run with ``wear_law``: result.wear is run_wear of result.timeseries (equal)."""
    _, track = worn_folder
    vehicle = load_vehicle("wheelset")
    result = run(vehicle, load_track(track), RunSettings(**RUN, wear_law="energy_usfd"))
    again = run_wear(result.timeseries, vehicle, "energy_usfd", evaluate_from_m=35.0)
    assert result.summary["wear"]["law"] == "energy_usfd"
    for a, b in zip(result.wear, again, strict=True):
        assert a.summary() == b.summary()
        assert np.array_equal(a.depth_per_km_m, b.depth_per_km_m)


def test_an_interrupted_run_writes_its_wear_and_says_so(worn_folder, tmp_path):
    """Ctrl-C at 37 m: the wear of the recorded part's window (35 .. 37 m) is written, and the
    block says the run did not complete."""
    _, track = worn_folder
    sent: list[float] = []

    def progress(distance, total, speed, eta):
        if distance > 37.0 and not sent:
            sent.append(distance)
            os.kill(os.getpid(), signal.SIGINT)

    old = signal.signal(signal.SIGINT, signal.default_int_handler)  # a runner may ignore it
    try:
        with pytest.raises(RunInterrupted) as info:
            run(load_vehicle("wheelset"), load_track(track),
                RunSettings(**RUN, wear_law="archard_jendel"), progress)  # fmt: skip
    finally:
        signal.signal(signal.SIGINT, old)
    result = info.value.result
    wear = result.summary["wear"]
    assert wear["run_state"] == "interrupted" and not wear["complete"] and wear["computed"]
    assert "the run stopped at 37" in wear["note"]
    assert 35.0 < wear["window_m"][1] < 40.0
    names = {p.name for p in write_run(result, tmp_path / "stopped", plots=False)}
    assert {"wear.csv", "wear.json", "summary.json"} <= names


def test_nothing_to_wear_is_said_not_hidden():
    reason = "the evaluation window holds no distance"
    block = wear_block(None, "archard_jendel", str(COEFFICIENTS_FILE), "diverged", False,
                       reason=reason, stopped_at_m=0.5)  # fmt: skip
    assert not block["computed"] and "no distance" in block["reason"]
    assert "stopped at 0.5 m (diverged)" in block["note"] and "wheels" not in block


def test_the_docs_name_the_option():
    text = (ROOT / "docs" / "wear.md").read_text()
    assert "--wear" in text and "has no option that writes the wear" not in text
