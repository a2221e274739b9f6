"""The command line as a user meets it: names of shipped files, units in options, negative
values, help texts, exit codes, errors that are bugs, broken pipes, output folders."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from railexu.cli import build_parser, main
from railexu.cli.common import EXIT_BUG, EXIT_INPUT, join_negative_values, quantity
from railexu.errors import InputError
from railexu.report.folder import MANIFEST, OutputFolder

ROOT = Path(__file__).resolve().parents[1]
SHORT_RUN = ["--distance", "3 m", "--quiet", "--plots", "none"]


def run_cli(args: list[str], cwd: Path | None = None) -> subprocess.CompletedProcess:
    """The installed ``railexu`` console script, as a user runs it."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    return subprocess.run(
        [sys.executable, "-c", "from railexu.console import entry_point; entry_point()", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


@pytest.mark.parametrize(
    ("text", "unit", "expected"),
    [
        ("108 km/h", "m/s", 30.0),  # 108 / 3.6
        ("108km/h", "m/s", 30.0),
        ("30", "m/s", 30.0),  # a bare number is SI
        ("82e9", "Pa", 82e9),  # an exponent is not a unit
        ("1.5E-3", "m", 1.5e-3),
        ("2km", "m", 2000.0),
        ("2 mm", "m", 0.002),
        ("-2 mm", "m", -0.002),
        ("5 ms", "s", 0.005),
    ],
)
def test_options_take_units(text, unit, expected):
    assert quantity(unit)(text) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("text", ["5 kg", "fast", "inf", "nan m/s"])
def test_options_refuse_wrong_units_and_non_finite_values(text):
    import argparse

    with pytest.raises(argparse.ArgumentTypeError):
        quantity("m/s")(text)


def test_a_value_with_units_reaches_the_run_settings():
    args = build_parser().parse_args(
        ["run", "eu07", "--speed", "108 km/h", "--distance", "2km", "--out", "x"]
    )
    assert args.speed == pytest.approx(30.0)
    assert args.distance == pytest.approx(2000.0)


def test_negative_option_values_are_values_not_options():
    argv = join_negative_values(["contact", "--lateral", "-0.010:0.010:0.0005", "--out", "x"])
    assert argv == ["contact", "--lateral=-0.010:0.010:0.0005", "--out", "x"]
    args = build_parser().parse_args(argv)
    assert args.lateral == "-0.010:0.010:0.0005"


def test_help_shows_defaults_choices_and_exit_codes(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(default: 10.0)" in text  # --speed
    assert "generalized_alpha" in text and "trapezoidal" in text  # --solver's choices
    assert "exit codes: 0" in text and "2 bad input" in text


def test_list_shows_shipped_files_with_descriptions(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in ("eu07", "eu07_bogie", "wheelset", "straight_irregular", "S1002", "UIC60"):
        assert f"  {name} " in out, name
    assert "EU07 Bo'Bo' electric locomotive" in out


def test_list_refuses_an_unknown_kind_with_a_suggestion(capsys):
    assert main(["list", "vehicle"]) == EXIT_INPUT
    assert "Did you mean 'vehicles'?" in capsys.readouterr().err


def test_shipped_names_work_from_any_folder(tmp_path):
    """`railexu run eu07_bogie --track straight_irregular` from a folder without input files."""
    out = tmp_path / "run"
    done = run_cli(
        ["run", "eu07_bogie", "--track", "straight_irregular", "--out", str(out), *SHORT_RUN],
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["vehicle"] == "EU07 bogie" or "bogie" in summary["vehicle"].lower()
    assert summary["track"]


def test_an_unknown_name_is_an_input_error_with_a_suggestion(tmp_path, capsys):
    assert main(["run", "eu7", "--out", str(tmp_path / "o"), *SHORT_RUN]) == EXIT_INPUT
    err = capsys.readouterr().err
    assert "Did you mean 'eu07'?" in err and "Traceback" not in err


def test_a_defect_shows_its_traceback_and_asks_for_a_report(monkeypatch, tmp_path, capsys):
    """Only InputError is bad input; anything else is a bug and must not hide as exit 2."""
    import railexu.cli.run as run_cmd

    def broken(args):
        raise ValueError("an internal inconsistency")

    monkeypatch.setattr(run_cmd, "command", broken)
    status = main(["run", "eu07", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert status == EXIT_BUG
    assert "Traceback" in err and "ValueError: an internal inconsistency" in err
    assert "Please report it" in err


def test_output_piped_into_head_gives_no_traceback():
    """`railexu list | head -1`: the reader goes away before railexu writes; no traceback."""
    proc = subprocess.Popen(
        [sys.executable, "-c", "import time; time.sleep(0.5)\n"
         "from railexu.cli import entry_point; import sys; sys.argv = ['railexu', 'list']\n"
         "entry_point()"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )  # fmt: skip
    proc.stdout.close()  # like `head` after its first line
    _, err = proc.communicate(timeout=120)
    assert b"Traceback" not in err and b"BrokenPipeError" not in err, err.decode()


def test_out_is_checked_before_the_run(tmp_path, capsys):
    a_file = tmp_path / "a_file"
    a_file.write_text("not a folder")
    for out in (a_file, a_file / "inside"):
        assert main(["run", "eu07", "--out", str(out), *SHORT_RUN]) == EXIT_INPUT
        err = capsys.readouterr().err
        assert "an output folder was expected" in err
        assert "status:" not in err  # nothing was simulated


def test_a_locked_folder_is_refused(tmp_path):
    first = OutputFolder(tmp_path / "out", "run").prepare()
    try:
        with pytest.raises(InputError, match="another railexu process is writing"):
            OutputFolder(tmp_path / "out", "run").prepare()
    finally:
        first.release()
    OutputFolder(tmp_path / "out", "run").prepare().release()  # free again


def test_a_new_run_removes_the_older_runs_figures(tmp_path):
    out = tmp_path / "out"
    assert main(["run", "wheelset", "--out", str(out), "--distance", "3", "--quiet",
                 "--plots", "png,svg"]) == 0  # fmt: skip
    assert sorted(p.suffix for p in out.glob("lateral_force.*")) == [".png", ".svg"]
    assert main(["run", "wheelset", "--out", str(out), "--distance", "3", "--quiet"]) == 0
    assert [p.suffix for p in out.glob("lateral_force.*")] == [".png"]  # the old SVG is gone
    manifest = json.loads((out / MANIFEST).read_text())
    assert manifest["kind"] == "run" and "summary.json" in manifest["files"]
    assert not list(out.glob(".*.tmp*"))  # no temporary files left


def test_a_folder_of_another_kind_of_output_is_refused(tmp_path, capsys):
    out = tmp_path / "study"
    out.mkdir()
    (out / "study.json").write_text("{}")
    (out / "results.csv").write_text("case_id\n")
    assert main(["run", "wheelset", "--out", str(out), *SHORT_RUN]) == EXIT_INPUT
    assert "holds the output of a study job" in capsys.readouterr().err


def test_the_front_door_exposes_the_public_functions():
    import railexu

    for name in ("load_vehicle", "load_track", "run", "contact_check", "critical_speed",
                 "run_study", "RunSettings", "RunResult", "TimeSeries", "InputError"):  # fmt: skip
        assert name in railexu.__all__
        assert getattr(railexu, name).__doc__, name
    vehicle = railexu.load_vehicle(ROOT / "vehicles" / "wheelset.yaml")
    result = railexu.run(vehicle, None, railexu.RunSettings(distance_m=2.0))
    assert result.status["state"] == "completed"
    assert isinstance(result.timeseries, railexu.TimeSeries)


def _python(code: str) -> subprocess.CompletedProcess:
    """``code`` run by a new Python process, which must end with status 0."""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


def test_importing_railexu_is_cheap():
    """`import railexu` loads neither Exudyn, numba nor matplotlib (the front door is lazy)."""
    code = (
        "import sys, railexu\n"
        "heavy = [m for m in ('exudyn', 'numba', 'matplotlib', 'scipy') if m in sys.modules]\n"
        "print(','.join(heavy))\n"
    )
    done = _python(code)
    assert done.stdout.strip() == ""


def test_the_command_line_answers_help_and_bad_names_before_the_numerical_libraries_load(
    tmp_path,
):
    """`railexu --help`, and `railexu run` with a vehicle that does not exist, answer without
    importing numpy, scipy, numba, Exudyn or matplotlib: the sub-commands import those when
    they work (a mistyped name is told in a tenth of a second, not half a second)."""
    code = (
        "import sys\n"
        "from railexu.cli import main\n"
        "heavy = ('numpy', 'scipy', 'numba', 'exudyn', 'matplotlib')\n"
        "print([m for m in heavy if m in sys.modules])\n"
        f"status = main(['run', 'nosuch_vehicle', '--out', {str(tmp_path / 'out')!r}])\n"
        "print(status, [m for m in heavy if m in sys.modules])\n"
    )
    done = _python(code)
    assert done.stdout.split("\n")[:2] == ["[]", f"{EXIT_INPUT} []"]
    assert "nosuch_vehicle" in done.stderr
    assert not (tmp_path / "out").exists()


def test_a_run_without_plots_does_not_import_matplotlib(tmp_path):
    """`railexu run --no-plots` (what a study's cases do) never pays matplotlib's import, nor
    the study layer's."""
    code = (
        "import sys\n"
        "from railexu.cli import main\n"
        f"main(['run', 'wheelset', '--distance', '1', '--no-plots', '--quiet', '--out', "
        f"{str(tmp_path / 'out')!r}])\n"
        "print('matplotlib' in sys.modules, 'railexu.study' in sys.modules)\n"
    )
    done = _python(code)
    assert done.stdout.strip().splitlines()[-1] == "False False"


def test_a_run_leaves_the_assessment_and_the_figures_to_its_warm_process(tmp_path):
    """`railexu run` with figures: the warm process started before the run imports scipy.signal
    and matplotlib while the run integrates, and assesses and draws (railexu.runtime.warm_process);
    the run's own process imports neither, and every file is there."""
    from railexu.runtime.warm_process import can_fork

    if not can_fork():
        pytest.skip("no warm process here: the run's process assesses and draws itself")
    out = tmp_path / "out"
    code = (
        "import sys\n"
        # the warm process starts and is waited for however busy the test machine is (issue
        # 26: a busy machine gets no helper, a starved one's work is done in the run's process)
        "import railexu.runtime.helpers as helpers\n"
        "helpers.MIN_CPU_SHARE = 0.0\n"
        "helpers.free_core = lambda *args, **kwargs: True\n"
        "from railexu.cli import main\n"
        f"main(['run', 'wheelset', '--distance', '2', '--quiet', '--out', {str(out)!r}])\n"
        "print('scipy.signal' in sys.modules, 'matplotlib' in sys.modules)\n"
    )
    done = _python(code)
    assert done.stdout.strip().splitlines()[-1] == "False False"
    assert "status: completed" in done.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert summary["hunting"] and summary["assessment"]["criteria"]
    assert {p.name for p in out.glob("*.png")} >= {"lateral_displacement.png", "wheel_load.png"}


def test_warnings_are_printed_on_the_console_too(tmp_path, capsys):
    """The declared axle load against masses and loads: in summary.json and on the console."""
    out = tmp_path / "out"
    status = main(["run", "wheelset", "--out", str(out), *SHORT_RUN,
                   "--set", "wheelsets.ws1.axle_load=150 kN"])  # fmt: skip
    assert status == 0
    err = capsys.readouterr().err
    assert "warning: wheelset ws1: declared axle load 150.0 kN" in err
    summary = json.loads((out / "summary.json").read_text())
    assert any("declared axle load 150.0 kN" in w for w in summary["warnings"])


def test_a_set_override_changes_the_value_it_names(tmp_path):
    """--set must reach the model: a heavier wheelset carries a larger wheel load."""
    loads = []
    for mass in ("4.25 t", "6.25 t"):
        out = tmp_path / mass.replace(" ", "")
        assert main(["run", "wheelset", "--out", str(out), *SHORT_RUN,
                     "--set", f"wheelsets.ws1.mass={mass}"]) == 0  # fmt: skip
        from railexu.results import TimeSeries

        ts = TimeSeries.from_csv(out / "timeseries.csv")
        loads.append(float(ts["ws1_left_Q_N"][0] + ts["ws1_right_Q_N"][0]))
    # 2 t more on the axle: 2000 kg x 9.81 m/s^2 = 19.6 kN more on the rails (statics)
    assert loads[1] - loads[0] == pytest.approx(2000.0 * 9.81, rel=0.01)


def test_python_dash_m_runs_the_command():
    done = subprocess.run(
        [sys.executable, "-m", "railexu.cli", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0 and done.stdout.startswith("railexu ")


def test_an_output_folder_named_like_the_vehicle_does_not_hide_it(tmp_path):
    """`railexu run wheelset --out wheelset` in an empty folder, twice (the second time the
    folder `wheelset` exists)."""
    for _ in range(2):
        done = run_cli(["run", "wheelset", "--out", "wheelset", *SHORT_RUN], cwd=tmp_path)
        assert done.returncode == 0, done.stderr
    assert (tmp_path / "wheelset" / "summary.json").is_file()


def test_a_run_that_exceeds_a_safety_limit_says_so_and_exits_1(tmp_path, capsys):
    """The EU07 bogie carrying 30 kN per spring seat (wheel load Q0 about 56 kN) pushed
    sideways by 75 kN applied suddenly: the sum of the guiding forces of a wheelset exceeds
    EN 14363's track-shifting limit alpha (10 kN + 2 Q0 / 3), about 47 kN. The run completes,
    but not cleanly: status completed_with_exceedances, exit code 1."""
    import yaml

    data = yaml.safe_load((ROOT / "vehicles" / "eu07_bogie.yaml").read_text())
    data["loads"]["car_body_share"]["force"] = [0, 0, "-30 kN"]
    for wheelset in data["wheelsets"].values():
        wheelset.pop("axle_load", None)
    data["loads"]["push"] = {
        "body": "bogie_1",
        "position": [0.0, 0.0, 0.75],
        "force": [0.0, "75 kN", 0.0],
        "static": False,
    }
    vehicle = tmp_path / "pushed.yaml"
    vehicle.write_text(yaml.safe_dump(data))
    out = tmp_path / "out"
    status = main(["run", str(vehicle), "--out", str(out), "--distance", "30", "--quiet",
                   "--plots", "none"])  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert status == 1
    assert summary["status"]["state"] == "completed_with_exceedances"
    assert "sum_y" in summary["status"]["reason"]
    assert summary["assessment"]["safety_exceeded"]
    sum_y = summary["assessment"]["criteria"]["sum_y"]
    assert sum_y["value"] > sum_y["limit"]
    assert "status: completed_with_exceedances" in capsys.readouterr().out


def test_console_script_skips_the_shutdown_collection_and_still_writes_everything(tmp_path):
    """The console script freezes the garbage collector before the interpreter's shutdown
    (whose cycle collections cost about 1 s after a run): the output is complete, the exit
    status kept, and the objects are frozen when the interpreter's exit handlers run."""
    code = (
        "import atexit, gc, sys\n"
        "atexit.register(lambda: print('frozen', gc.get_freeze_count() > 0, file=sys.stderr))\n"
        "from railexu.cli import entry_point\n"
        "entry_point()"
    )
    out = tmp_path / "o"
    proc = subprocess.run(
        [sys.executable, "-c", code, "run", "eu07", "--out", str(out), *SHORT_RUN],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "frozen True" in proc.stderr
    assert "status: completed" in proc.stdout and "wrote" in proc.stdout
    assert json.loads((out / "summary.json").read_text())["status"]["state"] == "completed"
