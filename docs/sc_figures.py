"""Figures of docs/switches-and-crossings.md: profile slices along a crossing and the
quasi-static transfer of a wheel from the wing rail to the nose.

Usage: ``python docs/sc_figures.py IMAGE_FOLDER``. Reads CONTACT's test-bank slices in
``tests/data/switches_crossings`` (Apache-2.0, see its README) and writes ``sc_slices.png``
(the interpolated surface of ``cross+wing_extd.slcs`` at several positions, features marked) and
``sc_transfer.png`` (the S1002 wheel at 20 mm lateral, pressed with 10 kN, moved along
``cross+wing.slcs``: contact position and vertical force per rail against the distance); prints
the transfer table.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from railexu.contact.variable_rail import ContactSettings, WheelSection, press_wheel
from railexu.profiles.variable import VariableProfile, read_slcs
from railexu.profiles.variable.slcs import _read_profile_points

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


def main(out: str) -> None:
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    slices_figure(folder / "sc_slices.png")
    transfer_figure(folder / "sc_transfer.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img")
