"""Write a run's output files on two processor cores.

A run's figures cost more than its integration's last seconds: six figures take some 3.5 s of one
core, and importing matplotlib another 0.5 s, while the second core of a laptop or a CI machine
sits idle (the integration is serial). Two ways use it:

- :func:`write_jobs` shares the writing of independent files (each figure, the time series, the
  state file) between this process and one child forked when the run is over, so the folder is
  complete in about half the time (``railexu.write_run`` called from a script);
- given a :class:`~railexu.runtime.warm_process.WarmProcess` started *before* the integration
  (``railexu run``), which imported matplotlib and the figure modules and drew a first small
  figure (:func:`warm_up_figures`) on the idle core while the run integrated, it hands that
  process the figures (:func:`write_shares`: it and a fork of it, which shares its warm state;
  each job carries its own data, the time series and the summary), while this process writes
  the time series and the state file.

The processes share the jobs by claiming them, the costliest first (:class:`_Claims`: a job's
claim is an atomic link in a private folder), so a faster process simply takes more of them.
Nothing waits on a starved helper (issue 26): when this process has written its own jobs, it
waits for the jobs no helper has begun only while the warm process progresses (it has the
figure modules imported; a forked writer without one gets no such wait), and for a job a
helper holds only while that helper progresses (:class:`railexu.runtime.helpers.CpuWatch`:
at least a fifth of a core over 0.2 s); a starved or dead helper's job, and every job left
after it, is written here, and the helpers are killed before :func:`write_jobs` returns
(``abandoned`` names them, so that their temporary files can be removed). The longest this
process waits on a helper that gets no processor time is one window of the watch.

Each job writes its own files under temporary names and renames them into place
(:func:`railexu.report.folder.atomic_path`), so two processes never write the same temporary
file, and a job another process did not finish (it failed, or the process died) is written
here afterwards: the files are the same whichever process writes them.

Children exist only where it is safe and useful: a platform with ``fork`` (Linux; macOS's and
Windows' default start methods would re-import everything), more than one core, no other Python
thread running (forking a threaded process can deadlock) and not inside a daemonic worker process
(a study's process pool, which may not have children) and not turned off
(``RAILEXU_HELPER_PROCESSES=0``, :mod:`railexu.runtime.helpers`). Anywhere else this process
writes everything itself.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from railexu.runtime.helpers import CpuWatch, cpu_seconds, end_with_parent, free_core
from railexu.runtime.threads import run_serially_in_this_process
from railexu.runtime.warm_process import POLL_S, WarmProcess, can_fork


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
    jobs: Sequence[FileJob],
    processes: int | None = None,
    warm: WarmProcess | None = None,
    abandoned: Callable[[list[int]], None] | None = None,
) -> None:
    """Run every job, on up to two processes (see the module's notes).

    Args:
        jobs: the jobs; each must write only its own files.
        processes: 1 to write everything here; None for two where :func:`can_fork` allows it.
        warm: a process started before the run: it takes the portable jobs (shared with a
            fork of it), this process the others and then what is left (``processes`` is then
            not used).
        abandoned: called with the ids of helper processes ended while they may have been
            writing (a starved helper, or an error here): the caller removes their temporary
            files.

    Raises:
        Exception: whatever a job raises when this process runs it.
    """
    portable = [job for job in jobs if job.portable]
    if warm is not None and warm.ready and portable:
        _write_with(warm, portable, [job for job in jobs if not job.portable], abandoned)
        return
    if processes is None:
        # a machine that starved the warm process, or has no free core, would starve a fork
        # too, which would only import the figure modules a second time: everything here
        starved = warm is not None and warm.starved_out
        processes = 2 if can_fork() and not starved and free_core() else 1
    if processes < 2 or len(jobs) < 2:
        for job in jobs:
            job.write()
        return
    _write_forked(jobs, processes, abandoned)


def _write_with(
    warm: WarmProcess,
    portable: list[FileJob],
    here: list[FileJob],
    abandoned: Callable[[list[int]], None] | None,
) -> None:
    """``portable`` on the warm process and a fork of it, ``here`` meanwhile in this process,
    which then takes what they have not begun and what a starved helper holds (see
    :func:`_take_over`)."""
    claims = _Claims()
    order = _by_cost(portable)
    warm.start(write_shares_as_child, order, 2, claims.path, fallback=_nothing)
    clean = False
    taken: list[int] = []
    try:
        for job in here:
            job.write()
        taken = _take_over(order, claims, warm.watch, warm.pid)
        clean = True
    finally:
        helpers = claims.claimers() - {os.getpid()}
        if clean and not taken:
            warm.finish()  # its answer (every job is written), or it is ended when starved
        else:  # end the helpers now: none may write after this function
            warm_pid = warm.pid
            _kill(helpers - {warm_pid})
            warm.close()
            if abandoned is not None and helpers:
                abandoned(sorted(helpers))
        claims.remove()


def _write_forked(
    jobs: Sequence[FileJob], processes: int, abandoned: Callable[[list[int]], None] | None
) -> None:
    """``jobs`` shared between this process and ``processes - 1`` forks of it; this process
    never waits for a fork that does not progress (:func:`_take_over`)."""
    claims = _Claims()
    order = _by_cost(jobs)
    forks: list[int] = []
    try:
        for _ in range(processes - 1):
            pid = _fork_worker(order, claims) if _may_fork() else None
            if pid is not None:
                forks.append(pid)
        _take_over(order, claims, CpuWatch())
    finally:  # the forks end in any case (Ctrl-C here does not leave them behind)
        killed = _end_forks(forks)
        if abandoned is not None and killed:
            abandoned(killed)
        claims.remove()


def _by_cost(jobs: Sequence[FileJob]) -> list[FileJob]:
    """The costliest job first: the processes that share them end at about the same time."""
    return sorted(jobs, key=lambda j: -j.cost)


def _take_over(
    jobs: Sequence[FileJob], claims: _Claims, watch: CpuWatch, helper: int | None = None
) -> list[int]:
    """This process's part once its own work is done. Without ``helper``: every job that no
    process has begun, at once. With ``helper`` (the warm process, which has the figure modules
    imported): a job nobody has begun waits while ``helper`` progresses, and is written here
    once it is starved. Then, for each job another process holds, a wait while that process
    progresses; a job whose process is starved or gone
    (:class:`~railexu.runtime.helpers.CpuWatch`) is written here, and so is every job left
    after that, without waiting. A job that failed elsewhere is written again here (its error is
    raised now, if it recurs). Returns the ids of the processes whose jobs were taken over."""
    me = os.getpid()
    if helper is None:
        _work(jobs, claims)
    else:
        watch.restart(helper)
    taken: list[int] = []
    given_up = False  # a helper was starved: no more waiting
    watched: set[int] = set()  # the processes waited for: their windows start with the wait
    for job in jobs:
        while True:
            state = claims.state(job.name)
            if state == "ok":
                break
            if state == "failed":
                job.write()
                break
            pid = claims.claimer(job.name)
            if pid is None:  # nobody has begun it
                if helper is not None and not given_up and not watch.starved(helper):
                    time.sleep(POLL_S)
                    continue
                given_up = True
                if claims.claim(job.name):
                    claims.mark(job.name, _write(job))
                elif claims.claimer(job.name) is None:  # no claim possible: write it here
                    job.write()
                    break
                continue
            if pid not in watched:
                watched.add(pid)
                watch.restart(pid)
            if given_up or pid == me or watch.starved(pid):
                given_up = True
                taken.append(pid)
                job.write()
                break
            time.sleep(POLL_S)
    return [pid for pid in taken if pid != me]


def _work(jobs: Sequence[FileJob], claims: _Claims) -> None:
    """Write, one after the other, every job that no other process has claimed."""
    for job in jobs:
        if claims.claim(job.name):
            claims.mark(job.name, _write(job))


def _nothing(*args) -> None:
    """The warm process's part when it cannot take it: nothing (this process writes all)."""


def write_shares(jobs: Sequence[FileJob], parts: int, claims_path: str | None = None) -> None:
    """Write ``jobs`` in ``parts`` processes: this one and forks of it (which share its imports:
    this is what a :class:`~railexu.runtime.warm_process.WarmProcess` runs), each taking the
    next job no process has claimed in ``claims_path`` (a :class:`_Claims` folder; a new one
    when None). Waits for its forks."""
    claims = _Claims(claims_path)
    forks = []
    for _ in range(max(1, parts) - 1):
        pid = _fork_worker(jobs, claims) if _may_fork() else None
        if pid is not None:
            forks.append(pid)
    try:
        _work(jobs, claims)
    finally:
        for pid in forks:
            with contextlib.suppress(ChildProcessError):
                os.waitpid(pid, 0)
        if claims_path is None:
            claims.remove()


def write_shares_as_child(
    jobs: Sequence[FileJob], parts: int, claims_path: str | None = None
) -> None:
    """:func:`write_shares` in a child process of the command (its warm process): the child
    ends with its parent and cleans up on SIGTERM (:func:`_stop_with_parent`)."""
    _stop_with_parent()
    write_shares(jobs, parts, claims_path)


def _stop_with_parent(parent_pid: int | None = None) -> None:
    """In a child process: SIGTERM raises :class:`KeyboardInterrupt` (so that the file being
    written is removed, not left half written), and the child gets SIGTERM when its parent dies,
    even by SIGKILL (:func:`railexu.runtime.helpers.end_with_parent`)."""
    parent = os.getppid() if parent_pid is None else parent_pid
    signal.signal(signal.SIGTERM, _raise_interrupt)
    end_with_parent(parent, _orphaned)


def _orphaned() -> None:
    raise KeyboardInterrupt("the command's process is gone")


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


_STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM}


class _Claims:
    """Which process writes which job: in a private folder, a job's claim is a file made by an
    atomic link (the first process to make it writes the job; it holds that process's id), and
    a mark ``NAME.ok`` or ``NAME.failed`` when the job is over."""

    def __init__(self, path: str | None = None) -> None:
        self.path = path or tempfile.mkdtemp(prefix="railexu-jobs-")

    def _file(self, name: str, kind: str) -> str:
        return os.path.join(self.path, f"{name}.{kind}")

    def claim(self, name: str) -> bool:
        """True when this process is the first to claim job ``name``."""
        tmp = os.path.join(self.path, f".{os.getpid()}.{name}")
        try:
            with open(tmp, "w") as fh:
                fh.write(str(os.getpid()))
            os.link(tmp, self._file(name, "claim"))
        except OSError:  # claimed already, or the folder is gone (the job is not ours)
            return False
        finally:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        return True

    def claimer(self, name: str) -> int | None:
        """The id of the process that claimed job ``name`` (None: nobody)."""
        try:
            with open(self._file(name, "claim")) as fh:
                return int(fh.read())
        except (OSError, ValueError):
            return None

    def claimers(self) -> set[int]:
        """The ids of every process that claimed a job."""
        names = os.listdir(self.path) if os.path.isdir(self.path) else []
        pids = {self.claimer(n[: -len(".claim")]) for n in names if n.endswith(".claim")}
        return {pid for pid in pids if pid is not None}

    def mark(self, name: str, ok: bool) -> None:
        """Job ``name`` is over: written, or failed."""
        with contextlib.suppress(OSError):
            open(self._file(name, "ok" if ok else "failed"), "w").close()  # noqa: SIM115

    def state(self, name: str) -> str | None:
        """``"ok"``, ``"failed"`` or None (not over, or not begun)."""
        for kind in ("ok", "failed"):
            if os.path.exists(self._file(name, kind)):
                return kind
        return None

    def remove(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)


def _may_fork() -> bool:
    """:func:`can_fork` without its test of a daemonic process: the warm process is one (so that
    it ends with the command), and a fork it waits for does not outlive it."""
    return (os.cpu_count() or 1) > 1 and hasattr(os, "fork") and threading.active_count() == 1


def _fork_worker(jobs: Sequence[FileJob], claims: _Claims) -> int | None:
    """Fork a process that writes the jobs it claims first (:func:`_work`) and exits; its pid,
    or None when the fork failed."""
    # what is buffered now would otherwise be written again by the child
    sys.stdout.flush()
    sys.stderr.flush()
    # SIGINT and SIGTERM wait while the process forks (one that arrived during the fork's own
    # handlers would be lost: Python ignores an exception there)
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
    parent = os.getpid()
    try:
        pid = os.fork()
    except OSError:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        return None
    if pid == 0:  # the child's only job is its files; a job's failure is marked for the parent
        try:
            _stop_with_parent(parent)
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
            run_serially_in_this_process()  # a forked child cannot start GNU OpenMP's threads
            _work(jobs, claims)
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(0)
    signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a signal that came meanwhile acts now
    return pid


def _end_forks(forks: Sequence[int]) -> list[int]:
    """Reap this process's forks; those still running (starved, or this process is being
    interrupted) are killed first. Returns the ids of the killed ones."""
    killed = []
    for pid in forks:
        try:
            done, _ = os.waitpid(pid, os.WNOHANG)
            if done == 0:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
                killed.append(pid)
                os.waitpid(pid, 0)
        except ChildProcessError:
            pass
    return killed


def _kill(pids: set[int], timeout_s: float = 2.0) -> None:
    """Kill processes that are not this one's children (the warm process's forks) and wait
    until they are gone (at most ``timeout_s``)."""
    for pid in pids:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    deadline = time.monotonic() + timeout_s
    while any(cpu_seconds(pid) is not None for pid in pids) and time.monotonic() < deadline:
        time.sleep(POLL_S)


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
