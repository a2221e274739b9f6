"""One assessment criterion: its value, limit, where it occurred, the window and rule used."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any


def finite_or_none(value: Any) -> float | None:
    """A finite Python float, or None (no -0.0)."""
    if value is None:
        return None
    v = float(value) + 0.0
    return v if math.isfinite(v) else None


@dataclass
class Criterion:
    """The evaluation of one criterion over a run's evaluation window.

    Attributes:
        value: the assessed value (in ``unit``), None if it could not be evaluated.
        limit: the limit it is compared with (None for information-only quantities).
        passed: ``value <= limit`` (None when either is missing); ``"pass"`` in the JSON.
        unit: the unit of value and limit (``"-"`` for ratios).
        where: the wheel or wheelset (``"ws1_left"``) or measurement point where it occurred.
        distance_m: distance at which it occurred (m; window centre for windowed values).
        window: the window the value is taken over (``"2 m sliding mean, 0.5 m steps"``).
        rule: how the value is formed and where the limit comes from (standard and clause, or
            railexu's choice), in words.
        details: further values (raw maxima, filter settings...).
    """

    value: float | None
    limit: float | None
    unit: str
    window: str
    rule: str
    where: str | None = None
    distance_m: float | None = None
    passed: bool | None = None
    details: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.value = finite_or_none(self.value)
        self.limit = finite_or_none(self.limit)
        self.distance_m = finite_or_none(self.distance_m)
        if self.passed is None and self.value is not None and self.limit is not None:
            self.passed = bool(self.value <= self.limit)

    @property
    def exceeded(self) -> bool:
        """True when the value is known and above its limit."""
        return self.passed is False

    def to_dict(self) -> dict:
        """The JSON form: ``value``, ``limit``, ``pass``, ``unit``, ``where``, ``distance_m``,
        ``window``, ``rule`` and the details."""
        out = {
            "value": self.value,
            "limit": self.limit,
            "pass": self.passed,
            "unit": self.unit,
            "where": self.where,
            "distance_m": self.distance_m,
            "window": self.window,
            "rule": self.rule,
        }
        out.update(self.details)
        return out
