"""The analysis behind ``railexu critical-speed``: the chosen methods, and why linear and
nonlinear values differ when they do."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict

from railexu.jsonable import jsonable
from railexu.stability.branch import branch_critical_speed
from railexu.stability.linear import HUNTING_MODES, linear_stability
from railexu.stability.nonlinear import bisection_critical_speed
from railexu.stability.ramp import ramp_critical_speed
from railexu.stability.settings import CriticalSpeedSettings
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle


def critical_speed(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: CriticalSpeedSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Critical speed of ``vehicle`` by the chosen methods; returns the content of
    ``critical_speed.json``: ``linear_m_per_s``, ``nonlinear_bisection_m_per_s``,
    ``nonlinear_ramp_m_per_s`` (None where a method was not run, found no crossing in the
    range or, for the ramp, its two rates disagree), ``nonlinear_ramp_fold_m_per_s``,
    ``nonlinear_branch_m_per_s`` (the lowest speed with a sustained cycle),
    ``nonlinear_branch_fold_m_per_s`` and ``nonlinear_branch_fold_bracket_m_per_s`` (where the
    branch followed from the top speed ends: its fold), one section per method with its
    details, and the settings used."""
    settings = settings or CriticalSpeedSettings()
    track = track or ideal_straight_track()
    out: dict = {
        "vehicle": vehicle.name,
        "track": track.name,
        "linear_m_per_s": None,
        "nonlinear_bisection_m_per_s": None,
        "nonlinear_ramp_m_per_s": None,
        "nonlinear_branch_m_per_s": None,
        "settings": asdict(settings),
    }
    if "linear" in settings.methods:
        out["linear"] = linear_stability(vehicle, track, settings, progress)
        out["linear_m_per_s"] = out["linear"]["critical_speed_m_per_s"]
        out["linear_mode"] = out["linear"]["critical_mode"]
    if "bisection" in settings.methods:
        out["bisection"] = bisection_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_bisection_m_per_s"] = out["bisection"]["critical_speed_m_per_s"]
    if "ramp" in settings.methods:
        out["ramp"] = ramp_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_ramp_m_per_s"] = out["ramp"]["critical_speed_m_per_s"]
        out["nonlinear_ramp_fold_m_per_s"] = out["ramp"].get("fold_m_per_s")
    if "branch" in settings.methods:
        out["branch"] = branch_critical_speed(vehicle, track, settings, progress)
        out["nonlinear_branch_m_per_s"] = out["branch"]["critical_speed_m_per_s"]
        fold = out["branch"].get("fold") or {}
        out["nonlinear_branch_fold_m_per_s"] = fold.get("speed_m_per_s")
        out["nonlinear_branch_fold_bracket_m_per_s"] = fold.get("bracket_m_per_s")
    out["comparison"] = compare_linear_nonlinear(out, settings)
    return out


#: Linear and nonlinear critical speeds that differ by more than this fraction get an
#: explanation in words.
COMPARISON_TOLERANCE = 0.25


def compare_linear_nonlinear(result: dict, settings: CriticalSpeedSettings) -> str | None:
    """Why the linear and a nonlinear critical speed differ by more than 25 %, in words (None
    when they agree, or when one of them is missing).

    The reasons, in the order they are checked: the linear value belongs to a car-body mode
    (weakly damped, a motion of the car body on the suspension elements joined to it, named
    from the vehicle; unstable only in a band when it is; the wheelsets' amplitude, which the
    nonlinear runs judge, stays small); the
    nonlinear value is the lower one (a subcritical bifurcation: the wheel-rail contact's
    nonlinearity lets a large disturbance settle into a limit cycle below the linear value); the
    nonlinear value is the higher one (the linearisation's equivalent conicity, taken at one
    amplitude, is larger than what the run's small motion sees, or near the linear value the
    motion changes by less than the growth-rate classification resolves)."""
    linear = result.get("linear_m_per_s")
    nonlinear = {k: result.get(f"nonlinear_{k}_m_per_s") for k in ("branch", "bisection", "ramp")}
    nonlinear = {k: v for k, v in nonlinear.items() if v is not None}
    if linear is None or not nonlinear:
        return None
    method, value = min(nonlinear.items(), key=lambda kv: abs(kv[1] - linear))
    if abs(value - linear) <= COMPARISON_TOLERANCE * value:
        return None
    lin = result.get("linear") or {}
    mode = lin.get("critical_mode") or "hunting"
    gap = abs(value - linear) / value
    head = (
        f"The linear critical speed ({linear:.1f} m/s, {mode} mode) and the nonlinear one "
        f"({method}, {value:.1f} m/s) differ by {gap:.0%}: "
    )
    name = (lin.get("modes") or {}).get(mode, {}).get("name", mode)
    if name not in HUNTING_MODES:
        hunting = lin.get("hunting_critical_speed_m_per_s")
        tail = " No hunting mode crosses zero in the range."
        if hunting is not None:
            tail = f" The hunting modes' damping crosses zero at {hunting:.1f} m/s."
        return (
            head
            + _car_body_words(lin, mode)
            + (
                " It grows slowly and moves the wheelsets little, so in the nonlinear runs the "
                "wheelsets' oscillation stays small within the distance run." + tail
            )
        )
    if value < linear:
        return head + (
            "the nonlinear value is lower: a subcritical bifurcation. The wheel-rail contact is "
            "nonlinear (the conicity grows with the amplitude towards the flange), so a "
            f"disturbance of {settings.initial_lateral_m * 1e3:g} mm settles into a limit cycle "
            "below the speed at which small motions become unstable; the limit-cycle branch "
            "(and the ramp) show where that limit cycle vanishes."
        )
    return head + (
        "the nonlinear value is higher: the linear analysis uses the equivalent conicity at "
        f"{settings.conicity_amplitude_m * 1e3:g} mm, larger than the conicity the run's small "
        "motion sees near the centre, or near the linear value the motion changes by less than "
        "the classification resolves within the fit window (1 % per period, and about 0.13 / N "
        f"per period over N periods of a {settings.distance_m:g} m run)."
    )


def _car_body_words(lin: dict, mode: str) -> str:
    """``the linear value belongs to the weakly damped car-body yaw mode, a motion of the car
    body on <its suspension elements>`` (the vehicle's own element names), with its band when it
    is unstable only in one."""
    elements = lin.get("car_body_suspension") or []
    on = f" on {', '.join(elements[:4])}" + (" and others" if len(elements) > 4 else "")
    name = (lin.get("modes") or {}).get(mode, {}).get("name", mode)
    text = f"the linear value belongs to the weakly damped {mode} mode"
    if name.startswith("car-body"):
        text += ", a motion of the car body" + (on if elements else "")
    text += "."
    band = lin.get("critical_band_m_per_s")
    if band and band[1] is not None:
        text += f" It is unstable only between {band[0]:.1f} and {band[1]:.1f} m/s."
    return text


_jsonable = jsonable
