"""Longitudinal outputs of a run: creepage and creep force per wheel, wheelset spin and axle
torque, the achieved speed and acceleration, and their summary (``docs/traction-and-braking.md``).

The recorder of :mod:`railexu.simulation` calls :meth:`LongitudinalColumns.fill` once per output
row with the state and the kernel's contact points; :func:`longitudinal_summary` gives the
``longitudinal`` entry of ``summary.json``.
"""

from __future__ import annotations

import numpy as np

from .contact import kernel as K
from .model import VehicleModel
from .timeseries import TimeSeries

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


class LongitudinalColumns:
    """Fills the :func:`longitudinal_columns` of one output row.

    Args:
        model: the vehicle model.
        order: wheelset indices from the front.
        col: column name -> index of the recorder's rows.
    """

    def __init__(self, model: VehicleModel, order, col: dict[str, int]) -> None:
        self.model = model
        self.order = np.asarray(order, dtype=int)
        n = self.order.size
        names = model.wheelset_names()
        self.c_wheel = np.array(
            [[[col[f"ws{i}_{s}_{f}"] for f in WHEEL_FIELDS] for s in SIDES]
             for i in range(1, n + 1)]
        )  # fmt: skip
        self.c_ws = np.array(
            [[col[f"ws{i}_{f}"] for f in WHEELSET_FIELDS] for i in range(1, n + 1)]
        )
        self.c_motion = np.array([col[c] for c in MOTION_COLUMNS])
        self.c_xi = self.c_wheel[..., 0].copy()
        self.c_fx = self.c_wheel[..., 1].copy()
        ltg = [model.ltg[names[k]] for k in self.order]
        self.i_spin = np.array([g[5] for g in ltg])
        self.i_roll = np.array([g[3] for g in ltg])
        self.i_yaw = np.array([g[4] for g in ltg])
        self.yaw_ref = np.array(
            [model.mbs.GetNodeParameter(model.node[names[k]], "referenceCoordinates")[4]
             for k in self.order]
        )  # fmt: skip
        self.i_speed = model.ltg[model.vehicle.speed_body][0]

    def fill(self, row: np.ndarray, q, qt, qtt, points: np.ndarray) -> None:
        """Write the columns into ``row`` from the state and the contact points (wheelsets from
        the front, ``(n_ws, 2, MAX_POINTS, fields)``; the kernel zeroes the candidate points that
        carry no load, and its normal forces are >= 0)."""
        normal = points[..., K.PF_N]
        total = normal.sum(axis=2)
        total[total == 0.0] = 1.0
        row[self.c_xi] = (normal * points[..., K.PF_XI]).sum(axis=2) / total
        row[self.c_fx] = points[..., K.PF_FX].sum(axis=2)
        # the angular velocity about the axle, omega . e_axle = theta2' + sin(theta1) theta0'
        row[self.c_ws[:, 0]] = (
            qt[self.i_spin] + np.sin(self.yaw_ref + q[self.i_yaw]) * qt[self.i_roll]
        )
        torques = getattr(self.model, "axle_torques_N_m", None)
        if torques is not None:
            row[self.c_ws[:, 1]] = torques[self.order]
        row[self.c_motion[0]] = qt[self.i_speed]
        if qtt is not None:
            row[self.c_motion[1]] = qtt[self.i_speed]


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
