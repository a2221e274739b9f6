"""Figures of a track's design geometry: the plan of the centre line, and curvature and cant
against distance, with the sections marked."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

if TYPE_CHECKING:
    from railexu.track.alignment import Alignment
    from railexu.track.vertical import VerticalAlignment

#: Colours of the section kinds (background bands).
SECTION_COLOURS = {"curve": "#f4d6c6", "transition": "#fbeed9", "measured": "#e8e8f4"}


def mark_sections(ax, alignment: Alignment, x_min: float | None = None, x_max: float | None = None):
    """Shade the transitions and curves of ``alignment`` on an axis whose x is the distance."""
    for sec in alignment.sections:
        colour = SECTION_COLOURS.get(sec.kind)
        if colour is None:
            continue
        lo, hi = sec.start_m, sec.end_m
        if x_min is not None and hi < x_min or x_max is not None and lo > x_max:
            continue
        ax.axvspan(lo, hi, color=colour, lw=0, zorder=0)


def track_figure(alignment: Alignment, title: str = "", step_m: float = 0.5) -> Figure:
    """Plan (x, y of the centre line) and curvature and cant against distance."""
    end = max(alignment.end_m, 1.0)
    s = np.arange(0.0, end + step_m, step_m)
    x, y = alignment.position(s)
    fig = Figure(figsize=(10, 9))
    fig.subplots_adjust(left=0.1, right=0.9, bottom=0.06, top=0.93, hspace=0.45)
    ax = fig.add_subplot(2, 1, 1)
    ax.plot(x, y, color="k", lw=1.2)
    for sec in alignment.sections:
        xs, ys = alignment.position(np.array([sec.start_m]))
        ax.plot(xs, ys, "o", ms=3, color="tab:red")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{title}: plan of the centre line (dots: start of a section)".lstrip(": "))
    ax.grid(True, alpha=0.4)
    ax1 = fig.add_subplot(2, 1, 2)
    mark_sections(ax1, alignment)
    ax1.plot(s, alignment.curvature(s) * 1e3, color="tab:blue", lw=3.0, label="curvature")
    ax1.set_xlabel("distance along the track [m]")
    ax1.set_ylabel("curvature [1/km] (+ left)", color="tab:blue")
    ax1.grid(True, alpha=0.4)
    ax2 = ax1.twinx()
    ax2.plot(s, alignment.cant(s) * 1e3, color="tab:orange", ls="--", label="cant")
    ax2.set_ylabel("cant [mm] (+ right rail higher)", color="tab:orange")
    ax1.set_title("curvature and cant (shaded: transitions, curves)")
    return fig


def vertical_profile_figure(
    vertical: VerticalAlignment, title: str = "", s_range_m: tuple[float, float] | None = None
) -> Figure:
    """Elevation, gradient and vertical curvature against distance (vertical curves shaded),
    over ``s_range_m`` (default: the profile's stations)."""
    lo, hi = s_range_m if s_range_m is not None else (vertical.grid_m[0], vertical.end_m)
    if not hi > lo:
        hi = lo + 1.0
    s = np.linspace(lo, hi, 1000)
    fig = Figure(figsize=(10, 8))
    fig.subplots_adjust(left=0.1, right=0.95, bottom=0.07, top=0.93, hspace=0.35)
    rows = (
        (vertical.elevation(s), "elevation [m]", "top of rail on the centre line"),
        (1e3 * vertical.gradient_at(s), "gradient [per mille] (+ rising)", "gradient"),
        (1e3 * vertical.curvature(s), "vertical curvature [1/km] (+ sag)",
         "vertical curvature = 1 / R_v"),
    )  # fmt: skip
    axes = []
    for k, (values, label, what) in enumerate(rows):
        ax = fig.add_subplot(3, 1, k + 1, sharex=axes[0] if axes else None)
        for curve in vertical.curves:
            if curve.end_m >= lo and curve.start_m <= hi:
                ax.axvspan(curve.start_m, curve.end_m, color=SECTION_COLOURS["curve"], lw=0)
        ax.plot(s, values, color="k", lw=1.2)
        ax.set_ylabel(label)
        ax.set_title(what, fontsize=10)
        ax.grid(True, alpha=0.4)
        axes.append(ax)
    axes[-1].set_xlabel("distance along the track [m]")
    head = f"{title}: vertical profile" if title else "vertical profile"
    fig.suptitle(f"{head} ({vertical.kind}; shaded: vertical curves)")
    return fig
