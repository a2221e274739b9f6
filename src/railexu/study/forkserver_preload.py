"""Imported by the fork server of a study's local workers before it forks the first worker
(:mod:`railexu.runtime.fork_server`): loads what every case needs once, so that each
worker forked from the server starts warm. Importing this module runs a 5 cm simulation of the
shipped single wheelset (:func:`railexu.study.worker.load_case_needs`); it is meant for that
process only. A failure is left to the cases to report (the worker then loads what it needs).

The loaded objects (some 140 000) are then frozen (``gc.freeze``, as Python's documentation
advises before forking without exec): the workers' garbage collections never scan them again
(a full collection in a worker's first case cost 0.09 s) nor write to the memory pages that
the workers share with the server."""

import gc

from railexu.runtime.threads import run_serially_in_this_process
from railexu.study.worker import _preload

run_serially_in_this_process()  # its forks are the workers: no numba threads to fork
_preload()
gc.freeze()
