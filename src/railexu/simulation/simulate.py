"""Run a vehicle on a track: solver settings, progress, status, outputs.

:func:`run` is the public function behind ``railexu run``: it builds the Exudyn model
(:mod:`railexu.model.assembly`), integrates it with Exudyn's implicit generalized-alpha solver at
constant forward speed, records a time series, watches for derailment and divergence, and returns a
:class:`RunResult` whose time series and summary :func:`write_run` saves (also for a run that
stopped early: the results up to that point are kept).

Step size: the default, 2 ms, was checked against a 0.25 ms reference on the seed's scenario
(see ``docs/validation.md`` and ``tests/test_dynamics.py``); generalized-alpha with spectral
radius 0.7 damps the stiff wheel-rail contact modes, and modified Newton with a relative
tolerance of 1e-4 re-uses one Jacobian for many steps (Rxyz nodes, ``docs/dev/exudyn-api.md``).
A step whose Newton iteration fails is halved and retried (Exudyn's adaptive step); every such cut
is counted (:mod:`railexu.simulation.step_watch`: the summary's ``solver`` block) and warned about.
"""

from __future__ import annotations

import contextlib
import math
import signal
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from railexu.model.assembly import VehicleModel
from railexu.operation.run_settings import RunSettings as RunSettings
from railexu.operation.run_settings import RunSettingsError as RunSettingsError
from railexu.operation.run_settings import run_settings_from_dict as run_settings_from_dict
from railexu.simulation.longitudinal import longitudinal_summary
from railexu.simulation.preflight import (
    check_initial_offset,
    check_run_within_track,
    check_time_step_for_track,
)
from railexu.simulation.recorder import CONTACT_FIELDS as CONTACT_FIELDS
from railexu.simulation.recorder import POINT_FIELDS as POINT_FIELDS
from railexu.simulation.recorder import Recorder
from railexu.simulation.recorder import contact_fields as contact_fields
from railexu.simulation.recorder import point_accelerations as point_accelerations
from railexu.simulation.step_watch import StepWatch
from railexu.simulation.timeseries import TimeSeries
from railexu.track.track import Track, ideal_straight_track
from railexu.vehicle.vehicle import Vehicle


@dataclass
class RunResult:
    """Outcome of a run: the time series up to the end (or the stop), the summary (a
    :class:`railexu.results.RunSummary` from :func:`railexu.results.run.run`; the run's facts only
    from :func:`simulate`), the status, the model."""

    timeseries: TimeSeries
    summary: Any
    status: dict
    settings: RunSettings
    vehicle: Vehicle
    track: Track
    timings_s: dict = field(default_factory=dict)
    model: VehicleModel | None = field(default=None, repr=False)
    #: the kernel's contact points at every output time, ``(n, n_ws, 2, MAX_POINTS, fields)``
    #: with the fields of :data:`POINT_FIELDS` (wheelsets from the front), or None
    contact_points: np.ndarray | None = field(default=None, repr=False)
    #: the signal that stopped the run (``"SIGINT"`` or ``"SIGTERM"``; status ``interrupted``),
    #: or None: :func:`railexu.results.run.run` then raises ``railexu.errors.RunInterrupted``
    stopped_by: str | None = None
    #: the wear and RCF of every wheel when the settings ask for it (``wear_law``): a list of
    #: ``railexu.results.wear.WheelWear`` set by :func:`railexu.results.run.run`, or None
    wear: list | None = field(default=None, repr=False)


ProgressCallback = Callable[[float, float, float, float], None]

#: Run states in which the run reached its end: cleanly, or with a safety criterion exceeded
#: (set by the assessment, :func:`railexu.results.run.run`).
COMPLETED_STATES = ("completed", "completed_with_exceedances")
#: Every run state: the run's end, or where and why it stopped.
RUN_STATES = (*COMPLETED_STATES, "derailed", "diverged", "interrupted")


def print_progress(stream=sys.stderr) -> ProgressCallback:
    """A progress callback printing distance, speed and time left on one updating line."""
    state = {"last": 0.0}

    def report(distance: float, total: float, speed: float, eta_s: float) -> None:
        now = time.perf_counter()
        if now - state["last"] < 0.5 and distance < total:
            return
        state["last"] = now
        eta = f"{eta_s:5.1f} s left" if math.isfinite(eta_s) else "  ... s left"
        end = "\n" if distance >= total else ""
        stream.write(
            f"\r  {distance:8.1f} / {total:.1f} m   {speed:6.2f} m/s ({speed * 3.6:5.1f} km/h)"
            f"   {eta}   {end}"
        )
        stream.flush()

    return report


def wheelset_order(vehicle: Vehicle) -> list[int]:
    """Indices of the wheelsets from the front (largest x) to the rear."""
    return sorted(range(len(vehicle.wheelsets)), key=lambda i: -vehicle.wheelsets[i].position_x_m)


_STOP_SIGNALS = {"SIGINT": "Ctrl-C, SIGINT", "SIGTERM": "SIGTERM"}


def _catch_stop_signals(rec: dict) -> dict:
    """Let SIGINT and SIGTERM end the run at the next step (``rec["interrupted"]`` then describes
    the signal, ``rec["signal"]`` names it); returns the previous handlers. A signal that the
    process ignores (a study's worker ignores SIGINT) stays ignored; outside the main thread
    nothing can be caught."""
    previous = {}
    for name, label in _STOP_SIGNALS.items():
        signum = getattr(signal, name)
        with contextlib.suppress(ValueError):
            if signal.getsignal(signum) is not signal.SIG_IGN:
                previous[signum] = signal.signal(
                    signum, lambda *_, n=name, label=label: rec.update(interrupted=label, signal=n)
                )
    return previous


def simulate(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: RunSettings | None = None,
    progress: ProgressCallback | None = None,
    contact_threads_when: Callable[[], bool] | None = None,
) -> RunResult:
    """Simulate ``vehicle`` running on ``track`` (ideal straight track by default), without the
    assessment: :func:`railexu.results.run.run` adds it (the public ``railexu.run``).

    ``contact_threads_when``: where the wheelsets' contacts may run on threads
    (:mod:`railexu.runtime.threads`), they start when this returns True, asked at every output time
    (``railexu run`` asks whether its warm process has done its imports: until then that process
    needs the second core); None: from the start. The results are the same either way.

    The run stops early with status ``derailed`` when a wheel climbs its rail or a wheelset
    leaves the track, ``diverged`` when the solver fails or the state becomes invalid, and
    ``interrupted`` on Ctrl-C or SIGTERM (the result's ``stopped_by`` names the signal); the
    time series up to that point is returned either way (:func:`railexu.results.run.run` then
    raises). The result's ``summary`` holds the facts of the run (status, solver statistics,
    settings, names, timings, warnings).

    Raises:
        InputError: an initial lateral offset that lifts a wheel up its flange
            (:func:`railexu.simulation.preflight.check_initial_offset`), a model that cannot be
            built.
    """
    settings = settings or RunSettings()
    track = track or ideal_straight_track()
    t_start = time.perf_counter()
    check_run_within_track(vehicle, track, settings)
    warnings = check_initial_offset(vehicle, track, settings)
    warnings += check_time_step_for_track(vehicle, track, settings)
    model = VehicleModel(
        vehicle,
        track,
        settings.speed_m_per_s,
        settings.initial_lateral_m,
        settings.distance_m,
        settings.deceleration_m_per_s2,
        speed_profile=settings.speed_profile,
        traction=settings.traction,
    )
    model.warm_up(threads_now=contact_threads_when is None)
    t_built = time.perf_counter()
    order = wheelset_order(vehicle)
    ss, n_steps = _solver_settings(settings)
    recorder = Recorder(
        model, vehicle, settings, order, n_steps // settings.output_every + 2,
        _flange_heights(model),
    )  # fmt: skip
    steps = StepWatch(settings.time_step_s, ss.timeIntegration.endTime)
    wall_int, error, stop, stopped_by = _integrate(
        model, settings, ss, recorder, progress, contact_threads_when, steps
    )
    status = _final_status(model, settings, recorder, error, stop)
    ts = recorder.timeseries()
    timings = {
        "build_s": t_built - t_start,
        "integration_s": wall_int,
        "total_s": time.perf_counter() - t_start,
    }
    facts = {
        "status": status,
        "timings_s": timings,
        "solver": {**_solver_statistics(model), **steps.facts()},
        "settings": asdict(settings),
        "vehicle": vehicle.name,
        "track": track.name,
    }
    warnings += list(model.axle_load_warnings)
    cut = steps.warning(model.distance_at)
    if cut is not None:
        warnings.append(cut)
    if warnings:
        facts["warnings"] = warnings
    facts["longitudinal"] = longitudinal_summary(ts, model)
    points = recorder.contact_points()
    return RunResult(
        ts, facts, status, settings, vehicle, track, timings, model, points, stopped_by
    )


def _flange_heights(model: VehicleModel) -> list[float]:
    """Height of the flange tip above the tape circle of every wheelset's wheel [m]."""
    return [
        float(
            np.max(g.left.wheel.height(np.linspace(g.left.wheel.y_min, g.left.wheel.y_max, 2001)))
        )
        for g in model.geometries
    ]


def _solver_settings(settings: RunSettings):
    """Exudyn's simulation settings for the run and the number of steps."""
    import exudyn as exu

    h = settings.time_step_s
    n_steps = int(math.ceil(settings.duration_s / h - 1e-9))
    ss = exu.SimulationSettings()
    ti = ss.timeIntegration
    ti.startTime = 0.0
    ti.endTime = n_steps * h
    ti.numberOfSteps = n_steps
    ti.verboseMode = 0
    ti.generalizedAlpha.spectralRadius = (
        settings.spectral_radius if settings.solver == "generalized_alpha" else 1.0
    )
    ti.newton.useModifiedNewton = True
    ti.newton.relativeTolerance = settings.newton_relative_tolerance
    ti.newton.modifiedNewtonContractivity = 0.2
    # Settings that decide whether a failure shows, explicit (docs/performance.md, "The
    # solver's steps"). Adaptive step: a step whose Newton iteration does not converge is
    # halved and retried (impacts on a rigid rail may need a few tiny steps), down to h/1024,
    # below which the solver raises (status diverged); after 10 steps with fewer than 7 Newton
    # iterations it is doubled again. Every cut is counted (StepWatch) and warned about.
    ti.adaptiveStep = True
    ti.adaptiveStepDecrease = 0.5
    ti.adaptiveStepIncrease = 2.0
    ti.adaptiveStepRecoverySteps = 10
    ti.adaptiveStepRecoveryIterations = 7
    ti.minimumStepSize = h / 1024.0
    # Discontinuous iterations (objects with a PostNewton switch: Exudyn's contact and
    # friction objects) would accept a step whose switching did not settle when
    # ignoreMaxIterations is True (Exudyn's default). railexu's model has no such object (the
    # contacts and the suspensions' friction are forces of user functions: one iteration per
    # step); False makes a future one fail the step (then cut and counted) instead of passing.
    ti.discontinuous.ignoreMaxIterations = False
    ti.discontinuous.maxIterations = 5
    # a state at rest in exact equilibrium (a centred free wheelset) leaves only the round-off
    # of the contact forces as residual (~1e-7 N: Hertz's K delta^1.5 with delta a difference
    # of positions ~0.6 m); Exudyn's default 1e-10 cannot be met then and the step fails.
    # 1e-4 (N per coordinate) is an acceleration error below 1e-7 m/s^2 of a 1 t body
    ti.newton.absoluteTolerance = 1.0e-4
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    ss.show.computationTime = False
    ss.show.statistics = False
    return ss, n_steps


def _integrate(model, settings, ss, recorder, progress, contact_threads_when=None, steps=None):
    """Run Exudyn's solver with recording, progress and stop signals (and the contacts' threads
    started when ``contact_threads_when()`` says so).

    Returns ``(wall-clock seconds, solver exception or None, stop status or None, the name of
    the stop signal or None)``. A signal that came after the last step still counts: the run
    is then ``interrupted`` at its end (a stop request is never lost). ``steps`` (a
    :class:`~railexu.simulation.step_watch.StepWatch`) counts the solver's attempts and
    accepted steps."""
    import exudyn as exu

    mbs = model.mbs
    ti = ss.timeIntegration
    h = settings.time_step_s
    rec = {"status": None, "next": 0.0, "interrupted": False, "signal": None}
    steps = steps if steps is not None else StepWatch(h, ti.endTime)
    begin_step = settings.speed_varies or getattr(model, "vertical_forces", None) is not None
    wall0 = [time.perf_counter()]

    def record(t: float) -> bool:
        """Store one output row at time t; returns False when the run must stop."""
        data = mbs.systemData
        status = recorder.record(
            t,
            data.GetODE2Coordinates(),
            data.GetODE2Coordinates_t(),
            data.GetODE2Coordinates_tt(),
        )
        if status is not None:
            rec["status"] = status
        if contact_threads_when is not None and model.threads_pending and contact_threads_when():
            model.start_threads(t)
        if progress is not None:
            elapsed = time.perf_counter() - wall0[0]
            frac = t / ti.endTime if ti.endTime > 0 else 1.0
            eta = elapsed * (1.0 - frac) / frac if frac > 0 else math.inf
            progress(model.distance_at(t), settings.distance_m, model.speed_at(t), eta)
        return rec["status"] is None

    interval = settings.output_every * h

    def pre_step(mbs_, t: float) -> bool:
        # called before every attempt of a step (a rejected one is retried with a smaller
        # step): t is the end time of the step about to be computed: the speed it must reach,
        # or (free motion) the torques; False ends a free run at its distance or standstill
        steps.attempt(t)
        if begin_step and not model.begin_step(t, h, settings.distance_m):
            steps.not_attempted()
            return False
        return True

    def post_step(mbs_, t: float) -> bool:
        # called with the initial state (t = 0) and after every accepted step, with the state
        # at t
        steps.accepted(t)
        if rec["interrupted"]:
            record(t)
            rec["status"] = ("interrupted", t, f"interrupted ({rec['interrupted']})")
            return False
        if t >= rec["next"] - 0.5 * h:
            # next output one interval later, on the grid k * interval, so that runs with
            # different steps record at the same times
            rec["next"] = (math.floor(t / interval + 0.5) + 1) * interval
            return record(t)
        return True

    mbs.SetPreStepUserFunction(pre_step)  # also for the step facts (StepWatch)
    mbs.SetPostStepUserFunction(post_step)
    solver_type = (
        exu.DynamicSolverType.GeneralizedAlpha
        if settings.solver == "generalized_alpha"
        else exu.DynamicSolverType.TrapezoidalIndex2
    )
    wall0[0] = time.perf_counter()
    error = None
    # Exudyn warns about memory allocations in user functions (the contact function returns a
    # numpy array, which it copies): harmless; its console output is off during the solution
    # so that the progress line stays readable (solver failures still raise exceptions)
    exu.config.printToConsole = False
    # Ctrl-C and SIGTERM (what `timeout`, `kill` and container stops send) end the run at the
    # next step with the results so far (not possible outside the main thread, e.g. in a Dask
    # worker thread; a process that ignores SIGINT, like a study's worker, keeps ignoring it)
    previous_handlers = _catch_stop_signals(rec)
    try:
        mbs.SolveDynamic(ss, solverType=solver_type)
    except Exception as exc:  # Exudyn raises its own error types on Newton failure
        error = exc
    finally:
        steps.finish(failed=error is not None)
        exu.config.printToConsole = True
        for signum, handler in previous_handlers.items():
            signal.signal(signum, handler)
    wall_int = time.perf_counter() - wall0[0]
    t_end = mbs.systemData.GetTime()
    # the final state, when the run's end is not on the output grid
    if (
        rec["status"] is None
        and error is None
        and (recorder.n == 0 or recorder.last_time < t_end - 1e-12)
    ):
        record(t_end)
    if rec["interrupted"] and rec["status"] is None and error is None:
        # the signal came after the last step: the run is complete, and still it was stopped
        rec["status"] = ("interrupted", t_end, f"interrupted ({rec['interrupted']})")
    return wall_int, error, rec["status"], rec["signal"]


def _final_status(model, settings, recorder, error, stop) -> dict:
    """The run's status: completed, derailed, diverged or interrupted, where and why."""
    t_end = model.mbs.systemData.GetTime()
    if stop is not None:
        state, t_stop, reason = stop
    elif error is not None:
        state, t_stop = "diverged", t_end
        reason = f"the solver failed at t = {t_end:.3f} s: {str(error).strip().splitlines()[0]}"
    else:
        state, t_stop, reason = "completed", t_end, ""
    return {
        "state": state,
        "distance_m": model.distance_at(t_stop),
        "time_s": t_stop,
        "reason": reason,
    }


def _solver_statistics(model: VehicleModel) -> dict:
    """Newton iterations and Jacobian updates of Exudyn's solver, the force function's calls
    and threads (the steps: :class:`~railexu.simulation.step_watch.StepWatch`)."""
    try:
        it = model.mbs.sys["dynamicSolver"].it
        calls, seconds = model.force_calls
        return {
            "newton_iterations": int(it.newtonStepsCount),
            "jacobian_updates": int(it.newtonJacobiCount),
            # evaluations of the wheel-rail force function and the wall-clock time in them
            "force_evaluations": int(calls),
            "force_function_s": float(seconds),
            # threads of the wheelsets' contacts (railexu.runtime.threads; 1: one after the other)
            "contact_threads": int(model.contact_threads),
            # the simulated time from which they ran (null: never)
            "contact_threads_from_s": model.contact_threads_from_s,
            # the share of the force calls made on the threads after that, and how often the
            # measured choice (railexu.runtime.thread_choice) switched between them and one
            # thread (a busy machine makes the threads slower than one thread)
            **_thread_choice_facts(model),
        }
    except (KeyError, AttributeError):
        return {}


def _thread_choice_facts(model: VehicleModel) -> dict:
    """``contact_threads_share`` and ``contact_thread_switches`` of a run whose contacts had
    threads (empty without)."""
    choice = getattr(model, "thread_choice", None)
    if choice is None:
        return {}
    return {
        "contact_threads_share": round(choice.threaded_share(), 4),
        "contact_thread_switches": int(choice.switches),
    }


def flange_angle_rad(model: VehicleModel) -> float:
    """Flange angle of the (first) wheel profile [rad]: the largest slope of the flank between
    the flange tip (the highest point) and the tape circle (S1002: 70 deg). The flange back
    beyond the tip is not part of it."""
    wheel = model.geometries[0].left.wheel
    s = np.linspace(wheel.y_min, 0.0, 8001)
    tip = s[int(np.argmax(wheel.height(s)))]
    flank = s[s >= tip]
    return float(np.max(np.arctan(np.abs(wheel.slope(flank)))))
