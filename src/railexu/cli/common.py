"""Helpers shared by the sub-commands: exit codes, errors, options with units, ranges,
overrides, the help formatter."""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import signal
from collections.abc import Callable, Iterator, Sequence

from railexu.errors import InputError

# Exit codes of every sub-command (documented in `railexu --help` and the README)
EXIT_OK = 0  # completed, and no safety criterion exceeded
EXIT_FAILED = 1  # a run that failed, derailed, diverged, exceeded a safety limit or was stopped
EXIT_INPUT = 2  # bad input: a file, an option, a value out of its range
EXIT_BUG = 3  # an unexpected error inside railexu (a defect: please report it)

EXIT_CODES_HELP = (
    "exit codes: 0 completed cleanly; 1 a run failed, derailed, diverged, exceeded a safety "
    "limit or was interrupted (its results are kept); 2 bad input (file, option or value); "
    "3 an unexpected error inside railexu (please report it)"
)

# a study may not ask for more than this many values of one range
MAX_RANGE_VALUES = 100_000


class CliError(InputError):
    """Bad command-line input."""


class Terminated(KeyboardInterrupt):
    """SIGTERM (``kill``, ``timeout``, a container's stop) received by the command: handled as
    Ctrl-C is (the command stops, keeps what it has, says so, exit code 1)."""


@contextlib.contextmanager
def stop_on_sigterm() -> Iterator[None]:
    """While the command runs, SIGTERM raises :class:`Terminated` in its main thread (Python's
    default would end the process at once, without its ``finally`` clauses: a folder half
    written, children left behind). A process forked meanwhile that kept this handler ends as
    by default. Nothing is changed outside the main thread."""
    pid = os.getpid()

    def handler(signum, frame) -> None:
        if os.getpid() != pid:  # a forked child: the default action
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        raise Terminated("SIGTERM")

    try:
        previous = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter, argparse.RawDescriptionHelpFormatter):
    """Shows every option's default (and its choices, which argparse lists in braces)."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if action.default in (None, False, [], argparse.SUPPRESS) or "default" in text:
            return text
        return super()._get_help_string(action)


def quantity(unit: str) -> Callable[[str], float]:
    """An argparse ``type`` for a value with a unit: ``"108 km/h"``, ``2km``, ``"2 mm"``; a bare
    number is SI (``unit``). Infinite or NaN values are refused."""
    from railexu.units import UnitError, to_si

    def parse(text: str) -> float:
        try:
            value = float(text)  # a bare number (82e9, -0.002): SI
        except ValueError:
            value = None
        if value is not None:
            if not math.isfinite(value):
                raise argparse.ArgumentTypeError(f"{text!r}: expected a finite value in {unit}")
            return value
        spaced = re.sub(r"^([-+]?[\d.]+(?:[eE][-+]?\d+)?)(?=[A-Za-z])", r"\1 ", text.strip())
        try:
            value = to_si(spaced, unit)
        except UnitError as exc:
            raise argparse.ArgumentTypeError(f"{exc} (a bare number is in {unit})") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{text!r}: expected a finite value in {unit}")
        return value

    parse.__name__ = f"value in {unit}"
    return parse


_NEGATIVE_VALUE = re.compile(r"^-(\d|\.\d)")


def join_negative_values(argv: Sequence[str]) -> list[str]:
    """``--lateral -0.010:0.010:0.0005`` -> ``--lateral=-0.010:0.010:0.0005``: argparse would
    take a value that starts with ``-`` (other than a plain negative number) for an option."""
    out: list[str] = []
    for token in argv:
        prev = out[-1] if out else ""
        if _NEGATIVE_VALUE.match(token) and prev.startswith("--") and "=" not in prev:
            out[-1] = f"{prev}={token}"
        else:
            out.append(token)
    return out


def parse_range(text: str, name: str = "range") -> tuple[float, ...]:
    """Values from ``FROM:TO:STEP`` (inclusive of TO within half a step), or a single value,
    or a comma-separated list."""
    import numpy as np  # here: the command line parses its arguments before numpy loads

    text = text.strip()
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) != 3:
                raise CliError(f"{name} {text!r}: expected FROM:TO:STEP")
            start, stop, step = parts
            if step <= 0 or stop < start:
                raise CliError(f"{name} {text!r}: need STEP > 0 and TO >= FROM")
            if not all(np.isfinite(parts)):
                raise CliError(f"{name} {text!r}: FROM, TO and STEP must be finite")
            n = int(np.floor((stop - start) / step + 0.5)) + 1
            if n > MAX_RANGE_VALUES:
                raise CliError(
                    f"{name} {text!r}: {n:.3g} values; at most {MAX_RANGE_VALUES} (a larger STEP?)"
                )
            return tuple(float(np.round(start + i * step, 12)) for i in range(n))
        values = tuple(float(v) for v in text.split(","))
        if not all(np.isfinite(values)):
            raise CliError(f"{name} {text!r}: values must be finite")
        return values
    except ValueError as exc:
        if isinstance(exc, CliError):
            raise
        raise CliError(f"{name} {text!r}: expected numbers as FROM:TO:STEP or a,b,c") from exc


def split_overrides(items: Sequence[str]) -> tuple[list[str], list[str]]:
    """``--set`` items: those for the vehicle file and those (``track.KEY=VALUE``) for the track."""
    vehicle, track = [], []
    for item in items:
        (track if item.startswith("track.") else vehicle).append(item.removeprefix("track."))
    return vehicle, track
