"""Limit values of the EN 14363:2016 running-behaviour assessment, by vehicle category.

:func:`limits_for` gives one :class:`Limit` per quantity of :mod:`.quantities` (same names), each
with its value (SI), the clause it comes from and whether it is railexu's assumption. The text of
EN 14363:2016 is not public: the values below are those of the standard as published in the
public texts listed in ``docs/acceptance.md`` (the table of processing and percentiles of
EN 14363 / UIC 518 on gensys.se, ERA/TD/2012-17/INT for the 2005 edition, CEN/TR 17039:2017 on
the revision). A value railexu could not confirm in a public text is marked
``assumption=True`` and named so in every verdict; a programme file may replace any limit
(``limits:`` in the programme, :func:`limits_for`'s ``overrides``). :func:`zone_limits` takes
the conditions from a zone and the loads from the vehicle.

Formulas (forces in kN where the standard writes kN; converted to N here):

- track-shifting force ``(sum Y_2m)_lim = alpha (10 + 2 Q0 / 3)`` kN (Prud'homme), ``alpha`` = 1
  for locomotives, power heads, coaches and multiple units, 0.85 for freight wagons
  (:data:`railexu.assessment.en14363.ALPHA`);
- running stability (normal method, instability criterion): the rms of sum Y at most half the
  track-shifting limit, ``(sum Y_2m)_lim / 2``;
- derailment quotient ``(Y/Q)_lim = 0.8`` for curves of radius >= 250 m;
- quasi-static guiding force ``Y_qst,lim = 30 + 10500 / R_m`` kN (``R_m`` the zone's mean
  radius in m; 60 kN at 350 m);
- quasi-static wheel force ``Q_qst,lim = 145`` kN;
- maximum wheel force ``Q_max,lim = 90 + Q0`` kN, at most 200 kN (V <= 160 km/h), 190 (<= 200),
  180 (<= 250), 170 (<= 300), 160 kN (above);
- simplified method, bogie frame lateral acceleration: ``12 - m_b / 5`` m/s^2 for the peak,
  half of it for the rms (``m_b`` the bogie mass in t);
- car-body accelerations (normal method, ride characteristics): per category, see
  :data:`CAR_BODY_LIMITS`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from railexu.assessment import en14363
from railexu.assessment.en14363 import ALPHA, Y_OVER_Q_LIMIT, alpha_for
from railexu.errors import InputError

if TYPE_CHECKING:
    from railexu.assessment.acceptance.programme import Zone

#: The EN 14363:2016 running-behaviour assessment this module's clauses refer to.
STANDARD = "EN 14363:2016"
KN = 1.0e3


@dataclass(frozen=True)
class Limit:
    """One limit value.

    Attributes:
        name: the quantity it limits (a key of :class:`.quantities.SectionValues` ``values``).
        value: the limit (SI: N, m/s^2, or 1 for ratios).
        unit: ``"N"``, ``"m/s^2"`` or ``"1"``.
        clause: standard and clause (or ``"railexu assumption"``).
        rule: the formula with the numbers put in, in words.
        assumption: True if railexu could not confirm the value in a public text (or the
            programme file set it): a verdict against it is railexu's, not the standard's.
    """

    name: str
    value: float
    unit: str
    clause: str
    rule: str
    assumption: bool = False

    def to_dict(self) -> dict:
        keys = ("name", "value", "unit", "clause", "rule", "assumption")
        return {k: getattr(self, k) for k in keys}


#: Car-body acceleration limits of the normal method (ride characteristics) per category, m/s^2:
#: (max lateral, max vertical, rms lateral, rms vertical, quasi-static lateral). Values railexu
#: attributes to EN 14363 (the 2005 table of ride limits, kept in 2016) but could not find in a
#: public text (docs/acceptance.md records the search): railexu's assumption, marked so in every
#: verdict until confirmed against the purchased standard.
CAR_BODY_LIMITS: dict[str, tuple[float, float, float, float, float]] = {
    "locomotive": (2.8, 2.8, 0.5, 1.0, 1.5),
    "coach": (2.5, 2.5, 0.5, 0.75, 1.5),
    "multiple_unit": (2.5, 2.5, 0.5, 0.75, 1.5),
    "wagon": (3.0, 5.0, 1.3, 2.0, 1.5),
}
CAR_BODY_NAMES = (
    "car_body_acc_y_max",
    "car_body_acc_z_max",
    "car_body_acc_y_rms",
    "car_body_acc_z_rms",
    "car_body_acc_y_qst",
)
#: Q_max caps by speed: (highest speed km/h, cap kN).
Q_MAX_CAPS_KN = ((160.0, 200.0), (200.0, 190.0), (250.0, 180.0), (300.0, 170.0), (math.inf, 160.0))
#: The derailment quotient's limit 0.8 holds for curves of at least this radius (m).
Y_OVER_Q_MIN_RADIUS_M = 250.0
#: Limit of the quasi-static wheel force Q_qst (kN).
Q_QST_LIMIT_KN = 145.0


def track_shifting_limit_N(static_wheel_load_N: float, category: str) -> float:
    """``alpha (10 kN + 2 Q0 / 3)`` (N) with ``Q0`` the static wheel load (N): the formula of
    :func:`railexu.assessment.en14363.track_shifting_limit_N` (which takes the axle load 2 Q0)."""
    return en14363.track_shifting_limit_N(2.0 * static_wheel_load_N, alpha_for(category))


def y_qst_limit_N(mean_radius_m: float) -> float:
    """``Y_qst,lim = 30 kN + 10500 kN m / R_m`` (N); 60 kN at ``R_m`` = 350 m."""
    return (30.0 + 10500.0 / mean_radius_m) * KN


def q_max_limit_N(static_wheel_load_N: float, speed_m_per_s: float) -> float:
    """``Q_max,lim = 90 kN + Q0``, capped by speed (:data:`Q_MAX_CAPS_KN`) (N)."""
    v_kmh = speed_m_per_s * 3.6
    cap = next(c for v, c in Q_MAX_CAPS_KN if v_kmh <= v + 1e-9)
    return min(90.0 * KN + static_wheel_load_N, cap * KN)


def bogie_frame_limit_m_per_s2(bogie_mass_kg: float) -> float:
    """Simplified method: ``12 - m_b / 5`` (m/s^2), ``m_b`` the bogie mass in t."""
    return 12.0 - bogie_mass_kg / 1000.0 / 5.0


def limits_for(
    category: str,
    static_wheel_load_N: float,
    speed_m_per_s: float | None = None,
    mean_radius_m: float | None = None,
    bogie_mass_kg: float | None = None,
    overrides: Mapping[str, tuple[float, str]] | None = None,
) -> dict[str, Limit]:
    """The limits of one test zone for a vehicle of ``category``.

    Args:
        category: ``locomotive``, ``coach``, ``multiple_unit`` or ``wagon``
            (:data:`railexu.assessment.en14363.CATEGORIES`).
        static_wheel_load_N: ``Q0``, the vehicle's mean static wheel load (N).
        speed_m_per_s: the zone's highest test speed (for the cap of ``Q_max``); None leaves
            ``Q_max`` out.
        mean_radius_m: the zone's mean radius (for ``Y_qst``); None (straight track) leaves the
            quasi-static limits out.
        bogie_mass_kg: mass of one bogie (frame with wheelsets) for the simplified method; None
            leaves the bogie-frame limits out.
        overrides: ``{name: (value SI, note)}`` from the programme file: replaces the value,
            marks it as an assumption and keeps the note.

    Raises:
        InputError: unknown category, absurd loads, radius or speed, unknown override name.
    """
    alpha_for(category)
    _check_positive("static_wheel_load", static_wheel_load_N, 1.0e3, 2.0e5, "N")
    out: dict[str, Limit] = {}
    alpha = ALPHA[category]
    out["sum_Y_2m"] = Limit(
        "sum_Y_2m", track_shifting_limit_N(static_wheel_load_N, category), "N",
        f"{STANDARD}, running safety: track-shifting force (Prud'homme)",
        f"alpha (10 kN + 2 Q0 / 3), alpha = {alpha:g} ({category}), "
        f"Q0 = {static_wheel_load_N / KN:.2f} kN",
    )  # fmt: skip
    out["sum_Y_rms"] = Limit(
        "sum_Y_rms", 0.5 * out["sum_Y_2m"].value, "N",
        f"{STANDARD}, normal measuring method: running stability (instability criterion)",
        f"(sum Y_2m)_lim / 2 = {0.5 * out['sum_Y_2m'].value / KN:.2f} kN",
    )  # fmt: skip
    out["Y_over_Q_2m"] = Limit(
        "Y_over_Q_2m", Y_OVER_Q_LIMIT, "1", f"{STANDARD}, running safety: derailment quotient",
        "(Y/Q)_lim = 0.8 (curves of radius >= 250 m)",
    )  # fmt: skip
    if speed_m_per_s is not None:
        _check_positive("speed", speed_m_per_s, 0.1, 150.0, "m/s")
        out["Q_max"] = Limit(
            "Q_max", q_max_limit_N(static_wheel_load_N, speed_m_per_s), "N",
            f"{STANDARD}, track loading: maximum wheel force",
            f"90 kN + Q0, at most the cap of {speed_m_per_s * 3.6:.0f} km/h "
            "(200/190/180/170/160 kN up to 160/200/250/300 km/h/above)",
        )  # fmt: skip
    if mean_radius_m is not None:
        _check_positive("mean_radius", mean_radius_m, 100.0, 1.0e5, "m")
        out["Y_qst"] = Limit(
            "Y_qst", y_qst_limit_N(mean_radius_m), "N",
            f"{STANDARD}, track loading: quasi-static guiding force",
            f"30 kN + 10500 kN m / R_m, R_m = {mean_radius_m:.0f} m",
        )  # fmt: skip
        out["Q_qst"] = Limit(
            "Q_qst", Q_QST_LIMIT_KN * KN, "N",
            f"{STANDARD}, track loading: quasi-static wheel force", "Q_qst,lim = 145 kN",
        )  # fmt: skip
    if bogie_mass_kg is not None:
        _check_positive("bogie_mass", bogie_mass_kg, 100.0, 59_000.0, "kg")
        peak = bogie_frame_limit_m_per_s2(bogie_mass_kg)
        rule = f"m_b = {bogie_mass_kg / 1000.0:.2f} t"
        clause = f"{STANDARD}, simplified measuring method: bogie frame lateral acceleration"
        out["bogie_frame_acc_y_max"] = Limit(
            "bogie_frame_acc_y_max", peak, "m/s^2", clause, f"12 - m_b / 5, {rule}"
        )
        out["bogie_frame_acc_y_rms"] = Limit(
            "bogie_frame_acc_y_rms", 0.5 * peak, "m/s^2", clause, f"(12 - m_b / 5) / 2, {rule}"
        )
    if category not in CAR_BODY_LIMITS:
        raise InputError(f"no car-body acceleration limits for the category {category!r} "
                         f"(known: {', '.join(CAR_BODY_LIMITS)})", key="category")  # fmt: skip
    for name, value in zip(CAR_BODY_NAMES, CAR_BODY_LIMITS[category], strict=True):
        out[name] = Limit(
            name, value, "m/s^2",
            f"{STANDARD}, normal measuring method: ride characteristics ({category})",
            f"{value:g} m/s^2 for a {category}; value not confirmed in a public text",
            assumption=True,
        )  # fmt: skip
    return _overridden(out, overrides or {})


def _overridden(limits: dict[str, Limit], overrides: Mapping[str, tuple[float, str]]) -> dict:
    for name, (value, note) in overrides.items():
        if name not in limits:
            raise InputError(
                f"no limit named {name!r} for this zone; known: {', '.join(limits)}",
                key=f"limits.{name}",
            )
        if not (math.isfinite(value) and value > 0.0):
            raise InputError(f"expected a finite positive limit, got {value!r}",
                             key=f"limits.{name}")  # fmt: skip
        limits[name] = replace(
            limits[name], value=float(value), clause="railexu assumption (programme file)",
            rule=note or "set in the programme file", assumption=True,
        )  # fmt: skip
    return limits


def _check_positive(key: str, value: float, lo: float, hi: float, unit: str) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and lo <= value <= hi):
        raise InputError(f"expected a finite value in [{lo:g}, {hi:g}] {unit}, got {value!r}",
                         key=key)  # fmt: skip


def y_qst_limit_radius_m(zone: Any, radii: list[float]) -> float | None:
    """The radius of the ``Y_qst`` limit of a curve zone (m): the mean of the sections' radii
    ``radii`` (EN 14363's ``R_m``), or with the programme's ``y_qst_limit_radius: evaluation``
    the radius of the zone's limit conditions ``evaluate_at``, where the two-dimensional
    estimate is taken (the limit and the estimate then at one radius). None without radii."""
    if not radii:
        return None
    if getattr(zone, "y_qst_limit_radius", "mean") == "evaluation":
        regressors = tuple(getattr(zone, "regressors", ()))
        at = tuple(getattr(zone, "evaluate_at", ()))
        if "curvature" in regressors and len(at) == len(regressors):
            curvature = at[regressors.index("curvature")]
            if curvature > 0.0:
                return 1.0 / curvature
        return min(radii)  # a regression on cant deficiency alone: the zone's smallest radius
    return sum(radii) / len(radii)


def with_y_qst_radius_rule(limits: dict[str, Limit], zone: Any) -> dict[str, Limit]:
    """Say in the ``Y_qst`` limit's rule which radius it was taken at (and mark the reading
    railexu's assumption)."""
    if "Y_qst" in limits and "programme file" not in limits["Y_qst"].clause:
        how = getattr(zone, "y_qst_limit_radius", "mean")
        where = ("the zone's mean radius" if how == "mean"
                 else "the radius of the zone's limit conditions (evaluate_at)")  # fmt: skip
        y = limits["Y_qst"]
        limits["Y_qst"] = replace(y, rule=f"{y.rule} ({where}; programme statistics."
                                  f"y_qst_limit_radius: {how}, railexu assumption)",
                                  assumption=True)  # fmt: skip
    return limits


def zone_limits(
    category: str,
    zone: Zone,
    vehicle: Any,
    overrides: Mapping[str, tuple[float, str]] | None = None,
) -> dict[str, Limit]:
    """:func:`limits_for` with the zone's conditions and the vehicle's loads: the highest
    section speed (``Q_max``'s cap), the sections' mean radius (``Y_qst``; curves only), ``Q0``
    (:func:`.quantities.static_wheel_load_N`) and the bogie mass of the simplified method
    (:func:`.quantities.bogie_mass_kg`); ``overrides`` as the programme's ``limits``."""
    from railexu.assessment.acceptance.quantities import bogie_mass_kg, static_wheel_load_N

    sections = zone.sections()
    radii = [s.radius_m for s in sections if s.radius_m is not None]
    out = limits_for(
        category,
        static_wheel_load_N(vehicle),
        speed_m_per_s=max(s.speed_m_per_s for s in sections),
        mean_radius_m=y_qst_limit_radius_m(zone, radii),
        bogie_mass_kg=bogie_mass_kg(vehicle),
        overrides=overrides,
    )
    with_y_qst_radius_rule(out, zone)
    y_q = out["Y_over_Q_2m"]
    if radii and min(radii) < Y_OVER_Q_MIN_RADIUS_M and not y_q.assumption:
        out["Y_over_Q_2m"] = replace(y_q, assumption=True, rule=(
            f"{y_q.rule}; the zone has radii below {Y_OVER_Q_MIN_RADIUS_M:g} m, where railexu "
            "applies 0.8 as its assumption"))  # fmt: skip
    return out
