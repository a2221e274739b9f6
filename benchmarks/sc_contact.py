"""Cost of the quasi-static contact search on variable rail profiles (switches and crossings).

Times :func:`railexu.contact.variable_rail.patches_at` (the 3-D overlap search on the coarse
grid, the fine grid per patch and the half-space normal problem of each patch) for one wheel:

- on one rail (CONTACT's ``wing_rail.slcs``, one patch),
- on two rails of one side at once (``uk_interrupt_v2.slcs``: nose and wing rail, two patches),

and the same split into search (overlap grids) and normal problem. This is the quasi-static
validation tool, not the dynamics' kernel (which does not read variable profiles yet).

Run: ``python benchmarks/sc_contact.py`` (timings vary by tens of percent between runs).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from railexu.contact.variable_rail import ContactSettings, WheelSection, _overlap, patches_at
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "switches_crossings" / "profiles"


def _best(f, repeat: int = 5) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return best


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
