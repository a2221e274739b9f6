"""A process forked at the start of a command that gets ready, while the run integrates, for the
work that follows it.

After its integration ``railexu run`` assesses the run (``scipy.signal``'s filters: importing it
costs some 0.8 s) and draws its figures (importing matplotlib, 0.5 s, and some 3.5 s of drawing),
while the integration itself keeps only one core busy. :class:`WarmProcess` forks before the run
is built: on the core the integration leaves idle, it imports the modules that the later work
needs and runs a warm-up (a first small figure: fonts, renderer). When the run is over,
:meth:`WarmProcess.call` hands it that work; the function is pickled by reference and its
arguments by value (the time series, the summary: a few MB).

Nothing waits on a starved helper (issue 26): the call and its value travel through files in a
private temporary folder, the pipe carries only a few bytes (so a hand-over never blocks on a
process that does not read), and while the command's process waits for the value it watches the
warm process's processor time (:class:`railexu.runtime.helpers.CpuWatch`): a warm process that
got less than a fifth of a core over 0.2 s (a busy machine, or it is gone) is ended and the call
runs in the command's process. The warm process runs at the command's own priority: at the
lowest one (niceness 19, before) a loaded machine gave it no processor time at all.

The results are the same whichever process computes them: a call that fails in the warm process,
or a warm process that is gone or starved, is run again in this one (which then raises its
error, if any).

The warm process exists only where it is safe and useful: a platform with ``fork`` (Linux;
macOS's and Windows' default start methods would re-import everything), more than one core, no
other Python thread running (forking a threaded process can deadlock), not inside a daemonic
worker process (a study's process pool, which may not have children) and not turned off
(``RAILEXU_HELPER_PROCESSES=0``, :mod:`railexu.runtime.helpers`). Anywhere else
:attr:`WarmProcess.ready` is False and every call runs here.
"""

from __future__ import annotations

import contextlib
import importlib
import multiprocessing
import os
import pickle
import shutil
import signal
import sys
import tempfile
import threading
from collections.abc import Callable, Sequence
from typing import Any

from railexu.runtime.helpers import CpuWatch, end_with_parent, helpers_enabled
from railexu.runtime.threads import run_serially_in_this_process

#: the warm process's niceness (``os.nice``): the command's own. At 19 (before issue 26) a
#: process of the default niceness that shared a core with it got nearly all of it (Linux's
#: scheduler weights 1024 and 15), and on a busy machine the warm process never ran
NICENESS = 0
#: how often the command's process looks for the warm process's answer while it waits [s]
POLL_S = 0.01


def can_fork() -> bool:
    """True where a forked child may work alongside this process (see the module's notes).

    Raises:
        InputError: a bad value of ``RAILEXU_HELPER_PROCESSES``.
    """
    if not helpers_enabled():
        return False
    if "fork" not in multiprocessing.get_all_start_methods():
        return False
    if (os.cpu_count() or 1) < 2 or sys.platform != "linux":
        return False
    return threading.active_count() == 1 and not multiprocessing.current_process().daemon


class WarmProcess:
    """A process that imports ``preload`` and runs ``warm_up()`` at once, then runs the calls it
    is given (one at a time); a context manager, or call :meth:`close`.

    Args:
        preload: module names to import.
        warm_up: a function without arguments run after the imports (its errors only cost
            their time).
        start: False for none (:attr:`ready` is then False and every call runs here).
        watch: how the waits judge the warm process's progress (default:
            :class:`~railexu.runtime.helpers.CpuWatch`).
    """

    def __init__(
        self,
        preload: Sequence[str] = (),
        warm_up: Callable[[], Any] | None = None,
        start: bool = True,
        watch: CpuWatch | None = None,
    ) -> None:
        self._worker: multiprocessing.process.BaseProcess | None = None
        self._conn = None
        self._dir: str | None = None
        self._warmed = None  # set by the warm process when its imports and warm-up are done
        self._pending: tuple[Callable, tuple, Callable | None, str | None] | None = None
        self._calls = 0
        self.watch = watch or CpuWatch()
        #: True once the warm process was ended because it was starved: the machine is busy
        self.starved_out = False
        if not start or not can_fork():
            return
        # what is buffered now would otherwise be written again by the child at its exit
        sys.stdout.flush()
        sys.stderr.flush()
        context = multiprocessing.get_context("fork")
        mine, theirs = context.Pipe()
        warmed = context.Event()
        folder = tempfile.mkdtemp(prefix="railexu-warm-")
        try:
            worker = context.Process(
                target=_serve,
                args=(theirs, mine, tuple(preload), warm_up, warmed, os.getpid()),
                daemon=True,
            )
            worker.start()
        except OSError:
            mine.close()
            shutil.rmtree(folder, ignore_errors=True)
            return
        finally:
            theirs.close()
        self._worker, self._conn, self._warmed, self._dir = worker, mine, warmed, folder

    @property
    def ready(self) -> bool:
        """True while the warm process is there to take calls."""
        return self._worker is not None

    @property
    def pid(self) -> int | None:
        """The warm process's id (None when there is none)."""
        return None if self._worker is None else self._worker.pid

    def warmed(self) -> bool:
        """True once the warm process has done its imports and warm-up (or failed at them), or
        when there is no warm process (any more), or when it gets no processor time
        (:meth:`starved`): nothing is then waiting for the processor."""
        if self._warmed is None or self._worker is None or self._warmed.is_set():
            return True
        return self.starved()

    def starved(self) -> bool:
        """True when the warm process is gone or got less than a fifth of a core over the last
        window (:class:`~railexu.runtime.helpers.CpuWatch`)."""
        return self._worker is None or self.watch.starved(self._worker.pid)

    def start(self, function: Callable, *args: Any, fallback: Callable | None = None) -> None:
        """Begin ``function(*args)`` in the warm process (``function`` must be importable by
        name, ``args`` picklable); :meth:`finish` returns its value. ``fallback(*args)`` (by
        default ``function`` itself) runs here in :meth:`finish` when the warm process cannot
        deliver. Never blocks: the call is written to a file and its name sent."""
        if self._pending is not None:
            raise RuntimeError("WarmProcess.start: the previous call is not finished")
        path = None
        if self._conn is not None:
            self._calls += 1
            path = os.path.join(self._dir, f"call-{self._calls}.pickle")
            try:
                with open(path, "wb") as fh:
                    pickle.dump((function, args), fh, protocol=pickle.HIGHEST_PROTOCOL)
                self._conn.send(path)  # a few bytes: the pipe's buffer takes them at once
            except Exception:  # not picklable, or the process is gone: finish() runs it here
                self.close()
                path = None
        self._pending = (function, args, fallback, path)

    def finish(self) -> Any:
        """The value of the call begun by :meth:`start`, computed in the warm process or, when
        that failed or the warm process does not progress (:meth:`starved`: it is then
        ended), here.

        Raises:
            Exception: whatever the call raises when it runs here.
        """
        if self._pending is None:
            raise RuntimeError("WarmProcess.finish: no call was started")
        function, args, fallback, path = self._pending
        self._pending = None
        if path is not None:
            done, value = self._answer(path)
            if done:
                return value
        return (fallback or function)(*args)

    def _answer(self, path: str) -> tuple[bool, Any]:
        """Wait for the warm process's answer to the call in ``path`` while it progresses:
        ``(True, value)``, or ``(False, None)`` when it failed, died or is starved (then it is
        ended)."""
        try:
            self.watch.restart(self._worker.pid)
            while not self._conn.poll(POLL_S):
                if self.starved():
                    self.starved_out = True
                    self.close()
                    return False, None
            self._conn.recv()  # a few bytes: "the answer is in its file"
            with open(path + ".answer", "rb") as fh:
                return pickle.load(fh)
        except Exception:  # the process died, or its value could not be read
            self.close()
            return False, None
        finally:
            for name in (path, path + ".answer"):
                with contextlib.suppress(OSError):
                    os.unlink(name)

    def call(self, function: Callable, *args: Any) -> Any:
        """``function(*args)`` in the warm process, or here when that is not possible."""
        self.start(function, *args)
        return self.finish()

    def close(self) -> None:
        """End the warm process (between calls it only waits: nothing is lost) and remove its
        folder."""
        if self._worker is None:
            return
        self._conn.close()
        self._worker.kill()  # SIGKILL: a starved process ends without running anything more
        self._worker.join()
        shutil.rmtree(self._dir, ignore_errors=True)
        self._worker = self._conn = None

    def __enter__(self) -> WarmProcess:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _serve(
    conn,
    parent_end,
    preload: tuple[str, ...],
    warm_up: Callable | None,
    warmed=None,
    parent_pid: int | None = None,
) -> None:
    """The warm process: imports, warm-up (then ``warmed`` is set), then each call read from the
    file whose name arrives, and its value (or a failure) written beside it."""
    parent_end.close()  # else its pipe never reads its end when the command's process dies
    parent_pid = os.getppid() if parent_pid is None else parent_pid
    end_with_parent(parent_pid, lambda: os._exit(0))  # no warm process outlives its command
    # Ctrl-C at a terminal reaches the whole process group: the command's process decides
    # about it (a run stops its integration and still assesses and writes its results)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    run_serially_in_this_process()  # a forked child cannot start GNU OpenMP's threads
    if NICENESS:
        with contextlib.suppress(OSError):
            os.nice(NICENESS)
    with contextlib.suppress(Exception):
        for name in preload:
            importlib.import_module(name)
        if warm_up is not None:
            warm_up()
    if warmed is not None:
        warmed.set()
    while True:
        try:
            path = conn.recv()
        except BaseException:  # the command's process closed the pipe (or died)
            return
        _answer_call(path)
        try:
            conn.send(True)
        except Exception:  # the command's process is gone
            return


def _answer_call(path: str) -> None:
    """Run the call pickled in ``path``; write ``(True, value)`` (or ``(False, None)`` when it
    failed or its value cannot be pickled) to ``path + ".answer"``, complete or not at all."""
    try:
        with open(path, "rb") as fh:
            function, args = pickle.load(fh)
        reply = (True, function(*args))
    except BaseException:  # run again by the command's process, which reports the error
        reply = (False, None)
    tmp = f"{path}.answer.tmp"
    try:
        try:
            data = pickle.dumps(reply, protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # a value that cannot be pickled is computed again there
            data = pickle.dumps((False, None))
        with open(tmp, "wb") as fh:
            fh.write(data)
        os.replace(tmp, f"{path}.answer")
    except OSError:  # the folder is gone: the command's process no longer waits
        pass
