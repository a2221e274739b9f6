"""The ``railexu run`` and ``railexu plot`` commands end to end."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from railexu.cli import main
from railexu.results import TimeSeries

ROOT = Path(__file__).resolve().parents[1]


def test_run_writes_timeseries_summary_and_plots(tmp_path, capsys):
    out = tmp_path / "run"
    status = main(
        [
            "run", str(ROOT / "vehicles" / "eu07_bogie.yaml"), "--track",
            str(ROOT / "tracks" / "straight.yaml"), "--speed", "10", "--distance", "20",
            "--initial-lateral", "0.002", "--out", str(out), "--quiet",
        ]
    )  # fmt: skip
    assert status == 0
    printed = capsys.readouterr().out
    assert "status: completed at 20.0 m" in printed and "real-time factor" in printed
    ts = TimeSeries.from_csv(out / "timeseries.csv")
    for col in [
        "time_s",
        "distance_m",
        "ws1_lateral_m",
        "ws1_yaw_rad",
        "ws1_left_Y_N",
        "ws1_left_Q_N",
        "ws1_left_n_contacts",
        "ws2_right_Y_N",
        "ws2_right_Q_N",
        "ws2_right_n_contacts",
        "bogie_1_lateral_m",
    ]:
        assert col in ts.columns, col
    assert ts.distance_m[-1] == 20.0
    assert ts["ws1_lateral_m"][0] == 0.002
    summary = json.loads((out / "summary.json").read_text())
    for key in [
        "status",
        "realtime_factor",
        "wheelsets",
        "flange_contact",
        "max_abs_lateral_force_N",
        "max_Y_over_Q",
        "max_sum_Y_N",
        "hunting",
    ]:
        assert key in summary, key
    assert summary["status"]["state"] == "completed"
    assert summary["realtime_factor"] > 0
    assert [w["name"] for w in summary["wheelsets"]] == ["ws1", "ws2"]
    # Nadal's limit for the S1002 flange (70 deg) and mu = 0.3
    tan70 = np.tan(np.radians(70.0))
    nadal = (tan70 - 0.3) / (1 + 0.3 * tan70)
    assert abs(summary["max_Y_over_Q"]["nadal_limit"] - nadal) < 1e-3
    pngs = {p.name for p in out.glob("*.png")}
    assert pngs == {
        "accelerations.png",  # at the car body's (here: the bogie frame's) measurement points
        "lateral_displacement.png",
        "lateral_force.png",
        "y_over_q.png",
        "wheel_load.png",
        "sum_y.png",
    }
    # redraw from the files
    for p in out.glob("*.png"):
        p.unlink()
    assert main(["plot", str(out)]) == 0
    assert {p.name for p in out.glob("*.png")} == pngs
    assert not list(out.glob("*.svg"))  # PNG unless asked
    assert main(["plot", str(out), "--plots", "png,svg"]) == 0
    assert {p.name for p in out.glob("*.svg")} == {n.replace(".png", ".svg") for n in pngs}
    # the redrawn figures are in the folder's list: the next run into it replaces them
    manifest = json.loads((out / ".railexu-files.json").read_text())
    assert {n.replace(".png", ".svg") for n in pngs} <= set(manifest["files"])


def test_run_with_set_override(tmp_path, capsys):
    out = tmp_path / "run"
    status = main(
        [
            "run", str(ROOT / "vehicles" / "wheelset.yaml"), "--distance", "5", "--out",
            str(out), "--quiet", "--no-plots", "--set", "wheelsets.ws1.mass=4.5 t",
        ]
    )  # fmt: skip
    assert status == 0
    assert not list(out.glob("*.png"))


def test_run_bad_input(tmp_path, capsys):
    status = main(
        [
            "run", str(ROOT / "vehicles" / "eu07.yaml"), "--out", str(tmp_path), "--quiet",
            "--set", "bodies.car_body.mas=3 t",
        ]
    )  # fmt: skip
    assert status == 2
    err = capsys.readouterr().err
    assert "eu07.yaml:" in err and "Did you mean 'mass'" in err
    assert main(["run", str(ROOT / "vehicles" / "eu07.yaml"), "--speed", "-3", "--out",
                 str(tmp_path), "--quiet"]) == 2  # fmt: skip
    assert "speed must be > 0" in capsys.readouterr().err


def test_plot_on_a_folder_without_results(tmp_path, capsys):
    assert main(["plot", str(tmp_path)]) == 2
    assert "no timeseries.csv" in capsys.readouterr().err


def test_ctrl_c_during_a_run_keeps_its_results_and_figures(tmp_path):
    """Ctrl-C at a terminal reaches the run's whole process group, the warm process that draws
    the figures included: the run stops as interrupted and still writes every file."""
    import re
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "run"
    code = (
        "import signal, sys\n"
        # an interactive process's Ctrl-C, also when the tests run in a shell's background job
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "from railexu.cli import entry_point\n"
        f"sys.argv = ['railexu', 'run', {str(ROOT / 'vehicles' / 'wheelset.yaml')!r}, "
        f"'--distance', '1000', '--out', {str(out)!r}]\n"
        "entry_point()\n"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", code], stderr=subprocess.PIPE, stdout=subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    progress = b""
    deadline = time.monotonic() + 300.0
    while time.monotonic() < deadline:
        chunk = proc.stderr.read1(4096)
        if not chunk:
            break
        progress += chunk
        done = [float(m) for m in re.findall(rb"(\d+\.\d) / 1000\.0 m", progress)]
        if done and done[-1] > 5.0:
            os.killpg(proc.pid, signal.SIGINT)
            break
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 1, (progress + stderr).decode()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"]["state"] == "interrupted"
    assert 5.0 < summary["status"]["distance_m"] < 1000.0
    for name in ("timeseries.csv", "state.npz", "lateral_displacement.png", "wheel_load.png"):
        assert (out / name).stat().st_size > 0, name
    assert not list(out.glob(".*.tmp*"))  # no file left half-written


def test_the_console_script_pauses_garbage_collection_only_for_the_start_up(tmp_path):
    """The console script (railexu.console) pauses the cyclic garbage collector before the
    first import (its collections over the growing heap cost about 0.4 s of a run); ``railexu
    run`` resumes it, with the start-up's objects frozen, before the run is built. The run
    completes and writes its files."""
    import subprocess
    import sys

    out = tmp_path / "run"
    code = (
        "import gc, sys\n"
        "import railexu.results.run as runs\n"
        "seen = {}\n"
        "real_run = runs.run\n"
        "def spy(*args, **kwargs):\n"
        "    seen.update(enabled=gc.isenabled(), frozen=gc.get_freeze_count())\n"
        "    return real_run(*args, **kwargs)\n"
        "runs.run = spy\n"
        "from railexu import console\n"
        f"sys.argv = ['railexu', 'run', 'wheelset', '--distance', '2', '--no-plots', "
        f"'--quiet', '--out', {str(out)!r}]\n"
        "gc_before = gc.isenabled()\n"
        "try:\n"
        "    console.entry_point()\n"
        "except SystemExit as exc:\n"
        "    print(gc_before, seen['enabled'], seen['frozen'] > 10000, exc.code)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split()[-4:] == ["True", "True", "True", "0"], proc.stdout + proc.stderr
    assert (out / "summary.json").exists()


def test_main_called_from_python_leaves_garbage_collection_alone(tmp_path, capsys):
    """Only the console script pauses the collector: ``main()`` from a script or a notebook
    neither freezes nor disables it."""
    import gc

    frozen = gc.get_freeze_count()
    assert main(["list"]) == 0
    assert gc.isenabled()
    assert gc.get_freeze_count() == frozen
