"""The compiled kernel along the UK turnout's generated switch panel (issue 29): whether each
rail's vertical force is monotone in the wheel's height, and whether the sum of the two rails'
forces is continuous along the panel (docs/switches-and-crossings.md, "Rail-to-rail transfer",
"The kernel on the blade"). Not a timing: the numbers the docs quote.

Usage: ``python benchmarks/sc_switch_kernel_scan.py [through|diverging] [monotone|pressed|touch]
[--range FROM TO]`` (default: both routes, the scans monotone and pressed, s = -0.1 .. 4.6 m;
~10 min of processor time per route and scan; ``--range 0.8 0.95``: from the toe [m]).

- ``monotone``: at every 25 mm from 0.1 m before the toe to 4.575 m, the wheelset vehicle's
  wheel (S1002, r0 = 625 mm) at lateral -8 .. +8 mm (every 2 mm, towards the panel rail's
  field side positive) and heights r0 +- 6 mm in 10 um steps: where a rail's (blade 0, stock
  rail 1) vertical force rises by more than 1 N as the wheel is lifted 10 um while the wheel
  carries less than three times its static load (294 kN). Lowering a wheel at a fixed
  lateral position deepens every overlap: no rail's force may fall.
- ``pressed``: every 5 mm from -0.1 to 4.595 m, the same lateral positions: the height pressed
  to 98.1 kN and the height where the wheel carries 1 N (the rigid touch); per lateral position
  the largest step of each along the panel and of their difference (a jump of the kernel's sum
  at a fixed height would show as a pressed step the touch height does not have).
"""

from __future__ import annotations

import contextlib
import sys

import numpy as np
from scipy.optimize import brentq

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_rail import WheelSection, rail_touch_heights
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.profiles.variable.rails import rail_index
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

LOAD_N = 98.1e3
LATERALS_M = np.arange(-0.008, 0.0081, 0.002)


class Panel:
    """A route's switch panel (facing, the crossing panel left out) and the compiled kernel."""

    def __init__(self, route: str) -> None:
        track = load_track(f"turnout_uk_r245_{route}_facing", ["turnout.panels=switch"])
        self.rails = track.variable_rails
        self.side = 0 if self.rails.left is not None else 1
        self.zoned = self.rails.sides()[self.side]
        self.toe_m = self.zoned.panels[0].s0_m
        geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
        self.pair = geometry.pairs[self.side]
        self.profile = self.zoned.panels[0].profile  # s from the toe
        self.model = WheelsetContactModel(geometry)
        self.s_m = None

    def at(self, s_m: float) -> None:
        """The effective section at ``s`` from the toe in the kernel (the dynamics' table)."""
        tab = section_rail_arrays(self.zoned, self.toe_m + s_m, self.pair,
                                  x_max_m=self.rails.x_max_m)  # fmt: skip
        if self.side == 0:
            self.model.rtab_l, self.model.rinfo_l = tab
        else:
            self.model.rtab_r, self.model.rinfo_r = tab
        self.s_m = s_m

    def forces(self, y_m: float, height_m: float) -> np.ndarray:
        """Vertical force [N] of blade and stock rail, the wheel ``y`` towards the rail."""
        lateral = y_m if self.side == 0 else -y_m
        y0 = self.pair.rail_origin_track_m[0]
        f = np.zeros(2)
        for p in self.model.evaluate(lateral, height_m).raw[self.side]:
            if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
                y = np.array([p[K.PF_YRAIL] - y0])
                f[rail_index(self.zoned, self.toe_m + self.s_m, y)[0]] += p[K.PF_FTZ]
        return f


#: The scanned range from the toe [m] (``--range``).
RANGE_M = [-0.1, 4.6]


def monotone(panel: Panel) -> int:
    r0 = panel.pair.nominal_radius_m
    heights = np.linspace(r0 - 0.006, r0 + 0.006, 1201)
    found = 0
    for s in np.arange(RANGE_M[0], RANGE_M[1], 0.025):
        panel.at(s)
        for y in LATERALS_M:
            f = np.array([panel.forces(y, h) for h in heights])
            rise = np.diff(f, axis=0)  # heights increasing: must not be > 0
            rise[f.sum(axis=1)[:-1] >= 3.0 * LOAD_N] = 0.0
            for k in range(2):
                j = int(np.argmax(rise[:, k]))
                if rise[j, k] > 1.0:
                    found += 1
                    at = (heights[j] - r0) * 1e3
                    print(f"  s {s:.3f} m, y {y * 1e3:+.0f} mm, rail {k}: +{rise[j, k]:.0f} N "
                          f"lifting 10 um at h - r0 = {at:.3f} mm")  # fmt: skip
    print(f"  rails' forces rising as the wheel is lifted (below 294 kN): {found}")
    return found


def pressed(panel: Panel) -> None:
    r0 = panel.pair.nominal_radius_m
    s_all = np.arange(RANGE_M[0], RANGE_M[1], 0.005)
    h = np.full((s_all.size, LATERALS_M.size, 2), np.nan)
    for i, s in enumerate(s_all):
        panel.at(s)
        for j, y in enumerate(LATERALS_M):
            for k, target in enumerate((LOAD_N, 1.0)):
                with contextlib.suppress(ValueError):  # no rail within reach: NaN
                    h[i, j, k] = brentq(lambda z, y=y, t=target: panel.forces(y, z).sum() - t,
                                        r0 - 0.006, r0 + 0.006, xtol=1e-10)  # fmt: skip
    for j, y in enumerate(LATERALS_M):
        dp, dt = np.abs(np.diff(h[:, j, 0])), np.abs(np.diff(h[:, j, 1]))
        gap = np.abs(np.diff(h[:, j, 0] - h[:, j, 1]))
        i, g = int(np.nanargmax(dp)), int(np.nanargmax(gap))
        approach = h[:, j, 1] - h[:, j, 0]
        print(f"  y {y * 1e3:+.0f} mm: largest pressed step {dp[i] * 1e6:.1f} um at {s_all[i]:.3f} "
              f"m (touch {dt[i] * 1e6:.1f} um); largest step of pressed - touch "
              f"{gap[g] * 1e6:.1f} um at {s_all[g]:.3f} m; approach "
              f"{np.nanmin(approach) * 1e6:.0f} .. {np.nanmax(approach) * 1e6:.0f} um")  # fmt: skip


def touch(panel: Panel) -> None:
    r0 = panel.pair.nominal_radius_m
    wheel = WheelSection.from_pair(panel.pair)
    s_all = np.arange(RANGE_M[0], RANGE_M[1], 0.005)
    kernel, rigid = np.full(s_all.size, np.nan), np.full(s_all.size, np.nan)
    for i, s in enumerate(s_all):
        panel.at(s)
        with contextlib.suppress(ValueError):
            h = brentq(lambda z: panel.forces(0.0, z).sum() - 1.0, r0 - 0.006, r0 + 0.006,
                       xtol=1e-11)  # fmt: skip
            kernel[i] = -(h - r0)  # z down, from the nominal radius
        rigid[i] = np.nanmin(rail_touch_heights(panel.profile, wheel, float(s), 0.0))
    d = kernel - rigid
    d -= np.nanmedian(d)  # the kernel's height from r0, the rigid one's from the profile's z
    for name, z in (("kernel", kernel), ("rigid", rigid)):
        j = int(np.nanargmax(np.abs(np.diff(z))))
        print(f"  {name}: largest step {abs(np.diff(z)[j]) * 1e6:.2f} um at {s_all[j]:.3f} m, "
              f"largest second difference {np.nanmax(np.abs(np.diff(z, 2))) * 1e6:.3f} um, "
              f"monotone {bool(np.all(np.diff(z) >= 0) or np.all(np.diff(z) <= 0))}")  # fmt: skip
    j = int(np.nanargmax(np.abs(d)))
    where = f"{abs(d[j]) * 1e6:.2f} um at {s_all[j]:.3f} m"
    print(f"  kernel - rigid (less its median): largest {where}")


def main(routes=("through", "diverging"), scans=("monotone", "pressed")) -> None:
    for route in routes:
        panel = Panel(route)
        for scan in scans:
            print(f"{route}, {scan} (s = {RANGE_M[0]} .. {RANGE_M[1]} m):", flush=True)
            {"monotone": monotone, "pressed": pressed, "touch": touch}[scan](panel)


if __name__ == "__main__":
    args = sys.argv[1:]
    if "--range" in args:
        k = args.index("--range")
        RANGE_M[:] = [float(args[k + 1]), float(args[k + 2])]
        del args[k : k + 3]
    routes = tuple(a for a in args if a in ("through", "diverging"))
    scans = tuple(a for a in args if a in ("monotone", "pressed", "touch"))
    main(routes or ("through", "diverging"), scans or ("monotone", "pressed"))
