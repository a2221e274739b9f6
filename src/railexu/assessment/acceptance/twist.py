"""Safety against derailment on twisted track, simulated (EN 14363:2016, 6.1; UIC 530-2).

The vehicle runs at walking speed through a small-radius curve (R 150 m) whose cant falls
linearly along the track, as in a curve's exit transition: the cant ramp is the twist (a cant
gradient ``g`` of 4 per mille lowers the outer rail by 4 mm per metre). The leading outer wheel
is then both the flanging wheel (large Y) and the unloaded one (small Q): the test's quantity is
its flange-climbing quotient ``Y/Q``, against ``(Y/Q)_lim = 1.2``; the wheel unloading
``Delta Q / Q0 = (Q0 - Q) / Q0`` of the most unloaded wheel is reported beside it, against the
0.6 of the wheel-unloading methods.

The track is built in code (:func:`twist_track`): one constant-radius curve with a cant ramp;
the vehicle starts with every wheelset on the ramp (the track's ``start``), runs
``settle_m`` to leave the start-up behind (the vertical modes of the suspension decay within a
few metres at walking speed) and is evaluated over the next ``evaluate_m``, still on the ramp,
where the twist under it and hence its wheel loads are constant: the state is quasi-static.
With ``radius_m=None`` the track is straight and only twisted (the twist rig of method 2).

The default twist is ``g_lim`` of the vehicle's wheelbase ``2a*`` (:func:`twist_limit_per_mille`,
railexu's assumption where the public sources are silent: ``docs/acceptance-quasistatic.md``).
One gradient is applied over the whole vehicle: a bogie vehicle's bogies see the same gradient
as its body, not the larger bogie twist of the standard's test track.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from railexu.assessment.en14363 import SAFETY_STEP_M, SAFETY_WINDOW_M, y_over_q_values
from railexu.assessment.signals import window_means
from railexu.errors import InputError
from railexu.operation.run_settings import RunSettings
from railexu.simulation.simulate import (
    COMPLETED_STATES,
    ProgressCallback,
    RunResult,
    simulate,
    wheelset_order,
)
from railexu.track.alignment import CANT_BASE_M, alignment_from_samples
from railexu.track.track import Track
from railexu.vehicle.vehicle import Vehicle

CLAUSE = "EN 14363:2016, 6.1 (safety against derailment on twisted track); UIC 530-2"
METHOD = "method 1 simulated: the whole vehicle on a twisted test track in a small-radius curve"
#: Limit of the flange-climbing quotient on the twisted test track (EN 14363:2016, 6.1).
Y_OVER_Q_LIMIT = 1.2
#: Limit of the wheel unloading Delta Q / Q0 on the twist (EN 14363:2016, 6.1, methods 2 and 3;
#: UIC 530-2), as :data:`railexu.assessment.safety.WHEEL_UNLOADING_LIMIT`.
UNLOADING_LIMIT = 0.6
#: Radius of the test track's curve [m] (EN 14363:2016, 6.1).
TEST_RADIUS_M = 150.0
#: Walking speed of the test [m/s] (railexu's assumption: "quasi-static", 5.4 km/h).
TEST_SPEED_M_PER_S = 1.5
#: Distance run before the evaluation and the evaluation window's length [m].
SETTLE_M = 5.0
EVALUATE_M = 4.0
#: Distance of the rearmost wheelset from the start of the ramp at the start [m]: beyond the
#: ramp's rounded kink (``railexu.track.alignment.CANT_ROUNDING_M``, 1 m).
RAMP_MARGIN_M = 3.0
#: Integration step of the test [s]: walking speed moves the vehicle 7.5 mm per step.
TIME_STEP_S = 0.005
#: The wheel loads below which Y/Q is not formed [N] (a lifted wheel).
MIN_LOAD_N = 1000.0


def twist_limit_per_mille(wheelbase_m: float) -> float:
    """The test track's twist ``g_lim`` [per mille] for the wheelbase ``2a*`` [m]:
    7 below 4 m, ``20 / 2a* + 2`` from 4 to 20 m, 3 above 20 m.

    railexu's assumption: the form of EN 14363's twist limit as commonly cited (continuous at
    4 m and 20 m); the standard's text was not available to check it.
    """
    if not (math.isfinite(wheelbase_m) and wheelbase_m > 0.0):
        raise InputError(f"twist test: wheelbase {wheelbase_m!r} m is not a positive number")
    if wheelbase_m < 4.0:
        return 7.0
    if wheelbase_m > 20.0:
        return 3.0
    return 20.0 / wheelbase_m + 2.0


def vehicle_wheelbase_m(vehicle: Vehicle) -> float:
    """``2a*`` of a vehicle [m]: the distance of its bogie centres (bodies carrying wheelsets
    under another body), else of its outermost wheelsets (a two-axle wagon)."""
    wheelsets = {w.name for w in vehicle.wheelsets}
    xs = []
    for b in vehicle.bodies:
        linked = {n for el in vehicle.suspension if b.name in el.bodies for n in el.bodies}
        if linked & wheelsets and linked - wheelsets - {b.name}:
            xs.append(b.position_m[0])
    if len(xs) < 2:
        xs = [w.position_x_m for w in vehicle.wheelsets]
    return float(max(xs) - min(xs)) if xs else 0.0


@dataclass(frozen=True)
class TwistTestResult:
    """The twist test's verdict (units in the names; quotients dimensionless).

    ``y_over_q``: the flanging wheel's quasi-static Y/Q (largest 2 m mean in the window) at
    ``wheel``; ``unloading``: the largest 2 m mean of ``(Q0 - Q) / Q0`` over the wheels, at
    ``unloading_wheel``. ``passed`` is False when a limit is exceeded or the run did not reach
    its end (``status``: the simulation's state and reason)."""

    y_over_q: float | None
    y_over_q_limit: float
    wheel: str | None
    unloading: float | None
    unloading_limit: float
    unloading_wheel: str | None
    passed: bool
    twist_per_mille: float
    twist_base_m: float
    radius_m: float | None
    direction: str
    max_cant_m: float
    speed_m_per_s: float
    window_m: tuple[float, float]
    status: dict
    method: str = METHOD
    clause: str = CLAUSE
    rule: str = (
        f"railexu: largest {SAFETY_WINDOW_M:g} m sliding mean ({SAFETY_STEP_M:g} m steps) of the "
        "signed Y/Q of every wheel (flanging positive) and of (Q0 - Q)/Q0 over the evaluation "
        "window, where every wheelset is on the cant ramp; Q0 the static wheel load"
    )
    run: RunResult | None = field(default=None, repr=False, compare=False)

    def to_dict(self) -> dict:
        """The verdict as plain values (JSON)."""
        return {
            "test": "safety against derailment on twisted track",
            "y_over_q": self.y_over_q,
            "y_over_q_limit": self.y_over_q_limit,
            "limit": self.y_over_q_limit,  # the test's deciding limit (issue 27's key)
            "wheel": self.wheel,
            "unloading": self.unloading,
            "unloading_limit": self.unloading_limit,
            "unloading_wheel": self.unloading_wheel,
            "pass": self.passed,
            "twist_per_mille": self.twist_per_mille,
            "twist_base_m": self.twist_base_m,
            "radius_m": self.radius_m,
            "direction": self.direction,
            "max_cant_m": self.max_cant_m,
            "speed_m_per_s": self.speed_m_per_s,
            "window_m": list(self.window_m),
            "status": dict(self.status),
            "method": self.method,
            "clause": self.clause,
            "rule": self.rule,
        }


def twist_track(
    radius_m: float | None,
    twist_per_mille: float,
    ramp_length_m: float,
    direction: str = "left",
    start_m: float = 0.0,
    end_cant_m: float = 0.0,
    entry_m: float = 0.0,
    lead_m: float = 0.0,
    cant_base_m: float = CANT_BASE_M,
) -> Track:
    """A track of one curve (``radius_m``; None: straight) whose cant falls linearly by
    ``twist_per_mille`` mm per metre over ``ramp_length_m`` to ``end_cant_m`` at its end, then
    stays there. With ``entry_m`` > 0 a straight of ``lead_m`` and an entry transition of
    ``entry_m`` (curvature and cant linear from 0, the cant rising at the ramp's gradient or
    less) come before the ramp: a vehicle started on the straight runs into the curve (a
    vehicle placed inside a small-radius curve starts far from its equilibrium there).

    The cant is signed like the curvature (a left curve's outer rail is the right one); on
    straight track ``direction`` says which rail the ramp lowers (left: the right rail).

    Raises:
        InputError: absurd numbers (a radius below 50 m, a twist above 50 per mille, a cant
            above 0.3 of the cant base).
    """
    if direction not in ("left", "right"):
        raise InputError(f"twist test: direction must be 'left' or 'right', got {direction!r}")
    if radius_m is not None and not (math.isfinite(radius_m) and radius_m >= 50.0):
        raise InputError(f"twist test: radius {radius_m!r} m: expected at least 50 m or None")
    if not (math.isfinite(twist_per_mille) and 0.0 < twist_per_mille <= 50.0):
        raise InputError(f"twist test: twist {twist_per_mille!r} per mille: expected 0 to 50")
    if not (math.isfinite(ramp_length_m) and ramp_length_m > 0.0):
        raise InputError(f"twist test: ramp length {ramp_length_m!r} m is not positive")
    sign = 1.0 if direction == "left" else -1.0
    cant = end_cant_m + twist_per_mille * 1.0e-3 * ramp_length_m
    if max(abs(cant), abs(end_cant_m)) > 0.3 * cant_base_m:
        raise InputError(f"twist test: a cant of {max(abs(cant), abs(end_cant_m)):.3f} m on "
                         "the ramp is more than 0.3 x the cant base: shorten the ramp or lower "
                         "the twist")  # fmt: skip
    kappa = 0.0 if radius_m is None else sign / radius_m
    tail = 50.0
    d = [0.0, ramp_length_m, ramp_length_m + tail]
    k = [kappa, kappa, kappa]
    c = [cant, end_cant_m, end_cant_m]
    if entry_m > 0.0:
        if not (math.isfinite(entry_m) and math.isfinite(lead_m) and lead_m >= 0.0):
            raise InputError("twist test: entry and lead lengths must be finite, lead >= 0")
        d = [0.0, lead_m, lead_m + entry_m] + [lead_m + entry_m + v for v in d[1:]]
        k = [0.0, 0.0] + k
        c = [0.0, 0.0] + c
        if lead_m == 0.0:
            d, k, c = d[1:], k[1:], c[1:]
    alignment = alignment_from_samples(
        np.array(d), np.array(k), sign * np.array(c), cant_base_m,
        source="twist test track (railexu.assessment.acceptance.twist)",
    )  # fmt: skip
    where = "straight" if radius_m is None else f"R {radius_m:g} m {direction} curve"
    return Track(
        name=f"twist {twist_per_mille:g} per mille, {where}",
        geometry="measured",
        description=(
            f"{where}, cant ramp {cant * 1e3:.0f} mm -> {end_cant_m * 1e3:.0f} mm over "
            f"{ramp_length_m:g} m"
        ),
        alignment=alignment,
        start_m=start_m,
    )


def twist_test(
    vehicle: Vehicle,
    *,
    radius_m: float | None = TEST_RADIUS_M,
    direction: str = "left",
    twist_per_mille: float | None = None,
    speed_m_per_s: float = TEST_SPEED_M_PER_S,
    settle_m: float = SETTLE_M,
    evaluate_m: float = EVALUATE_M,
    y_over_q_limit: float = Y_OVER_Q_LIMIT,
    unloading_limit: float = UNLOADING_LIMIT,
    time_step_s: float = TIME_STEP_S,
    centred: bool = False,
    progress: ProgressCallback | None = None,
) -> TwistTestResult:
    """Run ``vehicle`` over a twisted curve and judge its safety against flange climbing
    (module docstring).

    Args:
        vehicle: the vehicle.
        radius_m: the curve's radius [m]; None: straight track (twist only).
        direction: the curve's direction (left: the right rail is the outer one).
        twist_per_mille: the cant gradient; default :func:`twist_limit_per_mille` of the
            vehicle's ``2a*`` (:func:`vehicle_wheelbase_m`).
        speed_m_per_s: the speed (walking speed: quasi-static).
        settle_m, evaluate_m: distance run before the evaluation, and its window [m].
        y_over_q_limit, unloading_limit: the limits.
        time_step_s: the integration step [s].
        centred: False: the cant falls to 0 at the ramp's end (a curve's exit transition);
            True: it passes 0 under the vehicle's centre in the middle of the evaluation window
            (a pure twist, no mean cant: the twist rig).
        progress: the simulation's progress callback.

    Raises:
        InputError: absurd arguments.
    """
    base_m = vehicle_wheelbase_m(vehicle)
    if twist_per_mille is None and base_m <= 0.0:
        raise InputError(f"twist test: {vehicle.name} has no wheelbase (one wheelset): give "
                         "twist_per_mille")  # fmt: skip
    twist = twist_limit_per_mille(base_m) if twist_per_mille is None else float(twist_per_mille)
    for name, value in (("speed_m_per_s", speed_m_per_s), ("settle_m", settle_m),
                        ("evaluate_m", evaluate_m), ("y_over_q_limit", y_over_q_limit),
                        ("unloading_limit", unloading_limit)):  # fmt: skip
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0.0):
            raise InputError(f"twist test: {name} must be a positive finite number, got {value!r}")
    if speed_m_per_s > 5.0:
        raise InputError(f"twist test: {speed_m_per_s:g} m/s is not quasi-static: at most 5 m/s")
    layout = _layout(vehicle, radius_m is not None, twist, settle_m, evaluate_m, centred)
    track = twist_track(radius_m, twist, layout["ramp"], direction, start_m=layout["start"],
                        end_cant_m=layout["end_cant"], entry_m=layout["entry"],
                        lead_m=layout["lead"])  # fmt: skip
    settings = RunSettings(speed_m_per_s=speed_m_per_s, distance_m=layout["window"][1],
                           initial_lateral_m=0.0, time_step_s=time_step_s)  # fmt: skip
    result = simulate(vehicle, track, settings, progress)
    return _verdict(result, track, twist, base_m, radius_m, direction, speed_m_per_s,
                    layout["window"], y_over_q_limit, unloading_limit)  # fmt: skip


def _layout(vehicle: Vehicle, curved: bool, twist: float, settle_m: float, evaluate_m: float,
            centred: bool) -> dict:  # fmt: skip
    """Where the ramp lies and the vehicle starts, and the evaluation window (run distance).

    The ramp holds every wheelset from ``RAMP_MARGIN_M`` after its start through the settling
    distance and the window. On straight track the vehicle starts on it; in a curve it starts
    on a straight lead and runs through an entry transition as long as the ramp (cant rising
    at the ramp's gradient) into it."""
    xs = [w.position_x_m for w in vehicle.wheelsets]
    span = max(xs) - min(xs)
    ramp = RAMP_MARGIN_M + span + settle_m + evaluate_m + RAMP_MARGIN_M
    lead = span + 2.0 if curved else 0.0
    entry = ramp if curved else 0.0
    ramp_start = lead + entry
    start = 0.0 if curved else RAMP_MARGIN_M - 1.0
    # the rearmost wheelset is at start + 1 m at distance 0 (the track's `start` rule)
    d0 = ramp_start + RAMP_MARGIN_M - (start + 1.0)
    window = (d0 + settle_m, d0 + settle_m + evaluate_m)
    end_cant = 0.0
    if centred:  # zero cant under the vehicle's centre in the middle of the window
        centre_s = start + 1.0 + 0.5 * (window[0] + window[1]) + 0.5 * span
        end_cant = -twist * 1.0e-3 * (ramp - (centre_s - ramp_start))
    return {"ramp": ramp, "lead": lead, "entry": entry, "start": start, "window": window,
            "end_cant": end_cant}  # fmt: skip


def _verdict(
    result: RunResult,
    track: Track,
    twist: float,
    base_m: float,
    radius_m: float | None,
    direction: str,
    speed: float,
    window: tuple[float, float],
    y_lim: float,
    u_lim: float,
) -> TwistTestResult:
    """Y/Q and wheel unloading over the evaluation window of a twist run."""
    ts = result.timeseries
    order = wheelset_order(result.vehicle)
    loads = result.model.statics.wheel_loads_N
    x = np.asarray(ts["distance_m"], dtype=float)
    start = window[0]
    end = min(window[1], float(x[-1])) if x.size else start
    y_best: tuple[float | None, str | None] = (None, None)
    u_best: tuple[float | None, str | None] = (None, None)
    for k, i in enumerate(order, start=1):
        for s, side in enumerate(("left", "right")):
            wheel = f"ws{k}_{side}"
            q = np.asarray(ts[f"{wheel}_Q_N"], dtype=float)
            yq = y_over_q_values(ts[f"{wheel}_Y_N"], q, side, MIN_LOAD_N)
            q0 = float(loads[i][s])
            y_best = _larger(y_best, _max_mean(x, yq, start, end), wheel)
            u_best = _larger(u_best, _max_mean(x, (q0 - q) / q0, start, end), wheel)
    completed = result.status.get("state") in COMPLETED_STATES and end > start
    passed = bool(completed and y_best[0] is not None and u_best[0] is not None
                  and y_best[0] <= y_lim and u_best[0] <= u_lim)  # fmt: skip
    al = track.alignment
    cant = float(np.max(np.abs(al.cant(np.linspace(0.0, al.end_m, 2001)))))
    return TwistTestResult(
        y_over_q=y_best[0], y_over_q_limit=y_lim, wheel=y_best[1],
        unloading=u_best[0], unloading_limit=u_lim, unloading_wheel=u_best[1],
        passed=passed, twist_per_mille=twist, twist_base_m=base_m, radius_m=radius_m,
        direction=direction, max_cant_m=cant, speed_m_per_s=speed, window_m=(start, end),
        status=dict(result.status), run=result,
    )  # fmt: skip


def _max_mean(x: np.ndarray, values: np.ndarray, start: float, end: float) -> float | None:
    """The largest 2 m sliding mean (0.5 m steps) of ``values`` within ``[start, end]``."""
    _, means = window_means(x, values, SAFETY_WINDOW_M, SAFETY_STEP_M, start, end)
    if means.size == 0 or not np.any(np.isfinite(means)):
        return None
    return float(np.nanmax(means))


def _larger(best: tuple[float | None, str | None], value: float | None, wheel: str):
    if value is not None and (best[0] is None or value > best[0]):
        return (value, wheel)
    return best
