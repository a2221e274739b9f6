"""railexu.report.file_jobs: a run's files written on two processes (or by the warm processes
started before the run) are all there, whichever process writes them, and a failing or dead
child leaves nothing missing."""

from __future__ import annotations

import os
import signal
import time

import pytest

from railexu.report.file_jobs import FileJob, WarmWriters, _split, can_fork, write_jobs


def _writer(path, fail_outside_pid=None):
    def write():
        if fail_outside_pid is not None and os.getpid() != fail_outside_pid:
            raise RuntimeError("fails in the child")
        path.write_text(str(os.getpid()))

    return write


def test_the_split_balances_the_costs():
    jobs = [FileJob(str(i), lambda: None, c) for i, c in enumerate([1.4, 1.2, 1.0, 1.0, 0.7, 0.4])]
    here, there = _split(jobs)
    assert sorted(j.name for j in here + there) == [str(i) for i in range(6)]
    load_here = sum(j.cost for j in here)
    load_there = sum(j.cost for j in there)
    # greedy largest-first: the two loads differ by at most the smallest job
    assert abs(load_here - load_there) <= 0.4 + 1e-12


@pytest.mark.parametrize("processes", [1, 2])
def test_every_job_writes_its_file(tmp_path, processes):
    if processes == 2 and not can_fork():
        pytest.skip("no fork here")
    paths = [tmp_path / f"f{i}.txt" for i in range(5)]
    write_jobs([FileJob(p.name, _writer(p)) for p in paths], processes=processes)
    writers = {p.read_text() for p in paths}
    assert all(p.exists() for p in paths)
    if processes == 2:  # both processes wrote some of them
        assert len(writers) == 2 and str(os.getpid()) in writers


def test_a_failing_child_leaves_nothing_missing(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    paths = [tmp_path / f"f{i}.txt" for i in range(4)]
    me = os.getpid()
    write_jobs([FileJob(p.name, _writer(p, fail_outside_pid=me)) for p in paths], processes=2)
    # the child's jobs failed there and were written again here
    assert all(p.read_text() == str(me) for p in paths)


def test_an_error_here_is_raised(tmp_path):
    def fail():
        raise ValueError("bad figure")

    with pytest.raises(ValueError, match="bad figure"):
        write_jobs([FileJob("a", fail), FileJob("b", _writer(tmp_path / "b"))], processes=1)


# --- WarmWriters: a process forked before the run that draws the figures when they are due ---


class _PortableWriter:
    """A picklable job body: writes the pid of the process that runs it (fails outside
    ``fail_outside_pid`` when given)."""

    def __init__(self, path, fail_outside_pid=None):
        self.path = path
        self.fail_outside_pid = fail_outside_pid

    def __call__(self):
        if self.fail_outside_pid is not None and os.getpid() != self.fail_outside_pid:
            raise RuntimeError("fails in the warm process")
        self.path.write_text(str(os.getpid()))


def _portable_jobs(paths, **kw):
    return [FileJob(p.name, _PortableWriter(p, **kw), portable=True) for p in paths]


def test_warm_writers_write_the_portable_jobs_in_two_other_processes(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    portable = [tmp_path / f"fig{i}.png" for i in range(4)]
    local = tmp_path / "timeseries.csv"
    with WarmWriters(2) as writers:
        assert writers.ready
        write_jobs(_portable_jobs(portable) + [FileJob("csv", _writer(local))], writers=writers)
        assert not writers.ready  # the warm process ended with the writing
    me = str(os.getpid())
    assert local.read_text() == me  # a job that is not portable stays in this process
    drawn_by = {p.read_text() for p in portable}
    assert len(drawn_by) == 2 and me not in drawn_by  # the warm process and its fork


def test_jobs_that_fail_in_the_warm_process_are_written_here(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    paths = [tmp_path / f"fig{i}.png" for i in range(3)]
    me = os.getpid()
    with WarmWriters(2) as writers:
        write_jobs(_portable_jobs(paths, fail_outside_pid=me), writers=writers)
    assert all(p.read_text() == str(me) for p in paths)


def test_a_warm_process_that_died_leaves_nothing_missing(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    paths = [tmp_path / f"fig{i}.png" for i in range(3)]
    with WarmWriters(2) as writers:
        writers._worker.kill()
        writers._worker.join()
        write_jobs(_portable_jobs(paths), writers=writers)
    assert all(p.read_text() == str(os.getpid()) for p in paths)


def test_jobs_that_cannot_be_pickled_are_written_here(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    path = tmp_path / "fig.png"
    job = FileJob("fig", _writer(path), portable=True)  # a closure: not picklable
    with WarmWriters(2) as writers:
        write_jobs([job], writers=writers)
    assert path.read_text() == str(os.getpid())


def test_an_error_in_a_portable_job_is_raised_here(tmp_path):
    if not can_fork():
        pytest.skip("no fork here")
    job = FileJob("bad", _Failing(), portable=True)
    with WarmWriters(2) as writers, pytest.raises(ValueError, match="bad figure"):
        write_jobs([job], writers=writers)


class _Failing:
    def __call__(self):
        raise ValueError("bad figure")


def test_a_warm_process_ignores_ctrl_c_and_ends_with_close():
    if not can_fork():
        pytest.skip("no fork here")
    writers = WarmWriters(2)
    worker = writers._worker
    time.sleep(0.5)  # let it install its handlers
    os.kill(worker.pid, signal.SIGINT)  # Ctrl-C reaches the whole process group
    time.sleep(0.2)
    assert worker.is_alive()
    writers.close()  # a run that ended without files: the process ends at once
    assert not worker.is_alive()
    assert not writers.ready


def test_no_warm_process_when_none_is_asked_for(tmp_path):
    writers = WarmWriters(0)
    assert not writers.ready
    path = tmp_path / "fig.png"
    write_jobs(_portable_jobs([path]), processes=1, writers=writers)
    assert path.read_text() == str(os.getpid())
