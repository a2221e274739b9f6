"""The fork server of a study's local worker processes, and its early start.

A study's local workers are forked from a ``forkserver`` (Linux, macOS; ``spawn`` elsewhere),
never by plain ``fork`` of the study's own process, which may hold threads (a notebook's,
Dask's, numba's) and an Exudyn system. The fork server is a new, single-threaded interpreter that
imports :data:`PRELOAD` once: :mod:`railexu.runtime.blas_threads` first (BLAS on one thread: the
workers fill the cores), then the imports and compiled kernels every case needs (some 1.0 s, see
:mod:`railexu.study.forkserver_preload`). Each worker is then forked from it already warm, in
milliseconds: a second study in the same session, and a pool restarted after a worker died,
start at once. A forked worker also ends without the interpreter's shutdown. The fork server is
Python's one per session; it ends with the session.

``railexu study`` calls :func:`start` before it imports the study's own modules and reads the
study file, so that the fork server's preload runs on another core meanwhile (some 0.4 s of a
study command's start). A command that then fails on its study file ends at once; the fork
server finishes its preload on the other core (about 1 s), sees that the command is gone and
ends too. Only the standard library is imported here.
"""

from __future__ import annotations

import multiprocessing

#: What the fork server imports before it forks the first worker, in this order.
PRELOAD = ("railexu.runtime.blas_threads", "railexu.study.forkserver_preload")


def pool_context():
    """The ``multiprocessing`` context of the local workers: ``forkserver`` with
    :data:`PRELOAD` where there is one, ``spawn`` elsewhere (Windows)."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(list(PRELOAD))
    return ctx


def start() -> bool:
    """Start the fork server now, if this platform has one and it is not running yet; it
    preloads in the background and the first pool that needs it waits for the rest. Returns
    True when there is a fork server (started now or before)."""
    if pool_context().get_start_method() != "forkserver":
        return False
    from multiprocessing import forkserver

    forkserver.ensure_running()
    return True
