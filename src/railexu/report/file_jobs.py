"""Write a run's output files on two processor cores.

A run's figures cost more than its integration's last seconds: six figures take some 3.5 s of one
core, and importing matplotlib another 0.5 s, while the second core of a laptop or a CI machine
sits idle (the integration is serial). Two ways use it:

- :func:`write_jobs` splits the writing of independent files (each figure, the time series, the
  state file) between this process and one child forked when the run is over
  (:func:`write_shares`), so the folder is complete in about half the time (``railexu.write_run``
  called from a script);
- given a :class:`~railexu.runtime.warm_process.WarmProcess` started *before* the integration
  (``railexu run``), which imported matplotlib and the figure modules and drew a first small
  figure (:func:`warm_up_figures`) on the idle core while the run integrated, it hands that
  process the figures (:func:`write_shares`: it and a fork of it, which shares its warm state,
  draw half each; each job carries its own data, the time series and the summary), while this
  process writes the time series and the state file.

Each job writes its own files under temporary names and renames them into place
(:func:`railexu.report.folder.atomic_path`), so two processes never write the same file, and a job
another process did not finish (it failed, or the process died) is written here afterwards: the
files are the same whichever process writes them.

No child outlives the command: a child that writes files ends when its parent dies (Linux's
``PR_SET_PDEATHSIG``, even when the parent is killed with SIGKILL), SIGTERM makes it remove its
temporary file and exit, and a parent interrupted while writing (Ctrl-C, SIGTERM) ends its
children before it goes on (:func:`write_shares`, :func:`_write_with`).

Children exist only where it is safe and useful: a platform with ``fork`` (Linux; macOS's and
Windows' default start methods would re-import everything), more than one core, no other Python
thread running (forking a threaded process can deadlock) and not inside a daemonic worker process
(a study's process pool, which may not have children). Anywhere else this process writes
everything itself.
"""

from __future__ import annotations

import contextlib
import io
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from railexu.runtime.threads import run_serially_in_this_process
from railexu.runtime.warm_process import WarmProcess, can_fork


@dataclass(frozen=True)
class FileJob:
    """One independent piece of output: ``write()`` writes it; ``cost`` is its relative time
    (only its ratio to the other jobs' costs matters: it balances the processes); ``portable``:
    ``write`` can be pickled and run by a :class:`~railexu.runtime.warm_process.WarmProcess` (it
    carries its data, not the Exudyn model)."""

    name: str
    write: Callable[[], None]
    cost: float = 1.0
    portable: bool = False


def write_jobs(
    jobs: Sequence[FileJob], processes: int | None = None, warm: WarmProcess | None = None
) -> None:
    """Run every job, on up to two processes (see the module's notes).

    Args:
        jobs: the jobs; each must write only its own files.
        processes: 1 to write everything here; None for two where :func:`can_fork` allows it.
        warm: a process started before the run: it takes the portable jobs (split into two
            processes: it and a fork of it), this process the others (``processes`` is then
            not used).

    Raises:
        Exception: whatever a job raises when this process runs it.
    """
    portable = [job for job in jobs if job.portable]
    if warm is not None and warm.ready and portable:
        _write_with(warm, portable, [job for job in jobs if not job.portable])
        return
    if processes is None:
        processes = 2 if can_fork() else 1
    if processes < 2 or len(jobs) < 2:
        for job in jobs:
            job.write()
        return
    _write_again(jobs, write_shares(jobs, processes))


def _write_with(warm: WarmProcess, portable: list[FileJob], here: list[FileJob]) -> None:
    """``portable`` on the warm process and a fork of it, ``here`` meanwhile in this process;
    then here again what they did not write."""
    warm.start(write_shares_as_child, portable, 2, fallback=_write_all_here)
    try:
        for job in here:
            job.write()
    except BaseException:  # interrupted, or a write failed: the warm process stops now
        warm.close()
        raise
    failed = warm.finish()
    _write_again(portable, failed)


def _write_again(jobs: Sequence[FileJob], failed: list[str]) -> None:
    """Write here the jobs named in ``failed`` (a job's error is raised now, if it recurs)."""
    for job in jobs:
        if job.name in failed:
            job.write()


def _split(jobs: Sequence[FileJob], parts: int = 2) -> list[list[FileJob]]:
    """Greedy balance: the costliest job first, each to the part with the least work so far."""
    shares: list[list[FileJob]] = [[] for _ in range(parts)]
    load = [0.0] * parts
    for job in sorted(jobs, key=lambda j: -j.cost):
        side = load.index(min(load))
        shares[side].append(job)
        load[side] += job.cost
    return shares


def write_shares(jobs: Sequence[FileJob], parts: int) -> list[str]:
    """Write ``jobs`` split into ``parts`` processes: this one and forks of it (which share its
    imports: this is what a :class:`~railexu.runtime.warm_process.WarmProcess` runs); returns the
    names of the jobs that failed or whose process failed (to be written again by the caller)."""
    mine, *theirs = _split(jobs, max(1, parts))
    forks = {}
    for share in theirs:
        pid = _fork_writer(share) if share and _may_fork() else None
        if pid is None:
            mine += share
        else:
            forks[pid] = share
    failed: list[str] = []
    try:
        failed += [job.name for job in mine if not _write(job)]
    except BaseException:  # interrupted (Ctrl-C, SIGTERM): the forks stop too
        for pid in forks:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGTERM)
        raise
    finally:  # the forks end in any case (Ctrl-C here does not leave them behind)
        for pid, share in forks.items():
            if os.waitpid(pid, 0)[1] != 0:
                failed += [job.name for job in share]
    return failed


def write_shares_as_child(jobs: Sequence[FileJob], parts: int) -> list[str]:
    """:func:`write_shares` in a child process of the command (its warm process): the child
    ends with its parent and cleans up on SIGTERM (:func:`_stop_with_parent`)."""
    _stop_with_parent()
    return write_shares(jobs, parts)


def _stop_with_parent() -> None:
    """In a child process: SIGTERM raises :class:`KeyboardInterrupt` (so that the file being
    written is removed, not left half written), and on Linux the child gets SIGTERM when its
    parent dies, even by SIGKILL (``prctl(PR_SET_PDEATHSIG)``)."""
    parent = os.getppid()
    signal.signal(signal.SIGTERM, _raise_interrupt)
    if sys.platform.startswith("linux"):
        import ctypes

        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGTERM))  # PR_SET_PDEATHSIG
    if os.getppid() != parent:  # the parent died before the line above
        raise KeyboardInterrupt


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


def _write_all_here(jobs: Sequence[FileJob], parts: int) -> list[str]:
    """The fallback of :func:`write_shares` when the warm process cannot run it: every job is
    reported as not written, so the caller writes them all here."""
    return [job.name for job in jobs]


def _may_fork() -> bool:
    """:func:`can_fork` without its test of a daemonic process: the warm process is one (so that
    it ends with the command), and a fork it waits for does not outlive it."""
    return (os.cpu_count() or 1) > 1 and hasattr(os, "fork") and threading.active_count() == 1


def _fork_writer(share: list[FileJob]) -> int | None:
    """Fork a process that writes ``share`` and exits with 0 if every job succeeded; its pid,
    or None when the fork failed. SIGINT and SIGTERM wait while the process forks (one that
    arrived during the fork's own handlers would be lost: Python ignores an exception there)."""
    # what is buffered now would otherwise be written again by the child
    sys.stdout.flush()
    sys.stderr.flush()
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    try:
        pid = os.fork()
    except OSError:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        return None
    if pid == 0:  # the child's only job is its files; its errors are reported by its status
        status = 1
        try:
            _stop_with_parent()
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
            run_serially_in_this_process()  # a forked child cannot start GNU OpenMP's threads
            status = 0 if all([_write(job) for job in share]) else 1
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(status)
    signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a signal that came meanwhile acts now
    return pid


_STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM}


def _write(job: FileJob) -> bool:
    """Write ``job``; False if it failed (its process then reports it, without a traceback)."""
    try:
        job.write()
    except Exception:
        return False
    return True


def warm_up_figures(formats: Sequence[str] = ("png",)) -> None:
    """Import what the figures need and draw a small figure once (fonts, renderer, text): the
    warm-up of a :class:`~railexu.runtime.warm_process.WarmProcess` that will draw a run's
    figures."""
    from railexu.report import curving_figures, run_figures, track_figures  # noqa: F401
    from railexu.report.figures import new_figure, save_options

    fig = new_figure(figsize=(3, 2))
    ax = fig.subplots()
    ax.plot([0.0, 1.0], [0.0, 1.0], label="warm-up")
    ax.set_xlabel("distance [m]")
    ax.set_title("warm-up")
    ax.legend(loc="upper right")
    for fmt in formats:
        fig.savefig(io.BytesIO(), format=fmt, dpi=130, **save_options(fmt))
