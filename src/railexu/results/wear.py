"""Wear and rolling contact fatigue of a run, per wheel and per rail, where they land on the
profiles (docs/wear.md, "Per run").

From the recorded contact points (a run with ``contact_outputs: true``: creepages, normal force,
semi-axes, the contact's position on the wheel and the rail, contact angle, creep forces and
``T gamma`` of every point at every output time) over the evaluation window:

* wear: every loaded point's patch worn by the chosen law (:mod:`railexu.contact.wear.patch`),
  each sample standing for the distance to its neighbours (half the spacing either side). The
  wheel's depth is per km run (passages: distance / (2 pi r0)); the rail's per axle passage,
  averaged along the window. Depths are heights of the profile graph (the normal depth over
  ``cos(contact angle)``, so that the worn area is kept: :func:`~.patch.wear_on_profile_nb`);
* RCF: Ekberg's ``FI_surf`` of every loaded point (largest, where, share of the window's
  samples above 0) and Burstow's WLRM damage from each point's ``T gamma``, per axle passage on
  the rail and per km on the wheel, binned where the points lie.

The run itself is not changed: with ``contact_outputs`` off there is nothing to compute and the
run costs the same; the recording of the contact points is the only cost (measured in
``benchmarks/wear.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railexu.assessment.rcf.indices import fi_surf, wlrm_damage
from railexu.contact.wear.coefficients import Coefficients, load_coefficients
from railexu.contact.wear.laws import DEFAULT_WEAR_LAW, wear_law_code
from railexu.contact.wear.patch import PATCH_POINTS, PATCH_STRIPS, wear_on_profile
from railexu.errors import InputError
from railexu.results.evaluate import evaluation_window
from railexu.simulation.simulate import wheelset_order
from railexu.simulation.timeseries import TimeSeries
from railexu.vehicle.vehicle import Vehicle

__all__ = ["WHEEL_GRID", "RAIL_GRID", "WheelWear", "run_wear", "wear_rows"]

#: the wheel's lateral grid (profile coordinate from the tape circle) [m]: start, step, nodes
WHEEL_GRID = (-0.075, 2.0e-4, 726)
#: the rail's lateral grid [m]: from the gauge line (half the gauge from the track centre, the
#: gauge measured 14 mm below the top), outwards positive, both rails
RAIL_GRID = (-0.030, 2.0e-4, 601)
#: the widest contact patch worn as given [m]: Hertz's ellipse of a conformal contact (a worn
#: wheel on a rail of nearly the same lateral curvature) grows without bound (the kernel caps it
#: at 1 m); wider patches are worn with this half-width (and their own length and load, so a
#: higher pressure than Hertz's), railexu's assumption (docs/wear.md, "Left out")
MAX_HALF_WIDTH_M = 0.010
_SIDES = ("left", "right")
_FIELDS = ("creep_x", "creep_y", "spin_1_per_m", "N_N", "a_m", "b_m", "wheel_y_m", "rail_y_m",
           "angle_rad", "Fx_N", "Fy_N", "Tgamma_N")  # fmt: skip


@dataclass
class WheelWear:
    """Wear and RCF of one wheel and the rail under it over a run's window.

    Attributes:
        wheelset, side: ``ws1`` ... from the front, ``left`` or ``right``.
        radius_m: the wheel's nominal rolling radius.
        lateral_m: the wheel grid (:data:`WHEEL_GRID`); ``depth_per_km_m`` the graph height
            removed per km run at each node; ``area_per_km_m2`` its integral.
        rail_lateral_m: the rail grid; ``rail_depth_per_axle_m`` per axle passage.
        volume_rate_per_km_m2: the integral of the patches' volume rates over the window per km
            (the conservation reference of ``area_per_km_m2``).
        fi_surf_max, fi_surf_max_at_m: largest FI_surf and its wheel position;
            ``fi_surf_share``: share of the loaded samples with FI_surf > 0.
        wlrm_wheel_per_km: WLRM damage per km on the wheel grid; ``wlrm_rail_per_axle`` per
            axle passage on the rail grid.
        window: the evaluation window ``(start_m, end_m, rule)``.
        fi_surf_wheel_max: the largest FI_surf of the window's loaded points at each node of
            the wheel grid (NaN where no point lies); ``fi_surf_max_rail_at_m``: the rail
            position of the largest FI_surf (rail grid coordinate).
    """

    wheelset: str
    side: str
    radius_m: float
    lateral_m: np.ndarray
    depth_per_km_m: np.ndarray
    area_per_km_m2: float
    rail_lateral_m: np.ndarray
    rail_depth_per_axle_m: np.ndarray
    volume_rate_per_km_m2: float
    fi_surf_max: float
    fi_surf_max_at_m: float
    fi_surf_share: float
    wlrm_wheel_per_km: np.ndarray
    wlrm_rail_per_axle: np.ndarray
    window: tuple
    fi_surf_wheel_max: np.ndarray | None = None
    fi_surf_max_rail_at_m: float = math.nan

    def summary(self) -> dict:
        """The scalars (JSON-ready: None where not finite), with the window and the rules."""
        i = int(np.argmax(self.depth_per_km_m))
        j = int(np.argmax(self.wlrm_rail_per_axle))
        out = {
            "wheelset": self.wheelset,
            "side": self.side,
            "window_m": [self.window[0], self.window[1]],
            "window_rule": self.window[2],
            "wheel_area_per_km_mm2": self.area_per_km_m2 * 1e6,
            "wheel_max_depth_per_km_um": float(self.depth_per_km_m[i] * 1e6),
            "wheel_max_depth_at_mm": float(self.lateral_m[i] * 1e3),
            "rail_max_depth_per_axle_nm": float(self.rail_depth_per_axle_m.max() * 1e9),
            "rail_max_depth_at_mm": float(
                self.rail_lateral_m[int(np.argmax(self.rail_depth_per_axle_m))] * 1e3
            ),
            "rail_area_per_axle_um2": float(self.rail_depth_per_axle_m.sum() * RAIL_GRID[1] * 1e12),
            "fi_surf_max": self.fi_surf_max,
            "fi_surf_max_at_mm": self.fi_surf_max_at_m * 1e3,
            "fi_surf_max_rail_at_mm": self.fi_surf_max_rail_at_m * 1e3,
            "fi_surf_share_above_0": self.fi_surf_share,
            "wlrm_rail_max_per_axle": float(self.wlrm_rail_per_axle[j]),
            "wlrm_rail_max_at_mm": float(self.rail_lateral_m[j] * 1e3),
            "wlrm_rail_per_axle": float(self.wlrm_rail_per_axle.sum()),
            "wlrm_wheel_per_km": float(self.wlrm_wheel_per_km.sum()),
        }
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in out.items()}  # fmt: skip


def _sample_lengths(x: np.ndarray, start: float, end: float) -> np.ndarray:
    """The distance each sample stands for inside ``[start, end]`` (half the spacing to each
    neighbour, clipped to the window) [m]."""
    if x.size < 2:
        return np.zeros_like(x)
    mid = 0.5 * (x[1:] + x[:-1])
    lo = np.concatenate([[x[0]], mid])
    hi = np.concatenate([mid, [x[-1]]])
    return np.clip(np.minimum(hi, end) - np.maximum(lo, start), 0.0, None)


def _points(ts: TimeSeries, w: int, side: str) -> dict[str, np.ndarray]:
    """The contact fields of one wheel's points stacked ``(n, MAX_POINTS)``."""
    cols = ts.columns
    out = {}
    for f in _FIELDS:
        names = sorted(
            (c for c in cols if c.startswith(f"ws{w}_{side}_p") and c.endswith("_" + f)),
            key=lambda c: int(c.split("_p", 1)[1].split("_", 1)[0]),
        )
        out[f] = np.column_stack([cols[c] for c in names])
    return out


def wear_rows(
    pts: dict[str, np.ndarray], speed: np.ndarray, w_wheel: np.ndarray, w_rail: np.ndarray, sign
) -> np.ndarray:
    """The rows of :func:`~railexu.contact.wear.patch.wear_on_profile` of one wheel's loaded
    points (fields as :func:`_points`, weights per sample)."""
    n = pts["N_N"]
    loaded = (n > 0.0) & (pts["a_m"] > 0.0) & (pts["b_m"] > 0.0)
    loaded &= ((w_wheel > 0.0) | (w_rail > 0.0))[:, None]
    k, p = np.nonzero(loaded)
    a, b = pts["a_m"][k, p], pts["b_m"][k, p]
    capped = np.minimum(b, MAX_HALF_WIDTH_M)
    rows = np.column_stack([
        pts["creep_x"][k, p], pts["creep_y"][k, p], pts["spin_1_per_m"][k, p], n[k, p],
        a, capped, pts["wheel_y_m"][k, p], pts["rail_y_m"][k, p],
        pts["angle_rad"][k, p], speed[k], w_wheel[k], w_rail[k], np.full(k.size, float(sign)),
    ])  # fmt: skip
    return rows


def _bin(grid: tuple, y: np.ndarray, values: np.ndarray) -> np.ndarray:
    y0, step, n = grid
    i = np.clip(np.rint((y - y0) / step).astype(int), 0, n - 1)
    return np.bincount(i, weights=values, minlength=n)


def _bin_max(grid: tuple, y: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The largest of ``values`` at each node of ``grid`` (nearest node; NaN where none)."""
    y0, step, n = grid
    out = np.full(n, -np.inf)
    i = np.clip(np.rint((y - y0) / step).astype(int), 0, n - 1)
    np.maximum.at(out, i, values)
    return np.where(np.isfinite(out), out, np.nan)


def run_wear(
    ts: TimeSeries,
    vehicle: Vehicle,
    law: str = DEFAULT_WEAR_LAW,
    coef: Coefficients | None = None,
    evaluate_from_m: float | None = None,
    evaluate_to_m: float | None = None,
    n_strips: int = PATCH_STRIPS,
    n_points: int = PATCH_POINTS,
    gauge_m: float = 1.435,
) -> list[WheelWear]:
    """Wear and RCF of every wheel of a run (module doc), wheelsets from the front.

    Args:
        ts: the run's time series, recorded with ``contact_outputs: true``.
        vehicle: the vehicle (friction, shear modulus, Poisson's ratio, wheel radii).
        law: the wear law (:data:`~railexu.contact.wear.laws.WEAR_LAWS`).
        coef: the coefficients (default: the shipped file).
        evaluate_from_m, evaluate_to_m: the window (default: the run's evaluation window,
            :func:`~railexu.results.evaluate.evaluation_window`).
        gauge_m: the track gauge: the rail positions are from the gauge line (:data:`RAIL_GRID`).

    Raises:
        InputError: a time series without the contact points, or an unknown law.
    """
    wear_law_code(law)
    coef = coef or load_coefficients()
    cols = ts.columns
    if not any(c.endswith("_p1_creep_x") for c in cols):
        raise InputError(
            "the run has no contact points: run it with contact_outputs: true (run settings)",
            key="contact_outputs",
        )
    x = np.asarray(cols["distance_m"])
    win = evaluation_window(x, evaluate_from_m, evaluate_to_m)
    length = win.to_m - win.from_m if math.isfinite(win.to_m - win.from_m) else 0.0
    ds = _sample_lengths(x, win.from_m, win.to_m)
    speed = np.asarray(cols.get("speed_m_per_s", np.gradient(x, cols["time_s"])))
    c = vehicle.contact
    order = wheelset_order(vehicle)  # ws1, ws2, ... of the time series
    out = []
    km = 1000.0 / length if length > 0.0 else 0.0
    wy = np.arange(WHEEL_GRID[2]) * WHEEL_GRID[1] + WHEEL_GRID[0]
    ry = np.arange(RAIL_GRID[2]) * RAIL_GRID[1] + RAIL_GRID[0]
    for w, i in enumerate(order, start=1):
        ws = vehicle.wheelsets[i]
        for side in _SIDES:
            r0 = ws.nominal_radius_m if side == "left" else ws.radius_right_m
            pts = _points(ts, w, side)
            pts["rail_y_m"] = np.where(pts["N_N"] > 0.0, pts["rail_y_m"] - 0.5 * gauge_m, 0.0)
            w_wheel = ds / (2.0 * math.pi * r0) * km
            w_rail = ds / length if length > 0.0 else ds * 0.0
            sign = 1.0 if side == "left" else -1.0
            rows = wear_rows(pts, speed, w_wheel, w_rail, sign)
            area, rail, total = _wear_both_grids(rows, law, coef, c, n_strips, n_points)
            out.append(
                _wheel_wear(f"ws{w}", side, r0, pts, ds, w_wheel, w_rail, area, rail, total,
                            coef, (win.from_m, win.to_m, win.rule), wy, ry)
            )  # fmt: skip
    return out


def _wear_both_grids(rows, law, coef, c, n_strips, n_points):
    """The wheel's and the rail's worn areas on their own grids (two passes: the compiled
    function puts both on one grid)."""
    wheel_rows = rows.copy()
    wheel_rows[:, 11] = 0.0
    area, _, total = wear_on_profile(
        wheel_rows, law, coef, c.friction, c.shear_modulus_Pa, c.poisson, WHEEL_GRID[0],
        WHEEL_GRID[1], WHEEL_GRID[2], n_strips, n_points,
    )  # fmt: skip
    rail_rows = rows.copy()
    rail_rows[:, 6] = rows[:, 7]
    rail_rows[:, 10] = rows[:, 11]
    rail, _, _ = wear_on_profile(
        rail_rows, law, coef, c.friction, c.shear_modulus_Pa, c.poisson, RAIL_GRID[0],
        RAIL_GRID[1], RAIL_GRID[2], n_strips, n_points,
    )  # fmt: skip
    return area, rail, total


def _wheel_wear(name, side, r0, pts, ds, w_wheel, w_rail, area, rail, total, coef, win, wy, ry):
    n = pts["N_N"]
    loaded = (n > 0.0) & (ds > 0.0)[:, None]
    fi = fi_surf(pts["Fx_N"], pts["Fy_N"], n, pts["a_m"], pts["b_m"], coef.fi_surf.shear_yield_Pa)
    fi = np.where(loaded, fi, -np.inf)
    if np.any(loaded):
        k = np.unravel_index(int(np.argmax(fi)), fi.shape)
        fi_max, fi_at = float(fi[k]), float(pts["wheel_y_m"][k])
        fi_rail_at = float(pts["rail_y_m"][k])
        share = float(np.mean(fi[loaded] > 0.0))
    else:
        fi_max, fi_at, fi_rail_at, share = math.nan, math.nan, math.nan, 0.0
    fi_wheel = _bin_max(WHEEL_GRID, pts["wheel_y_m"][loaded], fi[loaded])
    dmg = np.where(loaded, wlrm_damage(pts["Tgamma_N"], coef), 0.0)
    wheel_dmg = _bin(WHEEL_GRID, pts["wheel_y_m"].ravel(), (dmg * w_wheel[:, None]).ravel())
    rail_dmg = _bin(RAIL_GRID, pts["rail_y_m"].ravel(), (dmg * w_rail[:, None]).ravel())
    return WheelWear(
        wheelset=name, side=side, radius_m=r0, lateral_m=wy,
        depth_per_km_m=area / WHEEL_GRID[1], area_per_km_m2=float(area.sum()),
        rail_lateral_m=ry, rail_depth_per_axle_m=rail / RAIL_GRID[1],
        volume_rate_per_km_m2=total, fi_surf_max=fi_max, fi_surf_max_at_m=fi_at,
        fi_surf_share=share, wlrm_wheel_per_km=wheel_dmg, wlrm_rail_per_axle=rail_dmg,
        window=win, fi_surf_wheel_max=fi_wheel, fi_surf_max_rail_at_m=fi_rail_at,
    )  # fmt: skip
