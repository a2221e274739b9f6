"""Running a study: :func:`run_study`, its progress reports and its result."""

from __future__ import annotations

import contextlib
import json
import math
import os
import signal
import sys
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from railexu.errors import RunInterrupted, RunTerminated
from railexu.study.errors import StudyError, StudyWarning
from railexu.study.execution import _dask_client, _run_dask, _run_inline, _run_local
from railexu.study.folder import (
    CASES_DIR,
    RESULTS_CSV,
    STUDY_JSON,
    _locked,
    _write_files,
    _write_json,
)
from railexu.study.input_files import changed_files, input_file_digests
from railexu.study.spec import Study, _sha256, load_study
from railexu.study.table import STATUSES, _Table, read_results
from railexu.study.worker import _make_task


@dataclass(frozen=True)
class StudyProgress:
    """State of a running study, passed to the progress callback after each case.

    Attributes:
        total: cases in the study.
        done: cases with a row in results.csv (finished now or before).
        skipped: of these, rows kept from before (resume).
        failed: failed cases among ``done``.
        elapsed_s: wall-clock time since the start [s].
        eta_s: estimated time left [s]: cases left x mean run time of this call's cases /
            workers; ``inf`` until a case has finished.
        case_id: the case that just finished (None for the first call, before any case).
        status: its status.
    """

    total: int
    done: int
    skipped: int
    failed: int
    elapsed_s: float
    eta_s: float
    case_id: str | None = None
    status: str | None = None


StudyProgressCallback = Callable[[StudyProgress], None]


@dataclass
class StudyResult:
    """Outcome of :func:`run_study`.

    Attributes:
        study: the study.
        out_dir: its output folder.
        rows: every row of results.csv after the run (column -> text), in case order.
        ran: cases run by this call.
        skipped: cases already in results.csv (resume).
        elapsed_s: wall-clock time of this call [s].
    """

    study: Study
    out_dir: Path
    rows: list[dict[str, str]]
    ran: int
    skipped: int
    elapsed_s: float

    @property
    def results_csv(self) -> Path:
        return self.out_dir / RESULTS_CSV

    @property
    def counts(self) -> dict[str, int]:
        """Number of cases per status."""
        out = dict.fromkeys(STATUSES, 0)
        for r in self.rows:
            out[r["status"]] = out.get(r["status"], 0) + 1
        return out

    @property
    def failed(self) -> list[dict[str, str]]:
        return [r for r in self.rows if r["status"] == "failed"]

    @property
    def ok(self) -> bool:
        """No case failed (derailed and diverged runs are results, not failures)."""
        return not self.failed


STALE_RESULTS_CSV = "results.before-input-change.csv"


def with_input_files(study: Study) -> Study:
    """``study`` with the digests of the files its cases read (vehicle, track, the profiles and
    measured files they name, file paths among the varied values) in its fingerprint, so that a
    change in any of them changes every case's hash."""
    values = [v for p in study.parameters for v in p.values] + _set_values(study.set)
    digests = input_file_digests(study.vehicle, study.track, values, Path(study.source).parent)
    fingerprint = {k: v for k, v in study.fingerprint.items() if k != "digest"}
    fingerprint["input_files"] = _sha256(digests)
    fingerprint["digest"] = _sha256(fingerprint)
    return replace(study, fingerprint=fingerprint, input_files=digests)


def _set_values(items) -> list:
    """The values of the base ``set`` overrides (``key=value``), parsed as YAML: a file they
    name (a worn wheel profile set by the wear loop, ``wheelsets.ws1.wheel_profile={left: a.txt,
    right: b.txt}``) is read by every case, so its content belongs in the fingerprint too."""
    import yaml

    out = []
    for item in items:
        try:
            out.append(yaml.safe_load(str(item).partition("=")[2]))
        except yaml.YAMLError:
            continue
    return out


def _set_aside_stale_results(out: Path, study: Study) -> None:
    """The same study as before, but a file its cases read changed since they ran: the old
    results no longer belong to these inputs. They are kept beside (never deleted) as
    ``results.before-input-change.csv``, and every case runs again."""
    try:
        old = json.loads((out / STUDY_JSON).read_text(encoding="utf-8"))
        old_fp = dict(old["fingerprint"])
        old_files = dict(old.get("input_files") or {})
    except (OSError, ValueError, KeyError, TypeError):
        return
    new_fp = study.fingerprint

    # the files' contents: the parsed vehicle and track files and the digests of all files
    inputs = ("vehicle", "track", "input_files", "digest")

    def settings_of(fp: dict) -> dict:
        return {k: v for k, v in fp.items() if k not in inputs}

    new = study.to_dict()
    results = out / RESULTS_CSV
    same_study = (
        settings_of(old_fp) == settings_of(new_fp)
        and old.get("parameters") == new["parameters"]
        and old.get("base", {}).get("vehicle") == new["base"]["vehicle"]
        and old.get("base", {}).get("track") == new["base"]["track"]
    )
    if not same_study or old_fp.get("digest") == new_fp.get("digest") or not results.exists():
        return
    changed = changed_files(old_files, study.input_files) or ["(files not recorded before)"]
    os.replace(results, out / STALE_RESULTS_CSV)
    warnings.warn(
        f"{out}: input files changed since the finished cases ran ({', '.join(changed)}): "
        f"their results are kept in {STALE_RESULTS_CSV} and every case runs again",
        StudyWarning,
        stacklevel=3,
    )


def run_study(
    study: Study | str | Path,
    out_dir: str | Path,
    workers: int | None = None,
    scheduler: Any = None,
    progress: StudyProgressCallback | None = None,
    retry_failed: bool = False,
) -> StudyResult:
    """Run every case of ``study`` not yet in ``out_dir/results.csv``.

    Args:
        study: a :class:`Study` or the path of a study file.
        out_dir: the output folder (created if needed).
        workers: local worker processes (default ``os.cpu_count()``); ``0`` runs the cases one
            after the other in this process (debugging: no isolation from crashes). Ignored
            with ``scheduler``.
        scheduler: a Dask scheduler address (``"tcp://host:port"``) or a
            ``distributed.Client``: the cases run as tasks on that cluster. The workers must be
            able to read the vehicle and track files (and the profile files they name) at the
            same absolute paths; each case's files are sent back and written here.
        progress: called with a :class:`StudyProgress` at the start and after each case.
        retry_failed: run the cases recorded as ``failed`` again.

    Resume: a case whose ``case_id`` and ``case_hash`` are in results.csv with status
    completed, derailed or diverged is not run again (nor a failed one, unless
    ``retry_failed``). A results.csv with rows that do not match this study's cases is refused.

    Raises:
        InputError: a bad study file (when given as a path).
        StudyError: the output folder holds another study's results or is in use, bad
            ``workers``, no connection to the scheduler.
        ImportError: ``scheduler`` given but dask.distributed is not installed.
        RunInterrupted: Ctrl-C (SIGINT), or ``RunTerminated`` (its subclass) for SIGTERM
            (:mod:`railexu.errors`; both are ``KeyboardInterrupt``), after cancelling the
            pending cases and ending the workers: the finished rows are kept in results.csv
            and the exception's ``result`` is a :class:`StudyResult` with them (``ran`` and
            ``skipped`` 0: the study did not finish). Running it again resumes it.
    """
    t0 = time.perf_counter()
    if not isinstance(study, Study):
        study = load_study(study)
    if workers is None:
        workers = os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise StudyError(f"workers must be an integer >= 0, got {workers!r}")
    if workers > max_workers():
        raise StudyError(
            f"workers {workers}: at most {max_workers()} ({WORKERS_PER_CORE} per core of this "
            "machine; each worker holds the imports and a model, a few hundred MB, and more "
            "than the cores only share them)"
        )
    out = Path(out_dir)
    try:
        with _sigterm_raises():
            return _run_study(study, out, workers, scheduler, progress, retry_failed, t0)
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM: the finished cases are kept
        kind = type(exc) if isinstance(exc, RunInterrupted) else RunInterrupted
        raise kind(result=_finished_so_far(study, out, t0)) from exc


#: Most local worker processes per core (:func:`max_workers`).
WORKERS_PER_CORE = 4


def max_workers() -> int:
    """The most local worker processes a study may start: :data:`WORKERS_PER_CORE` per core
    (at least 8)."""
    return max(8, WORKERS_PER_CORE * (os.cpu_count() or 1))


@contextlib.contextmanager
def _sigterm_raises():
    """SIGTERM raises :class:`~railexu.errors.RunTerminated` in this (main) thread while the
    study runs, so that it stops as on Ctrl-C: the pending cases cancelled, the workers ended,
    the finished rows kept, nothing leaked (its default would end the process at once, with
    exit code 143 and the pool's semaphores left behind). Outside the main thread, or when the
    process ignores SIGTERM, nothing changes."""

    def stop(signum, frame):
        raise RunTerminated()

    installed = False
    previous = signal.getsignal(signal.SIGTERM)
    if previous is not signal.SIG_IGN:
        with contextlib.suppress(ValueError):  # not the main thread
            signal.signal(signal.SIGTERM, stop)
            installed = True
    try:
        yield
    finally:
        if installed:
            signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


def _finished_so_far(study: Study, out: Path, t0: float) -> StudyResult | None:
    """The :class:`StudyResult` of an interrupted study: the rows of results.csv (the cases
    finished now and before); None when it cannot be read."""
    try:
        rows = read_results(out / RESULTS_CSV) if (out / RESULTS_CSV).exists() else []
    except Exception:  # a results.csv of another study, unreadable: nothing to attach
        return None
    return StudyResult(study, out, rows, ran=0, skipped=0, elapsed_s=time.perf_counter() - t0)


def _run_study(
    study: Study,
    out: Path,
    workers: int,
    scheduler: Any,
    progress: StudyProgressCallback | None,
    retry_failed: bool,
    t0: float,
) -> StudyResult:
    """:func:`run_study` once its arguments are checked."""
    out.mkdir(parents=True, exist_ok=True)
    study = with_input_files(study)
    cases = study.cases()
    with _locked(out):
        _set_aside_stale_results(out, study)
        table = _Table(out, study, cases)
        kept = table.prepare(retry_failed)
        _write_json(out / STUDY_JSON, {**study.to_dict(), "cases": [c.to_dict() for c in cases]})
        pending = [c for c in cases if c.case_id not in kept]
        by_id = {c.case_id: c for c in cases}
        failed = sum(1 for r in kept.values() if r["status"] == "failed")
        run_times: list[float] = []
        state = {"done": len(kept), "failed": failed}

        client, owned = (None, False)
        if pending and scheduler is not None:
            client, owned = _dask_client(scheduler)
        try:
            if client is not None:
                parallel = max(1, sum(client.nthreads().values()))
                tasks = [_make_task(study, c, None, True) for c in pending]
                outcomes = _run_dask(tasks, client)
            elif workers == 0:
                parallel = 1
                tasks = [_make_task(study, c, out / CASES_DIR / c.case_id, False) for c in pending]
                outcomes = _run_inline(tasks)
            else:
                parallel = workers
                tasks = [_make_task(study, c, out / CASES_DIR / c.case_id, True) for c in pending]
                outcomes = _run_local(tasks, workers)

            def report(case_id: str | None = None, status: str | None = None) -> None:
                if progress is None:
                    return
                left = len(cases) - state["done"]
                if left == 0:
                    eta = 0.0
                elif run_times:
                    eta = left * (sum(run_times) / len(run_times)) / max(1, min(parallel, left))
                else:
                    eta = math.inf
                progress(
                    StudyProgress(
                        total=len(cases),
                        done=state["done"],
                        skipped=len(kept),
                        failed=state["failed"],
                        elapsed_s=time.perf_counter() - t0,
                        eta_s=eta,
                        case_id=case_id,
                        status=status,
                    )
                )

            table.open()
            try:
                report()
                with contextlib.closing(outcomes):
                    for outcome in outcomes:
                        case = by_id[outcome["case_id"]]
                        if outcome.get("files") is not None:
                            _write_files(out / CASES_DIR / case.case_id, outcome["files"])
                        table.append(table.row(case, outcome))
                        state["done"] += 1
                        state["failed"] += outcome["status"] == "failed"
                        rt = outcome.get("run_time_s")
                        if rt is not None and math.isfinite(rt):
                            run_times.append(rt)
                        report(case.case_id, outcome["status"])
            finally:
                table.close()
        finally:
            if owned:
                with contextlib.suppress(Exception):
                    client.close()
        rows = read_results(table.path) if table.path.exists() else []
    order = {c.case_id: c.index for c in cases}
    rows.sort(key=lambda r: order.get(r["case_id"], len(order)))
    return StudyResult(
        study=study,
        out_dir=out,
        rows=rows,
        ran=len(pending),
        skipped=len(kept),
        elapsed_s=time.perf_counter() - t0,
    )


def _format_duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "--"
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}h{m:02d}m{s:02d}s" if h else (f"{m}m{s:02d}s" if m else f"{s}s")


def print_study_progress(stream=sys.stderr) -> StudyProgressCallback:
    """A progress callback printing cases done / total, failures, elapsed time and the time
    left on one updating line of ``stream``."""

    def report(p: StudyProgress) -> None:
        failed = f", {p.failed} failed" if p.failed else ""
        before = f" ({p.skipped} from before)" if p.skipped else ""
        left = "" if p.done >= p.total else f", about {_format_duration(p.eta_s)} left"
        end = "\n" if p.done >= p.total else ""
        stream.write(
            f"\r  {p.done}/{p.total} cases{before}{failed}, elapsed "
            f"{_format_duration(p.elapsed_s)}{left}    {end}"
        )
        stream.flush()

    return report
