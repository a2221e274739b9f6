"""Layer 0, the process: what a command's processes are set up with before and around a run.

BLAS on one thread (:mod:`~railexu.runtime.blas_threads`), the start-up without cyclic garbage
collection (:mod:`~railexu.runtime.gc_pause`), the contacts' threads
(:mod:`~railexu.runtime.threads`), numba's on-disk cache (:mod:`~railexu.runtime.compiled_cache`),
the warm helper process of ``railexu run`` (:mod:`~railexu.runtime.warm_process`) and the fork
server of a study's workers (:mod:`~railexu.runtime.fork_server`). These modules import the
standard library only (``threads`` imports numba when the first model is built), so that they can
run before numpy loads. ``docs/architecture.md`` and ``docs/performance.md`` explain them.
"""
