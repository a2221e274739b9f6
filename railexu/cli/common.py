"""Helpers shared by the sub-commands: errors, ranges, overrides."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import InputError


class CliError(InputError):
    """Bad command-line input."""


def parse_range(text: str, name: str = "range") -> tuple[float, ...]:
    """Values from ``FROM:TO:STEP`` (inclusive of TO within half a step), or a single value,
    or a comma-separated list."""
    text = text.strip()
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) != 3:
                raise CliError(f"{name} {text!r}: expected FROM:TO:STEP")
            start, stop, step = parts
            if step <= 0 or stop < start:
                raise CliError(f"{name} {text!r}: need STEP > 0 and TO >= FROM")
            n = int(np.floor((stop - start) / step + 0.5)) + 1
            return tuple(float(np.round(start + i * step, 12)) for i in range(n))
        return tuple(float(v) for v in text.split(","))
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
