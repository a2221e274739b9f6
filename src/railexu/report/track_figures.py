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
    spans = [(c.start_m, c.end_m) for c in vertical.curves if c.end_m >= lo and c.start_m <= hi]
    return _profile_figure(
        s, vertical.elevation(s), 1e3 * vertical.gradient_at(s), vertical.curvature(s), spans,
        f"{title}: vertical profile, {vertical.kind}".lstrip(": "),
    )  # fmt: skip


def vertical_run_figure(ts, title: str = "") -> Figure:
    """The vertical profile under a run's leading wheelset, from its time series
    (``track_elevation_m``, ``track_gradient_per_mille``, ``track_vertical_curvature_1_per_m``
    against ``ws1_s_m``): ``railexu run`` and ``railexu plot`` draw the same figure."""
    s = np.asarray(ts["ws1_s_m"], dtype=float)
    kappa = np.asarray(ts["track_vertical_curvature_1_per_m"], dtype=float)
    # in a vertical curve: R_v below 100 km (the rounded curvature's tails, 1 m Gaussian at the
    # curve's ends, are shaded from about 2 m before the end of a 1500 m curve)
    curved = np.abs(kappa) > 1e-5
    spans = []
    if np.any(curved):  # runs of samples in a vertical curve
        edges = np.flatnonzero(np.diff(curved.astype(int))) + 1
        for part in np.split(np.arange(s.size), edges):
            if curved[part[0]]:
                spans.append((float(s[part[0]]), float(s[part[-1]])))
    head = "vertical profile under the leading wheelset"
    head = f"{title}: {head}" if title else head
    return _profile_figure(
        s, np.asarray(ts["track_elevation_m"], dtype=float),
        np.asarray(ts["track_gradient_per_mille"], dtype=float), kappa, spans, head,
    )  # fmt: skip


def _profile_figure(s, elevation_m, gradient_per_mille, curvature_1_per_m, spans, head: str):
    """Three axes against distance: elevation [m], gradient [per mille], curvature [1/km]."""
    fig = Figure(figsize=(10, 8))
    fig.subplots_adjust(left=0.1, right=0.95, bottom=0.07, top=0.93, hspace=0.35)
    rows = (
        (elevation_m, "elevation [m]", "top of rail on the centre line"),
        (gradient_per_mille, "gradient [per mille] (+ rising)", "gradient"),
        (1e3 * np.asarray(curvature_1_per_m), "vertical curvature [1/km] (+ sag)",
         "vertical curvature = 1 / R_v"),
    )  # fmt: skip
    axes = []
    for k, (values, label, what) in enumerate(rows):
        ax = fig.add_subplot(3, 1, k + 1, sharex=axes[0] if axes else None)
        for lo, hi in spans:
            ax.axvspan(lo, hi, color=SECTION_COLOURS["curve"], lw=0)
        ax.plot(s, values, color="k", lw=1.2)
        ax.set_ylabel(label)
        ax.set_title(what, fontsize=10)
        ax.grid(True, alpha=0.4)
        axes.append(ax)
    axes[-1].set_xlabel("distance along the track [m]")
    fig.suptitle(f"{head} (shaded: vertical curves)")
    return fig
