"""One run with its assessment: :func:`run` (``railexu.run``, ``railexu run``).

:func:`railexu.simulation.simulate.simulate` integrates the model and records the time series;
:func:`run` adds what an engineer reads: the summary over the evaluation window (EN 14363
criteria, derailment criteria, ride comfort, hunting verdict; :func:`railexu.results.summarize`)
and, on curved track, the curving statistics. A completed run that exceeds a safety criterion
gets the status ``completed_with_exceedances``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from railexu.errors import interruption
from railexu.operation.run_settings import RunSettings
from railexu.simulation.simulate import (
    ProgressCallback,
    RunResult,
    flange_angle_rad,
    print_progress,
    simulate,
    wheelset_order,
)
from railexu.track.track import Track
from railexu.vehicle.vehicle import Vehicle

if TYPE_CHECKING:
    from railexu.results import RunSummary
    from railexu.runtime.warm_process import WarmProcess
    from railexu.simulation.timeseries import TimeSeries
    from railexu.track.alignment import Alignment

__all__ = ["RunResult", "RunSettings", "print_progress", "run"]

#: The facts of the run that the summary carries after the assessment, in this order.
_FACTS = ("timings_s", "solver", "settings", "vehicle", "track", "curving", "warnings",
          "longitudinal", "curve_transitions", "switches_crossings")  # fmt: skip


def run(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: RunSettings | None = None,
    progress: ProgressCallback | None = None,
    warm: WarmProcess | None = None,
) -> RunResult:
    """Simulate ``vehicle`` on ``track`` (ideal straight track by default) and assess the run.

    Args:
        warm: a :class:`~railexu.runtime.warm_process.WarmProcess` started before the run, as
            ``railexu run`` does: the assessment runs there (it imported ``scipy.signal`` while
            the run integrated); the summary is the same. The wheelsets' contacts go onto
            threads (:mod:`railexu.runtime.threads`) only once it has done its imports.

    Returns:
        The :class:`~railexu.simulation.simulate.RunResult`; its ``summary`` is a
        :class:`~railexu.results.RunSummary` (``summary["hunting"]`` reads like the JSON,
        ``summary.to_dict()`` is ``summary.json``). With ``settings.wear_law`` the wear and
        RCF of every wheel and rail (:func:`railexu.results.run_wear.wear_of_run`) are in
        ``result.wear`` and ``summary["wear"]`` (docs/wear.md, "Per run").

    Raises:
        InputError: bad settings, an initial offset that lifts a wheel up its flange, a model
            that cannot be built.
        RunInterrupted: Ctrl-C (SIGINT) during the integration; ``RunTerminated`` (its
            subclass) for SIGTERM (:mod:`railexu.errors`). The run is assessed first: the
            exception's ``result`` is this function's result, status ``interrupted``, with the
            time series up to the stop and its summary (``railexu.write_run`` writes it; with
            ``settings.wear_law`` its wear too, the summary's ``wear`` saying so). A
            script's loop of runs stops there; ``except Exception`` does not catch it.
    """
    settings = settings or RunSettings()
    # the contacts' threads wait until the warm process has imported what it needs
    when = warm.warmed if warm is not None and warm.ready else None
    result = simulate(vehicle, track, settings, progress, when)
    result.summary = assess(result, warm)
    if settings.wear_law is not None:  # also for a run that did not complete: it says so
        from railexu.results.run_wear import wear_of_run

        result.wear, result.summary["wear"] = wear_of_run(result)
    if result.stopped_by is not None:
        raise interruption(result.stopped_by, result)
    return result


def assess(result: RunResult, warm: WarmProcess | None = None) -> RunSummary:
    """The summary of a simulated run; updates ``result.status`` with the exceedance state.

    Args:
        warm: compute it in this process started before the run (see :func:`run`).
    """
    args = (result.timeseries, result.status, dict(result.summary), assessment_inputs(result))
    summary = warm.call(summarize_run, *args) if warm is not None else summarize_run(*args)
    if summary.status["state"] != result.status["state"]:  # computed in the warm process
        result.status.update(state=summary.status["state"], reason=summary.status["reason"])
    return summary


@dataclass(frozen=True)
class AssessmentInputs:
    """What the assessment needs of a run besides its time series: read off the vehicle, the
    track and the built model in the run's process, so that the assessment can run in another
    (:class:`~railexu.runtime.warm_process.WarmProcess`)."""

    wheelset_names: list[str]  # in the order of the time series' ws1, ws2, ...
    speed_m_per_s: float
    friction: float
    flange_angle_rad: float
    static_axle_loads_N: list[float]
    category: str | None
    evaluate_from_m: float | None
    evaluate_to_m: float | None
    track_irregular: bool
    alignment: Alignment | None  # curved track only
    flange_height_m: float | None = None  # flange tip above the tape circle (first wheel)
    placements: tuple = ()  # car-body points (results.transition_comfort.PointPlacement)
    comfort_points: tuple[str, ...] | None = None  # the car body's points; None: every point
    sc_zone_m: tuple[float, float] | None = None  # a switch-and-crossing zone (issue 29)
    sc_panels: dict | None = None  # per side its panels and their rails' names (sc_outputs)


def _sc_panels(rails) -> dict:
    """Per side with a variable profile its panels and their rails' names (issue 29)."""
    from railexu.profiles.variable.rails import panel_names

    sides = zip(("left", "right"), rails.sides(), strict=True)
    return {side: panel_names(p) for side, p in sides if p is not None}


def assessment_inputs(result: RunResult) -> AssessmentInputs:
    """The :class:`AssessmentInputs` of a simulated run."""
    model, vehicle, settings = result.model, result.vehicle, result.settings
    order = wheelset_order(vehicle)
    rails = getattr(result.track, "variable_rails", None)
    return AssessmentInputs(
        wheelset_names=[vehicle.wheelsets[i].name for i in order],
        speed_m_per_s=settings.speed_m_per_s,
        friction=vehicle.contact.friction,
        flange_angle_rad=flange_angle_rad(model),
        static_axle_loads_N=[float(np.sum(model.statics.wheel_loads_N[i])) for i in order],
        category=vehicle.category,
        evaluate_from_m=settings.evaluate_from_m,
        evaluate_to_m=settings.evaluate_to_m,
        track_irregular=result.track.irregularity.type != "none",
        alignment=model.alignment if model.curved else None,
        flange_height_m=_flange_height_m(model),
        placements=_placements(vehicle, order),
        comfort_points=vehicle.car_body_points,
        sc_zone_m=None if rails is None else rails.zone_m(),
        sc_panels=None if rails is None else _sc_panels(rails),
    )


def _placements(vehicle, order: list[int]) -> tuple:
    """Each car-body measurement point's body and its and the body's distance behind the
    leading wheelset (m), for the curve-transition comfort (not the bogie frames' points)."""
    from railexu.results.transition_comfort import PointPlacement

    lead = vehicle.wheelsets[order[0]].position_x_m if order else 0.0
    bodies = {b.name: b.position_m[0] for b in vehicle.bodies}
    return tuple(
        PointPlacement(p.name, p.body, lead - p.position_m[0], lead - bodies[p.body])
        for p in vehicle.measurement_points
        if p.body in bodies and p.name in vehicle.car_body_points
    )


def _flange_height_m(model) -> float:
    """Height of the (first) wheel profile's highest point above its tape circle [m]: the
    flange tip (S1002: 28 mm at the design point); a few millimetres for a cone."""
    wheel = model.geometries[0].left.wheel
    return float(np.max(wheel.height(np.linspace(wheel.y_min, wheel.y_max, 2001))))


def summarize_run(
    timeseries: TimeSeries, status: dict, facts: dict, inputs: AssessmentInputs
) -> RunSummary:
    """The summary over the evaluation window (:func:`railexu.results.summarize`) with the
    curving statistics on curved track and the run's ``facts`` (timings, solver, settings...);
    ``status`` gets the exceedance state."""
    from railexu.results import summarize  # scipy.signal's filters: imported when needed
    from railexu.simulation.curving import curving_statistics

    wall = facts["timings_s"]["integration_s"]
    simulated = status["time_s"]
    names = inputs.wheelset_names
    summary = summarize(
        timeseries,
        wheelset_names=names,
        status=status,
        realtime_factor=simulated / wall if wall > 0 else math.inf,
        speed_m_per_s=inputs.speed_m_per_s,
        friction=inputs.friction,
        flange_angle_rad=inputs.flange_angle_rad,
        static_axle_loads_N=inputs.static_axle_loads_N,
        category=inputs.category,
        evaluate_from_m=inputs.evaluate_from_m,
        evaluate_to_m=inputs.evaluate_to_m,
        track_irregular=inputs.track_irregular,
        flange_height_m=inputs.flange_height_m,
        comfort_points=inputs.comfort_points,
    )
    state = summary.state_with_exceedances(status["state"])
    if state != status["state"]:
        exceeded = ", ".join(summary.exceedances)
        for st in (status, summary.status):
            st.update(state=state, reason=f"safety criteria exceeded: {exceeded}")
    if inputs.alignment is not None:
        window = (summary.window.from_m, summary.window.to_m, summary.window.rule)
        facts["curving"] = curving_statistics(timeseries, inputs.alignment, names, window)
        if inputs.placements:
            from railexu.results.transition_comfort import curve_transition_comfort

            facts["curve_transitions"] = curve_transition_comfort(
                timeseries, inputs.alignment, list(inputs.placements)
            )
    if inputs.sc_zone_m is not None:
        from railexu.simulation.sc_outputs import crossing_summary

        facts["switches_crossings"] = crossing_summary(
            timeseries, inputs.sc_zone_m, len(names), inputs.sc_panels
        )
    for key in _FACTS:
        if key in facts:
            summary[key] = facts[key]
    return summary
