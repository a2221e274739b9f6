"""A process forked at the start of a command that gets ready, while the run integrates, for the
work that follows it.

After its integration ``railexu run`` assesses the run (``scipy.signal``'s filters: importing it
costs some 0.8 s) and draws its figures (importing matplotlib, 0.5 s, and some 3.5 s of drawing),
while the integration itself keeps only one core busy. :class:`WarmProcess` forks before the run
is built: at the lowest priority, on the core the integration leaves idle, it imports the modules
that the later work needs and runs a warm-up (a first small figure: fonts, renderer). When the
run is over, :meth:`WarmProcess.call` hands it that work; the function is pickled by reference and
its arguments by value (the time series, the summary: a few MB).

The results are the same whichever process computes them: a call that fails in the warm process,
or a warm process that is gone, is run again in this one (which then raises its error, if any).

The warm process exists only where it is safe and useful: a platform with ``fork`` (Linux;
macOS's and Windows' default start methods would re-import everything), more than one core, no
other Python thread running (forking a threaded process can deadlock) and not inside a daemonic
worker process (a study's process pool, which may not have children). Anywhere else
:attr:`WarmProcess.ready` is False and every call runs here.
"""

from __future__ import annotations

import contextlib
import importlib
import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

from railexu.runtime.threads import run_serially_in_this_process

#: the warm process's niceness (``os.nice``): a process of the default niceness that shares a
#: core with it gets nearly all of it (Linux's scheduler weights 1024 and 15)
NICENESS = 19


def can_fork() -> bool:
    """True where a forked child may work alongside this process (see the module's notes)."""
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
    """

    def __init__(
        self,
        preload: Sequence[str] = (),
        warm_up: Callable[[], Any] | None = None,
        start: bool = True,
    ) -> None:
        self._worker: multiprocessing.process.BaseProcess | None = None
        self._conn = None
        self._warmed = None  # set by the warm process when its imports and warm-up are done
        self._pending: tuple[Callable, tuple, Callable | None] | None = None
        if not start or not can_fork():
            return
        # what is buffered now would otherwise be written again by the child at its exit
        sys.stdout.flush()
        sys.stderr.flush()
        context = multiprocessing.get_context("fork")
        mine, theirs = context.Pipe()
        warmed = context.Event()
        try:
            worker = context.Process(
                target=_serve, args=(theirs, mine, tuple(preload), warm_up, warmed), daemon=True
            )
            worker.start()
        except OSError:
            mine.close()
            return
        finally:
            theirs.close()
        self._worker, self._conn, self._warmed = worker, mine, warmed

    @property
    def ready(self) -> bool:
        """True while the warm process is there to take calls."""
        return self._worker is not None

    def warmed(self) -> bool:
        """True once the warm process has done its imports and warm-up (or failed at them), or
        when there is no warm process (any more): nothing is then waiting for the processor."""
        if self._warmed is None or self._worker is None or self._warmed.is_set():
            return True
        return not self._worker.is_alive()

    def start(self, function: Callable, *args: Any, fallback: Callable | None = None) -> None:
        """Begin ``function(*args)`` in the warm process (``function`` must be importable by
        name, ``args`` picklable); :meth:`finish` returns its value. ``fallback(*args)`` (by
        default ``function`` itself) runs here in :meth:`finish` when the warm process cannot
        deliver."""
        if self._pending is not None:
            raise RuntimeError("WarmProcess.start: the previous call is not finished")
        self._pending = (function, args, fallback)
        if self._conn is None:
            return
        try:
            self._conn.send((function, args))
        except Exception:  # not picklable, or the process is gone: finish() runs it here
            self.close()

    def finish(self) -> Any:
        """The value of the call begun by :meth:`start`, computed in the warm process or, when
        that failed, here.

        Raises:
            Exception: whatever the call raises when it runs here.
        """
        if self._pending is None:
            raise RuntimeError("WarmProcess.finish: no call was started")
        function, args, fallback = self._pending
        self._pending = None
        if self._conn is not None:
            try:
                done, value = self._conn.recv()
            except Exception:  # the process died, or its value could not be unpickled
                self.close()
            else:
                if done:
                    return value
        return (fallback or function)(*args)

    def call(self, function: Callable, *args: Any) -> Any:
        """``function(*args)`` in the warm process, or here when that is not possible."""
        self.start(function, *args)
        return self.finish()

    def close(self) -> None:
        """End the warm process (between calls it only waits: nothing is lost)."""
        if self._worker is None:
            return
        self._conn.close()
        self._worker.terminate()
        self._worker.join()
        self._worker = self._conn = None

    def __enter__(self) -> WarmProcess:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _serve(
    conn, parent_end, preload: tuple[str, ...], warm_up: Callable | None, warmed=None
) -> None:
    """The warm process: imports, warm-up (then ``warmed`` is set), then each call's value (or
    a failure) back."""
    parent_end.close()  # else its pipe never reads its end when the command's process dies
    # Ctrl-C at a terminal reaches the whole process group: the command's process decides
    # about it (a run stops its integration and still assesses and writes its results)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    run_serially_in_this_process()  # a forked child cannot start GNU OpenMP's threads
    # the run's integration comes first: this process uses what it leaves of the processor
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
            function, args = conn.recv()
        except BaseException:  # the command's process closed the pipe (or died)
            return
        try:
            reply = (True, function(*args))
        except BaseException:  # run again by the command's process, which reports the error
            reply = (False, None)
        try:
            conn.send(reply)
        except Exception:  # a value that cannot be pickled is computed again there
            try:
                conn.send((False, None))
            except Exception:  # the command's process is gone
                return
