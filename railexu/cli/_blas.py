"""Imported first by :mod:`railexu.cli`, before numpy loads: BLAS on one thread in the
``railexu`` command's processes, unless ``OPENBLAS_NUM_THREADS`` is already set.

railexu's matrices are small (a vehicle's 40-odd coordinates), so BLAS never gains from
threads here; but OpenBLAS (under numpy and scipy, each with its own pool) keeps its idle
threads busy-waiting after a call, and in a seed run they took about 2 % of the processor
samples on the cores that the contacts' threads and the warm process need
(``docs/performance.md``). The variable is read when OpenBLAS loads, so it must be set before
numpy is imported; the command's children (the warm process, a study's fork server and workers)
inherit it. A script that imports railexu itself keeps its own setting."""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
