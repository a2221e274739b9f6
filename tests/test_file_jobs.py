"""railexu.report.file_jobs: a run's files written on two processes (or by the warm processes
started before the run) are all there, whichever process writes them, and a failing or dead
child leaves nothing missing."""

from __future__ import annotations

import os
import signal
import time
from functools import partial

import pytest

from railexu.report.file_jobs import FileJob, warm_up_figures, write_jobs
from railexu.runtime.helpers import CpuWatch, cpu_seconds
from railexu.runtime.warm_process import WarmProcess

#: a watch for which only a dead helper is starved
PATIENT = CpuWatch(min_share=0.0)


def _writer(path, fail_outside_pid=None):
    def write():
        if fail_outside_pid is not None and os.getpid() != fail_outside_pid:
            raise RuntimeError("fails in the child")
        path.write_text(str(os.getpid()))

    return write


@pytest.fixture
def patient(monkeypatch):
    """Wait for a helper however busy the machine is (only a dead helper counts as starved):
    the tests of who writes what must not depend on the test machine's load."""
    from railexu.runtime import helpers

    monkeypatch.setattr(helpers, "MIN_CPU_SHARE", 0.0)


def _spin_until(path, limit_s=60.0):
    """Busy-wait (a helper that waits like this still progresses) until ``path`` exists."""
    end = time.monotonic() + limit_s
    while not path.exists() and time.monotonic() < end:
        pass


def _waiting_writer(path, wait_for):
    def write():
        _spin_until(wait_for)
        path.write_text(str(os.getpid()))

    return write


@pytest.mark.parametrize("processes", [1, 2])
def test_every_job_writes_its_file(tmp_path, processes, request):
    if processes == 2:
        request.getfixturevalue("forking")  # tests/conftest.py
        request.getfixturevalue("patient")
    paths = [tmp_path / f"f{i}.txt" for i in range(5)]
    jobs = [FileJob(p.name, _writer(p)) for p in paths[1:]]
    # the costliest job, taken first by one process, waits for a file that another process
    # writes meanwhile: both processes write some of the files
    jobs.append(FileJob(paths[0].name, _waiting_writer(paths[0], paths[1]), cost=2.0))
    write_jobs(jobs, processes=processes)
    writers = {p.read_text() for p in paths}
    assert all(p.exists() for p in paths)
    if processes == 2:
        assert len(writers) == 2 and str(os.getpid()) in writers


def test_the_switch_writes_everything_here(tmp_path, forking, monkeypatch):
    monkeypatch.setenv("RAILEXU_HELPER_PROCESSES", "0")
    paths = [tmp_path / f"f{i}.txt" for i in range(4)]
    write_jobs([FileJob(p.name, _writer(p)) for p in paths])
    assert {p.read_text() for p in paths} == {str(os.getpid())}


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

    def __init__(self, path, fail_outside_pid=None, wait_for=None, stop_outside_pid=None):
        self.path = path
        self.fail_outside_pid = fail_outside_pid
        self.wait_for = wait_for
        self.stop_outside_pid = stop_outside_pid

    def __call__(self):
        if self.fail_outside_pid is not None and os.getpid() != self.fail_outside_pid:
            raise RuntimeError("fails in the warm process")
        if self.stop_outside_pid is not None and os.getpid() != self.stop_outside_pid:
            os.kill(os.getpid(), signal.SIGSTOP)  # a helper the machine gives no processor time
        if self.wait_for is not None:
            _spin_until(self.wait_for)
        self.path.write_text(str(os.getpid()))


class _Failing:
    def __call__(self):
        raise ValueError("bad figure")


def _portable_jobs(paths, **kw):
    return [FileJob(p.name, _PortableWriter(p, **kw), portable=True) for p in paths]


def test_the_warm_process_and_its_fork_write_the_portable_jobs(tmp_path, forking):
    portable = [tmp_path / f"fig{i}.png" for i in range(4)]
    local = tmp_path / "timeseries.csv"
    # this process's own job lasts until the helpers have drawn every figure; the costliest
    # figure waits for another one, drawn meanwhile by the other helper
    jobs = [FileJob(p.name, _PortableWriter(p), portable=True) for p in portable[1:]]
    jobs.append(FileJob(portable[0].name, _PortableWriter(portable[0], wait_for=portable[1]),
                        cost=2.0, portable=True))  # fmt: skip
    jobs.append(FileJob("csv", _waiting_writer(local, portable[3])))
    with WarmProcess(warm_up=partial(warm_up_figures, ("png",)), watch=PATIENT) as warm:
        write_jobs(jobs, warm=warm)
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


def _wait_until_stopped(pid, limit_s=60.0):
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        with open(f"/proc/{pid}/stat") as fh:
            if fh.read().rsplit(")", 1)[1].split()[0] == "T":
                return
        time.sleep(0.01)


def test_a_starved_helper_is_not_waited_for(tmp_path, forking):
    """A helper that gets no processor time in the middle of a job (here it stops itself, as a
    busy machine's scheduler would leave it) is not waited for: after one window of the watch
    this process writes its job and every job left, the helpers are killed, and the caller is
    told their ids (to remove their temporary files)."""
    paths = [tmp_path / f"fig{i}.png" for i in range(3)]
    me = os.getpid()
    jobs = [FileJob(p.name, _PortableWriter(p, stop_outside_pid=me), portable=True) for p in paths]
    told = []
    watch = CpuWatch(window_s=0.2, min_share=0.2)
    with WarmProcess(watch=watch) as warm:
        warm_pid = warm.pid
        # this process's own job lasts until the warm process has begun a figure and stopped
        jobs.append(FileJob("csv", partial(_wait_until_stopped, warm_pid)))
        write_jobs(jobs, warm=warm, abandoned=told.extend)
        assert not warm.ready  # ended
    assert all(p.read_text() == str(me) for p in paths)
    assert warm_pid in told
    assert all(cpu_seconds(pid) is None for pid in told)  # none is left running


def test_without_a_warm_process_the_portable_jobs_are_written_as_before(tmp_path):
    paths = [tmp_path / f"fig{i}.png" for i in range(2)]
    warm = WarmProcess(start=False)
    assert not warm.ready
    write_jobs(_portable_jobs(paths), processes=1, warm=warm)
    assert all(p.read_text() == str(os.getpid()) for p in paths)


def test_a_starved_fork_is_not_waited_for(tmp_path, forking):
    """Without a warm process (``railexu.write_run`` from a script) the same: a forked writer
    that gets no processor time in the middle of a job is killed and its jobs written here."""
    paths = [tmp_path / f"f{i}.txt" for i in range(4)]
    me = os.getpid()
    # the fork stops at the first job it takes
    jobs = [FileJob(p.name, _PortableWriter(p, stop_outside_pid=me)) for p in paths]
    told = []
    write_jobs(jobs, processes=2, abandoned=told.extend)
    assert all(p.read_text() == str(me) for p in paths)
    assert all(cpu_seconds(pid) is None for pid in told)  # killed and reaped
