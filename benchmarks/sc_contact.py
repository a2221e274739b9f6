"""Cost of the quasi-static contact search on variable rail profiles (switches and crossings).

Times :func:`railexu.contact.variable_rail.patches_at` (the 3-D overlap search on the coarse
grid, the fine grid per patch and the half-space normal problem of each patch) for one wheel:

- on one rail (CONTACT's ``wing_rail.slcs``, one patch),
- on two rails of one side at once (``uk_interrupt_v2.slcs``: nose and wing rail, two patches),

and the same split into search (overlap grids) and normal problem (the quasi-static validation
tool); then the dynamics' compiled kernel per wheelset evaluation on the plain rail and on the
two-rail effective section of the same crossing (:mod:`railexu.contact.variable_tables`): the
search on several rails against one.

Run: ``python benchmarks/sc_contact.py`` (timings vary by tens of percent between runs).
"""

from __future__ import annotations

import time
from pathlib import Path

import numba
import numpy as np

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.placement import symmetric_wheelset
from railexu.contact.variable_rail import ContactSettings, WheelSection, _overlap, patches_at
from railexu.contact.variable_tables import section_rail_arrays
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "switches_crossings" / "profiles"


def _best(f, repeat: int = 5, clock=time.perf_counter) -> float:
    best = np.inf
    for _ in range(repeat):
        t = clock()
        f()
        best = min(best, clock() - t)
    return best


@numba.njit(cache=True)
def _loop(n, wl, il, rl, ril, wr, ir, rr, rir, ht, kt, params, state, rails, points, force):
    acc = 0.0
    for _ in range(n):
        K.wheelset_contact(wl, il, rl, ril, wr, ir, rr, rir, ht, kt, params, state, rails,
                           points, force)  # fmt: skip
        acc += force[2]
    return acc


def kernel_costs(n: int = 20_000) -> None:
    """The compiled kernel per wheelset: plain rail both sides, and the left rail replaced by
    the two-rail effective section of uk_interrupt_v2 at s = 160 mm (two contact points)."""
    geo = symmetric_wheelset(
        "MBench_S1002", "MBench_UIC60", nominal_radius_m=0.46, inclination="1:40",
        gauge_m=1.435, flange_back_distance_m=1.36,
    )  # fmt: skip
    plain = WheelsetContactModel(geo, speed_m_per_s=2.0)
    crossing = WheelsetContactModel(geo, speed_m_per_s=2.0)
    rail = VariableProfile(read_slcs(DATA / "uk_interrupt_v2.slcs", scale_to_mm=1000.0))
    crossing.rtab_l, crossing.rinfo_l = section_rail_arrays(
        rail, 0.16, geo.left, rail_origin_m=(0.75, 0.0), x_max_m=0.06
    )
    print("compiled kernel, S1002 on Manchester UIC60 / crossing section, V = 2 m/s "
          "(per phase and rail: benchmarks/sc_kernel_breakdown.py):")  # fmt: skip
    for label, m, lateral, height in (
        ("plain rail both sides", plain, 0.0035, 0.45997),
        ("left wheel on nose + wing rail (2 points)", crossing, 0.0035, 0.4609236),
    ):
        state = np.array([0.0, lateral, height, 0, 0, 2.0, 0, 0, 0, 2.0 / 0.46, 0])
        args = (m.wtab_l, m.winfo_l, m.rtab_l, m.rinfo_l, m.wtab_r, m.winfo_r, m.rtab_r,
                m.rinfo_r, m.htab, m.ktab, m.params, state, np.zeros(8),
                np.zeros((2, K.MAX_POINTS, K.N_POINT_FIELDS)), np.zeros(6))  # fmt: skip
        _loop(10, *args)
        n_points = int(np.sum((args[13][0, :, K.PF_ACTIVE] > 0) & (args[13][0, :, K.PF_N] > 0)))
        # processor time of this thread: on a shared machine the wall clock counts the time
        # other processes hold the core (2-2.5x at a load of 10 on 2 cores)
        best = _best(lambda: _loop(n, *args), clock=time.thread_time) / n  # noqa: B023
        print(f"  {label:<44s} {best * 1e6:6.2f} us per wheelset ({n_points} loaded "
              "point(s) on the left wheel; processor time)")  # fmt: skip


def main() -> None:
    pts = _read_profile_points(DATA / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    wheel = WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)
    st = ContactSettings()
    cases = [
        ("one rail (wing_rail.slcs, s 100 mm)", read_slcs(DATA / "wing_rail.slcs"),
         (0.1, 0.0, 0.6589e-3)),
        ("two rails (uk_interrupt_v2.slcs, s 160 mm)",
         read_slcs(DATA / "uk_interrupt_v2.slcs", scale_to_mm=1000.0), (0.16, 3.52e-3, -0.9238e-3)),
    ]  # fmt: skip
    print("quasi-static S&C contact, S1002 wheel, grids 0.2 x 0.2 mm (coarse 1 x 0.25 mm):")
    for label, slices, (s, y, z) in cases:
        rail = VariableProfile(slices)
        n = len(patches_at(rail, wheel, s, y, z, st))
        total = _best(lambda: patches_at(rail, wheel, s, y, z, st))  # noqa: B023
        yw = wheel.points_m[:, 0] + y
        yc = np.arange(yw[0] + st.coarse_dy_m, yw[-1], st.coarse_dy_m)
        xc = np.arange(-st.x_max_m, st.x_max_m + 0.5 * st.coarse_dx_m, st.coarse_dx_m)
        search = _best(lambda: _overlap(rail, wheel, s, y, z, xc, yc))  # noqa: B023
        print(f"  {label:<44s} {n} patch(es): {total * 1e3:7.1f} ms per evaluation, "
              f"of which coarse search {search * 1e3:6.1f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
    kernel_costs()
