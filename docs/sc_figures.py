"""Figures of docs/switches-and-crossings.md: profile slices along a crossing and the
quasi-static transfer of a wheel from the wing rail to the nose.

Usage: ``python docs/sc_figures.py IMAGE_FOLDER``. Reads CONTACT's test-bank slices in
``tests/data/switches_crossings`` (Apache-2.0, see its README) and writes ``sc_slices.png``
(the interpolated surface of ``cross+wing_extd.slcs`` at several positions, features marked) and
``sc_transfer.png`` (the S1002 wheel at 20 mm lateral, pressed with 10 kN, moved along
``cross+wing.slcs``: contact position and vertical force per rail against the distance); prints
the transfer table. ``sc_switch_transfer.png``: the wheelset vehicle's wheel (S1002, r0 = 625
mm) pressed with its static 98.1 kN and moved along the UK turnout's generated switch panel
(``tracks/turnout_uk_r245_*_facing.yaml``): the through route's centred wheel (its tread from
the stock rail to the blade's top) and the diverging route's wheel 7 mm towards the panel's rail
(its flange root onto the blade's gauge corner), quasi-static (lines) and the compiled kernel on
the effective sections (points) (``python docs/sc_figures.py IMAGE_FOLDER switch`` makes only
this one).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from railexu.contact import kernel as K
from railexu.contact.evaluation import WheelsetContactModel
from railexu.contact.variable_rail import ContactSettings, WheelSection, press_wheel
from railexu.contact.variable_tables import section_rail_arrays
from railexu.model.assembly import wheelset_geometry
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.rails import rail_index
from railexu.profiles.variable.slcs import _read_profile_points
from railexu.track.track import load_track
from railexu.vehicle.vehicle import load_vehicle

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "switches_crossings" / "profiles"
DPI = 90


def slices_figure(path: Path) -> None:
    """The surface of cross+wing_extd.slcs at positions between and on slices."""
    vp = VariableProfile(read_slcs(DATA / "cross+wing_extd.slcs"))
    fig = Figure(figsize=(7.5, 3.6))
    ax = fig.add_subplot()
    for s in (-0.1, 0.0, 0.05, 0.15, 0.3, 0.6):
        for k, c in enumerate(vp.curves_at(s)):
            ax.plot(
                c[:, 0] * 1e3,
                -c[:, 1] * 1e3,
                lw=1,
                label=f"s = {s * 1e3:.0f} mm" if k == 0 else None,
            )
        f = vp.features_at(s)
        ax.plot(f[:, 0] * 1e3, -f[:, 1] * 1e3, "k.", ms=3)
    ax.set_xlabel("lateral y [mm] (rail profile axes, field side positive)")
    ax.set_ylabel("height [mm]")
    ax.set_title(
        "cross+wing_extd.slcs: stock rail (s < 0), then nose and wing rail; dots: features",
        fontsize=9,
    )
    ax.legend(fontsize=7, ncol=2)
    ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


def transfer_figure(path: Path) -> None:
    """Contact position and vertical force per rail of a pressed wheel along cross+wing.slcs."""
    pts = _read_profile_points(DATA / "x", 0, "MBench_S1002_v3.prw", 1.0)[::-1]
    wheel = WheelSection(np.ascontiguousarray(pts), 0.46, 0.0)
    vp = VariableProfile(read_slcs(DATA / "cross+wing.slcs"))
    st = ContactSettings(dx_m=4e-4, dy_m=4e-4, coarse_dx_m=2e-3, coarse_dy_m=5e-4)
    s_all = np.arange(0.05, 0.2501, 0.005)
    fz = np.zeros((s_all.size, 2))
    yc = np.full((s_all.size, 2), np.nan)
    print("| s [mm] | Fz wing rail [kN] | Fz nose [kN] | contact y wing / nose [mm] |")
    print("|---|---|---|---|")
    for i, s in enumerate(s_all):
        _, patches = press_wheel(vp, wheel, s, 0.02, 1.0e4, st)
        for p in patches:
            fz[i, p.rail_index] += p.vertical_force_n
            yc[i, p.rail_index] = p.y_m
        if i % 4 == 0:
            print(f"| {s * 1e3:.0f} | {fz[i, 1] / 1e3:.2f} | {fz[i, 0] / 1e3:.2f} | "
                  f"{yc[i, 1] * 1e3:.1f} / {yc[i, 0] * 1e3:.1f} |")  # fmt: skip
    fig = Figure(figsize=(7.5, 4.5))
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    for k, name in ((1, "wing rail"), (0, "nose")):
        ax1.plot(s_all * 1e3, yc[:, k] * 1e3, ".-", label=name)
        ax2.plot(s_all * 1e3, fz[:, k] / 1e3, ".-", label=name)
    ax2.plot(s_all * 1e3, fz.sum(axis=1) / 1e3, "k--", lw=1, label="sum")
    ax1.set_ylabel("contact y [mm]")
    ax2.set_ylabel("vertical force [kN]")
    ax2.set_xlabel("wheel position s along the crossing [mm]")
    ax1.set_title("S1002 wheel, y = 20 mm, 10 kN, cross+wing.slcs (quasi-static)", fontsize=9)
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


#: The switch panel's transfers (route, lateral position towards the rail's field side [m],
#: positions from the toe [m]): tests/test_sc_switch_transfer.py.
SWITCH_CASES = (
    ("through", 0.0, np.arange(3.27, 3.4001, 0.005)),
    ("diverging", 0.007, np.arange(2.60, 2.9201, 0.01)),
)
SWITCH_LOAD_N = 98.1e3


def _switch_panel(route: str):
    """The route's switch panel (facing, the crossing panel left out): its zoned profile, the
    toe's position in it, the side and the wheelset's geometry."""
    track = load_track(f"turnout_uk_r245_{route}_facing", ["turnout.panels=switch"])
    rails = track.variable_rails
    side = 0 if rails.left is not None else 1
    zoned = rails.sides()[side]
    geometry = wheelset_geometry(load_vehicle("wheelset").wheelsets[0], track)
    return rails, zoned, side, geometry


def _kernel_forces(rails, zoned, side, geometry, s_m: float, y_m: float):
    """Kernel pressed to the load at ``s`` from the toe: per rail (blade, stock) the vertical
    force [N] and the lateral contact position [m] (force-weighted, the rail's own axes)."""
    from scipy.optimize import brentq

    pair = geometry.pairs[side]
    toe = zoned.panels[0].s0_m
    model = WheelsetContactModel(geometry)
    tab = section_rail_arrays(zoned, toe + s_m, pair, x_max_m=rails.x_max_m)
    if side == 0:
        model.rtab_l, model.rinfo_l = tab
    else:
        model.rtab_r, model.rinfo_r = tab
    lateral = y_m if side == 0 else -y_m
    y0 = pair.rail_origin_track_m[0]

    def per_rail(h):
        f, m = np.zeros(2), np.zeros(2)
        for p in model.evaluate(lateral, h).raw[side]:
            if p[K.PF_ACTIVE] > 0 and p[K.PF_N] > 0:
                y = p[K.PF_YRAIL] - y0
                k = rail_index(zoned, toe + s_m, np.array([y]))[0]
                f[k] += p[K.PF_FTZ]
                m[k] += p[K.PF_FTZ] * y
        return f, m

    r0 = pair.nominal_radius_m
    h = brentq(lambda h: per_rail(h)[0].sum() - SWITCH_LOAD_N, r0 - 0.005, r0 + 0.005, xtol=1e-11)
    f, m = per_rail(h)
    with np.errstate(invalid="ignore", divide="ignore"):
        return f, np.where(f > 0, m / f, np.nan)


def switch_transfer_figure(path: Path) -> None:
    """Contact position and vertical force per rail (blade, stock rail) of the pressed wheel
    along the turnout's switch panel, quasi-static and compiled kernel; prints a table."""
    st = ContactSettings(dx_m=4e-4, dy_m=4e-4, coarse_dx_m=2e-3, coarse_dy_m=5e-4)
    fig = Figure(figsize=(9.0, 5.0))
    axes = fig.subplots(2, 2, sharex="col")
    for col, (route, y, s_all) in enumerate(SWITCH_CASES):
        rails, zoned, side, geometry = _switch_panel(route)
        panel = zoned.panels[0].profile
        wheel = WheelSection.from_pair(geometry.pairs[side])
        fz, yc = np.zeros((s_all.size, 2)), np.full((s_all.size, 2), np.nan)
        fk, yk = np.zeros((s_all.size, 2)), np.full((s_all.size, 2), np.nan)
        print(f"{route}, y = {y * 1e3:.0f} mm: | s [m] | Fz blade / stock [kN] quasi-static | "
              "kernel |")  # fmt: skip
        for i, s in enumerate(s_all):
            _, patches = press_wheel(panel, wheel, s, y, SWITCH_LOAD_N, st)
            for p in patches:
                fz[i, p.rail_index] += p.vertical_force_n
                yc[i, p.rail_index] = p.y_m
            fk[i], yk[i] = _kernel_forces(rails, zoned, side, geometry, s, y)
            if i % 4 == 0:
                print(f"| {s:.3f} | {fz[i, 0] / 1e3:.1f} / {fz[i, 1] / 1e3:.1f} | "
                      f"{fk[i, 0] / 1e3:.1f} / {fk[i, 1] / 1e3:.1f} |")  # fmt: skip
        ax1, ax2 = axes[0, col], axes[1, col]
        for k, name, colour in ((0, "blade", "C0"), (1, "stock rail", "C1")):
            ax1.plot(s_all, yc[:, k] * 1e3, "-", color=colour, label=f"{name}, quasi-static")
            ax1.plot(s_all, yk[:, k] * 1e3, ".", color=colour, label=f"{name}, kernel")
            ax2.plot(s_all, fz[:, k] / 1e3, "-", color=colour, label=f"{name}, quasi-static")
            ax2.plot(s_all, fk[:, k] / 1e3, ".", color=colour, label=f"{name}, kernel")
        ax2.plot(s_all, fz.sum(axis=1) / 1e3, "k--", lw=1, label="sum")
        what = "centred, tread" if y == 0 else f"{y * 1e3:.0f} mm to the rail, flange root"
        ax1.set_title(f"{route} route, facing, {what}", fontsize=9)
        ax1.set_ylabel("contact y [mm] (rail axes)")
        ax2.set_ylabel("vertical force [kN]")
        ax2.set_xlabel("wheel position from the switch toe [m]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("S1002 wheel (r0 625 mm), 98.1 kN, the UK R245 turnout's switch panel",
                 fontsize=9)  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


def main(out: str, which: str = "all") -> None:
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    if which == "all":
        slices_figure(folder / "sc_slices.png")
        transfer_figure(folder / "sc_transfer.png")
    switch_transfer_figure(folder / "sc_switch_transfer.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img", *sys.argv[2:3])
