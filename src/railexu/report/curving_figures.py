"""The ``curving`` figure of a run: the leading wheelset's lateral displacement and angle of
attack, Y and Q of its outer and inner wheel, and T-gamma of every wheelset against distance,
with the track's transitions and curves shaded."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from railexu.report.track_figures import mark_sections

if TYPE_CHECKING:
    from railexu.results import TimeSeries
    from railexu.track.alignment import Alignment


def _outer_side(alignment: Alignment, s: np.ndarray) -> np.ndarray:
    """True where the right rail is the outer one (left curve or straight)."""
    return alignment.curvature(s) >= 0.0


def curving_figure(ts: TimeSeries, alignment: Alignment, title: str = "") -> Figure:
    """Five stacked panels against the leading wheelset's distance along the track."""
    s = ts["ws1_s_m"]
    right_outer = _outer_side(alignment, s)
    fig = Figure(figsize=(10, 13))
    fig.subplots_adjust(left=0.1, right=0.97, bottom=0.05, top=0.95, hspace=0.5)
    axes = [fig.add_subplot(5, 1, k + 1) for k in range(5)]
    for ax in axes:
        mark_sections(ax, alignment, float(s.min()), float(s.max()))
        ax.grid(True, alpha=0.4)
    n_ws = len(ts.wheelset_indices())
    for i in range(1, n_ws + 1):
        axes[0].plot(ts[f"ws{i}_s_m"], ts[f"ws{i}_lateral_m"] * 1e3, lw=0.9, label=f"ws{i}")
        axes[1].plot(ts[f"ws{i}_s_m"], ts[f"ws{i}_yaw_rad"] * 1e3, lw=0.9, label=f"ws{i}")
        tgamma = ts[f"ws{i}_left_Tgamma_N"] + ts[f"ws{i}_right_Tgamma_N"]
        axes[4].plot(ts[f"ws{i}_s_m"], tgamma, lw=0.9, label=f"ws{i}")
    outer, inner = "right", "left"
    y_out = np.where(right_outer, ts["ws1_right_Y_N"], ts["ws1_left_Y_N"])
    y_in = np.where(right_outer, ts["ws1_left_Y_N"], ts["ws1_right_Y_N"])
    q_out = np.where(right_outer, ts["ws1_right_Q_N"], ts["ws1_left_Q_N"])
    q_in = np.where(right_outer, ts["ws1_left_Q_N"], ts["ws1_right_Q_N"])
    axes[2].plot(s, y_out / 1e3, label=f"outer ({outer} in a left curve)")
    axes[2].plot(s, y_in / 1e3, label=f"inner ({inner} in a left curve)")
    axes[3].plot(s, q_out / 1e3, label="outer")
    axes[3].plot(s, q_in / 1e3, label="inner")
    labels = [
        (
            "lateral displacement [mm] (+ left)",
            "wheelset lateral displacement from the centre line",
        ),
        ("angle of attack [mrad] (+ ccw)", "yaw relative to the local track direction"),
        ("Y [kN] (+ left)", "leading wheelset: lateral wheel-rail forces (track plane)"),
        ("Q [kN]", "leading wheelset: vertical wheel-rail forces (track plane)"),
        ("T-gamma [N]", "wear number per wheelset (sum of both wheels)"),
    ]
    for ax, (ylabel, panel) in zip(axes, labels, strict=True):
        ax.set_ylabel(ylabel)
        ax.set_title(panel)
        ax.set_xlabel("distance of the wheelset along the track [m]")
        ax.legend(fontsize="small", loc="upper right")
    if title:
        fig.suptitle(f"{title}: curving (shaded: transitions, curves)")
    return fig


def curved_track_figures(
    ts: TimeSeries, alignment: Alignment, track_name: str = "", title: str = ""
) -> dict[str, Figure]:
    """The figures a run on a curved track draws besides the common ones: ``track`` (plan,
    curvature and cant) and ``curving``; none on a straight track."""
    if alignment.is_straight:
        return {}
    from railexu.report.track_figures import track_figure

    return {
        "track": track_figure(alignment, track_name),
        "curving": curving_figure(ts, alignment, title),
    }
