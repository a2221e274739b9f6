"""Write a run's output files on two processor cores.

A run's figures cost more than its integration's last seconds: six figures take some 3.5 s of one
core, and importing matplotlib another 0.5 s, while the second core of a laptop or a CI machine
sits idle (the integration is serial). Two ways use it:

- :func:`write_jobs` splits the writing of independent files (each figure, the time series, the
  state file) between this process and one child forked when the run is over, so the folder is
  complete in about half the time (``railexu.write_run`` called from a script);
- :class:`WarmWriters`, started *before* the integration (``railexu run``), forks two processes
  that import matplotlib and the figure modules and draw a first small figure (fonts, renderer)
  on the idle core while the run integrates. When it is over they draw the figures, each job
  carrying its own data (the time series and the summary, pickled once per process), while this
  process writes the time series and the state file.

Each job writes its own files under temporary names and renames them into place
(:func:`railexu.report.folder.atomic_path`), so two processes never write the same file, and a job
another process did not finish (it failed, or the process died) is written here afterwards: the
files are the same whichever process writes them.

Children exist only where it is safe and useful: a platform with ``fork`` (Linux; macOS's and
Windows' default start methods would re-import everything), more than one core, no other Python
thread running (forking a threaded process can deadlock) and not inside a daemonic worker process
(a study's process pool, which may not have children). Anywhere else this process writes
everything itself.
"""

from __future__ import annotations

import contextlib
import io
import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class FileJob:
    """One independent piece of output: ``write()`` writes it; ``cost`` is its relative time
    (only its ratio to the other jobs' costs matters: it balances the processes); ``portable``:
    ``write`` can be pickled and run by a :class:`WarmWriters` process (it carries its data, not
    the Exudyn model)."""

    name: str
    write: Callable[[], None]
    cost: float = 1.0
    portable: bool = False


def write_jobs(
    jobs: Sequence[FileJob], processes: int | None = None, writers: WarmWriters | None = None
) -> None:
    """Run every job, on up to two processes (see the module's notes).

    Args:
        jobs: the jobs; each must write only its own files.
        processes: 1 to write everything here; None for two where :func:`can_fork` allows it.
        writers: warm processes started before the run: they take the portable jobs, this
            process the others (``processes`` is then not used).

    Raises:
        Exception: whatever a job raises when this process runs it.
    """
    portable = [job for job in jobs if job.portable]
    if writers is not None and writers.ready and portable:
        writers.write(portable, [job for job in jobs if not job.portable])
        return
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


def _split(jobs: Sequence[FileJob], parts: int = 2) -> list[list[FileJob]]:
    """Greedy balance: the costliest job first, each to the part with the least work so far."""
    shares: list[list[FileJob]] = [[] for _ in range(parts)]
    load = [0.0] * parts
    for job in sorted(jobs, key=lambda j: -j.cost):
        side = load.index(min(load))
        shares[side].append(job)
        load[side] += job.cost
    return shares


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


#: the warm processes' niceness (``os.nice``): a process of the default niceness that shares a
#: core with one of them gets nearly all of it (Linux's weights 1024 and 15)
_NICENESS = 19


class WarmWriters:
    """A process forked before a run's integration that gets ready to draw its figures, and
    splits into ``processes`` when they are due (see the module's notes); a context manager, or
    call :meth:`close`.

    Args:
        processes: how many processes draw (0: none is started, :attr:`ready` is False and
            :func:`write_jobs` writes as without it; also where :func:`can_fork` does not allow
            children).
        formats: the figure formats the warm-up draws once.
    """

    def __init__(self, processes: int = 2, formats: Sequence[str] = ("png",)) -> None:
        self.processes = processes
        self._worker: multiprocessing.process.BaseProcess | None = None
        self._conn = None
        self._sent = False
        if processes < 1 or not can_fork():
            return
        # what is buffered now would otherwise be written again by the child at its exit
        sys.stdout.flush()
        sys.stderr.flush()
        context = multiprocessing.get_context("fork")
        mine, theirs = context.Pipe()
        try:
            worker = context.Process(
                target=_serve, args=(theirs, mine, tuple(formats)), daemon=True
            )
            worker.start()
        except OSError:
            mine.close()
            return
        finally:
            theirs.close()
        self._worker, self._conn = worker, mine

    @property
    def ready(self) -> bool:
        """True while the warm process is there to take jobs."""
        return self._worker is not None

    def write(self, jobs: Sequence[FileJob], here: Sequence[FileJob] = ()) -> None:
        """Run ``jobs`` (portable) on the warm process and its forks and ``here`` in this process
        meanwhile; the jobs they did not finish are then run here. The warm process ends with
        this call.

        Raises:
            Exception: whatever a job raises when this process runs it.
        """
        again: list[FileJob] = list(jobs)
        if self._conn is not None:
            try:
                self._conn.send((list(jobs), self.processes))
                self._sent = True
            except Exception:  # not picklable after all, or the process is gone
                pass
        try:
            for job in here:
                job.write()
        finally:
            if self._sent:
                again = _unfinished(self._conn, jobs)
            self.close()
        for job in again:
            job.write()

    def close(self) -> None:
        """End the warm process: at once if it has no work (the run failed), else when its work
        is done (it has reported by then)."""
        if self._worker is None:
            return
        self._conn.close()
        if not self._sent:
            self._worker.terminate()
        self._worker.join(timeout=30.0)
        if self._worker.is_alive():
            self._worker.kill()
            self._worker.join()
        self._worker = self._conn = None

    def __enter__(self) -> WarmWriters:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _unfinished(conn, jobs: Sequence[FileJob]) -> list[FileJob]:
    """The jobs that the warm process reports as not written (all of them if it died)."""
    try:
        failed = set(conn.recv())
    except (EOFError, OSError):
        return list(jobs)
    return [job for job in jobs if job.name in failed]


def _serve(conn, parent_end, formats: tuple[str, ...]) -> None:
    """The warm process: get ready, wait for the jobs, split into ``processes`` (forks that
    share the warm state), write, report the names of the jobs not written (the run's process
    writes them again, and raises their error if it recurs)."""
    parent_end.close()  # else the pipe never reads its end when the run's process dies
    # Ctrl-C at a terminal reaches the whole process group: the run's process decides about it
    # (it stops the integration and still writes its files, with this process's help)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # the run's integration comes first: this process uses what it leaves of the processor
    with contextlib.suppress(OSError):
        os.nice(_NICENESS)
    with contextlib.suppress(Exception):  # a failing warm-up only costs its time
        _warm_up(formats)
    try:
        jobs, processes = conn.recv()
    except BaseException:  # the run ended without files (an error), or its process died
        return
    mine, *theirs = _split(jobs, max(1, processes))
    forks = {}
    for share in theirs:
        pid = _fork_writer(share) if share else None
        if pid is None:
            mine += share
        else:
            forks[pid] = share
    failed = [job.name for job in mine if not _write(job)]
    for pid, share in forks.items():
        if os.waitpid(pid, 0)[1] != 0:
            failed += [job.name for job in share]
    with contextlib.suppress(OSError):
        conn.send(failed)


def _fork_writer(share: list[FileJob]) -> int | None:
    """Fork a process that writes ``share`` and exits with 0 if every job succeeded; its pid,
    or None when the fork failed."""
    try:
        pid = os.fork()
    except OSError:
        return None
    if pid == 0:
        ok = [_write(job) for job in share]
        os._exit(0 if all(ok) else 1)
    return pid


def _write(job: FileJob) -> bool:
    try:
        job.write()
    except BaseException:
        return False
    return True


def _warm_up(formats: tuple[str, ...]) -> None:
    """Import what the figures need and draw a small figure once (fonts, renderer, text)."""
    from . import curving_figures, run_figures, track_figures  # noqa: F401
    from .figures import new_figure

    fig = new_figure(figsize=(3, 2))
    ax = fig.subplots()
    ax.plot([0.0, 1.0], [0.0, 1.0], label="warm-up")
    ax.set_xlabel("distance [m]")
    ax.set_title("warm-up")
    ax.legend(loc="upper right")
    for fmt in formats:
        fig.savefig(io.BytesIO(), format=fmt, dpi=130)
