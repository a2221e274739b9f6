"""The wheelsets' contacts on threads (railexu.runtime.threads): the same results to the last bit,
and threads only where the policy allows them."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from railexu.errors import InputError
from railexu.model.assembly import VehicleModel
from railexu.model.forces import generalized_forces, generalized_forces_threaded
from railexu.results.run import RunSettings, run
from railexu.runtime import threads
from railexu.track.track import ideal_straight_track, load_track, track_from_dict
from railexu.vehicle.vehicle import load_vehicle

ROOT = Path(__file__).resolve().parents[1]

ELASTIC = {
    "format_version": 1,
    "name": "elastic straight",
    "geometry": {"type": "sections", "sections": [{"type": "straight", "length": "200 m"}]},
    "track_model": {"type": "elastic"},
}


def _expected_threads(n_wheelsets: int) -> int:
    """What the policy gives in this process, from the facts it depends on."""
    import numba

    if threads.contact_threads(n_wheelsets) == 1:
        return 1  # no OpenMP or TBB here, one core, or RAILEXU_THREADS=1
    cap = threads.requested_threads() or n_wheelsets
    return min(n_wheelsets, threads.usable_cores(), cap, numba.config.NUMBA_NUM_THREADS)


@pytest.mark.parametrize(
    "vehicle, track",
    [
        ("eu07.yaml", lambda: load_track(ROOT / "tracks" / "straight_irregular.yaml")),
        ("eu07.yaml", lambda: load_track(ROOT / "tracks" / "curve_r300.yaml")),
        ("eu07_bogie.yaml", lambda: track_from_dict(ELASTIC)),
    ],
    ids=["straight irregular", "curve R300", "elastic track"],
)
def test_threaded_forces_equal_the_serial_ones_to_the_last_bit(vehicle, track):
    """Each wheelset's contact writes only its own rows and the sums are made in the
    wheelsets' order, so the generalized forces, contact points and wheelset forces are
    identical (not merely close) on states near the rail and in flange contact."""
    model = VehicleModel(load_vehicle(ROOT / "vehicles" / vehicle), track(), 20.0, 0.0, 100.0)
    model.warm_up()
    if threads.contact_threads(model.points.shape[0]) > 1:
        threads.use_threads(min(2, threads.usable_cores()))
    rng = np.random.default_rng(11)
    n = model._out.size
    data = model.kernel
    arrays = [(np.zeros(n), np.zeros_like(model.points), np.zeros_like(model.ws_force))
              for _ in range(2)]  # fmt: skip
    for scale in (1e-4, 2e-3, 8e-3):  # near the centre, on the tread, up the flange [m]
        for _ in range(40):
            q = rng.normal(0.0, scale, n)
            qt = rng.normal(0.0, 10.0 * scale, n)
            generalized_forces(q, qt, data, *arrays[0])
            generalized_forces_threaded(q, qt, data, *arrays[1])
            for serial, threaded in zip(*arrays, strict=True):
                assert np.array_equal(serial, threaded)
            assert np.any(arrays[0][0] != 0.0)


def test_a_run_on_threads_gives_the_serial_time_series(monkeypatch):
    """The EU07 over 8 m from a 2 mm offset: every column identical with threads from the start,
    threads from the middle of the run (as ``railexu run`` starts them once its warm process has
    done its imports) and without threads; the summary says how many threads the contacts used
    and from when."""
    from railexu.simulation.simulate import simulate

    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    settings = RunSettings(speed_m_per_s=20.0, distance_m=8.0, initial_lateral_m=0.002)
    expected = _expected_threads(4)
    threaded = run(vehicle, ideal_straight_track(), settings)
    assert threaded.summary["solver"]["contact_threads"] == expected
    asked = []

    def halfway() -> bool:
        asked.append(True)
        return len(asked) > 40  # asked at every output time: from the 41st on

    later = simulate(vehicle, ideal_straight_track(), settings, None, halfway)
    if expected > 1:
        assert later.summary["solver"]["contact_threads"] == expected
        from_s = later.summary["solver"]["contact_threads_from_s"]
        assert from_s == later.timeseries["time_s"][40] and 0.0 < from_s < 0.4
        assert threaded.summary["solver"]["contact_threads_from_s"] == 0.0
    monkeypatch.setenv(threads.ENV, "1")
    serial = run(vehicle, ideal_straight_track(), settings)
    assert serial.summary["solver"]["contact_threads"] == 1
    assert serial.summary["solver"]["contact_threads_from_s"] is None
    assert list(serial.timeseries.columns) == list(threaded.timeseries.columns)
    for name, column in serial.timeseries.columns.items():
        assert np.array_equal(column, threaded.timeseries[name]), name
        assert np.array_equal(column, later.timeseries[name]), name


def test_the_policy(monkeypatch):
    monkeypatch.delenv(threads.ENV, raising=False)
    monkeypatch.setattr(threads, "_start_threadsafe_layer", lambda: 16)  # numba's own cap
    monkeypatch.setattr(threads, "usable_cores", lambda: 8)
    assert threads.contact_threads(1) == 1  # one wheelset: nothing to share
    assert threads.contact_threads(4) == 4  # one per wheelset
    assert threads.contact_threads(12) == 8  # no more than the cores
    monkeypatch.setenv(threads.ENV, "3")
    assert threads.contact_threads(4) == 3
    monkeypatch.setenv(threads.ENV, "1")
    assert threads.contact_threads(4) == 1
    monkeypatch.delenv(threads.ENV)
    monkeypatch.setattr(threads, "usable_cores", lambda: 1)
    assert threads.contact_threads(4) == 1
    monkeypatch.setattr(threads, "usable_cores", lambda: 8)
    monkeypatch.setattr(threads, "_start_threadsafe_layer", lambda: 0)
    assert threads.contact_threads(4) == 1  # only numba's workqueue: slower than one thread
    monkeypatch.setattr(threads, "_start_threadsafe_layer", lambda: 2)
    assert threads.contact_threads(4) == 2  # NUMBA_NUM_THREADS=2
    monkeypatch.setattr(threads, "_serial", True)
    assert threads.contact_threads(4) == 1  # a study's worker, a forked child


@pytest.mark.parametrize("value", ["0", "-2", "two", "1.5"])
def test_a_bad_thread_count_names_the_variable(monkeypatch, value):
    monkeypatch.setenv(threads.ENV, value)
    with pytest.raises(InputError, match=rf"{threads.ENV}=.*whole number of threads"):
        threads.requested_threads()


def test_a_studys_workers_run_the_contacts_on_one_thread(tmp_path):
    """Two worker processes already fill two cores; the EU07 bogie's two wheelsets stay on one
    thread there, and in this process (``workers=0``) they may use threads."""
    from railexu.study import run_study

    study = tmp_path / "study.yaml"
    study.write_text(
        textwrap.dedent(f"""\
        format_version: 1
        name: threads
        base:
          vehicle: {ROOT / "vehicles" / "eu07_bogie.yaml"}
          run: {{distance: 2 m, initial_lateral: 2 mm}}
        vary:
          parameters:
            run.speed: [8 m/s, 12 m/s]
        collect: [solver.contact_threads]
        """)
    )
    workers = run_study(study, tmp_path / "workers", workers=2)
    inline = run_study(study, tmp_path / "inline", workers=0)
    assert [r["solver.contact_threads"] for r in workers.rows] == ["1", "1"]
    expected = str(_expected_threads(2))
    assert [r["solver.contact_threads"] for r in inline.rows] == [expected, expected]


def test_forked_children_never_start_threads(forking, monkeypatch):
    """GNU OpenMP cannot start its threads in a process forked from one where they ran: the
    warm process (and the figure writer, forked the same way) are serial from their start."""
    from railexu.runtime.warm_process import WarmProcess

    monkeypatch.setattr(threads, "_start_threadsafe_layer", lambda: 8)
    monkeypatch.setattr(threads, "usable_cores", lambda: 8)
    assert threads.contact_threads(4) == 4  # here
    with WarmProcess() as warm:
        assert warm.ready
        assert warm.call(threads.contact_threads, 4) == 1  # there


def test_the_command_runs_blas_on_one_thread_unless_told_otherwise():
    """``railexu.cli`` sets ``OPENBLAS_NUM_THREADS=1`` before numpy loads
    (:mod:`railexu.runtime.blas_threads`: OpenBLAS's idle threads busy-wait on the cores the
    contacts' threads need; railexu's matrices are small), so the process has no BLAS threads; a
    value the user set is kept."""
    import os
    import subprocess
    import sys

    code = (
        "import os, railexu.cli, numpy, scipy.linalg\n"
        "print(os.environ['OPENBLAS_NUM_THREADS'], len(os.listdir('/proc/self/task')))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True).stdout.split()  # fmt: skip
    assert out == ["1", "1"]  # the variable, and no thread beside the main one
    env["OPENBLAS_NUM_THREADS"] = "2"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True).stdout.split()  # fmt: skip
    assert out[0] == "2"
