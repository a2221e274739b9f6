"""railexu.report.file_jobs: a run's files written on two processes are all there, whichever
process writes them, and a failing child leaves nothing missing."""

from __future__ import annotations

import os

import pytest

from railexu.report.file_jobs import FileJob, _split, can_fork, write_jobs


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
