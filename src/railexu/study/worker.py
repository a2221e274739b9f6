"""One case of a study, as run in a worker process: the picklable task and running it.

``_run_case`` and ``_worker_init`` are pickled by reference (``forkserver`` and ``spawn``
workers, Dask): they must stay module-level functions of this module.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import tempfile
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

from railexu.errors import RunInterrupted
from railexu.runtime.threads import run_serially_in_this_process
from railexu.study.folder import _write_json
from railexu.study.spec import RESULT_FILES, Case, Study

#: Test hook: a worker process exits abruptly (as on a crash in native code) before running the
#: case whose id this environment variable names. Never set it outside the tests.
_CRASH_ENV = "RAILEXU_STUDY_TEST_CRASH"


@dataclass(frozen=True)
class _Task:
    """What a worker needs to run one case (plain, picklable data)."""

    case_id: str
    hash: str
    analysis: str
    source: str
    vehicle: str
    track: str | None
    vehicle_overrides: tuple[str, ...]
    track_overrides: tuple[str, ...]
    settings: dict
    values: dict
    case_dir: str | None  # None: write into a temporary folder and return the files
    plots: bool
    in_worker: bool


def _make_task(study: Study, case: Case, case_dir: Path | None, in_worker: bool) -> _Task:
    return _Task(
        case_id=case.case_id,
        hash=case.hash,
        analysis=study.analysis,
        source=study.source,
        vehicle=str(study.vehicle),
        track=None if study.track is None else str(study.track),
        vehicle_overrides=tuple(study.vehicle_overrides(case)),
        track_overrides=tuple(study.track_overrides(case)),
        settings=study.settings_data(case),
        values=dict(case.values),
        case_dir=None if case_dir is None else str(case_dir),
        plots=study.plots,
        in_worker=in_worker,
    )


def _worker_init(study_pid: int | None = None) -> None:
    """Worker processes ignore Ctrl-C (the main process cancels and ends them cleanly) and end
    when the study's process does: a study's main process that is killed (``kill -9``, an
    out-of-memory kill) must not leave workers of some 200 MB each blocked forever.

    ``study_pid`` is the study's process. A ``spawn`` worker is its child; a ``forkserver``
    worker is the fork server's child, and the fork server ends with the study's process."""
    import signal
    import threading

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    run_serially_in_this_process()  # the workers fill the cores: no threads on top
    if study_pid is None:
        study_pid = os.getppid()
    # a spawn worker watches the id passed in: a study killed while it started is noticed too
    spawner = study_pid if os.getppid() == study_pid else os.getppid()
    threading.Thread(target=_exit_with_parent, args=(study_pid, spawner), daemon=True).start()
    _preload()


_loaded = False  # load_case_needs has run in this process (or in the fork server it came from)


def _preload() -> None:
    """Load once per worker what every case needs (:func:`load_case_needs`). A failure here is
    left to the cases to report."""
    global _loaded
    if _loaded:
        return
    with contextlib.suppress(Exception):
        load_case_needs()
        _loaded = True


def load_case_needs() -> None:
    """The imports (numpy, scipy, Exudyn, numba, the model and the assessment) and the compiled
    kernels (a 5 cm run of the shipped single wheelset loads them from numba's cache), so that a
    worker's first case costs what its others do and a case's ``run_time_s`` is that of the
    run itself."""
    from railexu.inputs.catalog import shipped_path
    from railexu.operation.run_settings import RunSettings
    from railexu.report import run_files  # noqa: F401
    from railexu.results import run  # noqa: F401
    from railexu.simulation.simulate import simulate
    from railexu.vehicle.vehicle import load_vehicle

    simulate(load_vehicle(shipped_path("vehicle", "wheelset")), None, RunSettings(distance_m=0.05))


PARENT_POLL_S = 0.5


def _exit_with_parent(study_pid: int, spawner: int) -> None:
    """End this process when the study's process or the process that started this one is gone
    (this process is then re-parented, so its parent id changes): polls every
    :data:`PARENT_POLL_S` seconds."""
    while os.getppid() == spawner and _alive(study_pid):
        time.sleep(PARENT_POLL_S)
    os._exit(1)


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie (killed, not yet reaped)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by another user
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:  # no /proc (macOS): existence is all we know
        return True
    return stat.rsplit(")", 1)[-1].split()[0] != "Z"


def _error_text(exc: BaseException) -> str:
    msg = str(exc).strip() or type(exc).__name__
    if not isinstance(exc, ValueError):
        msg = f"{type(exc).__name__}: {msg}"
    return " ".join(msg.split())


def _outcome(task: _Task, status: str, error: str = "", run_time_s: float = math.nan) -> dict:
    return {
        "case_id": task.case_id,
        "hash": task.hash,
        "status": status,
        "error": error,
        "run_time_s": run_time_s,
        "result": None,
        "files": None,
    }


def _run_case(task: _Task) -> dict:
    """Run one case and return its outcome: status, error, run time, the content of its result
    file (for ``collect``) and, when ``task.case_dir`` is None, its files (name -> bytes).
    Never raises for a failing case: the error is part of the outcome."""
    t0 = time.perf_counter()
    if task.in_worker:
        run_serially_in_this_process()  # a Dask worker's too
    if task.in_worker and os.environ.get(_CRASH_ENV) == task.case_id:
        os._exit(70)  # test hook: a worker dying as on a crash in native code
    temporary = task.case_dir is None
    outcome = _outcome(task, "failed")
    try:
        if temporary:
            case_dir = Path(tempfile.mkdtemp(prefix=f"railexu-{task.case_id}-"))
        else:
            case_dir = Path(task.case_dir)
            if case_dir.exists():
                shutil.rmtree(case_dir)
            case_dir.mkdir(parents=True)
    except OSError as exc:
        outcome["error"] = _error_text(exc)
        outcome["run_time_s"] = time.perf_counter() - t0
        return outcome
    try:
        _write_json(
            case_dir / "case.json",
            {
                "case_id": task.case_id,
                "hash": task.hash,
                "values": task.values,
                "vehicle": task.vehicle,
                "vehicle_overrides": list(task.vehicle_overrides),
                "track": task.track,
                "track_overrides": list(task.track_overrides),
                task.analysis: task.settings,
            },
        )
        status, result = _execute(task, case_dir)
        outcome.update(status=status, result=result)
    except RunInterrupted as exc:  # a stop, not a result: the case is not recorded
        # without the run (its model cannot be pickled back from a worker process)
        raise type(exc)() from None
    except Exception as exc:  # any failure of a case is recorded, not raised
        outcome["error"] = _error_text(exc)
        with contextlib.suppress(OSError):
            (case_dir / "error.txt").write_text(traceback.format_exc(), encoding="utf-8")
    outcome["run_time_s"] = time.perf_counter() - t0
    if temporary:
        files = {}
        for p in sorted(case_dir.rglob("*")):
            if p.is_file():
                files[p.relative_to(case_dir).as_posix()] = p.read_bytes()
        outcome["files"] = files
        shutil.rmtree(case_dir, ignore_errors=True)
    return outcome


def _execute(task: _Task, case_dir: Path) -> tuple[str, dict]:
    from railexu.track.track import ideal_straight_track, load_track
    from railexu.vehicle.vehicle import load_vehicle

    source = f"{task.source} ({task.case_id})"
    if task.analysis == "run":
        from railexu.operation.run_settings import run_settings_from_dict
        from railexu.report.run_files import write_run
        from railexu.results import read_summary
        from railexu.results.run import run

        settings = run_settings_from_dict(task.settings, source, None, ("run",))
        vehicle = load_vehicle(task.vehicle, task.vehicle_overrides)
        track = load_track(task.track, task.track_overrides) if task.track else None
        result = run(vehicle, track or ideal_straight_track(), settings)
        write_run(result, case_dir, plots=task.plots)
        return str(result.status["state"]), read_summary(case_dir / RESULT_FILES["run"])
    from railexu import stability
    from railexu.report.stability_files import write_critical_speed

    settings = stability.critical_speed_settings_from_dict(
        task.settings, source, None, ("critical_speed",)
    )
    vehicle = load_vehicle(task.vehicle, task.vehicle_overrides)
    track = load_track(task.track, task.track_overrides) if task.track else None
    result = stability.critical_speed(vehicle, track or ideal_straight_track(), settings)
    write_critical_speed(result, case_dir, plots=task.plots)
    path = case_dir / RESULT_FILES["critical_speed"]
    return "completed", json.loads(path.read_text(encoding="utf-8"))
