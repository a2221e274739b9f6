"""The ``railexu report`` sub-command: one self-contained HTML page of a run or a study."""

from __future__ import annotations

import argparse
import sys
import time


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "report",
        help="write report.html for a run or a study folder",
        description=(
            "Write a self-contained report.html (no network, figures and animations embedded) "
            "into a run's folder: inputs with their files' SHA-256, settings, status, results "
            "against their limits, animations (run railexu animate first) and figures; or into "
            "a study's folder: the sortable table of cases, the study figures and a link to "
            "each case's own report (written too, unless --no-cases)."
        ),
    )
    p.add_argument("folder", help="output folder of railexu run or railexu study")
    p.add_argument(
        "--no-cases", action="store_true", help="study: do not write the cases' own reports"
    )
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=command)
    return p


def command(args: argparse.Namespace) -> int:
    from railexu.report.animate import progress_line
    from railexu.report.html_report import write_report

    t0 = time.perf_counter()
    progress = None if args.quiet else progress_line("case reports", unit="case")
    written = write_report(args.folder, cases=not args.no_cases, progress=progress)
    print(f"railexu report: wrote {written[-1]}" + (
        f" and {len(written) - 1} case reports" if len(written) > 1 else ""
    ))  # fmt: skip
    if not args.quiet:
        print(f"railexu report: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0
