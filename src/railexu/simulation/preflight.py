"""Checks of a run's start before any model is built: does the initial state make sense?

An initial lateral offset is applied to the whole vehicle at the start of a run (the seed's
scenario: 2 mm). An offset that puts a wheel on its flange starts the run with an impact; one
that takes the wheel far up its flange starts it half-derailed, with a wheel lifted by
centimetres and unloaded, and the run's verdicts would describe that start, not the vehicle.
:func:`check_initial_offset` finds, from the wheel and rail profiles of each wheelset, where
flange contact begins and how far the wheel rises at the requested offset (rigid contact of a
wheelset that rests on both rails, Wickens 2003, ch. 2), and

- refuses (:class:`~railexu.errors.InputError`) an offset at which a wheel rises by
  ``settings.derailment_lift_fraction`` of its flange height or more (the run's own derailment
  criterion) or at which no rigid contact exists;
- warns when the offset puts a wheel in flange contact (contact angle above
  :data:`FLANGE_ANGLE_RAD`), naming where flange contact begins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railexu.errors import ComputationError, InputError

#: A contact angle above this is flange contact (the flank of S1002 is at 70 deg, its root
#: blends from the tread between 10 and 60 deg; 45 deg is the usual mark, also in the plots).
FLANGE_ANGLE_RAD = math.radians(45.0)
#: Resolution of the search for the onset of flange contact [m].
SCAN_STEP_M = 0.25e-3


@dataclass(frozen=True)
class OffsetCheck:
    """What the geometry says about an initial lateral offset of one wheelset.

    Attributes:
        wheelset: its name.
        offset_m: the offset checked [m].
        flange_contact_from_m: the smallest offset (same sign) with flange contact [m], or
            None if none up to the offset.
        max_contact_angle_rad: the larger contact angle of the two wheels at the offset [rad].
        wheel_rise_m: how far the flanging wheel's centre rises above its centred height [m].
        flange_height_m: the wheel's flange height above its tape circle [m].
    """

    wheelset: str
    offset_m: float
    flange_contact_from_m: float | None
    max_contact_angle_rad: float
    wheel_rise_m: float
    flange_height_m: float


def _contact_state(model, lateral_m: float) -> tuple[float, float]:
    """Largest contact angle of the two wheels [rad] and the rise of the higher wheel [m] at a
    lateral offset, for a wheelset resting on rigid rails."""
    from railexu.contact.quasistatic import rigid_contact

    rc = rigid_contact(model, lateral_m)
    centred = rigid_contact(model, 0.0)
    angles = []
    for side in ("left", "right"):
        s, g = model.gap_candidates(side, lateral_m, rc.vertical_m, rc.roll_rad, 0.0)
        pair = model.geometry.left if side == "left" else model.geometry.right
        slope = float(pair.wheel.slope(s[int(np.argmin(g))]))
        angles.append(abs(math.atan(slope)) + abs(rc.roll_rad))
    half_base = 0.75  # half the distance of the contact points [m]; the rise is insensitive
    rise = max(
        (rc.vertical_m - centred.vertical_m) + sign * half_base * (rc.roll_rad - centred.roll_rad)
        for sign in (1.0, -1.0)
    )
    return max(angles), rise


def check_wheelset_offset(
    name: str, model, offset_m: float, step_m: float = SCAN_STEP_M
) -> OffsetCheck:
    """Where flange contact begins between 0 and ``offset_m``, and the state at ``offset_m``.

    Args:
        model: the wheelset's :class:`~railexu.contact.evaluation.WheelsetContactModel`.

    Raises:
        ComputationError: no rigid contact at the offset (the wheel is off its rail).
    """
    wheel = model.geometry.left.wheel
    flange_height = float(np.max(wheel.height(np.linspace(wheel.y_min, wheel.y_max, 2001))))
    angle, rise = _contact_state(model, offset_m) if offset_m != 0.0 else (0.0, 0.0)
    onset = None
    if angle > FLANGE_ANGLE_RAD or rise > 0.5 * flange_height:
        # only then: where between the centre and the offset does flange contact begin?
        for k in range(1, int(abs(offset_m) / step_m) + 1):
            y = math.copysign(k * step_m, offset_m)
            if _contact_state(model, y)[0] > FLANGE_ANGLE_RAD:
                onset = y
                break
        else:
            onset = offset_m if angle > FLANGE_ANGLE_RAD else None
    return OffsetCheck(name, offset_m, onset, angle, rise, flange_height)


def check_initial_offset(vehicle, track, settings) -> list[str]:
    """Check the run's initial lateral offset against every wheelset's profiles.

    Returns:
        Warnings (flange contact at the start), to print and keep in the summary.

    Raises:
        InputError: the offset lifts a wheel by the derailment criterion's share of its flange
            height or more, or no rigid contact exists there; the message says the largest
            offset that starts on the tread.
    """
    from railexu.contact.evaluation import WheelsetContactModel
    from railexu.model.assembly import wheelset_geometry

    offset = float(settings.initial_lateral_m)
    if offset == 0.0:
        return []
    warnings: list[str] = []
    seen: dict[tuple, OffsetCheck] = {}
    for ws in vehicle.wheelsets:
        key = (ws.wheel_profile, ws.nominal_radius_m, ws.flange_back_distance_m)
        if key not in seen:
            model = WheelsetContactModel(wheelset_geometry(ws, track), vehicle.contact)
            try:
                seen[key] = check_wheelset_offset(ws.name, model, offset)
            except ComputationError:
                raise InputError(
                    f"an initial lateral offset of {offset * 1e3:g} mm takes wheelset "
                    f"{ws.name} off its rails (no rigid contact): give a smaller offset",
                    key="initial_lateral",
                ) from None
        check = seen[key]
        limit = settings.derailment_lift_fraction * check.flange_height_m
        onset = check.flange_contact_from_m
        tread_limit = "" if onset is None else f"; flange contact begins at {onset * 1e3:.2f} mm"
        if check.wheel_rise_m >= limit:
            raise InputError(
                f"an initial lateral offset of {offset * 1e3:g} mm lifts a wheel of wheelset "
                f"{ws.name} by {check.wheel_rise_m * 1e3:.1f} mm up its flange (the derailment "
                f"criterion is {limit * 1e3:.1f} mm){tread_limit}: give a smaller offset",
                key="initial_lateral",
            )
        if onset is not None:
            warnings.append(
                f"the initial lateral offset of {offset * 1e3:g} mm puts wheelset {ws.name} in "
                f"flange contact (contact angle {math.degrees(check.max_contact_angle_rad):.0f} "
                f"deg, wheel {check.wheel_rise_m * 1e3:.1f} mm up{tread_limit}): the run starts "
                "with a flange impact"
            )
    return warnings


#: Largest product of the rail masses' contact mode's angular frequency and the step: the
#: generalized-alpha step resolves a mode with omega h below 1 (some six steps per period,
#: Chung & Hulbert 1993); above, the mode's single-step force peaks depend on the step.
MAX_OMEGA_STEP = 1.0


def rail_contact_mode_rad_per_s(vehicle, track) -> float | None:
    """Angular frequency of an elastic track's rail mass on the stiffer of its ground spring
    and the wheel-rail contact [rad/s]: ``sqrt((k_rail + k_H) / m_rail)`` with Hertz's contact
    stiffness ``k_H = 1.5 Q / delta`` (``Q = K delta^1.5``) at the static wheel load, the
    largest over the wheels. None on a rigid track.

    This is the mode of the P1 force of Jenkins et al. (1974, "The effect of track and
    vehicle parameters on wheel/rail vertical dynamic forces", Railway Engineering Journal 3):
    the rail mass oscillating on the contact spring, some hundreds of Hz."""
    elastic = getattr(track, "elastic", None)
    if elastic is None:
        return None
    from railexu.contact.evaluation import WheelsetContactModel
    from railexu.contact.quasistatic import press_wheelset
    from railexu.model.assembly import wheelset_geometry
    from railexu.model.statics import static_equilibrium

    k_contact = 0.0
    geometries = [wheelset_geometry(ws, track) for ws in vehicle.wheelsets]
    tape = [g.left.tape_circle_lateral_m for g in geometries]
    loads = static_equilibrium(vehicle, tape).wheel_loads_N
    for geometry, load in zip(geometries, loads, strict=True):
        model = WheelsetContactModel(geometry, vehicle.contact)
        try:
            st = press_wheelset(model, 0.0, 0.0, (float(load[0]), float(load[1])))
        except RuntimeError:
            continue  # the run itself reports a wheelset that cannot carry its load
        result = model.evaluate(st.lateral_m, st.vertical_m, st.roll_rad, 0.0)
        for p in result.points:
            if p.penetration_m > 0.0 and p.normal_force_N > 0.0:
                k_contact = max(k_contact, 1.5 * p.normal_force_N / p.penetration_m)
    k_rail = max(elastic.lateral_stiffness_N_per_m, elastic.vertical_stiffness_N_per_m)
    return math.sqrt((k_rail + k_contact) / elastic.rail_mass_kg)


def check_time_step_for_track(vehicle, track, settings) -> list[str]:
    """On an elastic track, a warning naming ``time_step`` when the step does not resolve the
    rail masses' contact mode (:func:`rail_contact_mode_rad_per_s`). Measured on the EU07 bogie
    at 45 m/s (docs/curving.md): the hunting amplitude, the rails' spring forces and the 20 Hz
    low-pass wheel-rail forces do not depend on the step, the unfiltered force peaks do, and
    have not converged even far below this step (236, 274, 409, 539 kN at 0.5, 0.25, 0.125,
    0.0625 ms with the default track, before the contact search's rework)."""
    omega = rail_contact_mode_rad_per_s(vehicle, track)
    if omega is None:
        return []
    h_max = MAX_OMEGA_STEP / omega
    h = float(settings.time_step_s)
    if h <= h_max:
        return []
    return [
        f"time_step: {h * 1e3:g} ms does not resolve the elastic track's rail-mass contact mode "
        f"({omega / (2.0 * math.pi):.0f} Hz: rail mass on the wheel-rail contact spring); use "
        f"at most {h_max * 1e3:.2g} ms to resolve it. Unfiltered wheel-rail force peaks on the "
        "elastic track depend on the step even then; the hunting, the rail deflections and "
        "filtered forces do not (docs/curving.md)"
    ]


#: Where the rearmost wheelset stands beyond the track's ``start`` [m] (docs/track-format.md).
START_CLEARANCE_M = 1.0


def check_run_within_track(vehicle, track, settings) -> None:
    """Refuse, before any model is built, a run whose leading wheelset would leave the end of a
    designed or measured geometry: beyond it railexu could only continue on the last tangent,
    which is track the file does not describe. Straight track (no geometry) has no end.

    Raises:
        InputError: naming ``start`` or ``distance``, the end of the geometry and what fits.
    """
    check_run_within_vertical(vehicle, track, settings)
    alignment = getattr(track, "alignment", None)
    if alignment is None or alignment.is_straight:
        return
    wheelbase_m = _wheelbase_m(vehicle)
    start_m = float(track.start_m)
    end_m = float(alignment.end_m)
    if start_m + START_CLEARANCE_M + wheelbase_m >= end_m:
        raise InputError(
            f"the vehicle ({wheelbase_m:.3g} m between its outer wheelsets) placed at "
            f"{start_m:g} m is beyond the end of the track's geometry at {end_m:g} m",
            source=str(track.source or "track"), key="start",
        )  # fmt: skip
    _check_distance_fits(wheelbase_m, start_m, settings, end_m, "geometry", "lengthen the geometry")


def check_run_within_vertical(vehicle, track, settings) -> None:
    """Refuse a run whose wheelsets would leave a vertical profile given by stations or
    measured (``docs/curving.md``, "Vertical alignment"): before its first and beyond its last
    station it could only continue on the end gradient, a profile the file does not describe.
    A constant gradient has no ends.

    Raises:
        InputError: naming ``start`` or ``distance``, the profile's ends and what fits.
    """
    vertical = getattr(track, "vertical", None)
    if vertical is None or vertical.kind not in ("stations", "measured"):
        return
    wheelbase_m = _wheelbase_m(vehicle)
    rear_m = float(track.start_m) + START_CLEARANCE_M
    first_m, end_m = float(vertical.grid_m[0]), float(vertical.end_m)
    if rear_m < first_m - 1e-9 or rear_m + wheelbase_m >= end_m:
        raise InputError(
            f"the vehicle's rearmost wheelset at {rear_m:g} m (start + {START_CLEARANCE_M:g} m) "
            f"is outside the track's vertical profile, {first_m:g} m to {end_m:g} m",
            source=str(track.source or "track"), key="start",
        )  # fmt: skip
    _check_distance_fits(
        wheelbase_m, float(track.start_m), settings, end_m, "vertical profile", "add a station"
    )


def _wheelbase_m(vehicle) -> float:
    """The distance between the vehicle's outer wheelsets [m]."""
    xs = [w.position_x_m for w in vehicle.wheelsets]
    return max(xs) - min(xs)


def _check_distance_fits(wheelbase_m, start_m, settings, end_m, what, remedy) -> None:
    """Refuse a run distance that takes the leading wheelset beyond ``end_m`` [m], the end of
    the track's ``what`` (the key ``run.distance``, with what fits and ``remedy``)."""
    needed_m = start_m + START_CLEARANCE_M + wheelbase_m + float(settings.distance_m)
    if needed_m > end_m + 1e-9:
        fits_m = end_m - start_m - START_CLEARANCE_M - wheelbase_m
        raise InputError(
            f"{float(settings.distance_m):g} m from {start_m:g} m takes the leading wheelset to "
            f"{needed_m:g} m, beyond the end of the track's {what} at {end_m:g} m; at most "
            f"{fits_m:.4g} m fit (or {remedy})",
            key="run.distance",
        )
