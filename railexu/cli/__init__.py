"""The ``railexu`` command: a thin shell over the public functions.

Each sub-command (one module here) parses its arguments into the settings object of a public
function, calls it and reports. ``main(argv=None)`` returns the exit status (0 success, 1 failed
run, 2 bad input).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from . import contact, critical_speed, plot, run, study
from .common import CliError as CliError
from .common import parse_range as parse_range
from .run import format_summary as format_summary


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="railexu",
        description="Railway vehicle dynamics on Exudyn: contact checks, runs, studies.",
    )
    from .. import __version__

    parser.add_argument("--version", action="version", version=f"railexu {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for command in (contact, run, study, critical_speed, plot):
        command.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``railexu`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except (ValueError, FileNotFoundError) as exc:
        # bad input: every loader raises a ValueError subclass naming file, key and expectation
        print(f"railexu {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"railexu {args.command}: failed: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
