"""The summary of a run: a typed :class:`RunSummary` with the assessment of every criterion.

:func:`railexu.results.evaluate.summarize` evaluates a run's time series over its
**evaluation window** (from ``evaluate_from`` to ``evaluate_to``, m; by default from 20 m, or
10 % of the distance covered if that is less, to the end: the start-up transient after the
initial offset is left out) and returns a :class:`RunSummary`. ``RunSummary.to_dict()`` is the
content of ``summary.json``; the summary also reads like that dict
(``summary["hunting"]["detected"]``), so code written for the dict keeps working.

The criteria and their sources are in :mod:`railexu.assessment` and ``docs/assessment.md``.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from railexu.assessment.comfort import PointComfort
from railexu.assessment.criterion import Criterion, finite_or_none
from railexu.assessment.hunting import HuntingResult
from railexu.jsonable import jsonable
from railexu.results.timeseries import ResultsError

#: Version of the ``summary.json`` layout (1: before the typed summary and the assessment).
FORMAT_VERSION = 2


# ----------------------------------------------------------------------------------------------
# Typed summary
# ----------------------------------------------------------------------------------------------


@dataclass
class EvaluationWindow:
    """The stretch of the run every statistic and maximum is taken over (m)."""

    from_m: float
    to_m: float
    rule: str

    def to_dict(self) -> dict:
        return {"from_m": finite_or_none(self.from_m), "to_m": finite_or_none(self.to_m),
                "rule": self.rule}  # fmt: skip


@dataclass
class WheelsetSummary:
    """Lateral motion of one wheelset over the evaluation window (m)."""

    name: str
    max_abs_lateral_m: float | None
    final_amplitude_m: float | None
    final_max_abs_lateral_m: float | None

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "max_abs_lateral_m": finite_or_none(self.max_abs_lateral_m),
            "final_amplitude_m": finite_or_none(self.final_amplitude_m),
            "final_max_abs_lateral_m": finite_or_none(self.final_max_abs_lateral_m),
        }


@dataclass
class FlangeContact:
    """Flange contact in the evaluation window: whether, where first, and how long per wheel."""

    occurred: bool = False
    first_distance_m: float | None = None
    length_m: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "occurred": bool(self.occurred),
            "first_distance_m": finite_or_none(self.first_distance_m),
            "length_m": {k: finite_or_none(v) for k, v in self.length_m.items()},
        }


@dataclass
class Peak:
    """A raw (unwindowed) maximum: value, where and at which distance."""

    value: float | None = None
    where: str | None = None
    distance_m: float | None = None


@dataclass
class RunSummary(Mapping):
    """Summary of a run (SI units): the evaluation window, the motion, every criterion.

    It behaves like the dict of :meth:`to_dict` for reading (``summary["max_Y_over_Q"]``,
    ``summary.get("hunting")``), and ``summary[key] = value`` adds an extra top-level entry
    (timings, settings, warnings: see :attr:`extra`).
    """

    status: dict
    realtime_factor: float | None
    window: EvaluationWindow
    category: str
    wheelsets: list[WheelsetSummary]
    flange_contact: FlangeContact
    max_abs_lateral_force_N: float | None
    raw_y_over_q: Peak
    raw_y_over_q_2m: float | None
    nadal_limit: float | None  # None: the wheel has no flange
    y_over_q: Criterion
    raw_sum_y_N: float | None
    sum_y: Criterion
    running_stability: Criterion
    wheel_unloading: Criterion
    flange_climb: Criterion
    hunting: HuntingResult
    comfort: dict[str, PointComfort] = field(default_factory=dict)
    comfort_note: str = ""
    extra: dict = field(default_factory=dict)

    # -- verdicts ---------------------------------------------------------------------------

    @property
    def safety_criteria(self) -> dict[str, Criterion]:
        """The criteria whose exceedance makes a run unsafe, by name."""
        return {
            "y_over_q": self.y_over_q,
            "sum_y": self.sum_y,
            "running_stability": self.running_stability,
            "wheel_unloading": self.wheel_unloading,
            "flange_climb": self.flange_climb,
        }

    @property
    def exceedances(self) -> list[str]:
        """Names of the safety criteria exceeded (empty for a safe run)."""
        return [name for name, c in self.safety_criteria.items() if c.exceeded]

    @property
    def safety_exceeded(self) -> bool:
        """True when any safety criterion is exceeded: the run's status should say so."""
        return bool(self.exceedances)

    def state_with_exceedances(self, state: str) -> str:
        """The run state to report: ``"completed_with_exceedances"`` for a ``"completed"`` run
        that exceeds a safety criterion, else ``state`` unchanged (``"derailed"`` stays)."""
        return (
            "completed_with_exceedances" if state == "completed" and self.safety_exceeded else state
        )

    # -- JSON form ---------------------------------------------------------------------------

    def to_dict(self) -> dict:
        """The content of ``summary.json`` (JSON-serialisable; None where undefined)."""
        raw = self.raw_y_over_q
        out: dict[str, Any] = {
            "format_version": FORMAT_VERSION,
            "status": _jsonable(dict(self.status)),
            "realtime_factor": finite_or_none(self.realtime_factor),
            "evaluation_window": self.window.to_dict(),
            "wheelsets": [w.to_dict() for w in self.wheelsets],
            "flange_contact": self.flange_contact.to_dict(),
            "max_abs_lateral_force_N": finite_or_none(self.max_abs_lateral_force_N),
            "max_Y_over_Q": {
                "value": finite_or_none(raw.value),
                "wheel": raw.where,
                "distance_m": finite_or_none(raw.distance_m),
                "value_2m": finite_or_none(self.raw_y_over_q_2m),
                "value_en14363": self.y_over_q.value,
                "limit": self.y_over_q.limit,
                "nadal_limit": finite_or_none(self.nadal_limit),
                "exceeded": self.y_over_q.exceeded,
                "pass": self.y_over_q.passed,
            },
            "max_sum_Y_N": {
                "value": self.sum_y.value,
                "raw_value": finite_or_none(self.raw_sum_y_N),
                "wheelset": self.sum_y.where,
                "distance_m": self.sum_y.distance_m,
                "limit_N": self.sum_y.limit,
                "exceeded": self.sum_y.exceeded,
                "pass": self.sum_y.passed,
            },
            "running_stability": {
                "rms_sum_Y_N": self.running_stability.value,
                "limit_N": self.running_stability.limit,
                "band_Hz": self.running_stability.details.get("band_Hz"),
                "exceeded": self.running_stability.exceeded,
                "pass": self.running_stability.passed,
            },
            "hunting": self.hunting.to_dict(),
            "assessment": {
                "category": self.category,
                "safety_exceeded": self.safety_exceeded,
                "exceedances": self.exceedances,
                "criteria": {k: c.to_dict() for k, c in self.safety_criteria.items()},
            },
            "comfort": {
                "points": {k: c.to_dict() for k, c in self.comfort.items()},
                "note": self.comfort_note,
            },
        }
        out.update(_jsonable(self.extra))
        return out

    # -- dict-style access -----------------------------------------------------------------

    def __getitem__(self, key: str) -> Any:
        return self.to_dict()[key]

    def __setitem__(self, key: str, value: Any) -> None:
        self.extra[key] = value

    def __iter__(self) -> Iterator[str]:
        return iter(self.to_dict())

    def __len__(self) -> int:
        return len(self.to_dict())


# ----------------------------------------------------------------------------------------------
# summary.json
# ----------------------------------------------------------------------------------------------


_jsonable = jsonable


def write_summary(summary: Mapping[str, Any] | RunSummary, path: str | Path) -> Path:
    """Write ``summary`` (a :class:`RunSummary` or a dict) as JSON (indent 2); non-finite
    numbers become ``null``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(_jsonable(summary), indent=2, allow_nan=False)
    path.write_text(text + "\n", encoding="utf-8")
    return path


def read_summary(path: str | Path) -> dict:
    """Read a summary written by :func:`write_summary` (as a dict).

    Raises:
        ResultsError: naming the file, if it cannot be read or is not a JSON object.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ResultsError(f"{path}: cannot read summary: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise ResultsError(f"{path}: invalid JSON at line {exc.lineno}: {exc.msg}") from None
    if not isinstance(data, dict):
        raise ResultsError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data
