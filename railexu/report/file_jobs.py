"""Write a run's output files on two processor cores.

A run's figures cost more than its integration's last seconds: six figures take some 3 s of one
core, while the second core of a laptop or a CI machine sits idle (the integration is serial).
:func:`write_jobs` splits the writing of independent files (each figure, the time series, the
state file) between this process and one forked child, so the folder is complete in about half
the time. Each job writes its own files under temporary names and renames them into place
(:func:`railexu.report.folder.atomic_path`), so the two processes never write the same file.

The child exists only where it is safe and useful: a platform with ``fork`` (Linux; macOS's and
Windows' default start methods would re-import everything), more than one core, no other Python
thread running (forking a threaded process can deadlock) and not inside a daemonic worker process
(a study's process pool, which may not have children). Anywhere else, and whenever the child
fails, this process writes everything itself: the files are the same either way.
"""

from __future__ import annotations

import multiprocessing
import os
import sys
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class FileJob:
    """One independent piece of output: ``write()`` writes it; ``cost`` is its relative time
    (only its ratio to the other jobs' costs matters: it balances the two processes)."""

    name: str
    write: Callable[[], None]
    cost: float = 1.0


def write_jobs(jobs: Sequence[FileJob], processes: int | None = None) -> None:
    """Run every job, on up to two processes (see the module's notes).

    Args:
        jobs: the jobs; each must write only its own files.
        processes: 1 to write everything here; None for two where :func:`can_fork` allows it.

    Raises:
        Exception: whatever a job raises when this process runs it.
    """
    if processes is None:
        processes = 2 if can_fork() else 1
    if processes < 2 or len(jobs) < 2:
        for job in jobs:
            job.write()
        return
    here, there = _split(jobs)
    child = _start_child(there)
    if child is None:  # the fork itself failed: write everything here
        here = list(jobs)
    try:
        for job in here:
            job.write()
    finally:
        if child is not None:
            child.join()
    if child is not None and child.exitcode != 0:
        # the child's files are not all there: write them here
        for job in there:
            job.write()


def can_fork() -> bool:
    """True where a forked child may write files alongside this process (see the module's
    notes)."""
    if "fork" not in multiprocessing.get_all_start_methods():
        return False
    if (os.cpu_count() or 1) < 2 or sys.platform != "linux":
        return False
    return threading.active_count() == 1 and not multiprocessing.current_process().daemon


def _split(jobs: Sequence[FileJob]) -> tuple[list[FileJob], list[FileJob]]:
    """Greedy balance: the costliest job first, each to the process with less work so far."""
    here: list[FileJob] = []
    there: list[FileJob] = []
    load = [0.0, 0.0]
    for job in sorted(jobs, key=lambda j: -j.cost):
        side = 0 if load[0] <= load[1] else 1
        (here if side == 0 else there).append(job)
        load[side] += job.cost
    return here, there


def _start_child(jobs: list[FileJob]) -> multiprocessing.process.BaseProcess | None:
    # what is buffered now would otherwise be written twice (by the child at its exit too)
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        child = multiprocessing.get_context("fork").Process(
            target=_run_in_child, args=(jobs,), daemon=True
        )
        child.start()
    except OSError:
        return None
    return child


def _run_in_child(jobs: list[FileJob]) -> None:
    # the child's only job is its files: an error ends it with a non-zero exit code (the
    # parent then writes them), without a second traceback on the console
    try:
        for job in jobs:
            job.write()
    except BaseException:
        os._exit(1)
