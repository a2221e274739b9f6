"""Imported for its effect, before numpy loads: BLAS on one thread in this process and its
children, unless ``OPENBLAS_NUM_THREADS`` is already set. :mod:`railexu.cli` imports it first
(the console script, :mod:`railexu.console`, through it), and a study's fork server before its
preload (:data:`railexu.runtime.fork_server.PRELOAD`).

railexu's matrices are small (a vehicle's 40-odd coordinates), so BLAS never gains from
threads here; but OpenBLAS (under numpy and scipy, each with its own pool) keeps its idle
threads busy-waiting after a call, and in a seed run they took about 2 % of the processor
samples on the cores that the contacts' threads, the warm process or the other workers of a
study need (``docs/performance.md``). The variable is read when OpenBLAS loads, so it must be
set before numpy is imported; the process's children (the warm process, a study's workers)
inherit it. A script that imports railexu itself keeps its own setting.
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
