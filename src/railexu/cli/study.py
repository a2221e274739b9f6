"""The ``railexu study`` sub-command."""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from pathlib import Path

from railexu.cli.common import CliError


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``study`` sub-command to the ``railexu`` parser's sub-parsers; its function
    returns the exit status: 0 when every case completed, derailed or diverged, 1 when a case
    failed."""
    p = subparsers.add_parser(
        "study",
        help="run a parameter study (many runs over varied inputs)",
        description=(
            "Run every case of a study file (docs/study-format.md) in parallel worker processes "
            "or on a Dask cluster. Writes OUT/study.json, OUT/results.csv (one row per case, "
            "appended as cases finish), OUT/cases/<case_id>/ and the study plots OUT/plots/. "
            "Running the same study into the same folder again resumes it."
        ),
    )
    p.add_argument("study", help="study file (YAML), e.g. studies/eu07_lateral_force_vs_speed.yaml")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help="local worker processes (default: the number of CPUs; 0: run in this process)",
    )
    p.add_argument(
        "--scheduler",
        help="run the cases on a Dask cluster: scheduler address tcp://host:port "
        "(needs pip install railexu[dask])",
    )
    p.add_argument("--retry-failed", action="store_true", help="run failed cases again")
    p.add_argument("--no-plots", action="store_true", help="do not draw the study plots")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=command)
    return p


def start_workers_early(args: argparse.Namespace) -> None:
    """With local workers, start their fork server now: it preloads on another core while this
    process imports the study layer and reads the study (:mod:`railexu.runtime.fork_server`). Not
    for ``--workers 0``, a Dask cluster or a study file that does not exist."""
    if args.scheduler is None and args.workers != 0 and Path(args.study).is_file():
        from railexu.runtime import fork_server

        fork_server.start()


def check_out(study_file: str, out: str) -> None:
    """The study's ``--out`` folder: not the study file (nor any file), and writable (created
    if missing).

    Raises:
        CliError: naming ``--out`` and what is wrong (exit 2, before any case runs).
    """
    target = Path(out).resolve()
    if target == Path(study_file).resolve():
        raise CliError(f"--out {out}: is the study file itself; give a folder for the results")
    if target.exists() and not target.is_dir():
        raise CliError(f"--out {out}: is a file; give a folder for the results")
    try:  # created here, as the run would, so that a read-only place is refused before any case
        target.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CliError(f"--out {out}: cannot create the folder: {exc.strerror}") from None
    if not os.access(target, os.W_OK | os.X_OK):
        raise CliError(f"--out {out}: the folder is not writable")


def command(args: argparse.Namespace) -> int:
    start_workers_early(args)
    # imported here: `railexu run` and the other sub-commands do not load the study layer
    from railexu.study.errors import StudyWarning
    from railexu.study.folder import PLOTS_DIR, RESULTS_CSV
    from railexu.study.plots import plot_study
    from railexu.study.runner import print_study_progress, run_study
    from railexu.study.spec import load_study
    from railexu.study.table import STATUSES, read_results

    study = load_study(args.study)
    check_out(args.study, args.out)
    n = len(study.cases())
    err = sys.stderr

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        err.write(f"\nrailexu study: warning: {message}\n")

    if not args.quiet:
        where = f"Dask cluster {args.scheduler}" if args.scheduler else (
            "this process" if args.workers == 0
            else f"{args.workers or os.cpu_count()} worker processes"
        )  # fmt: skip
        err.write(f"railexu study: {study.name}: {n} cases ({study.analysis}) on {where}\n")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", StudyWarning)
            warnings.showwarning = show
            result = run_study(
                study,
                args.out,
                workers=args.workers,
                scheduler=args.scheduler,
                progress=None if args.quiet else print_study_progress(err),
                retry_failed=args.retry_failed,
            )
    except KeyboardInterrupt:
        path = Path(args.out) / RESULTS_CSV
        kept = len(read_results(path)) if path.exists() else 0
        err.write(
            f"\nrailexu study: interrupted; {kept} finished case(s) are kept in {path}. Run the "
            "same command again to resume.\n"
        )
        return 130
    except ImportError as exc:
        err.write(f"railexu study: error: {exc}\n")
        return 2
    counts = result.counts
    summary = ", ".join(f"{counts[s]} {s}" for s in STATUSES if counts.get(s))
    print(
        f"railexu study: {study.name}: {len(result.rows)} of {n} cases ({summary}); ran "
        f"{result.ran}, {result.skipped} from before, {result.elapsed_s:.1f} s"
    )
    for r in result.failed[:10]:
        print(f"  {r['case_id']} failed: {r['error']}")
    if len(result.failed) > 10:
        print(f"  ... {len(result.failed) - 10} more failed cases in {result.results_csv}")
    print(f"  results: {result.results_csv}")
    if not args.no_plots:
        written = plot_study(args.out)
        if written:
            print(f"  plots: {len(written)} files in {Path(args.out) / PLOTS_DIR}")
    return 1 if result.failed else 0
