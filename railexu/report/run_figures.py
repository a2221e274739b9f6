"""Figures of a run: lateral displacement, lateral force, Y/Q against distance."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from .figures import SIDES

if TYPE_CHECKING:
    from ..results import TimeSeries

_FLANGE_ANGLE_PLOT_RAD = np.radians(45.0)


def _wheelset_labels(ts: TimeSeries, summary: dict | None) -> dict[int, str]:
    indices = ts.wheelset_indices()
    names = [w.get("name") for w in (summary or {}).get("wheelsets", [])]
    if len(names) == len(indices) and all(names):
        return {
            i: f"ws{i}" if n == f"ws{i}" else f"ws{i} ({n})"
            for i, n in zip(indices, names, strict=True)
        }
    return {i: f"wheelset {i}" for i in indices}


def _finish_axes(ax, xlabel: str, ylabel: str, title: str, legend: bool = True) -> None:
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.4)
    if legend and ax.get_legend_handles_labels()[0]:
        # a fixed place: "best" searches every data point, slow on long runs
        ax.legend(fontsize="small", loc="upper right")


def _stacked_figure(rows: int) -> Figure:
    """A figure for ``rows`` stacked subplots with fixed margins (in inches)."""
    height = 1.2 + 2.4 * rows
    fig = Figure(figsize=(10, height))
    fig.subplots_adjust(
        left=0.08, right=0.98, bottom=0.55 / height, top=1.0 - 0.75 / height, hspace=0.55
    )
    return fig


def _envelope(x: np.ndarray, y: np.ndarray, buckets: int = 1000) -> tuple[np.ndarray, np.ndarray]:
    """Thin a long series for plotting, keeping each bucket's minimum and maximum in order, so
    that peaks (flange impacts) survive while drawing time and SVG size stay bounded."""
    n = len(y)
    if n <= 2 * buckets:
        return x, y
    size = n // buckets
    m = size * buckets
    block = np.where(np.isfinite(y[:m]), y[:m], np.nan).reshape(buckets, size)
    valid = np.isfinite(block).any(axis=1)
    filled_lo = np.where(np.isfinite(block), block, np.inf)
    filled_hi = np.where(np.isfinite(block), block, -np.inf)
    i_min = np.argmin(filled_lo, axis=1)
    i_max = np.argmax(filled_hi, axis=1)
    first = np.minimum(i_min, i_max)
    second = np.maximum(i_min, i_max)
    base = np.arange(buckets) * size
    idx = np.column_stack([base + first, base + second]).ravel()
    keep = np.repeat(valid, 2)
    idx = np.concatenate([idx[keep], np.arange(m, n)])
    return x[idx], y[idx]


def run_figures(ts: TimeSeries, summary: dict | None = None, title: str = "") -> dict[str, Figure]:
    """Figures of a running simulation against the distance travelled (m).

    - ``"lateral_displacement"``: lateral displacement (mm, positive left) of every wheelset
      (solid) and of the other bodies (dashed);
    - ``"lateral_force"``: lateral contact force Y (kN, on the wheel, positive left) of the left
      and right wheel, one subplot per wheelset; spans with a flange contact (largest loaded
      contact angle above 45 deg) are shaded in the wheel's colour;
    - ``"y_over_q"``: Y/Q of every wheel, signed so that the flanging wheel is positive (see
      :func:`railexu.results.y_over_q`; raw thin, 2 m sliding mean thick), with Nadal's limit
      from ``summary`` as a horizontal line. Samples where Q is below 5 % of the mean wheel load
      of the run (unloaded wheel) are left out.

    Args:
        ts: the recorded time series.
        summary: the dict of :func:`railexu.results.summarize` (wheelset names, Nadal limit,
            hunting), optional.
        title: figure title prefix (vehicle, speed...).
    """
    from ..results import MIN_LOAD_FRACTION, SAFETY_WINDOW_M, sliding_mean, y_over_q

    x = ts.distance_m
    indices = ts.wheelset_indices()
    labels = _wheelset_labels(ts, summary)
    prefix = f"{title}: " if title else ""
    xlabel = "distance travelled [m]"
    side_colour = {"left": "tab:blue", "right": "tab:red"}
    figs: dict[str, Figure] = {}

    # 1. lateral displacement
    # run figures use fixed margins: the constrained layout engine costs ~40 % of the drawing
    fig = Figure(figsize=(10, 5))
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.11, top=0.92)
    ax = fig.subplots()
    for i in indices:
        ax.plot(*_envelope(x, ts[f"ws{i}_lateral_m"] * 1e3), lw=1.2, label=labels[i])
    for body in ts.body_names():
        ax.plot(
            *_envelope(x, ts[f"{body}_lateral_m"] * 1e3),
            "--",
            lw=1.0,
            label=body.replace("_", " "),
        )
    hunting = (summary or {}).get("hunting") or {}
    extra = ""
    if hunting.get("wavelength_m"):
        state = "hunting" if hunting.get("detected") else "no hunting"
        extra = f" ({state}, wavelength {hunting['wavelength_m']:.2f} m"
        if hunting.get("frequency_Hz"):
            extra += f", {hunting['frequency_Hz']:.2f} Hz"
        extra += ")"
    elif hunting:
        extra = " (hunting)" if hunting.get("detected") else " (no hunting)"
    _finish_axes(
        ax,
        xlabel,
        "lateral displacement (positive left) [mm]",
        f"{prefix}lateral displacement{extra}",
    )
    figs["lateral_displacement"] = fig

    # 2. lateral force with flange contact
    rows = max(1, len(indices))
    fig = _stacked_figure(rows)
    axes = np.atleast_1d(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    for ax, i in zip(axes, indices, strict=False):
        for side in SIDES:
            name = f"ws{i}_{side}"
            if f"{name}_Y_N" not in ts:
                continue
            c = side_colour[side]
            ax.plot(
                *_envelope(x, ts[f"{name}_Y_N"] * 1e-3), color=c, lw=1.0, label=f"{side} wheel Y"
            )
            angle_col = f"{name}_max_angle_rad"
            if angle_col in ts:
                flange = ts[angle_col] > _FLANGE_ANGLE_PLOT_RAD
                if flange.any():
                    ax.fill_between(
                        x,
                        0,
                        1,
                        where=flange,
                        transform=ax.get_xaxis_transform(),
                        color=c,
                        alpha=0.15,
                        lw=0,
                        label=f"{side} flange contact (> 45 deg)",
                    )
        ax.axhline(0.0, color="0.5", lw=0.6)
        _finish_axes(ax, xlabel, "lateral force Y [kN]", f"{labels[i]}: lateral force on wheels")
    fig.suptitle(f"{prefix}lateral wheel-rail force (on the wheel, positive left)")
    figs["lateral_force"] = fig

    # 3. Y/Q, flanging wheel positive
    fig = _stacked_figure(rows)
    axes = np.atleast_1d(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    q_cols = [ts[f"ws{i}_{s}_Q_N"] for i in indices for s in SIDES if f"ws{i}_{s}_Q_N" in ts]
    mean_q = float(np.nanmean(np.concatenate(q_cols))) if q_cols and len(ts) else 0.0
    nadal = ((summary or {}).get("max_Y_over_Q") or {}).get("nadal_limit")
    for ax, i in zip(axes, indices, strict=False):
        for side in SIDES:
            if f"ws{i}_{side}_Y_N" not in ts or f"ws{i}_{side}_Q_N" not in ts:
                continue
            c = side_colour[side]
            yq = y_over_q(ts, i, side, MIN_LOAD_FRACTION * max(mean_q, 0.0))
            ax.plot(*_envelope(x, yq), color=c, lw=0.7, alpha=0.45, label=f"{side} wheel")
            if len(ts) > 1 and x[-1] - x[0] >= SAFETY_WINDOW_M:
                ax.plot(
                    *_envelope(x, sliding_mean(x, yq, SAFETY_WINDOW_M)),
                    color=c,
                    lw=1.6,
                    label=f"{side} wheel, {SAFETY_WINDOW_M:g} m mean",
                )
        if nadal is not None:
            ax.axhline(nadal, color="k", ls="--", lw=1.0, label=f"Nadal limit {nadal:.2f}")
        ax.axhline(0.0, color="0.5", lw=0.6)
        _finish_axes(ax, xlabel, "Y/Q (flanging positive) [-]", f"{labels[i]}: Y/Q")
    fig.suptitle(f"{prefix}derailment quotient Y/Q (EN 14363)")
    figs["y_over_q"] = fig
    return figs


# ----------------------------------------------------------------------------------------------
# Study figures (results of ``railexu study``)
# ----------------------------------------------------------------------------------------------
