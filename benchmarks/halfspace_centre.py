"""Issue 28: the rolling radius near the centre, deepest point, load centroid and elastic
half-space, for the EU07's wheelset (S1002 on 60E1 1:40, static wheel load 98.1 kN).

Prints, per lateral shift and wheel: the wheel's profile coordinate of main's deepest point, of
this kernel's load centroid and of the half-space's pressure centroid; the kernel's approach
(the gap's depth at its minimum) against the half-space's under the same load; the centroid with
the half-space's plane through the deepest point instead; and per shift ``Delta r / (2 y)`` of
each definition, with the half-space's radius at the pressure centroid, its pressure-weighted
mean radius and the radius of Kalker's linear theory on its patch. The reference is
``tests/halfspace.py`` (its checks: ``tests/test_contact_halfspace_centre.py``); the table of
``docs/validation.md`` comes from this script.

Run: ``python benchmarks/halfspace_centre.py [--grid 1,0.5]`` (element size along the track
and across, mm; ``--grid 0.5,0.25`` for the grid study, about ten times slower).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import halfspace as hs  # noqa: E402  (the tests' reference module)

from railexu.contact.evaluation import WheelsetContactModel  # noqa: E402
from railexu.contact.quasistatic import press_wheelset  # noqa: E402
from railexu.model.assembly import wheelset_geometry  # noqa: E402
from railexu.track.track import load_track  # noqa: E402
from railexu.vehicle.vehicle import load_vehicle  # noqa: E402

SHIFTS_MM = (0.0, 0.25, 0.5, 1.0, 2.0, 3.0, 4.0)
GRAVITY_M_PER_S2 = 9.81


def _wheel(model, geometry, state, side, mirror, y, load, e_star, nu, dx, dt):
    """One wheel's numbers (lengths in m)."""
    r0 = geometry.left.nominal_radius_m
    pair = geometry.left if side == "left" else geometry.right
    wheel = hs.WheelOnRail(pair, mirror * y, mirror * state.roll_rad)
    patch = hs.wheel_patch(wheel, load, e_star, dx_m=dx, dt_m=dt)
    s, gap = model.gap_candidates(side, y, state.vertical_m, state.roll_rad, 0.0)
    k = int(np.argmin(gap))
    points = [p for p in state.result.wheel(side) if p.normal_force_N > 0.0]
    total = sum(p.normal_force_N for p in points)
    s_deep = wheel.deepest_s()
    wy, *_ = wheel.wheel_point(s_deep)
    plane = wheel.plane(float(wy))
    other = hs._solve_on_plane(plane, load, e_star, dx, dt, 0.03, patch.solution.approach_m)
    _, s_other, _, _ = plane.section(np.array([other.centroid_y_m]))
    return {
        "s_deep": float(s[k]),
        "r_deep": r0 + float(pair.wheel.height(s[k])),
        "s_centroid": sum(p.normal_force_N * p.wheel_lateral_m for p in points) / total,
        "r_centroid": sum(p.normal_force_N * p.rolling_radius_m for p in points) / total,
        "s_hs": patch.centroid_s_m,
        "r_hs": patch.centroid_radius_m,
        "r_hs_mean": patch.mean_radius_m,
        "r_linear": hs.linear_theory_radius(patch, dx, dt, nu),
        "s_hs_plane_deepest": float(s_other[0]),
        "approach_kernel": -float(gap[k]),
        "approach_hs": patch.solution.approach_m,
        "area_hs": patch.solution.contact_area_m2,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", default="1,0.5", help="element size along, across [mm]")
    args = parser.parse_args()
    dx, dt = (float(v) * 1e-3 for v in args.grid.split(","))
    vehicle = load_vehicle(ROOT / "vehicles" / "eu07.yaml")
    track = load_track(ROOT / "tracks" / "straight.yaml")
    geometry = wheelset_geometry(vehicle.wheelsets[0], track)
    model = WheelsetContactModel(geometry, vehicle.contact, 10.0)
    load = vehicle.total_mass_kg * GRAVITY_M_PER_S2 / (2 * len(vehicle.wheelsets))
    nu = vehicle.contact.poisson
    e_star = vehicle.contact.shear_modulus_Pa / (1.0 - nu)
    print(f"static wheel load {load / 1e3:.1f} kN, grid {dx * 1e3} x {dt * 1e3} mm")
    for y_mm in SHIFTS_MM:
        y = y_mm * 1e-3
        state = press_wheelset(model, y, 0.0, load)
        rows = {}
        for side, mirror in (("left", 1.0), ("right", -1.0)):
            rows[side] = r = _wheel(
                model, geometry, state, side, mirror, y, load, e_star, nu, dx, dt
            )
            print(
                f"y {y_mm:4.2f} mm {side:5s}  s [mm]: deepest {r['s_deep'] * 1e3:7.2f}"
                f"  centroid {r['s_centroid'] * 1e3:7.2f}  half-space {r['s_hs'] * 1e3:7.2f}"
                f" (plane at the deepest point {r['s_hs_plane_deepest'] * 1e3:7.2f})"
                f"  approach [um]: kernel {r['approach_kernel'] * 1e6:5.1f}"
                f" half-space {r['approach_hs'] * 1e6:5.1f}"
                f"  area {r['area_hs'] * 1e6:4.0f} mm^2"
            )
        if y > 0.0:
            values = {
                key: (rows["left"][key] - rows["right"][key]) / (2.0 * y)
                for key in ("r_deep", "r_centroid", "r_linear", "r_hs", "r_hs_mean")
            }
            print(
                "    Delta r / 2y: deepest {r_deep:.3f}  load centroid {r_centroid:.3f}"
                "  half-space: linear theory {r_linear:.3f}, at the pressure centroid"
                " {r_hs:.3f}, pressure-weighted mean {r_hs_mean:.3f}".format(**values)
            )


if __name__ == "__main__":
    main()
