"""Run a vehicle on a track: solver settings, progress, status, outputs.

:func:`run` is the public function behind ``railexu run``: it builds the Exudyn model
(:mod:`railexu.model`), integrates it with Exudyn's implicit generalized-alpha solver at constant
forward speed, records a time series, watches for derailment and divergence, and returns a
:class:`RunResult` whose time series and summary :func:`write_run` saves (also for a run that
stopped early: the results up to that point are kept).

Step size: the default, 2 ms, was checked against a 0.25 ms reference on the seed's scenario
(see ``docs/validation.md`` and ``tests/test_dynamics.py``); generalized-alpha with spectral
radius 0.7 damps the stiff wheel-rail contact modes, and modified Newton with a relative
tolerance of 1e-4 re-uses one Jacobian for many steps (Rxyz nodes, ``docs/dev/exudyn-api.md``).
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

from .contact import kernel as K
from .curving import track_columns
from .forces import FR_S, WL_LATERAL, WL_ROLL, WL_S, WL_VERTICAL, WL_YAW, track_position
from .longitudinal import LongitudinalRecord, longitudinal_summary
from .model import VehicleModel
from .preflight import check_initial_offset
from .run_settings import RunSettings as RunSettings
from .run_settings import RunSettingsError as RunSettingsError
from .run_settings import run_settings_from_dict as run_settings_from_dict
from .timeseries import TimeSeries
from .track import Track, ideal_straight_track
from .vehicle import Vehicle


@dataclass
class RunResult:
    """Outcome of a run: the time series up to the end (or the stop), the summary (a
    :class:`railexu.results.RunSummary` from :func:`railexu.runs.run`; the run's facts only from
    :func:`simulate`), the status, the model."""

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


ProgressCallback = Callable[[float, float, float, float], None]

#: Run states in which the run reached its end: cleanly, or with a safety criterion exceeded
#: (set by the assessment, :func:`railexu.runs.run`).
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


#: Per contact point in the time series (``--contact-outputs``): ``ws{i}_{side}_p{k}_<field>``
#: with the kernel's field of each (position on the wheel profile from the tape circle, on the
#: rail, contact angle, creepages, forces on the wheel in the contact frame, semi-axes).
CONTACT_FIELDS = {
    "wheel_y_m": K.PF_S,
    "rail_y_m": K.PF_YRAIL,
    "angle_rad": K.PF_ANGLE,
    "creep_x": K.PF_XI,
    "creep_y": K.PF_ETA,
    "spin_1_per_m": K.PF_SPIN,
    "Fx_N": K.PF_FX,
    "Fy_N": K.PF_FY,
    "N_N": K.PF_N,
    "a_m": K.PF_A,
    "b_m": K.PF_B,
    "Tgamma_N": -1,  # |Fx xi + Fy eta|: the wear number (Pearce and Sherratt 1991)
}


#: The kernel fields of every contact point a run keeps in memory (``RunResult.contact_points``,
#: last axis): active flag, position on the wheel profile, track-frame position, contact angle,
#: normal force, semi-axes, tangential forces in the contact frame.
POINT_FIELDS = {
    "active": K.PF_ACTIVE,
    "wheel_s_m": K.PF_S,
    "y_m": K.PF_Y,
    "z_m": K.PF_Z,
    "angle_rad": K.PF_ANGLE,
    "N_N": K.PF_N,
    "a_m": K.PF_A,
    "b_m": K.PF_B,
    "Fx_N": K.PF_FX,
    "Fy_N": K.PF_FY,
    "FY_N": K.PF_FTY,
    "FZ_N": K.PF_FTZ,
}


_POINT_INDEX = np.array(list(POINT_FIELDS.values()))
_CONTACT_INDEX = np.array([f for f in CONTACT_FIELDS.values() if f >= 0])


def contact_fields(points: np.ndarray) -> np.ndarray:
    """The :data:`CONTACT_FIELDS` of every contact point, shape ``(n_ws, 2, MAX_POINTS,
    n_fields)``, zero where a candidate point carries no load."""
    loaded = points[..., K.PF_N] > 0.0
    out = np.zeros((*points.shape[:3], len(CONTACT_FIELDS)))
    out[..., : _CONTACT_INDEX.size] = points[..., _CONTACT_INDEX]
    out[..., -1] = np.abs(
        points[..., K.PF_FX] * points[..., K.PF_XI] + points[..., K.PF_FY] * points[..., K.PF_ETA]
    )
    return np.where(loaded[..., None], out, 0.0)


def point_accelerations(qtt_body: np.ndarray, lever_m: np.ndarray) -> np.ndarray:
    """Lateral and vertical accelerations [m/s^2] of points fixed to bodies, from the bodies'
    coordinate accelerations ``(x, y, z, roll, pitch, yaw)`` (one row per point) and the points'
    lever arms from the centres of gravity (vehicle axes).

    Small rotations (the car body's angles stay below a few degrees): a = a_cg + alpha x r; the
    centripetal term omega x (omega x r) is of second order in the angular rates and left out.
    Relative to the track (its frame in a curve): the quasi-static lateral acceleration of a
    curve is not in it (the EN 12299 weightings remove it; ``docs/assessment.md``).
    """
    a_y = qtt_body[:, 1] + qtt_body[:, 5] * lever_m[:, 0] - qtt_body[:, 3] * lever_m[:, 2]
    a_z = qtt_body[:, 2] + qtt_body[:, 3] * lever_m[:, 1] - qtt_body[:, 4] * lever_m[:, 0]
    return np.stack([a_y, a_z], axis=1)


class _Recorder:
    """Records the time series of a run into a preallocated array, vectorised over wheelsets,
    and checks for derailment."""

    def __init__(
        self,
        model: VehicleModel,
        vehicle: Vehicle,
        settings: RunSettings,
        order: list[int],
        n_out: int,
        flange_height: list[float],
    ) -> None:
        self.model = model
        self.settings = settings
        self.speed = settings.speed_m_per_s
        self.order = np.asarray(order)
        names = [vehicle.wheelsets[i].name for i in order]
        self.ws_names = names
        self.body_names = [b.name for b in vehicle.bodies]
        columns = ["time_s", "distance_m"]
        for i in range(1, len(names) + 1):
            columns += [f"ws{i}_{k}" for k in ("lateral_m", "yaw_rad", "roll_rad", "vertical_m")]
            for side in ("left", "right"):
                columns += [
                    f"ws{i}_{side}_{k}" for k in ("Y_N", "Q_N", "n_contacts", "max_angle_rad")
                ]
        columns += [f"{name}_lateral_m" for name in self.body_names]
        # track-relative extras: distance of each wheelset along the track, the wear number
        # T-gamma of each wheel
        columns += [f"ws{i}_s_m" for i in range(1, len(names) + 1)]
        columns += [
            f"ws{i}_{side}_Tgamma_N" for i in range(1, len(names) + 1) for side in ("left", "right")
        ]
        if settings.speed_varies:
            columns.append("speed_m_per_s")
        columns += [
            f"{p.name}_acc_{k}_m_per_s2" for p in vehicle.measurement_points for k in ("y", "z")
        ]
        if settings.contact_outputs:
            columns += [
                f"ws{i}_{side}_p{k}_{field}"
                for i in range(1, len(names) + 1)
                for side in ("left", "right")
                for k in range(1, K.MAX_POINTS + 1)
                for field in CONTACT_FIELDS
            ]
        self.columns = columns
        self.data = np.zeros((n_out, len(columns)))
        col = {c: j for j, c in enumerate(columns)}
        self.c_ws = np.array(
            [[col[f"ws{i}_{k}"] for k in ("lateral_m", "yaw_rad", "roll_rad", "vertical_m")]
             for i in range(1, len(names) + 1)]
        )  # fmt: skip
        self.c_wheel = np.array(
            [[[col[f"ws{i}_{side}_{k}"] for k in ("Y_N", "Q_N", "n_contacts", "max_angle_rad")]
              for side in ("left", "right")] for i in range(1, len(names) + 1)]
        )  # fmt: skip
        self.c_body = np.array([col[f"{n}_lateral_m"] for n in self.body_names], dtype=int)
        self.c_speed = col.get("speed_m_per_s")
        self.longitudinal = LongitudinalRecord(model, order, n_out)
        n_ws = len(names)
        self.c_s = np.array([col[f"ws{i}_s_m"] for i in range(1, n_ws + 1)])
        self.c_tgamma = np.array(
            [[col[f"ws{i}_{side}_Tgamma_N"] for side in ("left", "right")]
             for i in range(1, n_ws + 1)]
        )  # fmt: skip
        self.curved = model.curved
        self._init_accelerations(vehicle, col)
        # the kernel's contact points at every output time, kept in memory for the state file
        # of the animations (the time series carries them only with contact_outputs)
        self.point_data = np.zeros((n_out, len(names), 2, K.MAX_POINTS, len(POINT_FIELDS)))
        self.c_points = None
        if settings.contact_outputs:
            first = col["ws1_left_p1_" + next(iter(CONTACT_FIELDS))]
            self.c_points = first + np.arange(
                len(names) * 2 * K.MAX_POINTS * len(CONTACT_FIELDS)
            ).reshape(len(names), 2, K.MAX_POINTS, len(CONTACT_FIELDS))
        # elastic track: deflections of the rail masses under each wheelset
        self.rail_columns = []
        self.rail_coords = []
        for i, name in enumerate(names, start=1):
            if name in model.rail_node:
                self.rail_columns.append(len(self.columns))
                for side in ("left", "right"):
                    for k in ("lateral", "vertical"):
                        self.columns.append(f"ws{i}_{side}_rail_{k}_m")
                self.rail_coords.append(model.rail_ltg[name])
        if self.rail_columns:
            self.data = np.zeros((n_out, len(self.columns)))
            self.c_rail = np.array([[c + k for k in range(4)] for c in self.rail_columns])
            self.i_rail = np.array(self.rail_coords)
        ltg = model.ltg
        self.i_ws = np.array([ltg[n] for n in names])  # (n_ws, 6) global coordinates
        self.ref = np.array([model.centre[n] for n in names])
        self.theta0 = np.array(
            [math.atan2(model.rotation[n][2, 1], model.rotation[n][1, 1]) for n in names]
        )
        self.i_body = np.array([ltg[n][1] for n in self.body_names], dtype=int)
        self.i_body_x = np.array([ltg[n][0] for n in self.body_names], dtype=int)
        self.ref_body = np.array([model.centre[n][1] for n in self.body_names])
        self.ref_body_x = np.array([model.centre[n][0] for n in self.body_names])
        self.i_body_z = np.array([ltg[n][2] for n in self.body_names], dtype=int)
        self.ref_body_z = np.array([model.centre[n][2] for n in self.body_names])
        # lateral positions are recorded relative to the track centre line (the mean lateral
        # offset of the two rails, i.e. the alignment irregularity)
        values = model.irr_values
        self.irr_x = model.irr_start + model.irr_step * np.arange(values.shape[0])
        self.irr_centre = 0.5 * (values[:, 0] + values[:, 2])
        self.has_alignment = bool(np.any(self.irr_centre != 0.0))
        st = [model.initial_wheelsets[i] for i in order]
        self.z0 = np.array([s.vertical_m for s in st])
        self.sin_roll0 = np.sin([s.roll_rad for s in st])
        self.e = np.array([model.geometries[i].left.tape_circle_lateral_m for i in order])
        self.lift_limit = settings.derailment_lift_fraction * np.array(
            [flange_height[i] for i in order]
        )
        self.out = np.zeros_like(model._out)
        self.points = np.zeros_like(model.points)
        self.ws_force = np.zeros_like(model.ws_force)
        self.n = 0
        self.last_time = -math.inf

    def _init_accelerations(self, vehicle: Vehicle, col: dict[str, int]) -> None:
        """Node coordinates and lever arms of the measurement points."""
        ltg = self.model.ltg
        points = vehicle.measurement_points
        self.c_acc = np.array(
            [[col[f"{p.name}_acc_{k}_m_per_s2"] for k in ("y", "z")] for p in points], dtype=int
        ).reshape(-1, 2)
        self.i_acc = np.array([ltg[p.body] for p in points], dtype=int).reshape(-1, 6)
        centres = {b.name: b.position_m for b in vehicle.bodies}
        self.lever = np.array([np.subtract(p.position_m, centres[p.body]) for p in points]).reshape(
            -1, 3
        )

    def record(
        self, t: float, q: np.ndarray, qt: np.ndarray, qtt: np.ndarray | None = None
    ) -> tuple | None:
        """Store the state at time ``t``; returns a status tuple when the run must stop."""
        k = self.n
        if k >= self.data.shape[0]:
            return None
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(qt))):
            return ("diverged", t, "the state became NaN or infinite")
        self.model.evaluate(q, qt, t, self.out, self.points, self.ws_force)
        row = self.data[k]
        row[0] = t
        row[1] = self.settings.distance_at(t)
        if self.c_speed is not None:
            row[self.c_speed] = self.settings.speed_at(t)
        if self.curved:
            loc = self.model.kernel.ws_local[self.order]
            s_ws = loc[:, WL_S]
            y = loc[:, WL_LATERAL] - self._track_centre(s_ws)
            z = loc[:, WL_VERTICAL]
            phi = loc[:, WL_ROLL]
            psi = loc[:, WL_YAW]
        else:
            s_ws = self.ref[:, 0] + q[self.i_ws[:, 0]]
            y = self.ref[:, 1] + q[self.i_ws[:, 1]] - self._track_centre(s_ws)
            z = self.ref[:, 2] + q[self.i_ws[:, 2]]
            phi = self.theta0 + q[self.i_ws[:, 3]] + 0.5 * math.pi
            psi = -q[self.i_ws[:, 4]]
        row[self.c_s] = s_ws
        row[self.c_ws[:, 0]] = y
        row[self.c_ws[:, 1]] = psi
        row[self.c_ws[:, 2]] = phi
        row[self.c_ws[:, 3]] = z
        pts = self.points[self.order]
        loaded = pts[:, :, :, K.PF_N] > 0.0
        row[self.c_wheel[:, :, 0]] = pts[:, :, :, K.PF_FTY].sum(axis=2)
        row[self.c_wheel[:, :, 1]] = pts[:, :, :, K.PF_FTZ].sum(axis=2)
        row[self.c_wheel[:, :, 2]] = loaded.sum(axis=2)
        angle = np.where(loaded, pts[:, :, :, K.PF_ANGLE], -np.inf).max(axis=2)
        row[self.c_wheel[:, :, 3]] = np.where(np.isfinite(angle), angle, 0.0)
        # wear number: sum over the contact points of |creep force . creepage|
        power = pts[:, :, :, K.PF_FX] * pts[:, :, :, K.PF_XI]
        power += pts[:, :, :, K.PF_FY] * pts[:, :, :, K.PF_ETA]
        row[self.c_tgamma] = np.abs(np.where(loaded, power, 0.0)).sum(axis=2)
        self.longitudinal.keep(k, q, qt, qtt, pts)
        if self.c_body.size:
            row[self.c_body] = self._body_lateral(q)
        if self.rail_columns:
            row[self.c_rail] = q[self.i_rail]
        if qtt is not None and self.c_acc.size:
            row[self.c_acc] = point_accelerations(qtt[self.i_acc], self.lever)
        if self.c_points is not None:
            row[self.c_points] = contact_fields(pts)
        self.point_data[k] = pts[..., _POINT_INDEX]
        self.n = k + 1
        self.last_time = t
        # derailment: a wheel climbing its rail, or a wheelset off the track
        droll = self.e * (np.sin(phi) - self.sin_roll0)
        rise = np.stack([(z - self.z0) + droll, (z - self.z0) - droll], axis=1)
        climbed = rise.max(axis=1) > self.lift_limit
        if np.any(climbed):
            w = int(np.argmax(climbed))
            side = "left" if rise[w, 0] > rise[w, 1] else "right"
            return (
                "derailed",
                t,
                f"wheelset {self.ws_names[w]} ({w + 1}), {side} wheel rose "
                f"{rise[w].max() * 1e3:.1f} mm above its rail (flange climb or wheel lift) at "
                f"lateral {y[w] * 1e3:.1f} mm",
            )
        off = np.abs(y) > self.settings.derailment_lateral_m
        if np.any(off):
            w = int(np.argmax(off))
            return (
                "derailed",
                t,
                f"wheelset {self.ws_names[w]} ({w + 1}) left the track: lateral "
                f"{y[w] * 1e3:.1f} mm",
            )
        return None

    def _body_lateral(self, q: np.ndarray) -> np.ndarray:
        """Lateral position of every body's centre relative to the track centre line [m]."""
        x_body = self.ref_body_x + q[self.i_body_x]
        y_body = self.ref_body + q[self.i_body]
        if not self.curved:
            return y_body - self._track_centre(x_body)
        # in the canted plane of the track at the foot point, as the wheelsets' lateral
        data = self.model.kernel
        z_body = self.ref_body_z + q[self.i_body_z]
        out = np.empty(x_body.size)
        for j in range(x_body.size):
            s, lateral, height, _ = track_position(
                data, x_body[j] - data.frame[FR_S], y_body[j], z_body[j]
            )
            cant = float(self.model.alignment.cant_angle(s))
            out[j] = math.cos(cant) * lateral + math.sin(cant) * height - self._track_centre(s)
        return out

    def _track_centre(self, x: np.ndarray) -> np.ndarray | float:
        if not self.has_alignment:
            return 0.0
        return np.interp(x, self.irr_x, self.irr_centre, left=0.0, right=0.0)

    def timeseries(self) -> TimeSeries:
        columns = {c: self.data[: self.n, j].copy() for j, c in enumerate(self.columns)}
        columns.update(self.longitudinal.columns(self.n))
        speed = columns.get("speed_m_per_s")
        if speed is None:
            speed = np.full(self.n, self.speed)
        columns.update(
            track_columns(self.model.alignment, columns["ws1_s_m"], speed,
                          self.model.vehicle.gravity_m_per_s2)
        )  # fmt: skip
        return TimeSeries(columns)


_STOP_SIGNALS = {"SIGINT": "Ctrl-C, SIGINT", "SIGTERM": "SIGTERM"}


def _catch_stop_signals(rec: dict) -> dict:
    """Let SIGINT and SIGTERM end the run at the next step (``rec["interrupted"]`` then names the
    signal); returns the previous handlers. A signal that the process ignores (a study's worker
    ignores SIGINT) stays ignored; outside the main thread nothing can be caught."""
    previous = {}
    for name, label in _STOP_SIGNALS.items():
        signum = getattr(signal, name)
        with contextlib.suppress(ValueError):
            if signal.getsignal(signum) is not signal.SIG_IGN:
                previous[signum] = signal.signal(
                    signum, lambda *_, label=label: rec.__setitem__("interrupted", label)
                )
    return previous


def simulate(
    vehicle: Vehicle,
    track: Track | None = None,
    settings: RunSettings | None = None,
    progress: ProgressCallback | None = None,
) -> RunResult:
    """Simulate ``vehicle`` running on ``track`` (ideal straight track by default), without the
    assessment: :func:`railexu.runs.run` adds it (the public ``railexu.run``).

    The run stops early with status ``derailed`` when a wheel climbs its rail or a wheelset
    leaves the track, ``diverged`` when the solver fails or the state becomes invalid, and
    ``interrupted`` on Ctrl-C or SIGTERM; the time series up to that point is returned either
    way. The result's ``summary`` holds the facts of the run (status, solver statistics,
    settings, names, timings, warnings).

    Raises:
        InputError: an initial lateral offset that lifts a wheel up its flange
            (:func:`railexu.preflight.check_initial_offset`), a model that cannot be built.
    """
    settings = settings or RunSettings()
    track = track or ideal_straight_track()
    t_start = time.perf_counter()
    warnings = check_initial_offset(vehicle, track, settings)
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
    model.warm_up()
    t_built = time.perf_counter()
    order = wheelset_order(vehicle)
    ss, n_steps = _solver_settings(settings)
    recorder = _Recorder(
        model, vehicle, settings, order, n_steps // settings.output_every + 2,
        _flange_heights(model),
    )  # fmt: skip
    wall_int, error, stop = _integrate(model, settings, ss, recorder, progress)
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
        "solver": _solver_statistics(model),
        "settings": asdict(settings),
        "vehicle": vehicle.name,
        "track": track.name,
    }
    warnings += list(model.axle_load_warnings)
    if warnings:
        facts["warnings"] = warnings
    facts["longitudinal"] = longitudinal_summary(ts, model)
    points = recorder.point_data[: len(ts)]
    return RunResult(ts, facts, status, settings, vehicle, track, timings, model, points)


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
    ti.minimumStepSize = h / 1024.0  # impacts on a rigid rail may need a few tiny steps
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    ss.show.computationTime = False
    ss.show.statistics = False
    return ss, n_steps


def _integrate(model, settings, ss, recorder, progress):
    """Run Exudyn's solver with recording, progress and stop signals.

    Returns ``(wall-clock seconds, solver exception or None, stop status or None)``."""
    import exudyn as exu

    mbs = model.mbs
    ti = ss.timeIntegration
    h = settings.time_step_s
    rec = {"status": None, "next": 0.0, "interrupted": False}
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
        if progress is not None:
            elapsed = time.perf_counter() - wall0[0]
            frac = t / ti.endTime if ti.endTime > 0 else 1.0
            eta = elapsed * (1.0 - frac) / frac if frac > 0 else math.inf
            progress(model.distance_at(t), settings.distance_m, model.speed_at(t), eta)
        return rec["status"] is None

    interval = settings.output_every * h

    def pre_step(mbs_, t: float) -> bool:
        # t is the end time of the step about to be computed: the speed it must reach, or
        # (free motion) the torques; False ends a free run at its distance or standstill
        return model.begin_step(t, h, settings.distance_m)

    def post_step(mbs_, t: float) -> bool:
        # called with the initial state (t = 0) and after every step, with the state at t
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

    if settings.speed_varies:
        mbs.SetPreStepUserFunction(pre_step)
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
    return wall_int, error, rec["status"]


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
    """Newton iterations, Jacobian updates and steps of Exudyn's solver."""
    try:
        it = model.mbs.sys["dynamicSolver"].it
        return {
            "newton_iterations": int(it.newtonStepsCount),
            "jacobian_updates": int(it.newtonJacobiCount),
            "steps": int(it.currentStepIndex),
        }
    except (KeyError, AttributeError):
        return {}


def flange_angle_rad(model: VehicleModel) -> float:
    """Flange angle of the (first) wheel profile [rad]: the largest slope of the flank between
    the flange tip (the highest point) and the tape circle (S1002: 70 deg). The flange back
    beyond the tip is not part of it."""
    wheel = model.geometries[0].left.wheel
    s = np.linspace(wheel.y_min, 0.0, 8001)
    tip = s[int(np.argmax(wheel.height(s)))]
    flank = s[s >= tip]
    return float(np.max(np.arctan(np.abs(wheel.slope(flank)))))
