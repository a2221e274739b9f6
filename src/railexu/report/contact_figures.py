"""Figures of a quasi-static contact check (``railexu contact``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from railexu.report.figures import SIDES, _colour_for

if TYPE_CHECKING:
    from railexu.contact.check import ContactCheckResult


def contact_check_figures(result: ContactCheckResult) -> dict[str, Figure]:
    """Figures of a quasi-static contact check: contact points on the profiles, Delta r(y),
    contact angle against y and equivalent conicity against amplitude."""
    rows = result.rows
    lateral = np.array(result.settings.lateral_m, dtype=float)
    colour = _colour_for(lateral * 1e3)
    figs: dict[str, Figure] = {}

    # 1. contact points on wheel and rail profiles (profile own coordinates)
    fig = Figure(figsize=(11, 7.5), layout="constrained")
    axes = fig.subplots(2, 2)
    for i, side in enumerate(SIDES):
        pair = result.model.geometry.pairs[i]
        wheel = pair.wheel
        ax_w, ax_r = axes[i]
        s = np.linspace(wheel.y_min, wheel.y_max, 800)
        ax_w.plot(s * 1e3, wheel.height(s) * 1e3, color="0.3", lw=1.2)
        outline = np.asarray(pair.rail.outline_m)
        ax_r.plot(outline[:, 0] * 1e3, outline[:, 1] * 1e3, color="0.3", lw=1.2)
        for r in rows:
            if r["side"] != side:
                continue
            c = colour(r["lateral_m"] * 1e3)
            marker = "o" if r["point"] == 1 else "s"
            sw = r["wheel_lateral_m"]
            ax_w.plot(sw * 1e3, wheel.height(sw) * 1e3, marker, color=c, ms=5)
            yr = r["rail_lateral_m"]
            ax_r.plot(yr * 1e3, float(pair.rail.height(yr)) * 1e3, marker, color=c, ms=5)
        ax_w.set_title(f"{side} wheel ({wheel.name}): contact points")
        ax_w.set_xlabel("wheel lateral coordinate from tape circle, outwards [mm]")
        ax_w.set_ylabel("radius increase F [mm]")
        ax_w.grid(True, alpha=0.4)
        ax_r.set_title(f"{side} rail ({pair.rail.name}, own axes)")
        ax_r.set_xlabel("rail lateral coordinate, outwards [mm]")
        ax_r.set_ylabel("rail height [mm]")
        ax_r.set_aspect("equal", adjustable="datalim")
        ax_r.grid(True, alpha=0.4)
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    sm = ScalarMappable(norm=Normalize(lateral.min() * 1e3, lateral.max() * 1e3), cmap="viridis")
    fig.colorbar(sm, ax=axes, label="wheelset lateral displacement [mm]  (o tread, s 2nd point)")
    figs["contact_points"] = fig

    # 2. rolling radius difference
    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.subplots()
    ax.plot(result.delta_r_lateral_m * 1e3, result.delta_r_m * 1e3, lw=1.5)
    ax.set_xlabel("wheelset lateral displacement y [mm]")
    ax.set_ylabel("rolling radius difference r_left - r_right [mm]")
    ax.set_title("Rolling radius difference (rigid contact, no yaw)")
    ax.grid(True, alpha=0.4)
    figs["delta_r"] = fig

    # 3. contact angle against lateral displacement
    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.subplots()
    for side, style in zip(SIDES, ("o-", "s--"), strict=True):
        for point in (1, 2, 3):
            sel = [r for r in rows if r["side"] == side and r["point"] == point]
            if not sel:
                continue
            ax.plot(
                [r["lateral_m"] * 1e3 for r in sel],
                [np.degrees(r["contact_angle_rad"]) for r in sel],
                style,
                ms=4,
                label=f"{side} wheel, point {point}",
            )
    ax.set_xlabel("wheelset lateral displacement y [mm]")
    ax.set_ylabel("contact angle [deg]")
    ax.set_title("Contact angle (positive towards the flange)")
    ax.grid(True, alpha=0.4)
    ax.legend()
    figs["contact_angle"] = fig

    # 4. equivalent conicity
    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.subplots()
    ax.plot(result.conicity_amplitude_m * 1e3, result.conicity, "o-", ms=4)
    ax.set_xlabel("amplitude of lateral motion [mm]")
    ax.set_ylabel("equivalent conicity [-]")
    ax.set_title("Equivalent conicity (EN 15302, harmonic linearisation)")
    ax.grid(True, alpha=0.4)
    figs["conicity"] = fig
    return figs


# ----------------------------------------------------------------------------------------------
# Run figures (time series of ``railexu run``)
# ----------------------------------------------------------------------------------------------
