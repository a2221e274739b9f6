"""How many threads the wheelsets' contact evaluations use in this process.

The contact evaluations of a vehicle's wheelsets are independent of each other, so the force
function can run them on threads (:func:`railexu.model.forces.generalized_forces_threaded`, the same
operations in the same order: the same results to the last bit). The policy:

- **Only with a thread-safe threading layer of numba** (OpenMP or TBB). numba's fallback,
  ``workqueue``, made the same call twice as slow as one thread (``docs/performance.md``), so
  without OpenMP or TBB (e.g. macOS without libomp) the wheelsets run one after the other.
- **One thread per wheelset at most, and no more than the cores this process may use.**
- **One thread in a study's workers** (:func:`run_serially_in_this_process`): the worker
  processes already fill the cores; threads on top would slow the study down.
- **The environment variable ``RAILEXU_THREADS``** caps the number: ``1`` turns threads off.
- **After the warm process's imports**: ``railexu run`` starts the threads once its warm
  process (:mod:`railexu.runtime.warm_process`, at the lowest priority) has imported what it needs;
  OpenMP's thread spins between the force function's calls and would otherwise hold the core
  that process is waiting for (:func:`railexu.simulation.simulate.simulate`'s
  ``contact_threads_when``).
- **Left while a busy machine makes them slower than one thread**, measured while the run goes
  on (:mod:`railexu.runtime.thread_choice`).
- **Never in a forked child** (:func:`run_serially_in_this_process`): GNU OpenMP cannot start
  its threads in a process forked from one where they ran. railexu's forked children (the warm
  process, the figure writer of :mod:`railexu.report.file_jobs`) only assess and draw, and are
  marked serial as they start.

On two cores the seed scenario's integration is about a fifth shorter; OpenMP's idle thread
spins between the calls, so a run uses more processor time (figures in
``docs/performance.md``).
"""

from __future__ import annotations

import os
import sys

from railexu.errors import InputError

ENV = "RAILEXU_THREADS"

_serial = False


def run_serially_in_this_process() -> None:
    """The wheelsets' contacts run on one thread in this process from now on (a study's
    worker)."""
    global _serial
    _serial = True


def requested_threads() -> int | None:
    """The cap set by :data:`ENV`, or None when it is not set.

    Raises:
        InputError: the variable is set to something other than a whole number of at least 1.
    """
    text = os.environ.get(ENV, "").strip()
    if not text:
        return None
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise InputError(
            f"environment variable {ENV}={text!r}: expected a whole number of threads of at "
            "least 1 (1 runs the wheelsets' contacts one after the other)"
        )
    return value


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def contact_threads(n_wheelsets: int) -> int:
    """The number of threads for the contacts of ``n_wheelsets`` wheelsets (1: no threads)."""
    if _serial or n_wheelsets < 2:
        return 1
    cap = requested_threads()
    n = min(n_wheelsets, usable_cores(), cap if cap is not None else n_wheelsets)
    if n < 2:
        return 1
    return max(1, min(n, _start_threadsafe_layer()))


def threads_started() -> bool:
    """Whether numba's threads have been started in this process."""
    parallel = sys.modules.get("numba.np.ufunc.parallel")
    return bool(parallel is not None and getattr(parallel, "_is_initialized", False))


def _start_threadsafe_layer() -> int:
    """Start numba's threads with OpenMP or TBB; how many threads numba may use
    (``NUMBA_NUM_THREADS``), or 0 if neither layer can be loaded or another layer already runs
    in this process."""
    import numba
    from numba.np.ufunc import parallel

    if not threads_started():
        chosen = numba.config.THREADING_LAYER
        if "NUMBA_THREADING_LAYER" not in os.environ:
            numba.config.THREADING_LAYER = "threadsafe"
        try:
            parallel._launch_threads()
        except (ValueError, ImportError, OSError, AttributeError):
            # (AttributeError: a numba whose internals moved.) Leave the choice as it was for
            # other numba code in this process.
            numba.config.THREADING_LAYER = chosen
            return 0
    try:
        layer = numba.threading_layer()
    except ValueError:
        return 0
    return int(numba.config.NUMBA_NUM_THREADS) if layer in ("omp", "tbb") else 0


def use_threads(n: int) -> None:
    """Set numba's thread count for the calls made from this thread."""
    import numba

    numba.set_num_threads(n)
