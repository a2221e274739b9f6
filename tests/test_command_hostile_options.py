"""Hostile options of the commands that read a finished run (issue 26, part 4): each is refused
with one line and exit code 2 before any frame is drawn, never a traceback (exit 3) or an
animation of nonsense. The ranges: src/railexu/report/animate.py (their reasons there)."""

from __future__ import annotations

from pathlib import Path

import pytest

from railexu.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory) -> Path:
    """The single wheelset over 0.3 m, data only."""
    out = tmp_path_factory.mktemp("hostile") / "run"
    argv = ["run", str(ROOT / "vehicles" / "wheelset.yaml"), "--distance", "0.3", "--quiet",
            "--no-plots", "--no-helper-processes", "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    return out


@pytest.mark.parametrize(
    ("option", "value", "words"),
    [
        ("--playback", "1e-30", "expected 0.001 .. 1000"),  # was a traceback (exit 3)
        ("--playback", "1e30", "expected 0.001 .. 1000"),
        ("--dpi", "0", "expected 10 .. 600"),  # was a traceback (exit 3)
        ("--dpi", "-1", "expected 10 .. 600"),
        ("--dpi", "100000", "expected 10 .. 600"),
        ("--exaggeration", "1e30", "expected 1 .. 1000"),
        ("--force-scale", "1e30", "mm/kN: expected"),
        ("--force-scale", "1e-30", "mm/kN: expected"),
        ("--wheelset", "0", "numbered from 1"),  # was the last wheelset (index -1)
        ("--wheelset", "-1", "numbered from 1"),
        ("--start", "-1", "starts at 0 s"),
        ("--end", "nan", "finite"),
        ("--fps", "inf", "finite"),
    ],
)
def test_animate_refuses_absurd_options(run_folder, tmp_path, capsys, option, value, words):
    argv = ["animate", str(run_folder), "--view", "plan", "--out", str(tmp_path), "--quiet"]
    try:
        status = main([*argv, option, value])
    except SystemExit as exc:  # argparse's own refusal: its usage, then one error line
        status = exc.code
    err = capsys.readouterr().err.strip()
    assert status == 2, err
    assert words in err.splitlines()[-1] and "Traceback" not in err, err
    assert not list(tmp_path.glob("*.gif"))


def test_animate_refuses_more_frames_than_an_animation_holds():
    """1000 times slower at 60 fps over 2 s of run: 120 000 frames, above 60 000."""
    import numpy as np

    from railexu.errors import InputError
    from railexu.report.animate import AnimationSettings, frame_indices

    t = np.linspace(0.0, 2.0, 401)
    with pytest.raises(InputError, match="frames at playback 0.001"):
        frame_indices(t, AnimationSettings(fps=60.0, playback=1e-3))
    assert frame_indices(t, AnimationSettings(fps=20.0, playback=0.25)).size == 161


@pytest.mark.parametrize("value", ["-inf", "-nan", "-Infinity"])
def test_minus_infinity_is_refused_as_a_value_not_taken_for_an_option(capsys, value):
    """``--load -inf`` said "expected one argument" (argparse took it for an option)."""
    with pytest.raises(SystemExit) as info:
        main(["creep", "--load", value, "--semi-axes", "6 mm", "4 mm"])
    assert info.value.code == 2
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert f"argument --load: '{value}': expected a finite value in N" in last, last


@pytest.mark.parametrize(
    ("option", "value", "words"),
    [
        ("--inclination", "nan", "expected 0 .. 0.1 rad"),  # was a traceback (exit 3)
        ("--inclination", "inf", "expected 0 .. 0.1 rad"),  # was a traceback (exit 3)
        ("--inclination", "-1", "expected 0 .. 0.1 rad"),  # -1 rad: was a traceback
        ("--inclination", "1:0", "expected '1:40'"),
        ("--inclination", "abc", "expected '1:40'"),
        ("--lateral", "1e30", "off its rail"),  # was: every position skipped, exit 1
        ("--lateral", "-1:1:0.1", "off its rail"),
        ("--amplitudes", "0", "expected > 0"),
        ("--amplitudes", "-1", "expected > 0"),
        ("--amplitudes", "1", "EN 15302"),
    ],
)
def test_contact_refuses_absurd_geometry_before_computing(tmp_path, capsys, option, value, words):
    status = main(["contact", option, value, "--out", str(tmp_path / "c")])
    err = capsys.readouterr().err.strip()
    assert status == 2 and words in err and "Traceback" not in err, err
    assert len(err.splitlines()) == 1, err
    assert not (tmp_path / "c" / "contact.csv").exists()


@pytest.mark.parametrize(
    ("option", "value", "words"),
    [
        ("--deceleration", "0", "ramp_deceleration 0 m/s^2: expected > 0"),  # was exit 3
        ("--deceleration", "1e30", "<= 5 m/s^2"),  # was "speed must be <= 150 m/s, got 2.5e+30"
        ("--linear-points", "1000000000", "linear_points must be 2 .. 1000"),  # ran on and on
        ("--speed-min", "1e-30", "expected at least 1 m/s"),  # ran
        ("--tolerance", "1e30", "the searched range (75 m/s)"),  # ran, then failed (exit 1)
        ("--tolerance", "1e-30", "expected 0.01 m/s"),  # ran
        ("--threshold", "1e30", "at most 0.02 m"),  # ran: hunting never found
        ("--threshold", "1e-30", "at least the floor"),  # ran: any motion is hunting
        ("--initial-lateral", "-1", "at most 0.02 m"),  # ran
        ("--distance", "1e-30", "at least 20 m"),  # ran
    ],
)
def test_critical_speed_refuses_absurd_settings_before_running(
    tmp_path, capsys, option, value, words
):
    argv = ["critical-speed", "wheelset", "--out", str(tmp_path / "cs"), "--quiet"]
    status = main([*argv, option, value])
    err = capsys.readouterr().err.strip()
    assert status == 2 and words in err and "Traceback" not in err, err
    assert len(err.splitlines()) == 1, err


def test_study_refuses_a_million_workers_before_starting_any(tmp_path, capsys):
    """``--workers 1000000`` forked one process per pending case (several hundred MB each)."""
    from railexu.study.runner import max_workers

    study = tmp_path / "s.yaml"
    study.write_text(
        "format_version: 1\nname: workers\nbase:\n  vehicle: wheelset\n"
        "  run: {distance: 0.3 m}\nvary:\n  parameters:\n    run.speed: [10 m/s, 11 m/s]\n"
    )
    out = tmp_path / "out"
    status = main(["study", str(study), "--out", str(out), "--quiet", "--workers", "1000000"])
    err = capsys.readouterr().err.strip()
    assert status == 2 and f"at most {max_workers()}" in err and "Traceback" not in err, err
    assert not (out / "results.csv").exists()


@pytest.mark.parametrize("address", ["abc", "", "nan"])
def test_study_refuses_a_scheduler_that_is_no_address(tmp_path, capsys, address):
    """'abc' was a traceback from dask.distributed's address parser (exit 3)."""
    pytest.importorskip("distributed")
    study = tmp_path / "s.yaml"
    study.write_text(
        "format_version: 1\nname: scheduler\nbase:\n  vehicle: wheelset\n"
        "  run: {distance: 0.3 m}\nvary:\n  parameters:\n    run.speed: [10 m/s]\n"
    )
    argv = ["study", str(study), "--out", str(tmp_path / "o"), "--quiet", "--scheduler", address]
    status = main(argv)
    err = capsys.readouterr().err.strip()
    assert status == 2 and "not a Dask scheduler address" in err and "Traceback" not in err, err


@pytest.mark.parametrize("value", ["", ","])
def test_plot_refuses_an_empty_format_list(run_folder, capsys, value):
    """``--plots ''`` drew nothing and exited 0."""
    status = main(["plot", str(run_folder), "--plots", value])
    err = capsys.readouterr().err.strip()
    assert status == 2 and "give png, svg" in err, err
