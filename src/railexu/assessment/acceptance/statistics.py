"""Statistical evaluation of a test zone's section values (EN 14363:2016, statistical evaluation
of the on-track test zones), with numpy (and Student's t quantile from scipy).

Each section of a zone gives one value per quantity (:mod:`.quantities`); the zone's *estimated
value* combines them:

- **one-dimensional** (straight track, or a curve zone evaluated without regression)::

      x_est = mean + k s,   s = sqrt(sum (x_i - mean)^2 / (N - 1))

  with ``k`` of the programme (2.2 for running safety and track loading, 3.0 for ride
  characteristics, as railexu attributes them to EN 14363; not found in a public text, so
  railexu's assumption: see ``docs/acceptance.md``);
- **two-dimensional** (curve zones): the least-squares regression of the section values on the
  zone's regressors (cant deficiency ``I`` and/or curvature ``1/R``), evaluated at the zone's
  limit conditions ``x0`` with the one-sided upper prediction bound::

      y_est = x0' b + t(N - p, q) s sqrt(1 + x0' (X'X)^-1 x0),   s^2 = RSS / (N - p)

  ``p`` the number of coefficients (intercept included), ``q`` the programme's quantile.

Quasi-static quantities (``Y_qst``, ``Q_qst``, the car body's quasi-static lateral
acceleration) are estimated without the dispersion term (the mean, or the regression at ``x0``):
they describe the curving itself, not its scatter (railexu's reading, stated in each result).

The running-stability criteria (the rms of sum Y of the normal measuring method, the rms of the
bogie frame's lateral acceleration of the simplified method) take the **largest section value**:
an instability is judged where it occurs, in any section, not as a zone's statistical estimate
(railexu's reading of EN 14363's stability assessment, stated in each result). Which method's
criteria decide is the programme's ``statistics.stability_method``; the other method's are
**informative**: value and limit reported, ``pass`` None, ``details.within_limit`` set.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from railexu.assessment.acceptance.limits import STANDARD, Limit
from railexu.errors import InputError

if TYPE_CHECKING:
    from railexu.assessment.acceptance.programme import Zone
    from railexu.assessment.acceptance.quantities import SectionValues

#: Quantities estimated without the dispersion term (see the module doc).
QUASI_STATIC = ("Y_qst", "Q_qst", "car_body_acc_y_qst")
#: Quantities of the ride characteristics (k of ride); every other one uses k of safety.
RIDE = ("car_body_acc_y_max", "car_body_acc_z_max", "car_body_acc_y_rms", "car_body_acc_z_rms")
CLAUSE = f"{STANDARD}, statistical evaluation of the test zones"
#: Running-stability criteria: the largest section value, no statistics (see the module doc).
STABILITY = ("sum_Y_rms", "bogie_frame_acc_y_rms")
#: The criteria of each measuring method that only it judges (``stability_method``).
METHOD_ONLY = {
    "normal": ("sum_Y_rms",),
    "simplified": ("bogie_frame_acc_y_max", "bogie_frame_acc_y_rms"),
}


class AcceptanceError(InputError):
    """An acceptance evaluation that cannot be made from the data given (too few sections,
    regressors without spread)."""


@dataclass(frozen=True)
class OneDimensional:
    """``estimate = mean + k std`` over ``n`` values."""

    estimate: float
    mean: float
    std: float
    k: float
    n: int


@dataclass(frozen=True)
class Regression:
    """The regression's value at ``at`` plus the prediction term ``t s sqrt(1 + h)``."""

    estimate: float
    fitted: float
    coefficients: tuple[float, ...]
    residual_std: float
    t: float
    leverage: float
    at: tuple[float, ...]
    n: int


@dataclass(frozen=True)
class CriterionResult:
    """One quantity of one zone against its limit.

    Attributes:
        name, unit: the quantity (a key of the section values) and its SI unit.
        value: the estimated value (None if not evaluated: see ``note``).
        limit: the limit value (None if the quantity has none in this zone).
        passed: ``value <= limit`` (None if either is missing).
        method: ``one_dimensional`` or ``two_dimensional``, with its parameters in ``details``.
        clause: the standard's clause of the statistics and of the limit.
        sections: names of the sections whose values were used.
        assumption: the limit or the statistics rest on a railexu assumption.
        details: mean, std, k, or the regression coefficients, t, leverage, the point x0.
    """

    name: str
    value: float | None
    limit: float | None
    unit: str
    passed: bool | None
    method: str
    clause: str
    sections: tuple[str, ...]
    assumption: bool
    details: dict = field(default_factory=dict)
    note: str = ""

    def to_dict(self) -> dict:
        """The JSON form (``pass`` for ``passed``, sections as a list)."""
        return {"name": self.name, "value": self.value, "limit": self.limit, "unit": self.unit,
                "pass": self.passed, "method": self.method, "clause": self.clause,
                "sections": list(self.sections), "assumption": self.assumption,
                "details": dict(self.details), "note": self.note}  # fmt: skip


@dataclass(frozen=True)
class ZoneResult:
    """The verdict of one zone: every criterion, passed if all evaluated criteria pass.

    ``reduced``: the zone was evaluated with fewer sections than the programme's minimum (the
    ``--quick`` variant): a trend, not an acceptance verdict.
    """

    zone: str
    method: str
    criteria: dict[str, CriterionResult]
    reduced: bool = False

    @property
    def passed(self) -> bool | None:
        """False if any criterion fails, None if none could be judged, else True."""
        verdicts = [c.passed for c in self.criteria.values() if c.passed is not None]
        if not verdicts:
            return None
        return all(verdicts)

    def to_dict(self) -> dict:
        """The JSON form."""
        return {"zone": self.zone, "method": self.method, "pass": self.passed,
                "reduced": self.reduced,
                "criteria": {k: c.to_dict() for k, c in self.criteria.items()}}  # fmt: skip


def one_dimensional(values: ArrayLike, k: float, minimum: int = 2) -> OneDimensional:
    """``mean + k s`` of the finite ``values`` (``s`` with ``N - 1``).

    Raises:
        AcceptanceError: fewer than ``minimum`` (and at least 2) finite values.
    """
    x = _finite(values)
    _need(x.size, max(2, minimum), "one-dimensional")
    mean, std = float(np.mean(x)), float(np.std(x, ddof=1))
    return OneDimensional(mean + k * std, mean, std, float(k), int(x.size))


def two_dimensional(
    values: ArrayLike, regressors: ArrayLike, at: Sequence[float], quantile: float,
    minimum: int = 0, dispersion: bool = True,
) -> Regression:  # fmt: skip
    """Least-squares ``y = b0 + sum b_j x_j`` over the sections, evaluated at ``at`` with the
    one-sided prediction bound ``t(N - p, quantile) s sqrt(1 + x0' (X'X)^-1 x0)``.

    Args:
        values: the section values ``y`` (N).
        regressors: ``(N, m)`` (or ``(N,)``) section conditions, m = 1 or 2.
        at: the zone's limit conditions, one per regressor column.
        quantile: one-sided quantile of Student's t (e.g. 0.95).
        minimum: the programme's least number of sections (at least ``p + 1``).
        dispersion: False leaves the prediction term out (quasi-static quantities).

    Raises:
        AcceptanceError: too few sections, or a regressor without spread.
    """
    y = np.asarray(values, dtype=float)
    x = np.asarray(regressors, dtype=float).reshape(y.size, -1)
    keep = np.isfinite(y) & np.all(np.isfinite(x), axis=1)
    y, x = y[keep], x[keep]
    p = x.shape[1] + 1
    _need(y.size, max(p + 1, minimum), "two-dimensional")
    design = np.column_stack([np.ones(y.size), x])
    if np.linalg.matrix_rank(design) < p:
        raise AcceptanceError(
            "the regressors of the two-dimensional evaluation do not vary independently over "
            "the sections (give sections with different cant deficiencies / radii)"
        )
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    residual = y - design @ coef
    s = math.sqrt(float(residual @ residual) / (y.size - p))
    x0 = np.concatenate(([1.0], np.asarray(at, dtype=float)))
    leverage = float(x0 @ np.linalg.solve(design.T @ design, x0))
    t = _student_t(quantile, y.size - p) if dispersion else 0.0
    fitted = float(x0 @ coef)
    return Regression(fitted + t * s * math.sqrt(1.0 + leverage), fitted,
                      tuple(float(c) for c in coef), s, t, leverage,
                      tuple(float(a) for a in at), int(y.size))  # fmt: skip


def evaluate_zone(
    zone: Zone, section_values: Sequence[SectionValues], limits: Mapping[str, Limit]
) -> ZoneResult:
    """Every quantity of the zone's sections, combined as the zone's ``method`` says, against
    ``limits`` (:func:`.limits.limits_for`).

    Raises:
        AcceptanceError: fewer sections than the zone's minimum (named in the message).
    """
    _need(len(section_values), zone.min_sections, f"zone {zone.name!r}")
    names = list(dict.fromkeys(n for sv in section_values for n in sv.values))
    criteria = {n: _criterion(zone, n, section_values, limits.get(n)) for n in names}
    return ZoneResult(zone.name, zone.method, criteria, reduced=zone.reduced)


def _criterion(zone: Zone, name: str, svs: Sequence[SectionValues], limit: Limit | None):
    values = np.array([sv.values.get(name, math.nan) for sv in svs], dtype=float)
    used = tuple(sv.section.name for sv, v in zip(svs, values, strict=True) if math.isfinite(v))
    unit = svs[0].units.get(name, "") if svs else ""
    quasi = name in QUASI_STATIC
    k = 0.0 if quasi else (zone.k_ride if name in RIDE else zone.k_safety)
    base = dict(name=name, limit=None if limit is None else limit.value, unit=unit,
                method=zone.method, sections=used)  # fmt: skip
    clause = CLAUSE + ("" if limit is None else f"; limit: {limit.clause}")
    assumption = zone.statistics_assumption or bool(limit and limit.assumption)
    if not used:
        why = next((sv.notes[name] for sv in svs if name in getattr(sv, "notes", {})), "")
        return CriterionResult(value=None, passed=None, clause=clause, assumption=assumption,
                               note=f"not evaluated: no section has a value ({why or 'NaN'})",
                               **base)  # fmt: skip
    try:
        if name in STABILITY:
            k_max = int(np.nanargmax(values))
            value, details = float(values[k_max]), {
                "rule": "largest section value: an instability is judged in every section, "
                "not statistically (railexu's reading)", "section": svs[k_max].section.name,
                "n": len(used)}  # fmt: skip
            base["method"] = "largest_section_value"
        elif zone.method == "one_dimensional":
            est = one_dimensional(values, k, zone.min_sections)
            value, details = est.estimate, {"mean": est.mean, "std": est.std, "k": est.k,
                                            "n": est.n, "rule": "mean + k std"}  # fmt: skip
        else:
            reg = two_dimensional(values, [sv.regressors(zone.regressors) for sv in svs],
                                  zone.evaluate_at, zone.prediction_quantile, zone.min_sections,
                                  dispersion=not quasi)  # fmt: skip
            value, details = reg.estimate, {
                "regressors": list(zone.regressors), "at": list(reg.at),
                "coefficients": list(reg.coefficients), "residual_std": reg.residual_std,
                "t": reg.t, "leverage": reg.leverage, "n": reg.n,
                "quantile": zone.prediction_quantile,
                "rule": "regression at the limit conditions + t s sqrt(1 + x0'(X'X)^-1 x0)",
            }  # fmt: skip
    except AcceptanceError as exc:
        return CriterionResult(value=None, passed=None, clause=clause, assumption=assumption,
                               note=f"not evaluated: {exc.detail}", **base)  # fmt: skip
    if quasi:
        details["note"] = "quasi-static quantity: no dispersion term (railexu's reading)"
    passed = None if limit is None else bool(value <= limit.value)
    note = ""
    if _informative(zone, name):
        details["within_limit"], passed = passed, None
        note = (
            f"informative: the programme judges running stability by the "
            f"{zone.stability_method} measuring method (statistics.stability_method)"
        )
    return CriterionResult(value=float(value), passed=passed, clause=clause,
                           assumption=assumption, details=details, note=note,
                           **base)  # fmt: skip


def _informative(zone: Zone, name: str) -> bool:
    """The criterion belongs to a measuring method the programme does not judge by."""
    method = getattr(zone, "stability_method", "normal")
    return any(name in names for m, names in METHOD_ONLY.items() if method not in (m, "both"))


def _finite(values: ArrayLike) -> np.ndarray:
    x = np.asarray(values, dtype=float).ravel()
    return x[np.isfinite(x)]


def _need(n: int, minimum: int, what: str) -> None:
    if n < minimum:
        raise AcceptanceError(
            f"{what}: {n} section value(s), the evaluation needs at least {minimum} sections"
        )


def _student_t(quantile: float, dof: int) -> float:
    """One-sided quantile of Student's t with ``dof`` degrees of freedom."""
    if not 0.5 <= quantile < 1.0:
        raise AcceptanceError(f"prediction quantile must be in [0.5, 1), got {quantile!r}")
    from scipy import stats

    return float(stats.t.ppf(quantile, dof))
