"""The time series of a run: equal-length columns, SI units, the unit in each column's name.

Column names (wheelsets numbered from 1 = leading, sides ``left``/``right`` seen in the direction
of travel; SI units, suffix = unit):

- ``time_s``, ``distance_m`` (always the first two columns);
- per wheelset ``i``: ``ws{i}_lateral_m`` (lateral displacement, positive to the left) and
  ``ws{i}_yaw_rad`` (yaw, positive counter-clockwise seen from above);
- per wheel (``side`` = ``left`` or ``right``): ``ws{i}_{side}_Y_N`` (lateral wheel-rail force on
  the wheel in the track frame, positive to the left), ``ws{i}_{side}_Q_N`` (vertical force on the
  wheel, positive up = load), ``ws{i}_{side}_n_contacts`` (number of loaded contact points) and
  ``ws{i}_{side}_max_angle_rad`` (largest contact angle among the loaded points, positive towards
  the flange, 0 if there is none);
- per wheel and contact point ``k`` (1 = tread, 2 = flange, ...), when recorded:
  ``ws{i}_{side}_p{k}_`` + ``wheel_y_m``, ``rail_y_m``, ``angle_rad``, ``creep_x``, ``creep_y``,
  ``spin_1_per_m``, ``Fx_N``, ``Fy_N``, ``N_N``, ``Tgamma_N``;
- accelerations at measurement points on bodies, when recorded: ``{point}_acc_y_m_per_s2``
  (lateral) and ``{point}_acc_z_m_per_s2`` (vertical), e.g. ``body_front``, ``body_centre``,
  ``body_rear``: what an accelerometer fixed in the body reads (specific force in the body's
  axes, the vertical less g; ``docs/conventions.md``);
- other bodies: ``{name}_lateral_m`` (``bogie_1_lateral_m``, ``car_body_lateral_m``, ...) and
  ``{name}_roll_rel_track_rad`` (roll relative to the design track's cant, left side up
  positive).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from railexu.errors import InputError

FloatArray = NDArray[np.float64]

_WHEELSET_LATERAL = re.compile(r"^ws(\d+)_lateral_m$")
_ACCELERATION = re.compile(r"^(.+)_acc_([yz])_m_per_s2$")


class ResultsError(InputError):
    """Invalid results data: bad time-series columns, unreadable CSV or summary file."""


class TimeSeries:
    """Equal-length columns of a run, in insertion order (SI units, name suffix = unit).

    Built from a dict of arrays in one go (no appending): ``TimeSeries({"time_s": t,
    "distance_m": x, "ws1_lateral_m": y1, ...})``. ``time_s`` and ``distance_m`` are required
    and are moved to the front if they are not already there; the order of the other columns is
    kept. Every column is stored as a 1-D ``float64`` array (counts such as ``_n_contacts`` too).

    Attributes:
        columns: ``name -> array``, all of the same length.
    """

    REQUIRED = ("time_s", "distance_m")

    def __init__(self, columns: Mapping[str, ArrayLike]) -> None:
        missing = [name for name in self.REQUIRED if name not in columns]
        if missing:
            raise ResultsError(f"time series lacks the required column(s) {', '.join(missing)}")
        order = list(self.REQUIRED) + [n for n in columns if n not in self.REQUIRED]
        data: dict[str, FloatArray] = {}
        length: int | None = None
        for name in order:
            if not isinstance(name, str) or not name or "," in name or name != name.strip():
                raise ResultsError(f"invalid column name {name!r} (non-empty, no comma/space)")
            try:
                arr = np.array(columns[name], dtype=float)
            except (TypeError, ValueError) as exc:
                raise ResultsError(f"column {name!r} is not numeric: {exc}") from None
            if arr.ndim != 1:
                raise ResultsError(f"column {name!r} must be 1-D, got shape {arr.shape}")
            if length is None:
                length = arr.size
            elif arr.size != length:
                raise ResultsError(
                    f"column {name!r} has {arr.size} rows, expected {length} (as 'time_s')"
                )
            data[name] = arr
        self.columns: dict[str, FloatArray] = data

    # -- container protocol ------------------------------------------------------------------

    def __len__(self) -> int:
        return int(self.columns["time_s"].size)

    def __getitem__(self, name: str) -> FloatArray:
        try:
            return self.columns[name]
        except KeyError:
            raise KeyError(f"no column {name!r} in the time series") from None

    def __contains__(self, name: object) -> bool:
        return name in self.columns

    def __repr__(self) -> str:
        return f"TimeSeries({len(self)} rows, columns={self.names})"

    @property
    def names(self) -> list[str]:
        """Column names in order."""
        return list(self.columns)

    @property
    def time_s(self) -> FloatArray:
        """Simulated time (s)."""
        return self.columns["time_s"]

    @property
    def distance_m(self) -> FloatArray:
        """Distance travelled along the track (m)."""
        return self.columns["distance_m"]

    # -- naming helpers ----------------------------------------------------------------------

    def wheelset_indices(self) -> list[int]:
        """1-based indices ``i`` of the wheelsets with a ``ws{i}_lateral_m`` column, ascending."""
        found = (_WHEELSET_LATERAL.match(n) for n in self.columns)
        return sorted(int(m.group(1)) for m in found if m)

    def wheelset_count(self) -> int:
        """Number of wheelsets (columns ``ws{i}_lateral_m``)."""
        return len(self.wheelset_indices())

    def body_names(self) -> list[str]:
        """Names of the other bodies with a lateral displacement (``bogie_1``, ``car_body``...):
        the ``{name}_lateral_m`` columns that are not wheelsets, in column order."""
        return [
            n[: -len("_lateral_m")]
            for n in self.columns
            if n.endswith("_lateral_m") and not _WHEELSET_LATERAL.match(n)
        ]

    def measurement_points(self) -> list[str]:
        """Names of the points with recorded accelerations (``{point}_acc_y_m_per_s2`` or
        ``{point}_acc_z_m_per_s2`` columns), in column order."""
        found = (_ACCELERATION.match(n) for n in self.columns)
        return list(dict.fromkeys(m.group(1) for m in found if m))

    def to_pandas(self) -> Any:
        """The series as a :class:`pandas.DataFrame` (one column per series column, same names).

        pandas is not a dependency of railexu: this needs it installed.

        Raises:
            ImportError: pandas is not installed.
        """
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError("TimeSeries.to_pandas() needs pandas: pip install pandas") from exc
        return pd.DataFrame({k: v.copy() for k, v in self.columns.items()})

    def truncated(self, n: int) -> TimeSeries:
        """A new series with the first ``n`` rows (copies)."""
        if n < 0:
            raise ValueError(f"n must be >= 0, got {n}")
        return TimeSeries({k: v[:n].copy() for k, v in self.columns.items()})

    # -- CSV -----------------------------------------------------------------------------------

    def to_csv(self, path: str | Path) -> Path:
        """Write a CSV file: one header row of column names, values as ``%.9g``."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        table = np.column_stack(list(self.columns.values())) if self.columns else np.empty((0, 0))
        with path.open("w", encoding="utf-8", newline="\n") as fh:
            fh.write(",".join(self.columns) + "\n")
            if len(self):
                np.savetxt(fh, table.reshape(len(self), -1), fmt="%.9g", delimiter=",")
        return path

    @classmethod
    def from_csv(cls, path: str | Path) -> TimeSeries:
        """Read a CSV file written by :meth:`to_csv` (header row of names, numbers below).

        Raises:
            ResultsError: naming the file and the problem (missing file, empty file, duplicate
                or missing columns, non-numeric value, wrong number of fields in a row).
        """
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise ResultsError(f"{path}: cannot read time series: {exc.strerror or exc}") from None
        lines = [ln for ln in text.splitlines() if ln.strip()]
        if not lines:
            raise ResultsError(f"{path}: empty file, expected a header row of column names")
        names = [s.strip() for s in lines[0].split(",")]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ResultsError(f"{path}: duplicate column name(s) {', '.join(dup)}")
        table = np.empty((len(lines) - 1, len(names)))
        for row, line in enumerate(lines[1:]):
            fields = line.split(",")
            if len(fields) != len(names):
                raise ResultsError(
                    f"{path}, line {row + 2}: {len(fields)} fields, expected {len(names)} "
                    "(one per header column)"
                )
            try:
                table[row] = [float(f) for f in fields]
            except ValueError:
                bad = next(f for f in fields if not _is_float(f))
                raise ResultsError(
                    f"{path}, line {row + 2}: value {bad.strip()!r} is not a number"
                ) from None
        try:
            return cls({n: table[:, j] for j, n in enumerate(names)})
        except ResultsError as exc:
            raise ResultsError(f"{path}: {exc}") from None


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
