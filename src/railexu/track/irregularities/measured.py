"""Measured irregularity records from CSV files."""

from __future__ import annotations

import csv
import math
import re
import warnings
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from railexu.track.irregularities.common import (
    _CSV_BASES,
    _FADE_DEFAULT_M,
    _UNIFORM_RTOL,
    IrregularityError,
    _did_you_mean,
)
from railexu.track.irregularities.profile import IrregularityProfile

# ----------------------------------------------------------------------------------------------
# Measured data
# ----------------------------------------------------------------------------------------------

_CSV_EXPECTED = tuple(f"{b}_{u}" for b in _CSV_BASES for u in ("m", "mm"))
_CSV_NAME = re.compile(r"^(distance|lateral|vertical|cross_level|gauge)_(m|mm)$")


def read_measured_irregularities(
    path: str | Path, fade_length_m: float = _FADE_DEFAULT_M
) -> IrregularityProfile:
    """Read measured irregularities from a CSV file.

    The first row that is neither blank nor a ``#`` comment is the header; it must name the five
    columns ``distance_m, lateral_m, vertical_m, cross_level_m, gauge_m`` (any order; each may
    instead carry ``_mm``, in which case the values are millimetres and are converted to
    metres; other columns are ignored). The quantities and signs are those of the module
    docstring. Distances must increase strictly; an unevenly spaced record is resampled onto a
    uniform grid with its median step by a not-a-knot cubic spline (with a warning). No
    filtering is applied.

    Raises:
        IrregularityError: naming the file, the line and column, and what was expected, for a
            missing or repeated column, a wrong number of fields, a non-numeric or non-finite
            value, a non-increasing distance, or fewer than two data rows.
        OSError: the file cannot be read.
    """
    path = Path(path)
    where = str(path)
    header: list[str] | None = None
    columns: dict[str, tuple[int, float, str]] = {}
    rows: list[list[float]] = []
    row_lines: list[int] = []
    header_line = 0
    with open(path, newline="", encoding="utf-8-sig") as fh:
        reader = csv.reader(fh)
        for row in reader:
            line = reader.line_num
            if not row or all(not f.strip() for f in row) or row[0].lstrip().startswith("#"):
                continue
            if header is None:
                header = [f.strip() for f in row]
                header_line = line
                columns = _parse_header(header, where, line)
                continue
            if len(row) != len(header):
                raise IrregularityError(
                    f"{where}, line {line}: expected {len(header)} comma-separated fields "
                    f"(as in the header on line {header_line}), found {len(row)}"
                )
            values = []
            for base in _CSV_BASES:
                idx, scale, name = columns[base]
                text = row[idx].strip()
                try:
                    value = float(text)
                except ValueError:
                    raise IrregularityError(
                        f"{where}, line {line}, column {idx + 1} ({name!r}): expected a "
                        f"number, found {text!r}"
                    ) from None
                if not math.isfinite(value):
                    raise IrregularityError(
                        f"{where}, line {line}, column {idx + 1} ({name!r}): expected a finite "
                        f"number, found {text!r}"
                    )
                values.append(value * scale)
            if rows and values[0] <= rows[-1][0]:
                idx, _, name = columns["distance"]
                raise IrregularityError(
                    f"{where}, line {line}, column {idx + 1} ({name!r}): expected a distance "
                    f"greater than {rows[-1][0]:g} m (line {row_lines[-1]}), "
                    f"found {values[0]:g} m; distances must increase strictly"
                )
            rows.append(values)
            row_lines.append(line)
    if header is None:
        raise IrregularityError(
            f"{where}: no header row; expected the columns {', '.join(_default_names())}"
        )
    if len(rows) < 2:
        raise IrregularityError(
            f"{where}: expected at least 2 data rows after the header on line {header_line}, "
            f"found {len(rows)}"
        )
    data = np.asarray(rows, dtype=float)
    x = data[:, 0]
    dx = np.diff(x)
    h = (x[-1] - x[0]) / (x.size - 1)
    description = f"measured: {where}"
    if np.max(np.abs(dx - h)) > _UNIFORM_RTOL * h:
        step = float(np.median(dx))
        n = max(1, round((x[-1] - x[0]) / step)) + 1
        grid = np.linspace(x[0], x[-1], n)
        warnings.warn(
            f"{where}: distances are not evenly spaced (steps {dx.min():g}-{dx.max():g} m); "
            f"resampled onto a uniform grid of {n} points by cubic spline",
            UserWarning,
            stacklevel=2,
        )
        data = np.column_stack([grid, CubicSpline(x, data[:, 1:], axis=0)(grid)])
        description += " (resampled to a uniform grid)"
    else:
        data[:, 0] = x[0] + h * np.arange(x.size)
        data[-1, 0] = x[-1]
    try:
        return IrregularityProfile(
            distance_m=data[:, 0],
            lateral_m=data[:, 1],
            vertical_m=data[:, 2],
            cross_level_m=data[:, 3],
            gauge_m=data[:, 4],
            fade_length_m=fade_length_m,
            description=description,
        )
    except IrregularityError as exc:
        raise IrregularityError(f"{where}: {exc}") from None


def _default_names() -> list[str]:
    return [f"{b}_m" for b in _CSV_BASES]


def _parse_header(header: list[str], where: str, line: int) -> dict[str, tuple[int, float, str]]:
    columns: dict[str, tuple[int, float, str]] = {}
    unknown: list[str] = []
    for idx, raw in enumerate(header):
        m = _CSV_NAME.match(raw.lower())
        if m is None:
            unknown.append(raw)
            continue
        base, unit = m.group(1), m.group(2)
        if base in columns:
            raise IrregularityError(
                f"{where}, line {line}, column {idx + 1} ({raw!r}): {base!r} is already given "
                f"by column {columns[base][0] + 1} ({columns[base][2]!r}); expected one "
                f"column per quantity"
            )
        columns[base] = (idx, 1.0 if unit == "m" else 1e-3, raw)
    missing = [b for b in _CSV_BASES if b not in columns]
    if missing:
        hints = "".join(_did_you_mean(u.lower(), _CSV_EXPECTED) for u in unknown)
        raise IrregularityError(
            f"{where}, line {line} (header): missing column(s) "
            + ", ".join(f"{b}_m (or {b}_mm)" for b in missing)
            + f"; expected {', '.join(_default_names())}; found {', '.join(header)}."
            + hints
        )
    return columns
