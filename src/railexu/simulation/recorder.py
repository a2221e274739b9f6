"""The time series of a run: raw state kept at every output time, columns computed after the run.

During the integration the recorder only copies what the solver already has: the
track-relative pose of every wheelset and the contact points that the force function computed
for the converged state of the step (its last evaluation in a step is at the converged state:
Exudyn's Newton iteration ends with the residual of the accepted update, checked by
``tests/test_recorder_outputs.py``), a few node coordinates and accelerations. It checks for
derailment on the spot (a few vectorised operations on the wheelsets' poses). Everything else
(forces per wheel, wear numbers, accelerations of the measurement points, body positions
relative to the track) is computed once, vectorised over time, by :meth:`Recorder.timeseries`.
This keeps the recorder's cost per output sample to a few microseconds (issue 11: it used to
evaluate the contact forces again in Python at every sample).
"""

from __future__ import annotations

import math

import numpy as np

from railexu.contact import kernel as K
from railexu.model.assembly import VehicleModel
from railexu.model.forces import (
    FR_S,
    FR_SIZE,
    WL_LATERAL,
    WL_ROLL,
    WL_S,
    WL_SIZE,
    WL_VERTICAL,
    WL_YAW,
    frame_motion,
    track_position,
)
from railexu.model.record_row import ROW_OFF_TRACK, ROW_WHEEL_ROSE, derailment, keep_row
from railexu.operation.run_settings import RunSettings
from railexu.simulation.curving import track_columns
from railexu.simulation.longitudinal import LongitudinalRecord
from railexu.simulation.sc_outputs import sc_columns
from railexu.simulation.timeseries import TimeSeries
from railexu.track.vertical import vertical_columns
from railexu.vehicle.vehicle import Vehicle

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
#: The kernel fields the recorder keeps of every contact point at every output time.
_KEPT = np.unique(np.concatenate([
    _POINT_INDEX, _CONTACT_INDEX,
    [K.PF_N, K.PF_FTY, K.PF_FTZ, K.PF_ANGLE, K.PF_FX, K.PF_FY, K.PF_XI, K.PF_ETA, K.PF_SPIN],
])).astype(np.int64)  # fmt: skip
#: an empty array: no accelerations to keep, or no irregularities
_EMPTY = np.zeros(0)
_SIDES = ("left", "right")


def contact_fields(points: np.ndarray) -> np.ndarray:
    """The :data:`CONTACT_FIELDS` of every contact point, shape ``(..., MAX_POINTS, n_fields)``
    for kernel points ``(..., MAX_POINTS, N_POINT_FIELDS)``, zero where a candidate point
    carries no load."""
    loaded = points[..., K.PF_N] > 0.0
    out = np.zeros((*points.shape[:-1], len(CONTACT_FIELDS)))
    out[..., : _CONTACT_INDEX.size] = points[..., _CONTACT_INDEX]
    out[..., -1] = np.abs(
        points[..., K.PF_FX] * points[..., K.PF_XI] + points[..., K.PF_FY] * points[..., K.PF_ETA]
    )
    return np.where(loaded[..., None], out, 0.0)


def point_accelerations(qtt_body: np.ndarray, lever_m: np.ndarray) -> np.ndarray:
    """Lateral and vertical accelerations [m/s^2] of points fixed to bodies relative to the
    vehicle frame (the track's frame in a curve), from the bodies' coordinate accelerations
    ``(..., 6)``: ``(x, y, z, roll, pitch, yaw)``, one row per point, and the points' lever arms
    ``(n, 3)`` from the centres of gravity (vehicle axes); returns ``(..., 2)``.

    Small rotations (the car body's angles stay below a few degrees): a = a_cg + alpha x r; the
    centripetal term omega x (omega x r) is of second order in the angular rates and left out.
    This is the kinematic part of :func:`accelerometer_readings` (what the time series records).
    """
    return relative_point_accelerations(qtt_body, lever_m)[..., 1:]


def relative_point_accelerations(qtt_body: np.ndarray, lever_m: np.ndarray) -> np.ndarray:
    """Longitudinal, lateral and vertical accelerations ``(..., 3)`` [m/s^2] of body points
    relative to the vehicle frame, as :func:`point_accelerations`."""
    a = qtt_body
    r = lever_m
    a_x = a[..., 0] + a[..., 4] * r[..., 2] - a[..., 5] * r[..., 1]
    a_y = a[..., 1] + a[..., 5] * r[..., 0] - a[..., 3] * r[..., 2]
    a_z = a[..., 2] + a[..., 3] * r[..., 1] - a[..., 4] * r[..., 0]
    return np.stack([a_x, a_y, a_z], axis=-1)


def accelerometer_readings(
    qtt_body: np.ndarray,
    lever_m: np.ndarray,
    angles_rad: np.ndarray,
    position_m: np.ndarray,
    frame_motion_: np.ndarray,
    gravity_m_per_s2: float,
) -> np.ndarray:
    """What an accelerometer fixed in a body reads, lateral and vertical ``(..., 2)`` [m/s^2]
    (``docs/conventions.md``, "Accelerations"): the specific force ``f = a - g`` (absolute
    acceleration minus gravity), in the body's own axes; the vertical reading minus ``g``, so
    that it is 0 at rest on level track.

    With the vehicle frame's origin acceleration ``a_O``, angular velocity ``Omega`` and
    acceleration ``Omega'`` (:func:`railexu.model.forces.frame_motion`), a point at ``r`` from
    the frame's origin has ``a = a_O + a_rel + Omega' x r + Omega x (Omega x r)`` (the Coriolis
    term ``2 Omega x r'`` is left out: below 0.01 m/s^2 for a yaw rate of 0.05 rad/s and a
    lateral velocity of 0.1 m/s); it is turned into the body's axes by ``A^T`` with
    ``A = Rx(theta0) Ry(theta1) Rz(theta2)`` of the body's angles relative to the frame. At rest
    on track canted by ``phi`` the lateral reading is ``-g sin(phi_total)`` with ``phi_total``
    the body's total roll (cant plus its own roll); in a steady curve it is
    ``V^2/R cos(phi) - g sin(phi)`` plus ``g`` times the body's roll relative to the track
    (outwards positive), phi the magnitude of the cant angle.

    Args:
        qtt_body: the points' bodies' coordinate accelerations ``(..., 6)``.
        lever_m: the points' levers from their bodies' centres ``(P, 3)`` (vehicle axes).
        angles_rad: the bodies' angles relative to the frame ``(..., 3)``.
        position_m: the points' positions relative to the frame's origin ``(..., 3)`` [m].
        frame_motion_: the frame's motion ``(..., 12)`` of
            :func:`railexu.model.forces.frame_motion` (zero on straight track).
        gravity_m_per_s2: g.
    """
    fm = np.asarray(frame_motion_)[..., None, :]
    a = relative_point_accelerations(qtt_body, lever_m)
    omega, omega_dot = fm[..., 2:5], fm[..., 5:8]
    r = position_m
    a = a + np.cross(omega_dot, r) + np.cross(omega, np.cross(omega, r))
    g = gravity_m_per_s2
    # f = a - g_vec; the origin's acceleration (V' in the first coordinate already) and
    # gravity (0, -g sin(phi), -g cos(phi)) in frame axes: fm[10] = -g sin(phi),
    # fm[11] = g (1 - cos(phi))
    f_x = a[..., 0]
    f_y = a[..., 1] + fm[..., 8] - fm[..., 10]
    f_z = a[..., 2] + fm[..., 9] - (fm[..., 11] - g)
    t0, t1, t2 = angles_rad[..., 0], angles_rad[..., 1], angles_rad[..., 2]
    c0, s0, c1, s1 = np.cos(t0), np.sin(t0), np.cos(t1), np.sin(t1)
    c2, s2 = np.cos(t2), np.sin(t2)
    # columns 2 and 3 of A = Rx Ry Rz: the body's lateral and vertical axes in frame axes
    e_y = (-c1 * s2, c0 * c2 - s0 * s1 * s2, s0 * c2 + c0 * s1 * s2)
    e_z = (s1, -s0 * c1, c0 * c1)
    lateral = e_y[0] * f_x + e_y[1] * f_y + e_y[2] * f_z
    vertical = e_z[0] * f_x + e_z[1] * f_y + e_z[2] * f_z - g
    return np.stack([lateral, vertical], axis=-1)


class Recorder:
    """Keeps the raw state of a run at its output times (preallocated), checks for derailment
    at each, and makes the time series after the run.

    Args:
        model: the built model (its force function's arrays are read after every step).
        vehicle: the vehicle.
        settings: the run settings (speed and distance at a time; contact outputs).
        order: wheelset indices from the front.
        n_out: the number of output samples to make room for.
        flange_height: height of the flange tip above the tape circle, per wheelset [m].
    """

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
        self.vehicle = vehicle
        self.settings = settings
        self.order = np.asarray(order, dtype=np.int64)
        self.ws_names = [vehicle.wheelsets[i].name for i in order]
        self.body_names = [b.name for b in vehicle.bodies]
        n_ws = len(order)
        ltg = model.ltg
        # node coordinates kept: the bodies' x, y, z and angles (relative to the frame); the
        # elastic track's rail coordinates; accelerations of the measurement points' bodies
        self.i_body = np.array([ltg[n][:6] for n in self.body_names], dtype=int).reshape(-1, 6)
        self.ref_body = np.array([model.centre[n] for n in self.body_names]).reshape(-1, 3)
        rails = [n for n in self.ws_names if n in model.rail_node]
        self.rail_names = rails
        self.i_rail = np.array([model.rail_ltg[n] for n in rails], dtype=int).reshape(-1, 4)
        points = vehicle.measurement_points
        self.i_acc = np.array([ltg[p.body] for p in points], dtype=int).reshape(-1, 6)
        centres = {b.name: b.position_m for b in vehicle.bodies}
        self.lever = np.array([np.subtract(p.position_m, centres[p.body]) for p in points]).reshape(
            -1, 3
        )
        # the same, flat, for the compiled copy at each output
        self._i_body = np.ascontiguousarray(self.i_body.ravel(), dtype=np.int64)
        self._i_rail = np.ascontiguousarray(self.i_rail.ravel(), dtype=np.int64)
        self._i_acc = np.ascontiguousarray(self.i_acc.ravel(), dtype=np.int64)
        # the raw record
        self.time = np.zeros(n_out)
        self.local = np.zeros((n_out, n_ws, WL_SIZE))
        self.points = np.zeros((n_out, n_ws, 2, K.MAX_POINTS, _KEPT.size))
        self.body_q = np.zeros((n_out, self.i_body.size))
        self.rail_q = np.zeros((n_out, self.i_rail.size))
        # the rail masses' velocities and accelerations (their force balance can be checked)
        self.rail_qt = np.zeros_like(self.rail_q)
        self.rail_qtt = np.zeros_like(self.rail_q)
        self.acc_q = np.zeros((n_out, self.i_acc.size))
        self.frame_s = np.zeros(n_out)
        self.frame_state = np.zeros((n_out, FR_SIZE))
        self.point_body = np.array([self.body_names.index(p.body) for p in points], dtype=np.int64)
        # derailment: the wheels' rise above their rails from the static state
        self.irregularity_centre = _IrregularityCentre(model)
        st = [model.initial_wheelsets[i] for i in order]
        self.z0 = np.array([s.vertical_m for s in st])
        self.sin_roll0 = np.sin([s.roll_rad for s in st])
        self.e = np.array([model.geometries[i].left.tape_circle_lateral_m for i in order])
        self.lift_limit = settings.derailment_lift_fraction * np.array(
            [flange_height[i] for i in order]
        )
        # traction and braking: creepages, creep forces, spin, achieved motion
        self.longitudinal = LongitudinalRecord(model, order, n_out)
        self.n = 0
        self.last_time = -math.inf

    def record(
        self, t: float, q: np.ndarray, qt: np.ndarray, qtt: np.ndarray | None = None
    ) -> tuple | None:
        """Keep the state at time ``t`` (the force function's arrays hold its evaluation at the
        step's converged state); returns a status tuple when the run must stop."""
        k = self.n
        if k >= self.time.size:
            return None
        model = self.model
        kept = keep_row(
            k, q, qt, _EMPTY if qtt is None else qtt, model.kernel.ws_local,
            model.points, self.order, _KEPT, self._i_body, self._i_rail, self._i_acc,
            self.local, self.points, self.body_q, self.rail_q, self.acc_q,
        )  # fmt: skip
        if not kept:
            return ("diverged", t, "the state became NaN or infinite")
        if self._i_rail.size:
            self.rail_qt[k] = np.asarray(qt)[self._i_rail]
            if qtt is not None:
                self.rail_qtt[k] = np.asarray(qtt)[self._i_rail]
        self.time[k] = t
        self.frame_s[k] = model.kernel.frame[FR_S]
        self.frame_state[k] = model.kernel.frame
        self.longitudinal.keep(k, q, qt, qtt)
        self.n = k + 1
        self.last_time = t
        return self._derailment(t, self.local[k])

    def _derailment(self, t: float, loc: np.ndarray) -> tuple | None:
        """A wheel climbing its rail, or a wheelset off the track."""
        centre = self.irregularity_centre
        verdict, w, side, rise, y = derailment(
            loc, self.z0, self.sin_roll0, self.e, self.lift_limit,
            centre.x if centre.active else _EMPTY, centre.centre,
            self.settings.derailment_lateral_m,
        )  # fmt: skip
        if verdict == ROW_WHEEL_ROSE:
            return (
                "derailed",
                t,
                f"wheelset {self.ws_names[w]} ({w + 1}), {_SIDES[side]} wheel rose "
                f"{rise * 1e3:.1f} mm above its rail (flange climb or wheel lift) at "
                f"lateral {y * 1e3:.1f} mm",
            )
        if verdict == ROW_OFF_TRACK:
            return (
                "derailed",
                t,
                f"wheelset {self.ws_names[w]} ({w + 1}) left the track: lateral {y * 1e3:.1f} mm",
            )
        return None

    def contact_points(self) -> np.ndarray:
        """The :data:`POINT_FIELDS` of every contact point at every output time,
        ``(n, n_ws, 2, MAX_POINTS, fields)``."""
        return self.points[: self.n][..., np.searchsorted(_KEPT, _POINT_INDEX)]

    def timeseries(self) -> TimeSeries:
        """The run's time series (wheelsets from the front as ``ws1``, ``ws2``, ...)."""
        n = self.n
        t = self.time[:n]
        cols: dict[str, np.ndarray] = {"time_s": t.copy()}
        cols["distance_m"] = np.array([self.settings.distance_at(float(x)) for x in t])
        speed = np.array([self.settings.speed_at(float(x)) for x in t])
        loc = self.local[:n]
        pts = self._kernel_points(self.points[:n])
        s_ws = loc[:, :, WL_S]
        lateral = loc[:, :, WL_LATERAL] - self.irregularity_centre(s_ws)
        loaded = pts[..., K.PF_N] > 0.0
        y_wheel = pts[..., K.PF_FTY].sum(axis=-1)
        q_wheel = pts[..., K.PF_FTZ].sum(axis=-1)
        n_contacts = loaded.sum(axis=-1)
        angle = np.where(loaded, pts[..., K.PF_ANGLE], -np.inf).max(axis=-1)
        angle = np.where(np.isfinite(angle), angle, 0.0)
        # wear number: sum over the contact points of |creep force . creepage|
        power = pts[..., K.PF_FX] * pts[..., K.PF_XI] + pts[..., K.PF_FY] * pts[..., K.PF_ETA]
        tgamma = np.abs(np.where(loaded, power, 0.0)).sum(axis=-1)
        for i in range(len(self.ws_names)):
            w = f"ws{i + 1}"
            cols[f"{w}_lateral_m"] = lateral[:, i]
            cols[f"{w}_yaw_rad"] = loc[:, i, WL_YAW]
            cols[f"{w}_roll_rad"] = loc[:, i, WL_ROLL]
            cols[f"{w}_vertical_m"] = loc[:, i, WL_VERTICAL]
            for s, side in enumerate(("left", "right")):
                cols[f"{w}_{side}_Y_N"] = y_wheel[:, i, s]
                cols[f"{w}_{side}_Q_N"] = q_wheel[:, i, s]
                cols[f"{w}_{side}_n_contacts"] = n_contacts[:, i, s].astype(float)
                cols[f"{w}_{side}_max_angle_rad"] = angle[:, i, s]
        body_lateral, body_s = self._body_lateral()
        for name, values in zip(self.body_names, body_lateral.T, strict=True):
            cols[f"{name}_lateral_m"] = values
        frame = self._frame_motion()
        roll = self._body_roll_rel_track(frame, body_s)
        for name, values in zip(self.body_names, roll.T, strict=True):
            cols[f"{name}_roll_rel_track_rad"] = values
        for i in range(len(self.ws_names)):
            cols[f"ws{i + 1}_s_m"] = s_ws[:, i]
        for i in range(len(self.ws_names)):
            for s, side in enumerate(("left", "right")):
                cols[f"ws{i + 1}_{side}_Tgamma_N"] = tgamma[:, i, s]
        if self.settings.speed_varies:
            cols["speed_m_per_s"] = speed
        acc = self._accelerometers(frame)
        for j, p in enumerate(self.vehicle.measurement_points):
            cols[f"{p.name}_acc_y_m_per_s2"] = acc[:, j, 0]
            cols[f"{p.name}_acc_z_m_per_s2"] = acc[:, j, 1]
        # a free run's achieved distance and speed replace the prescribed ones
        cols.update(self.longitudinal.columns(n, pts))
        speed = cols.get("speed_m_per_s", speed)
        if self.settings.contact_outputs:
            fields = contact_fields(pts)
            for i in range(len(self.ws_names)):
                for s, side in enumerate(("left", "right")):
                    for k in range(K.MAX_POINTS):
                        for f, field in enumerate(CONTACT_FIELDS):
                            cols[f"ws{i + 1}_{side}_p{k + 1}_{field}"] = fields[:, i, s, k, f]
        rail = self.rail_q[:n].reshape(n, -1, 4)
        rail_v = self.rail_qt[:n].reshape(n, -1, 4)
        rail_a = self.rail_qtt[:n].reshape(n, -1, 4)
        for j, name in enumerate(self.rail_names):
            i = self.ws_names.index(name) + 1
            for c, key in enumerate(("left_rail_lateral", "left_rail_vertical",
                                     "right_rail_lateral", "right_rail_vertical")):  # fmt: skip
                cols[f"ws{i}_{key}_m"] = rail[:, j, c]
            for c, key in ((1, "left_rail_vertical"), (3, "right_rail_vertical")):
                # the rail mass's vertical velocity and acceleration (its force balance)
                cols[f"ws{i}_{key}_velocity_m_per_s"] = rail_v[:, j, c]
                cols[f"ws{i}_{key}_acceleration_m_per_s2"] = rail_a[:, j, c]
        cols.update(
            track_columns(self.model.alignment, cols["ws1_s_m"], speed,
                          self.vehicle.gravity_m_per_s2)
        )  # fmt: skip
        if getattr(self.model, "vertical", None) is not None:
            cols.update(vertical_columns(self.model.vertical, cols["ws1_s_m"]))
        # switches and crossings: forces, contact position and Tgamma per rail (issue 29)
        rails = getattr(self.model.track, "variable_rails", None)
        cols.update(sc_columns(rails, self.model.geometries[0], pts, s_ws))
        return TimeSeries(cols)

    @staticmethod
    def _kernel_points(kept: np.ndarray) -> np.ndarray:
        """The kept fields back at their kernel indices (the others zero)."""
        full = np.zeros((*kept.shape[:-1], K.N_POINT_FIELDS))
        full[..., _KEPT] = kept
        return full

    def _body_coordinates(self) -> tuple[np.ndarray, np.ndarray]:
        """Every body's centre (vehicle frame, first coordinate along the track) and angles
        relative to the frame at every output time, ``(n, n_bodies, 3)`` each."""
        n = self.n
        q = self.body_q[:n].reshape(n, -1, 6)
        return self.ref_body + q[..., :3], q[..., 3:]

    def _frame_motion(self) -> np.ndarray:
        """The vehicle frame's motion (:func:`railexu.model.forces.frame_motion`) at every
        output time ``(n, 12)``; zero on straight track."""
        n = self.n
        out = np.zeros((n, 12))
        if not self.model.curved:
            return out
        data = self.model.kernel
        saved = data.frame.copy()
        try:
            for k in range(n):
                data.frame[:] = self.frame_state[k]
                frame_motion(data, out[k])
        finally:
            data.frame[:] = saved
        return out

    def _body_roll_rel_track(self, frame: np.ndarray, body_s: np.ndarray) -> np.ndarray:
        """Every body's roll relative to the design track's cant under its centre,
        ``(n, n_bodies)`` [rad]: its angle about the frame's x axis plus the frame's roll minus
        the track's cant angle at the body's foot point (small angles; positive: left side up,
        ``docs/conventions.md``)."""
        _, angles = self._body_coordinates()
        roll = angles[..., 0] + frame[:, 1:2]
        if self.model.curved:
            roll = roll - np.asarray(self.model.alignment.cant_angle(body_s.ravel())).reshape(
                body_s.shape
            )
        return roll

    def _accelerometers(self, frame: np.ndarray) -> np.ndarray:
        """The accelerometer readings ``(n, n_points, 2)`` of the measurement points
        (:func:`accelerometer_readings`)."""
        n = self.n
        pos, angles = self._body_coordinates()
        j = self.point_body
        position = pos[:, j] + self.lever
        position[..., 0] -= self.frame_s[:n, None]
        return accelerometer_readings(
            self.acc_q[:n].reshape(n, -1, 6), self.lever, angles[:, j], position, frame,
            self.vehicle.gravity_m_per_s2,
        )  # fmt: skip

    def _body_lateral(self) -> tuple[np.ndarray, np.ndarray]:
        """Lateral position of every body's centre relative to the track centre line and the
        distance along the track of its foot point at every output time, ``(n, n_bodies)``
        each [m]."""
        n = self.n
        pos, _ = self._body_coordinates()
        if not self.model.curved:
            return pos[..., 1] - self.irregularity_centre(pos[..., 0]), pos[..., 0]
        # in the canted plane of the track at the foot point, as the wheelsets' lateral
        data = self.model.kernel
        saved = data.frame.copy()
        foot = np.empty((*pos.shape[:2], 3))
        try:
            for k in range(n):
                data.frame[FR_S] = self.frame_s[k]
                for j in range(pos.shape[1]):
                    x, y, z = pos[k, j]
                    foot[k, j] = track_position(data, x - self.frame_s[k], y, z)[:3]
        finally:
            data.frame[:] = saved
        s, lateral, height = foot[..., 0], foot[..., 1], foot[..., 2]
        cant = np.asarray(self.model.alignment.cant_angle(s.ravel())).reshape(s.shape)
        return np.cos(cant) * lateral + np.sin(cant) * height - self.irregularity_centre(s), s


class _IrregularityCentre:
    """The track centre line's lateral offset from the design line (the mean of the two rails'
    lateral irregularities) at distances along the track [m]; zero without irregularities."""

    def __init__(self, model: VehicleModel) -> None:
        values = model.irr_values
        self.x = model.irr_start + model.irr_step * np.arange(values.shape[0])
        self.centre = 0.5 * (values[:, 0] + values[:, 2])
        self.active = bool(np.any(self.centre != 0.0))

    def __call__(self, x):
        if not self.active:
            return 0.0 if np.ndim(x) == 0 else np.zeros(np.shape(x))
        return np.interp(x, self.x, self.centre, left=0.0, right=0.0)


__all__ = [
    "CONTACT_FIELDS",
    "POINT_FIELDS",
    "Recorder",
    "accelerometer_readings",
    "contact_fields",
    "point_accelerations",
]
