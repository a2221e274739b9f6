"""Parameter studies: one vehicle run (or critical-speed analysis) per combination of inputs.

A study file (``docs/study-format.md``) names a base vehicle, track and run settings, the
parameters to vary (vehicle, track, run or critical-speed settings, with units) and the results to
collect from each case's ``summary.json`` (or ``critical_speed.json``)::

    study = load_study("studies/eu07_lateral_force_vs_speed.yaml")
    result = run_study(study, "out/lateral_force", workers=4)
    result.rows            # the rows of out/lateral_force/results.csv
    plot_study("out/lateral_force")

Execution: every case runs in a worker process (``concurrent.futures.ProcessPoolExecutor``
whose workers are forked from a ``forkserver`` that has loaded the imports and compiled kernels
once, or started with ``spawn`` where there is no fork server; never forked from the study's own
process, which may hold threads), or as a task on a Dask distributed cluster
(``scheduler="tcp://host:port"``). The main process is the only writer of ``results.csv``: one
row is appended, flushed and synced to disk as each case finishes, so an interrupted study keeps
every finished case, and running the same study again into the same folder resumes it (cases
are identified by ``case_id`` and a hash of everything that decides their result).

Files written into the output folder ``DIR``:

- ``study.json``: the study as read (base, parameters with their values, collect list) and its
  cases, written at the start;
- ``results.csv``: one row per finished case (see :meth:`Study.columns`);
- ``cases/<case_id>/``: the case's ``case.json`` (its parameter values and overrides), the run's
  ``timeseries.csv`` and ``summary.json`` (or ``critical_speed.json``), plots if the study asks
  for them, and ``error.txt`` (the traceback) for a failed case;
- ``plots/``: the study plots of :func:`plot_study` (PNG and SVG).
"""

from __future__ import annotations

from railexu.study.errors import StudyError, StudyWarning
from railexu.study.folder import CASES_DIR as CASES_DIR
from railexu.study.folder import PLOTS_DIR as PLOTS_DIR
from railexu.study.folder import RESULTS_CSV as RESULTS_CSV
from railexu.study.folder import STUDY_JSON as STUDY_JSON
from railexu.study.folder import is_study_folder
from railexu.study.runner import StudyProgress, StudyResult, print_study_progress, run_study
from railexu.study.runner import StudyProgressCallback as StudyProgressCallback
from railexu.study.spec import ANALYSES as ANALYSES
from railexu.study.spec import BASE_KEYS as BASE_KEYS
from railexu.study.spec import COMBINE as COMBINE
from railexu.study.spec import DEFAULT_COLLECT as DEFAULT_COLLECT
from railexu.study.spec import FORMAT_VERSION as FORMAT_VERSION
from railexu.study.spec import MAX_CASES as MAX_CASES
from railexu.study.spec import RESULT_FILES as RESULT_FILES
from railexu.study.spec import TARGETS as TARGETS
from railexu.study.spec import TOP_KEYS as TOP_KEYS
from railexu.study.spec import VARY_KEYS as VARY_KEYS
from railexu.study.spec import Case, Parameter, Study, load_study
from railexu.study.table import DONE_STATUSES as DONE_STATUSES
from railexu.study.table import STATUSES as STATUSES
from railexu.study.table import _cell as _cell
from railexu.study.table import read_results
from railexu.study.values import MAX_VALUES as MAX_VALUES
from railexu.study.values import RANGE_KEYS as RANGE_KEYS
from railexu.study.values import _yaml_text as _yaml_text
from railexu.study.worker import _CRASH_ENV as _CRASH_ENV

__all__ = [
    "Case",
    "Parameter",
    "Study",
    "StudyError",
    "StudyProgress",
    "StudyResult",
    "StudyWarning",
    "is_study_folder",
    "load_study",
    "print_study_progress",
    "read_results",
    "run_study",
]
