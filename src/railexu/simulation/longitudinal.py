"""Longitudinal outputs of a run: creepage and creep force per wheel, wheelset spin and axle
torque, the achieved speed and acceleration, and their summary (``docs/traction-and-braking.md``).

The recorder (:mod:`railexu.simulation.recorder`) keeps the wheelsets' spin and the speed body's
motion at every output time (:meth:`LongitudinalRecord.keep`) and adds
:meth:`LongitudinalRecord.columns`, computed with the contact points it kept, to the time series
after the run (in a free run they include the achieved ``distance_m`` and ``speed_m_per_s``);
:func:`longitudinal_summary` gives the ``longitudinal`` entry of ``summary.json``.
"""

from __future__ import annotations

import numpy as np

from railexu.contact import kernel as K
from railexu.model.assembly import VehicleModel
from railexu.simulation.timeseries import TimeSeries

SIDES = ("left", "right")
#: Per wheel: the longitudinal creepage (normal-force weighted mean over the wheel's contact
#: points) and the longitudinal creep force on the wheel (sum) [N].
WHEEL_FIELDS = ("creep_x", "Fx_N")
#: Per wheelset: the spin about the axle [rad/s] and the torque applied about it [N m].
WHEELSET_FIELDS = ("spin_rad_per_s", "axle_torque_N_m")
#: The speed body's achieved forward speed and acceleration along the track.
MOTION_COLUMNS = ("achieved_speed_m_per_s", "achieved_acceleration_m_per_s2")


def longitudinal_columns(n_wheelsets: int) -> list[str]:
    """Names of the longitudinal columns of a vehicle with ``n_wheelsets`` (from the front)."""
    out = []
    for i in range(1, n_wheelsets + 1):
        out += [f"ws{i}_{side}_{f}" for side in SIDES for f in WHEEL_FIELDS]
        out += [f"ws{i}_{f}" for f in WHEELSET_FIELDS]
    return out + list(MOTION_COLUMNS)


class LongitudinalRecord:
    """Keeps the longitudinal state of a run at its output times and makes its columns.

    The recorder calls :meth:`keep` at every output time (with the state) and adds
    :meth:`columns` (with the contact points it kept) to the time series after the run.

    Args:
        model: the vehicle model.
        order: wheelset indices from the front.
        n_out: the number of output times to make room for.
    """

    def __init__(self, model: VehicleModel, order, n_out: int) -> None:
        self.model = model
        self.order = np.asarray(order, dtype=int)
        names = model.wheelset_names()
        ltg = [model.ltg[names[k]] for k in self.order]
        self.i_spin = np.array([g[5] for g in ltg])
        self.i_roll = np.array([g[3] for g in ltg])
        self.i_yaw = np.array([g[4] for g in ltg])
        self.yaw_ref = np.array(
            [model.mbs.GetNodeParameter(model.node[names[k]], "referenceCoordinates")[4]
             for k in self.order]
        )  # fmt: skip
        self.i_speed = model.ltg[model.vehicle.speed_body][0]
        self.x_speed = float(
            model.mbs.GetNodeParameter(
                model.node[model.vehicle.speed_body], "referenceCoordinates"
            )[0]
        )
        n_ws = self.order.size
        self.wheelset = np.zeros((n_out, n_ws, len(WHEELSET_FIELDS)))
        self.motion = np.zeros((n_out, 3))  # distance, speed, acceleration of the speed body

    def keep(self, k: int, q, qt, qtt) -> None:
        """Keep output ``k``: the wheelsets' spin and torques, the speed body's motion (the
        wheels' creepages and creep forces come from the contact points the recorder keeps)."""
        # the angular velocity about the axle, omega . e_axle = theta2' + sin(theta1) theta0'
        spin = qt[self.i_spin] + np.sin(self.yaw_ref + q[self.i_yaw]) * qt[self.i_roll]
        self.wheelset[k, :, 0] = spin
        torques = getattr(self.model, "axle_torques_N_m", None)
        if torques is not None:
            self.wheelset[k, :, 1] = torques[self.order]
        i = self.i_speed
        self.motion[k] = (q[i], qt[i], 0.0 if qtt is None else qtt[i])

    def columns(self, n: int, points: np.ndarray) -> dict[str, np.ndarray]:
        """The :func:`longitudinal_columns` of the first ``n`` outputs, with the kernel's
        contact points at those outputs ``(n, n_ws, 2, MAX_POINTS, N_POINT_FIELDS)`` (wheelsets
        from the front; the kernel zeroes the candidate points that carry no load, and its
        normal forces are >= 0); for a free run also ``distance_m`` and ``speed_m_per_s``, the
        achieved ones (they replace the prescribed)."""
        normal = points[..., K.PF_N]
        total = normal.sum(axis=-1)
        total[total == 0.0] = 1.0
        wheel = np.stack(
            [
                (normal * points[..., K.PF_XI]).sum(axis=-1) / total,
                points[..., K.PF_FX].sum(axis=-1),
            ],
            axis=-1,
        )
        out: dict[str, np.ndarray] = {}
        for i in range(self.order.size):
            for s, side in enumerate(SIDES):
                for f, field in enumerate(WHEEL_FIELDS):
                    out[f"ws{i + 1}_{side}_{field}"] = wheel[:, i, s, f]
            for f, field in enumerate(WHEELSET_FIELDS):
                out[f"ws{i + 1}_{field}"] = self.wheelset[:n, i, f].copy()
        out[MOTION_COLUMNS[0]] = self.motion[:n, 1].copy()
        out[MOTION_COLUMNS[1]] = self.motion[:n, 2].copy()
        if self.model.traction is not None:
            out["distance_m"] = self.x_speed + self.motion[:n, 0] - self.model.frame_start_m
            out["speed_m_per_s"] = self.motion[:n, 1].copy()
        return out


def longitudinal_summary(ts: TimeSeries, model: VehicleModel) -> dict:
    """The ``longitudinal`` entry of ``summary.json``: largest achieved acceleration and
    deceleration, largest longitudinal creepage and ratio of longitudinal creep force to wheel
    load of any wheel, the final speed, and why a free run stopped early."""
    cols = ts.columns
    acc = np.asarray(cols.get("achieved_acceleration_m_per_s2", np.zeros(0)))[1:]
    creep = [np.asarray(v) for c, v in cols.items() if c.endswith("_creep_x") and "_p" not in c]
    ratios = []
    for c, fx in cols.items():
        if c.endswith("_Fx_N") and c.count("_") == 3:
            q = np.asarray(cols[c.replace("_Fx_N", "_Q_N")])
            ratios.append(np.abs(np.asarray(fx)) / np.where(q > 0.0, q, np.inf))
    speed = cols.get("achieved_speed_m_per_s")
    out = {
        "max_acceleration_m_per_s2": float(np.max(acc)) if acc.size else None,
        "max_deceleration_m_per_s2": float(max(-np.min(acc), 0.0)) if acc.size else None,
        "max_abs_creepage": float(max(np.max(np.abs(v)) for v in creep)) if creep else None,
        "max_adhesion_ratio": float(max(np.max(r) for r in ratios)) if ratios else None,
        "final_speed_m_per_s": float(speed[-1]) if speed is not None and len(speed) else None,
        "free_motion": model.traction is not None,
    }
    if getattr(model, "stop_reason", ""):
        out["stopped"] = model.stop_reason
    return out
