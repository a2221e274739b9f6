"""The wear figure of a run (``wear.png``, docs/wear.md, "Per run"): one row per wheel
(wheelsets from the front, left and right) with the depth removed per km across the wheel's
profile, FI_surf and the WLRM damage per km along it, and the rail's depth and WLRM damage per
axle passage across the rail under it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from railexu.report.figures import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["run_wear_figure"]


def run_wear_figure(wears: list, law: str, title: str = "") -> Figure:
    """The figure of ``wears`` (:func:`railexu.results.wear.run_wear`), worn by ``law``.

    Per wheel three panels: the depth per km [um/km] against the profile coordinate ``s`` from
    the tape circle [mm]; the largest FI_surf [-] (the shakedown line at 0 dashed) and the WLRM
    damage per km (second axis) along ``s``; the rail's depth per axle passage [nm] and its WLRM
    damage per axle passage (second axis) against the rail position from the gauge line,
    outwards positive [mm].
    """
    fig = new_figure(figsize=(13, 2.9 * len(wears) + 0.6))
    n = len(wears)
    for j, w in enumerate(wears):
        key = f"{w.wheelset} {w.side}"
        s_mm = np.asarray(w.lateral_m) * 1e3
        ax = fig.add_subplot(n, 3, 3 * j + 1)
        ax.plot(s_mm, np.asarray(w.depth_per_km_m) * 1e6, lw=0.9)
        ax.set(xlabel="wheel profile s from the tape circle [mm]",
               ylabel="depth per km [um/km]", title=f"{key}: wheel wear ({law})")  # fmt: skip
        ax.grid(True, lw=0.3)
        ax = fig.add_subplot(n, 3, 3 * j + 2)
        fi = w.fi_surf_wheel_max if w.fi_surf_wheel_max is not None else s_mm * np.nan
        ax.plot(s_mm, fi, "o", ms=3, color="C3", label="FI_surf (largest)")
        ax.axhline(0.0, color="k", lw=0.6, ls="--")
        ax.set(xlabel="wheel profile s from the tape circle [mm]", ylabel="FI_surf [-]",
               title=f"{key}: RCF along the wheel")  # fmt: skip
        ax.grid(True, lw=0.3)
        ax2 = ax.twinx()
        ax2.plot(s_mm, w.wlrm_wheel_per_km, lw=0.8, color="C2", label="WLRM")
        ax2.set_ylabel("WLRM damage per km [1/km]")
        _front(ax, ax2)
        ax.legend(fontsize=7, loc="upper left")
        ax2.legend(fontsize=7, loc="upper right")
        r_mm = np.asarray(w.rail_lateral_m) * 1e3
        ax = fig.add_subplot(n, 3, 3 * j + 3)
        ax.plot(r_mm, np.asarray(w.rail_depth_per_axle_m) * 1e9, lw=0.9, label="depth")
        ax.set(xlabel="rail from the gauge line, outwards [mm]",
               ylabel="depth per axle passage [nm]",
               title=f"{key}: rail under it")  # fmt: skip
        ax.grid(True, lw=0.3)
        ax2 = ax.twinx()
        ax2.plot(r_mm, w.wlrm_rail_per_axle, lw=0.8, color="C2")
        ax2.set_ylabel("WLRM damage per axle passage [-]")
        _front(ax, ax2)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def _front(ax, twin) -> None:
    """Draw ``ax`` (the first quantity) over its second axis ``twin``."""
    ax.set_zorder(twin.get_zorder() + 1)
    ax.patch.set_visible(False)
