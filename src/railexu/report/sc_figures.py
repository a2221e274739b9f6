"""The ``crossing`` figure of a run through a switch-and-crossing zone (issue 29): per wheelset
and side with a variable rail, the vertical force of each rail (nose and wing rail, or check
rail and stock rail) and their sum,
the lateral contact position on each rail and Tgamma per rail against the wheelset's distance
along the track, the zone shaded."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

if TYPE_CHECKING:
    from railexu.results import TimeSeries

#: Rail 1 is the gauge side's (the nose, a check rail, a switch blade), rail 2 the field side's
#: (the wing rail, the stock rail beside a check rail or a blade): profiles.variable.rails.
_RAILS = ("rail 1 (nose / check rail / blade)", "rail 2 (wing / stock rail)")


def sc_sides(ts: TimeSeries) -> list[str]:
    """The ``ws{i}_{side}`` prefixes with outputs per rail (``..._rail1_Q_N``)."""
    return [n[: -len("_in_zone")] for n in ts.names if n.endswith("_in_zone")]


def crossing_figure(ts: TimeSeries, zone_m: tuple[float, float], title: str = "") -> Figure:
    """Three stacked panels against distance: Q per rail [kN], contact position [mm], Tgamma
    per rail [N]; one line style per wheelset and side."""
    fig = Figure(figsize=(10, 10))
    fig.subplots_adjust(left=0.1, right=0.97, bottom=0.06, top=0.94, hspace=0.35)
    axes = [fig.add_subplot(3, 1, k + 1) for k in range(3)]
    for ax in axes:
        ax.axvspan(zone_m[0], zone_m[1], color="0.9", zorder=0, label="S&C zone")
        ax.grid(True, alpha=0.4)
    for prefix in sc_sides(ts):
        inside = ts[f"{prefix}_in_zone"] > 0.5
        s = ts[prefix.split("_")[0] + "_s_m"][inside]
        total = ts[f"{prefix}_rail1_Q_N"][inside] + ts[f"{prefix}_rail2_Q_N"][inside]
        axes[0].plot(s, total * 1e-3, "k-", lw=0.8, label=f"{prefix} sum")
        for r, label in enumerate(_RAILS, start=1):
            q = ts[f"{prefix}_rail{r}_Q_N"][inside]
            y = np.where(q > 0.0, ts[f"{prefix}_rail{r}_contact_y_m"][inside], np.nan)
            axes[0].plot(s, q * 1e-3, lw=1.0, label=f"{prefix} {label}")
            axes[1].plot(s, y * 1e3, ".", ms=2, label=f"{prefix} {label}")
            axes[2].plot(s, ts[f"{prefix}_rail{r}_Tgamma_N"][inside], lw=1.0,
                         label=f"{prefix} {label}")  # fmt: skip
    axes[0].set_ylabel("vertical force Q [kN]")
    axes[1].set_ylabel("contact position y [mm]\n(rail axes, field side +)")
    axes[2].set_ylabel("Tgamma [N]")
    axes[2].set_xlabel("wheelset position along the track [m]")
    for ax in axes:
        ax.legend(fontsize=7, loc="best")
    fig.suptitle(f"{title}: forces and contact positions per rail in the S&C zone")
    return fig
