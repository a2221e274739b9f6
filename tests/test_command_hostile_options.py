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
