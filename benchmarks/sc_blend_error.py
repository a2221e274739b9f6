"""The blend's error halfway between two stations on the shipped crossing (issue 29).

The dynamics blends the effective-section tables of two neighbouring stations linearly at a
fixed lateral position (:mod:`railexu.model.forces`). Where a rail moves laterally (the wing
rail's and the nose's gauge faces) the blend of two shifted flanks is not the shifted flank.
This measures, at positions ``s`` along the crossing side of ``tracks/uk_crossing_facing``
(wing rail and nose; the profile's own ``s``), the blend of the stations ``s`` and ``s + h``
halfway against the effective section computed at ``s + h / 2`` (the same grid: one call of
:func:`railexu.contact.variable_tables.station_tables` for the three), as the
blended point's distance from the true section's polyline (the normal distance), per ``s`` its
largest value within 5 mm of the section's top and on the gauge faces 10-35 mm below it;
printed: the median and the largest over ``s`` for each station step ``h``.

Run: ``python benchmarks/sc_blend_error.py [--steps-mm 20 10] [--from -0.6 --to 0.5 --every 0.05]``
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.spatial import cKDTree

from railexu.contact.variable_tables import station_tables
from railexu.model.assembly import wheelset_geometry
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

COL_HEIGHT = 0  # the kernel table's height column (track axes, z up)
TOP_M = 0.005  # "within 5 mm of the top" [m]
FACE_M = (0.010, 0.035)  # the gauge faces' band below the top [m]


def blend_errors(rails, pair, side: int, s_m: np.ndarray, step_m: float) -> np.ndarray:
    """Per ``s`` the largest normal distance [m] of the halfway blend from the true effective
    section: ``(n, 2)``, within :data:`TOP_M` of the top and in the :data:`FACE_M` band."""
    profile = rails.sides()[side]
    out = np.full((s_m.size, 2), np.nan)
    for k, s in enumerate(s_m):
        tabs, info = station_tables(
            profile, pair, np.array([s, s + 0.5 * step_m, s + step_m]),
            rail_origin_m=rails.rail_origin_m, x_max_m=rails.x_max_m,
        )  # fmt: skip
        z0, z1, z2 = (tabs[j][:, COL_HEIGHT] for j in range(3))
        y = info[0] + info[1] * np.arange(z1.size)
        ok = np.isfinite(z0) & np.isfinite(z1) & np.isfinite(z2) & (np.abs(z1) < 1.0)
        # the tables are z up (the gap is the wheel's height minus the rail's): the depth below
        # the section's top is measured from its highest point (a first version took z as down
        # and measured its bands from the lowest point: the flangeway's bottom and the table's
        # ends; the figures it gave, 191 um on the nose and 676 um on the wing rail's flank, are
        # those bands')
        depth = np.max(z1[ok]) - z1
        normal = _distance_to_curve(y[ok], 0.5 * (z0 + z2)[ok], y[ok], z1[ok])
        top = depth[ok] <= TOP_M
        face = (depth[ok] >= FACE_M[0]) & (depth[ok] <= FACE_M[1])
        out[k] = (normal[top].max(), normal[face].max() if face.any() else np.nan)
    return out


def _distance_to_curve(py, pz, cy, cz) -> np.ndarray:
    """Distance [m] of each point ``(py, pz)`` from the polyline ``(cy, cz)`` (the segments at
    the 8 nearest vertices: the normal distance, not the height difference)."""
    curve = np.column_stack([cy, cz])
    _, near = cKDTree(curve).query(np.column_stack([py, pz]), k=8)
    best = np.full(py.size, np.inf)
    for j in range(near.shape[1]):
        for a in (near[:, j] - 1, near[:, j]):
            a = np.clip(a, 0, cy.size - 2)
            ay, az, by, bz = cy[a], cz[a], cy[a + 1], cz[a + 1]
            dy, dz = by - ay, bz - az
            t = np.clip(((py - ay) * dy + (pz - az) * dz) / (dy * dy + dz * dz), 0.0, 1.0)
            best = np.minimum(best, np.hypot(py - ay - t * dy, pz - az - t * dz))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps-mm", type=float, nargs="+", default=[20.0, 10.0])
    ap.add_argument("--from", dest="lo", type=float, default=-0.6, help="first s [m]")
    ap.add_argument("--to", dest="hi", type=float, default=0.5, help="last s [m]")
    ap.add_argument("--every", type=float, default=0.05, help="spacing of the s [m]")
    a = ap.parse_args()
    track = load_track("uk_crossing_facing")
    rails = track.variable_rails
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    side = 0  # the crossing (wing rail and nose) on the left
    s = np.arange(a.lo, a.hi + 1e-9, a.every)
    print(f"uk_crossing_facing, crossing side, s = {s[0]:g} .. {s[-1]:g} m ({s.size} positions), "
          f"effective section +-{rails.x_max_m * 1e3:g} mm; normal distance of the halfway "
          "blend from the true section [um]")  # fmt: skip
    print(f"{'step':>8s} {'top: median':>12s} {'top: largest':>13s} "
          f"{'faces: median':>14s} {'faces: largest':>15s}")  # fmt: skip
    for h in a.steps_mm:
        e = blend_errors(rails, geometry.pairs[side], side, s, h * 1e-3) * 1e6
        print(f"{h:6g}mm {np.nanmedian(e[:, 0]):12.1f} {np.nanmax(e[:, 0]):13.1f} "
              f"{np.nanmedian(e[:, 1]):14.1f} {np.nanmax(e[:, 1]):15.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
