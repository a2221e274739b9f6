"""Cost of the tangential solution per patch of the quasi-static S&C contact: ``fastsim_grid``
(FASTSIM on the patch's grid) against ``exact`` (the steady rolling half-space solution,
:mod:`railexu.contact.halfspace_tangential`).

The four single patches of CONTACT's ``examples_s+c`` cases at CONTACT's wheel positions
(tests/test_sc_contact_creep.py), on railexu's default 0.2 x 0.2 mm grid and on CONTACT's own
0.2 x 0.05 mm: processor time of :func:`railexu.contact.variable_creep.tangential_forces` per
patch (best of 3; the numba functions compiled before timing), the number of loaded elements,
and FX, FS against CONTACT's in % of mu N.

Run: ``python benchmarks/sc_tangential.py`` (timings vary by tens of percent between runs).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from railexu.contact import variable_rail
from railexu.contact.variable_creep import WheelMotion
from railexu.contact.variable_rail import ContactSettings, WheelSection, patches_at
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "switches_crossings"
CASES = [
    ("cross_brute", "cross_nose", 0),
    ("wing_brute", "wing_rail", 0),
    ("cross+wing", "cross+wing", 0),
    ("cw_interrupt", "cross+wing_extd", 1),
]


def _reference(case: str, index: int) -> dict:
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from contact_ref_out import read_ref_out

    return read_ref_out(DATA / "examples_s+c" / f"{case}.ref_out")[index]


def main() -> None:
    pts = _read_profile_points(DATA / "profiles" / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    wheel = WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)
    timed = variable_rail.tangential_forces
    record: list[tuple[float, int]] = []

    def tangential_forces(pressure, *args):
        t = time.process_time()
        out = timed(pressure, *args)
        record.append((time.process_time() - t, int(np.count_nonzero(pressure > 0.0))))
        return out

    variable_rail.tangential_forces = tangential_forces
    print("tangential solution per patch, processor time [ms] (best of 3), loaded elements;")
    print("FX, FS - CONTACT in % of CONTACT's mu N")
    for grid, settings in (
        ("0.2 x 0.2", ContactSettings()),
        ("0.2 x 0.05", ContactSettings(dy_m=5e-5)),
    ):
        for case, slcs, index in CASES:
            ref = _reference(case, index)
            (t,) = ref["patches"]
            rail = VariableProfile(read_slcs(DATA / "profiles" / f"{slcs}.slcs"))
            row = [f"{grid:10s} {case:13s}"]
            for law in ("fastsim_grid", "exact"):
                motion = WheelMotion(2.0, -4.34811810, friction=0.3, tangential=law)
                best = np.inf
                for _ in range(3):
                    record.clear()
                    (p,) = patches_at(rail, wheel, ref["s_m"], ref["y_m"], ref["z_m"], settings,
                                      motion)  # fmt: skip
                    best = min(best, record[0][0])
                mu_n = 0.3 * t["fn_n"]
                dfx = 100 * (p.fx_n - t["fx_n"]) / mu_n
                dfs = 100 * (p.fs_n - t["fs_n"]) / mu_n
                row.append(
                    f"{law} {1e3 * best:7.1f} ms ({record[0][1]:4d} el.) {dfx:+5.1f} {dfs:+5.1f}"
                )
            print(" | ".join(row), flush=True)
    variable_rail.tangential_forces = timed


if __name__ == "__main__":
    main()
