"""Quasi-static wheel/rail check: the public function behind ``railexu contact``.

An engineer checks a wheel/rail pair before any dynamics: for a sweep of lateral displacements
(with yaw proportional to it, as in the Manchester contact benchmark), each wheel is pressed onto
its rail until it carries the given load, while the wheelset rolls forward at a speed and spins
freely (the pitch rate at which the creep forces exert no pitch moment, as CONTACT sets up the
benchmark) or, on request, at speed / nominal radius. A position where the wheelset cannot be
pressed is reported with its status and a warning, and the sweep goes on. Every contact point is
reported with its position on wheel and rail, rolling radius, contact angle, ellipse, creepages and
creep forces; the rolling radius difference and the equivalent conicity follow from the rigid
contact.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from railexu.contact.conicity import ConicityError, equilibrium_lateral, equivalent_conicity
from railexu.contact.creep import spin_moment
from railexu.contact.evaluation import ContactParameters, ContactPoint, WheelsetContactModel
from railexu.contact.kalker import kalker_coefficients
from railexu.contact.kik_piotrowski import patch_creep_forces, wheel_point_patch
from railexu.contact.parameters import ContactParameterError
from railexu.contact.placement import wheelset_geometry
from railexu.contact.quasistatic import (
    ContactSolveError,
    PressedWheelset,
    press_free_rolling,
    press_wheelset,
)
from railexu.contact.standard_gauge import STANDARD_FLANGE_BACK_M, STANDARD_GAUGE_M

#: Rolling conditions of :func:`contact_check`.
ROLLING_MODES = ("free", "nominal")

#: Normal contact models of :func:`contact_check`: ``hertz`` (the kernel's), or
#: ``kik_piotrowski`` reported beside it at the same pose and approach.
CHECK_NORMAL_MODELS = ("hertz", "kik_piotrowski")

#: Extra ``contact.csv`` columns with ``normal_model = "kik_piotrowski"``.
KP_COLUMNS = (
    "kp_normal_force_N",
    "kp_p_max_Pa",
    "kp_length_m",
    "kp_width_m",
    "kp_force_long_N",
    "kp_force_lat_N",
    "kp_spin_moment_Nm",
)

#: Largest number of lateral positions or amplitudes a check accepts.
MAX_SWEEP_POINTS = 10001

#: Columns of ``contact.csv`` (units in the names; angles in rad, creepages dimensionless).
CONTACT_COLUMNS = (
    "lateral_m",
    "yaw_rad",
    "roll_rad",
    "vertical_m",
    "side",
    "point",
    "wheel_lateral_m",
    "rail_lateral_m",
    "contact_x_m",
    "contact_y_m",
    "contact_z_m",
    "rolling_radius_m",
    "contact_angle_rad",
    "penetration_m",
    "normal_force_N",
    "a_m",
    "b_m",
    "creep_long",
    "creep_lat",
    "spin_per_m",
    "force_long_N",
    "force_lat_N",
    "force_x_track_N",
    "force_y_track_N",
    "force_z_track_N",
    "wheel_curvature_long_per_m",
    "wheel_curvature_lat_per_m",
    "rail_curvature_lat_per_m",
    "spin_moment_Nm",
    "pitch_rate_rad_per_s",
    "status",
)


@dataclass(frozen=True)
class ContactCheckSettings:
    """Settings of a quasi-static contact check (defaults: the Manchester contact benchmark).

    Attributes:
        wheel, rail: built-in profile names or profile files (the wheel: both wheels, or the
            left one when ``wheel_right`` is given).
        wheel_right: profile of the right wheel if it differs (asymmetric wheelset).
        inclination: rail inclination (``"1:40"``, ``"1:20"``, ``"none"``).
        gauge_m: track gauge measured 14 mm below the top of rail [m].
        flange_back_m: flange-back distance of the wheelset [m].
        radius_m: nominal rolling radius [m] (the left wheel's when ``radius_right_m`` is set).
        radius_right_m: nominal rolling radius of the right wheel [m], if it differs.
        rolling: ``"free"`` (default; zero pitch moment) or ``"nominal"`` (spin V / r0).
        normal_model: ``"hertz"`` (default) or ``"kik_piotrowski"``: the wheelset is pressed
            with the kernel's Hertz contacts, and each loaded point's Kik-Piotrowski patch (same
            pose, same approach) and FASTSIM forces on it are reported beside
            (:mod:`.kik_piotrowski`; ``KP_COLUMNS``).
        lateral_m: lateral displacements to evaluate [m].
        yaw_per_lateral_rad_per_m: yaw = factor * lateral [rad/m].
        load_N: vertical load of each wheel [N].
        speed_m_per_s: forward speed [m/s]; the wheelset spins at speed / radius.
        contact: contact parameters (material, friction, creep law).
        conicity_amplitudes_m: amplitudes for the equivalent conicity [m].
    """

    wheel: str = "S1002"
    rail: str = "UIC60"
    inclination: str | float = "1:40"
    gauge_m: float = STANDARD_GAUGE_M
    flange_back_m: float = STANDARD_FLANGE_BACK_M
    radius_m: float = 0.46
    lateral_m: tuple[float, ...] = tuple(np.round(np.arange(0.0, 0.01 + 1e-12, 0.0005), 10))
    yaw_per_lateral_rad_per_m: float = 0.0
    load_N: float = 10000.0
    speed_m_per_s: float = 2.0
    contact: ContactParameters = field(default_factory=ContactParameters)
    conicity_amplitudes_m: tuple[float, ...] = tuple(
        np.round(np.arange(0.0005, 0.01 + 1e-12, 0.0005), 10)
    )
    wheel_right: str | None = None
    radius_right_m: float | None = None
    rolling: str = "free"
    normal_model: str = "hertz"

    def __post_init__(self) -> None:
        if self.normal_model not in CHECK_NORMAL_MODELS:
            raise ContactParameterError(
                f"normal model {self.normal_model!r}: expected one of "
                f"{', '.join(CHECK_NORMAL_MODELS)}"
            )
        if self.rolling not in ROLLING_MODES:
            raise ContactParameterError(
                f"rolling {self.rolling!r}: expected one of {', '.join(ROLLING_MODES)}"
            )
        for name in ("lateral_m", "conicity_amplitudes_m"):
            n = len(getattr(self, name))
            if not 1 <= n <= MAX_SWEEP_POINTS:
                raise ContactParameterError(f"{name}: {n} values; expected 1 .. {MAX_SWEEP_POINTS}")


@dataclass
class ContactCheckResult:
    """Outcome of :func:`contact_check`."""

    settings: ContactCheckSettings
    model: WheelsetContactModel
    pressed: list[PressedWheelset]
    rows: list[dict]
    conicity_amplitude_m: np.ndarray
    conicity: np.ndarray
    delta_r_lateral_m: np.ndarray
    delta_r_m: np.ndarray
    pitch_rates_rad_per_s: list[float] = field(default_factory=list)
    failures: list[tuple[float, str]] = field(default_factory=list)
    equilibrium_lateral_m: float = float("nan")

    @property
    def columns(self) -> tuple[str, ...]:
        """The columns of ``contact.csv``."""
        if self.settings.normal_model == "kik_piotrowski":
            return CONTACT_COLUMNS + KP_COLUMNS
        return CONTACT_COLUMNS


def _geometry(settings: ContactCheckSettings):
    wheel = settings.wheel
    if settings.wheel_right is not None:
        wheel = {"left": settings.wheel, "right": settings.wheel_right}
    radius = settings.radius_m
    if settings.radius_right_m is not None:
        radius = {"left": settings.radius_m, "right": settings.radius_right_m}
    return wheelset_geometry(
        wheel,
        settings.rail,
        nominal_radius_m=radius,
        inclination=settings.inclination,
        gauge_m=settings.gauge_m,
        flange_back_distance_m=settings.flange_back_m,
    )


def _point_row(p: ContactPoint, params: ContactParameters) -> dict:
    c11, c22, c23 = kalker_coefficients(p.a_m / p.b_m, params.poisson)
    mz = spin_moment(
        params.creep_model, p.creep_long, p.creep_lat, p.spin_per_m, p.normal_force_N,
        p.a_m, p.b_m, params.shear_modulus_Pa, c11, c22, c23, params.friction,
    )  # fmt: skip
    return {
        "side": p.side,
        "point": p.point,
        "wheel_lateral_m": p.wheel_lateral_m,
        "rail_lateral_m": p.rail_lateral_m,
        "contact_x_m": p.position_m[0],
        "contact_y_m": p.position_m[1],
        "contact_z_m": p.position_m[2],
        "rolling_radius_m": p.rolling_radius_m,
        "contact_angle_rad": p.contact_angle_rad,
        "penetration_m": p.penetration_m,
        "normal_force_N": p.normal_force_N,
        "a_m": p.a_m,
        "b_m": p.b_m,
        "creep_long": p.creep_long,
        "creep_lat": p.creep_lat,
        "spin_per_m": p.spin_per_m,
        "force_long_N": p.force_long_N,
        "force_lat_N": p.force_lat_N,
        "force_x_track_N": p.force_track_N[0],
        "force_y_track_N": p.force_track_N[1],
        "force_z_track_N": p.force_track_N[2],
        "wheel_curvature_long_per_m": p.wheel_curvature_long_per_m,
        "wheel_curvature_lat_per_m": p.wheel_curvature_lat_per_m,
        "rail_curvature_lat_per_m": p.rail_curvature_lat_per_m,
        "spin_moment_Nm": mz if params.tangential else 0.0,
    }


def _kp_row(model, state: PressedWheelset, p: ContactPoint, params: ContactParameters) -> dict:
    kp = wheel_point_patch(
        model, p.side, state.lateral_m, state.vertical_m, state.roll_rad, state.yaw_rad,
        p.wheel_lateral_m, p.contact_angle_rad,
    )  # fmt: skip
    fx, fy, mz = patch_creep_forces(
        kp, p.creep_long, p.creep_lat, p.spin_per_m, params.friction, params.shear_modulus_Pa,
        params.poisson,
    )  # fmt: skip
    return {
        "kp_normal_force_N": kp.normal_force_N,
        "kp_p_max_Pa": kp.p_max_Pa,
        "kp_length_m": 2.0 * kp.half_length_m,
        "kp_width_m": kp.lateral_extent_m[1] - kp.lateral_extent_m[0],
        "kp_force_long_N": fx,
        "kp_force_lat_N": fy,
        "kp_spin_moment_Nm": mz,
    }


def contact_check(settings: ContactCheckSettings) -> ContactCheckResult:
    """Run the quasi-static check: press the wheelset at each lateral displacement, report.

    A lateral position where the wheelset cannot be pressed (a wheel off its rail, no
    convergence) gives one ``contact.csv`` row with ``status = failed: ...`` and a
    :class:`RuntimeWarning`; the sweep goes on. The rigid-contact conicity uses the integral
    method of EN 15302 about the wheelset's equilibrium position (:mod:`.conicity`); an amplitude
    it cannot reach is NaN.
    """
    geometry = _geometry(settings)
    model = WheelsetContactModel(geometry, settings.contact, settings.speed_m_per_s)
    pressed: list[PressedWheelset] = []
    rows: list[dict] = []
    rates: list[float] = []
    failures: list[tuple[float, str]] = []
    for y in settings.lateral_m:
        yaw = settings.yaw_per_lateral_rad_per_m * y
        try:
            if settings.rolling == "free":
                state, rate = press_free_rolling(model, float(y), float(yaw), settings.load_N)
            else:
                state = press_wheelset(model, float(y), float(yaw), settings.load_N)
                rate = settings.speed_m_per_s / geometry.left.nominal_radius_m
        except ContactSolveError as exc:
            message = str(exc)
            warnings.warn(
                f"contact check: lateral position {float(y) * 1e3:.3f} mm skipped: {message}",
                RuntimeWarning,
                stacklevel=2,
            )
            failures.append((float(y), message))
            row = dict.fromkeys(CONTACT_COLUMNS + KP_COLUMNS, float("nan"))
            row.update(lateral_m=float(y), yaw_rad=float(yaw), side="", point=0)
            row["status"] = f"failed: {message}"
            rows.append(row)
            continue
        pressed.append(state)
        rates.append(rate)
        for p in state.result.points:
            if not p.loaded:
                continue
            row = {
                "lateral_m": float(y),
                "yaw_rad": float(yaw),
                "roll_rad": state.roll_rad,
                "vertical_m": state.vertical_m,
            }
            row.update(_point_row(p, settings.contact))
            if settings.normal_model == "kik_piotrowski":
                row.update(_kp_row(model, state, p, settings.contact))
            row["pitch_rate_rad_per_s"] = rate
            row["status"] = "ok"
            rows.append(row)
    _renumber(rows)
    amps = np.asarray(settings.conicity_amplitudes_m, dtype=float)
    conicity, y_dr, dr = equivalent_conicity(model, amps, out_of_range="nan")
    try:
        y_eq = equilibrium_lateral(model)
    except ConicityError:
        y_eq = float("nan")
    return ContactCheckResult(
        settings, model, pressed, rows, amps, conicity, y_dr, dr, rates, failures, y_eq
    )


def _renumber(rows: list[dict]) -> None:
    """Number the loaded points of each wheel 1, 2, ... from the tread towards the flange."""
    groups: dict[tuple[float, str], list[dict]] = {}
    for r in rows:
        if r["status"] != "ok":
            continue
        groups.setdefault((r["lateral_m"], r["side"]), []).append(r)
    for group in groups.values():
        group.sort(key=lambda r: -r["wheel_lateral_m"])
        for i, r in enumerate(group, start=1):
            r["point"] = i


def _fmt(v):
    if isinstance(v, float) and v != v:
        return ""
    if isinstance(v, float):
        return f"{v:.10g}"
    return v
