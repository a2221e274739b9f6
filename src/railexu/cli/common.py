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


def _in(unit: str) -> str:
    return "" if unit == "1" else f" in {unit}"


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
                raise argparse.ArgumentTypeError(f"{text!r}: expected a finite value{_in(unit)}")
            return value
        spaced = re.sub(r"^([-+]?[\d.]+(?:[eE][-+]?\d+)?)(?=[A-Za-z])", r"\1 ", text.strip())
        try:
            value = to_si(spaced, unit)
        except UnitError as exc:
            raise argparse.ArgumentTypeError(f"{exc} (a bare number is in {unit})") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{text!r}: expected a finite value{_in(unit)}")
        return value

    parse.__name__ = f"value in {unit}"
    return parse


def check_within(
    option: str, value: float, low: float, high: float, unit: str, why: str, *, low_open=False
) -> float:
    """``value`` of ``option`` if finite and within ``low .. high`` (``low < value`` with
    ``low_open``), else a :class:`CliError` that states the range and ``why`` it is physical."""
    inside = (low < value if low_open else low <= value) and value <= high
    if not (math.isfinite(value) and inside):
        bound = ">" if low_open else ">="
        unit = f" {unit}" if unit else ""
        raise CliError(f"{option} {value:g}: must be {bound} {low:g} and <= {high:g}{unit} ({why})")
    return value


#: Ranges of the quantity options of ``creep``, ``contact`` and others: ``option: (low, high,
#: unit, why)``; the low bound is excluded for quantities that must be positive
#: (:data:`POSITIVE`). Stated in docs/cli.md.
LIMITS = {
    "--load": (0.0, 1.0e6, "N", "1 MN is 100 t on one wheel: a larger load is a unit mistake"),
    "--semi-axes": (0.0, 0.1, "m", "wheel-rail contact ellipses are mm to a few cm across"),
    "--curvatures": (0.0, 1.0e4, "1/m", "a curvature sum of 1e4 1/m is a 0.05 mm radius"),
    "--xi": (-1.0, 1.0, "", "a creepage of 1 is a slip as fast as the rolling speed"),
    "--eta": (-1.0, 1.0, "", "a creepage of 1 is a slip as fast as the rolling speed"),
    "--spin": (-100.0, 100.0, "1/m", "sin(contact angle) / rolling radius is below 5 1/m on "
               "real wheels; 100 1/m leaves room for yaw and small radii"),
    "--friction": (0.0, 1.0, "", "the range of vehicle files; dry steel on steel is about 0.5"),
    "--poisson": (0.0, 0.499, "", "the range of vehicle files; steel is 0.28-0.30"),
    "--shear-modulus": (1.0e9, 1.0e12, "Pa", "the range of vehicle files; steel is 80-82 GPa"),
    "--speed": (0.0, 150.0, "m/s", "Polach 2005's slip velocity needs a rolling speed; "
                "150 m/s is the limit of a run's speed"),
    "--gauge": (0.5, 2.0, "m", "track gauges in use are 0.6 m to 1.676 m"),
    "--flange-back": (0.4, 1.9, "m", "flange-back distances are about gauge - 75 mm"),
    "--radius": (0.1, 1.0, "m", "rolling radii of rail vehicles are 0.18 m to 0.63 m"),
    "--yaw-per-lateral": (-10.0, 10.0, "rad/m", "10 rad/m yaws the wheelset 0.1 rad at 10 mm"),
    "a/b": (0.1, 10.0, "", "the range of Kalker's coefficient table, which would clamp"),
}  # fmt: skip
POSITIVE = frozenset({"--load", "--semi-axes", "--curvatures", "--speed"})


def check_option(option: str, value: float) -> float:
    """``value`` of ``option`` checked against :data:`LIMITS` (:func:`check_within`)."""
    low, high, unit, why = LIMITS[option]
    return check_within(option, value, low, high, unit, why, low_open=option in POSITIVE)


#: a value that starts with "-": a negative number, or -inf / -nan (refused by the option's
#: type with what was expected, not taken for an unknown option)
_NEGATIVE_VALUE = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


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
