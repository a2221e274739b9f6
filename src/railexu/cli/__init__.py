"""The ``railexu`` command: a thin shell over the public functions.

Each sub-command (one module here) parses its arguments into the settings object of a public
function, calls it and reports. ``main(argv=None)`` returns the exit status: 0 completed
cleanly, 1 a run failed or was unsafe, 2 bad input, 3 a defect of railexu
(:data:`~railexu.cli.common.EXIT_CODES_HELP`).

Only :class:`railexu.errors.InputError` (bad input) becomes a short message; any other exception
is a defect and is shown with its traceback and a request to report it.
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import traceback
from collections.abc import Sequence

# isort: off
# first: BLAS on one thread, before anything imports numpy (railexu.runtime.blas_threads)
from railexu.runtime import blas_threads  # noqa: F401
from railexu.runtime import gc_pause

# isort: on
from railexu.cli import (
    acceptance,
    animate,
    contact,
    creep,
    critical_speed,
    listing,
    plot,
    report,
    run,
    study,
    wear,
)
from railexu.cli.common import (
    EXIT_BUG,
    EXIT_CODES_HELP,
    EXIT_FAILED,
    EXIT_INPUT,
    HelpFormatter,
    Terminated,
    join_negative_values,
    stop_on_sigterm,
)
from railexu.cli.common import CliError as CliError
from railexu.cli.common import parse_range as parse_range
from railexu.cli.run import format_summary as format_summary
from railexu.errors import ComputationError, InputError

COMMANDS = (run, contact, creep, critical_speed, study, acceptance, wear, plot, animate, report,
            listing)  # fmt: skip
ISSUES_URL = "https://github.com/railexu/railexu/issues"


def build_parser() -> argparse.ArgumentParser:
    """The ``railexu`` argument parser with all its sub-commands."""
    from railexu.version import __version__

    parser = argparse.ArgumentParser(
        prog="railexu",
        description="Railway vehicle dynamics on Exudyn: runs, contact checks, critical "
        "speeds, parameter studies. Vehicles and tracks are YAML files or shipped names "
        '(`railexu list`); values with units ("108 km/h") wherever a number goes.',
        epilog=EXIT_CODES_HELP,
        formatter_class=HelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"railexu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for command in COMMANDS:
        p = command.add_parser(sub)
        if p is not None:
            p.formatter_class = HelpFormatter
            p.epilog = p.epilog or EXIT_CODES_HELP
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``railexu`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else argv))
    if not getattr(args, "resumes_collection", False):
        gc_pause.resume()  # the console script paused it for the imports (railexu.runtime.gc_pause)
    name = f"railexu {args.command}"
    try:
        with stop_on_sigterm():
            return int(args.func(args))
    except InputError as exc:
        print(f"{name}: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except ComputationError as exc:
        print(f"{name}: failed: {exc}", file=sys.stderr)
        return EXIT_FAILED
    except BrokenPipeError:
        _silence_broken_pipe()
        return EXIT_FAILED
    except KeyboardInterrupt as exc:
        how = "terminated (SIGTERM)" if isinstance(exc, Terminated) else "interrupted"
        print(f"\n{name}: {how}", file=sys.stderr)
        return EXIT_FAILED
    except Exception:
        traceback.print_exc()
        print(
            f"\n{name}: an unexpected error inside railexu (a defect, not your input). Please "
            f"report it with the command line and the input files: {ISSUES_URL}",
            file=sys.stderr,
        )
        return EXIT_BUG


def _silence_broken_pipe() -> None:
    """The reader of our output went away (``railexu list | head``): no traceback; point
    stdout at /dev/null so that Python's final flush does not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def entry_point() -> None:
    """The console script: ``sys.exit(main())``, quiet when the reader of the output has gone
    (``railexu list | head -1``)."""
    status = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        _silence_broken_pipe()
    # The process ends now: its objects (some 240 000 after a run: numba's and matplotlib's
    # among them) need no more cycle collection. Without this, the collections of the
    # interpreter's shutdown cost about 1 s of a `railexu run` (docs/performance.md); with it,
    # objects are still freed and files closed as before, only not searched for cycles.
    gc.freeze()
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    entry_point()
