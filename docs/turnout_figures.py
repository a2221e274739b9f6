"""Figures of docs/switches-and-crossings.md, "The turnout": the switch panel's rails along the
track and the plan of the two routes.

Usage: ``python docs/turnout_figures.py IMAGE_FOLDER``. Reads the shipped turnout tracks and
writes ``turnout_switch_slices.png`` (the left side's rails of the through route, facing, at
several distances from the toe: blade on the gauge side, stock rail moving to the field side)
and ``turnout_plan.png`` (the gauge lines of the through and the diverging route from the toe to
beyond the crossing, the intersection of the gauge lines marked). The contact positions against
the distance come from a run's ``crossing.png`` (the command is in the docs).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from railexu.track.track import load_track
from railexu.track.turnout import TurnoutGeometry

TRACKS = Path(__file__).resolve().parents[1] / "tracks"
DPI = 90


def slices_figure(path: Path) -> None:
    """The through route's switch side (left) at distances from the toe."""
    track = load_track(TRACKS / "turnout_uk_r245_through_facing.yaml")
    zone = track.variable_rails
    fig = Figure(figsize=(7.5, 3.8))
    ax = fig.add_subplot()
    for j, s in enumerate((-0.5, 0.0, 1.0, 2.0, 3.0, 3.5, 5.0, 7.0)):
        for k, c in enumerate(zone.left.curves_at(40.0 + s - zone.start_m)):
            ax.plot(c[:, 0] * 1e3, -c[:, 1] * 1e3, lw=1, color=f"C{j}",
                    label=f"{s:g} m from the toe" if k == 0 else None)  # fmt: skip
    ax.set_xlabel("y [mm] (rail axes, field side +)")
    ax.set_ylabel("height [mm]")
    ax.set_ylim(-30, 3)
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


def plan_figure(path: Path) -> None:
    """The two routes' gauge lines in the turnout's plan (left-hand, seen from the toe)."""
    g = TurnoutGeometry(245.0, 9.25)
    x_ip, s_ip, theta = g.intersection()
    half = 0.5 * g.gauge_m
    s = np.linspace(0.0, s_ip + 5.0, 600)
    r = g.radius_m
    psi = np.minimum(s / r, theta)
    on_circle = s <= g.curve_length_m
    xc = np.where(on_circle, r * np.sin(psi), r * math.sin(theta) + (s - g.curve_length_m)
                  * math.cos(theta))  # fmt: skip
    yc = np.where(on_circle, r * (1 - np.cos(psi)), r * (1 - math.cos(theta))
                  + (s - g.curve_length_m) * math.sin(theta))  # fmt: skip
    fig = Figure(figsize=(7.5, 3.2))
    ax = fig.add_subplot()
    x = np.array([0.0, xc[-1]])
    for y in (half, -half):
        ax.plot(x, [y, y], color="C0", lw=1)
    for sign in (1, -1):
        ax.plot(xc - sign * half * np.sin(psi), yc + sign * half * np.cos(psi), color="C1", lw=1)
    ax.plot([x_ip], [half], "ko", ms=4, label=f"IP: {x_ip:.2f} m from the toe")
    ax.plot([], [], color="C0", label="through route")
    ax.plot([], [], color="C1", label="diverging route (R 245 m, then 1:9.25)")
    ax.set_xlabel("x from the switch toe [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)


if __name__ == "__main__":
    out = Path(sys.argv[1])
    slices_figure(out / "turnout_switch_slices.png")
    plan_figure(out / "turnout_plan.png")
