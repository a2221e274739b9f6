"""railexu.report.file_jobs: a run's files written on two processes (or by the warm processes
started before the run) are all there, whichever process writes them, and a failing or dead
child leaves nothing missing."""

from __future__ import annotations

import os
from functools import partial

import pytest

from railexu.report.file_jobs import FileJob, _split, warm_up_figures, write_jobs
from railexu.runtime.warm_process import WarmProcess


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
def test_every_job_writes_its_file(tmp_path, processes, request):
    if processes == 2:
        request.getfixturevalue("forking")  # tests/conftest.py
    paths = [tmp_path / f"f{i}.txt" for i in range(5)]
    write_jobs([FileJob(p.name, _writer(p)) for p in paths], processes=processes)
    writers = {p.read_text() for p in paths}
    assert all(p.exists() for p in paths)
    if processes == 2:  # both processes wrote some of them
        assert len(writers) == 2 and str(os.getpid()) in writers


def test_a_failing_child_leaves_nothing_missing(tmp_path, forking):
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


# --- with a warm process started before the run (railexu run) ---


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


class _Failing:
    def __call__(self):
        raise ValueError("bad figure")


def _portable_jobs(paths, **kw):
    return [FileJob(p.name, _PortableWriter(p, **kw), portable=True) for p in paths]


def test_the_warm_process_and_its_fork_write_the_portable_jobs(tmp_path, forking):
    portable = [tmp_path / f"fig{i}.png" for i in range(4)]
    local = tmp_path / "timeseries.csv"
    with WarmProcess(warm_up=partial(warm_up_figures, ("png",))) as warm:
        write_jobs(_portable_jobs(portable) + [FileJob("csv", _writer(local))], warm=warm)
        assert warm.ready  # it stays for more work until closed
    me = str(os.getpid())
    assert local.read_text() == me  # a job that is not portable stays in this process
    drawn_by = {p.read_text() for p in portable}
    assert len(drawn_by) == 2 and me not in drawn_by  # the warm process and its fork


def test_jobs_that_fail_in_the_warm_process_are_written_here(tmp_path, forking):
    paths = [tmp_path / f"fig{i}.png" for i in range(3)]
    me = os.getpid()
    with WarmProcess() as warm:
        write_jobs(_portable_jobs(paths, fail_outside_pid=me), warm=warm)
    assert all(p.read_text() == str(me) for p in paths)


def test_a_dead_warm_process_leaves_nothing_missing(tmp_path, forking):
    paths = [tmp_path / f"fig{i}.png" for i in range(3)]
    with WarmProcess() as warm:
        warm._worker.kill()
        warm._worker.join()
        write_jobs(_portable_jobs(paths), warm=warm)
    assert all(p.read_text() == str(os.getpid()) for p in paths)


def test_an_error_in_a_portable_job_is_raised_here(forking):
    with WarmProcess() as warm, pytest.raises(ValueError, match="bad figure"):
        write_jobs([FileJob("bad", _Failing(), portable=True)], warm=warm)


def test_without_a_warm_process_the_portable_jobs_are_written_as_before(tmp_path):
    paths = [tmp_path / f"fig{i}.png" for i in range(2)]
    warm = WarmProcess(start=False)
    assert not warm.ready
    write_jobs(_portable_jobs(paths), processes=1, warm=warm)
    assert all(p.read_text() == str(os.getpid()) for p in paths)
