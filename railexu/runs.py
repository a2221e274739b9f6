"""One run with its assessment: :func:`run` (``railexu.run``, ``railexu run``).

:func:`railexu.simulation.simulate` integrates the model and records the time series;
:func:`run` adds what an engineer reads: the summary over the evaluation window (EN 14363
criteria, derailment criteria, ride comfort, hunting verdict; :func:`railexu.results.summarize`)
and, on curved track, the curving statistics. A completed run that exceeds a safety criterion
gets the status ``completed_with_exceedances``.
"""

from __future__ import annotations

import math

import numpy as np

from .curving import curving_statistics
from .results import RunSummary, summarize
from .run_settings import RunSettings
from .simulation import (
    ProgressCallback,
    RunResult,
    flange_angle_rad,
    print_progress,
    simulate,
    wheelset_order,
)
from .track import Track
from .vehicle import Vehicle

__all__ = ["RunResult", "RunSettings", "print_progress", "run"]

#: The facts of the run that the summary carries after the assessment, in this order.
_FACTS = ("timings_s", "solver", "settings", "vehicle", "track", "curving", "warnings",
          "longitudinal")  # fmt: skip


def run(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: RunSettings | None = None,
    progress: ProgressCallback | None = None,
) -> RunResult:
    """Simulate ``vehicle`` on ``track`` (ideal straight track by default) and assess the run.

    Returns:
        The :class:`~railexu.simulation.RunResult`; its ``summary`` is a
        :class:`~railexu.results.RunSummary` (``summary["hunting"]`` reads like the JSON,
        ``summary.to_dict()`` is ``summary.json``).

    Raises:
        InputError: bad settings, an initial offset that lifts a wheel up its flange, a model
            that cannot be built.
    """
    settings = settings or RunSettings()
    result = simulate(vehicle, track, settings, progress)
    result.summary = assess(result)
    return result


def assess(result: RunResult) -> RunSummary:
    """The summary of a simulated run; updates ``result.status`` with the exceedance state."""
    model, vehicle, settings = result.model, result.vehicle, result.settings
    facts = dict(result.summary)
    order = wheelset_order(vehicle)
    names = [vehicle.wheelsets[i].name for i in order]
    wall = facts["timings_s"]["integration_s"]
    simulated = result.status["time_s"]
    summary = summarize(
        result.timeseries,
        wheelset_names=names,
        status=result.status,
        realtime_factor=simulated / wall if wall > 0 else math.inf,
        speed_m_per_s=settings.speed_m_per_s,
        friction=vehicle.contact.friction,
        flange_angle_rad=flange_angle_rad(model),
        static_axle_loads_N=[float(np.sum(model.statics.wheel_loads_N[i])) for i in order],
        category=vehicle.category,
        evaluate_from_m=settings.evaluate_from_m,
        evaluate_to_m=settings.evaluate_to_m,
        track_irregular=result.track.irregularity.type != "none",
    )
    state = summary.state_with_exceedances(result.status["state"])
    if state != result.status["state"]:
        exceeded = ", ".join(summary.exceedances)
        for status in (result.status, summary.status):
            status.update(state=state, reason=f"safety criteria exceeded: {exceeded}")
    if model.curved:
        window = (summary.window.from_m, summary.window.to_m, summary.window.rule)
        facts["curving"] = curving_statistics(result.timeseries, model.alignment, names, window)
    for key in _FACTS:
        if key in facts:
            summary[key] = facts[key]
    return summary
