"""Running the tasks of a study: on a local process pool, on a Dask cluster, or in this process.

Each executor yields the outcome of every task (see :func:`railexu.study.worker._run_case`) as
the task finishes.
"""

from __future__ import annotations

import contextlib
import os
import uuid
from collections import deque
from collections.abc import Iterator, Sequence
from typing import Any

from railexu.runtime.fork_server import pool_context
from railexu.study.errors import StudyError
from railexu.study.worker import _error_text, _outcome, _run_case, _Task, _worker_init


def _run_inline(tasks: Sequence[_Task]) -> Iterator[dict]:
    for task in tasks:
        yield _run_case(task)


def _run_local(tasks: Sequence[_Task], workers: int) -> Iterator[dict]:
    """Run tasks on a local process pool (:func:`railexu.runtime.fork_server.pool_context`), at most
    ``workers`` in flight. If a worker process dies (a crash in native code, out of memory),
    the cases that were in flight are run again one at a time, so that only the case that
    kills its worker is recorded as failed."""
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    ctx = pool_context()
    queue: deque[_Task] = deque(tasks)
    suspects: deque[_Task] = deque()
    isolated: set[str] = set()  # suspects in flight: nothing else runs beside them
    inflight: dict[Any, _Task] = {}
    pool: ProcessPoolExecutor | None = None
    clean = False

    def collect(futures) -> Iterator[tuple[_Task, dict | None]]:
        for fut in futures:
            task = inflight.pop(fut)
            isolated.discard(task.case_id)
            try:
                yield task, fut.result()
            except BrokenProcessPool:
                yield task, None
            except Exception as exc:  # e.g. a result that cannot be pickled
                yield task, _outcome(task, "failed", _error_text(exc))

    try:
        while queue or suspects or inflight:
            if pool is None:
                n = max(1, min(workers, len(queue) + len(suspects)))
                pool = ProcessPoolExecutor(
                    n, mp_context=ctx, initializer=_worker_init, initargs=(os.getpid(),)
                )
            limit = 1 if suspects or isolated else workers
            pool_broken = False
            while len(inflight) < limit and (suspects or queue):
                source = suspects if suspects else queue
                task = source.popleft()
                try:
                    fut = pool.submit(_run_case, task)
                except BrokenProcessPool:  # a worker died since the last look
                    source.appendleft(task)
                    pool_broken = True
                    break
                if source is suspects:
                    isolated.add(task.case_id)
                inflight[fut] = task
            alone = len(inflight) == 1
            done, _ = wait(list(inflight), return_when=FIRST_COMPLETED)
            broken: list[_Task] = []
            for task, outcome in collect(done):
                if outcome is None:
                    broken.append(task)
                else:
                    yield outcome
            if not (broken or pool_broken):
                continue
            # the pool is unusable: the other cases in flight end with it
            rest, _ = wait(list(inflight))
            for task, outcome in collect(rest):
                if outcome is None:
                    broken.append(task)
                else:
                    yield outcome
            pool.shutdown(wait=True)
            pool = None
            if alone and broken:
                yield _outcome(
                    broken[0],
                    "failed",
                    "the worker process died while running this case (a crash in native code, "
                    "or out of memory)",
                )
            else:
                suspects.extend(broken)  # run each alone to find the one that kills its worker
        clean = True
    finally:
        if pool is not None:
            _stop_pool(pool, list(inflight), terminate=not clean)


def _stop_pool(pool, futures: list, terminate: bool) -> None:
    for fut in futures:
        fut.cancel()
    if terminate:
        stop = getattr(pool, "terminate_workers", None)  # Python >= 3.14
        if stop is not None:
            stop()
        else:
            for proc in list((getattr(pool, "_processes", None) or {}).values()):
                if proc.is_alive():
                    proc.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def _dask_client(scheduler: Any):
    """``(client, owned)``: a ``distributed.Client`` for an address, or the client given."""
    if not isinstance(scheduler, str):
        return scheduler, False
    try:
        import distributed
    except ImportError as exc:
        raise ImportError(
            f"running a study on a Dask cluster ({scheduler}) needs dask.distributed, which is "
            "not installed: pip install railexu[dask]"
        ) from exc
    try:
        return distributed.Client(scheduler, timeout="20s"), True
    except (OSError, TimeoutError) as exc:
        raise StudyError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from exc
    except ValueError as exc:  # not an address: 'abc', '' (distributed's parser)
        raise StudyError(
            f"--scheduler {scheduler!r}: not a Dask scheduler address ({exc}); expected "
            "tcp://HOST:PORT"
        ) from None


def _run_dask(tasks: Sequence[_Task], client) -> Iterator[dict]:
    """Submit every task to the cluster and yield outcomes as they complete."""
    from distributed import as_completed

    futures = {}
    for task in tasks:
        key = f"railexu-study-{task.case_id}-{uuid.uuid4().hex[:8]}"
        futures[client.submit(_run_case, task, key=key, pure=False)] = task
    try:
        for fut in as_completed(list(futures)):
            task = futures.pop(fut)
            try:
                outcome = fut.result()
            except (KeyboardInterrupt, SystemExit, GeneratorExit):
                raise
            except BaseException as exc:  # KilledWorker, CancelledError, ...
                outcome = _outcome(task, "failed", f"the Dask task failed: {_error_text(exc)}")
            yield outcome
    finally:
        if futures:
            with contextlib.suppress(Exception):
                client.cancel(list(futures))
