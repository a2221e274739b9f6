"""Figures of a run against the distance travelled: lateral displacement, lateral force with
flange contact, Y/Q against EN 14363's limit (and Nadal's, as information), wheel load Q and
unloading Delta Q / Q0, track-shifting force sum Y against its limit, and the accelerations of
the measurement points with their ride comfort."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from railexu.report.figures import SIDES, new_figure
from railexu.results import MIN_LOAD_FRACTION, SAFETY_WINDOW_M, sliding_mean, y_over_q

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from railexu.results import TimeSeries

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
    # an explicit title position: the automatic one measures every tick label of the axes first
    # (half the drawing time of a figure of stacked axes)
    ax.set_title(title, y=1.0)
    ax.grid(True, alpha=0.4)
    if legend and ax.get_legend_handles_labels()[0]:
        # a fixed place: "best" searches every data point, slow on long runs
        ax.legend(fontsize="small", loc="upper right")


def _deduplicate_legends(fig: Figure) -> None:
    """Keep the legend of a stacked subplot only where its entries differ from those of a
    subplot above it in the same column (one legend per column instead of one per wheelset:
    easier to read, and legends are a tenth of the drawing time)."""
    shown: dict[float, set] = {}
    for ax in sorted(fig.axes, key=lambda a: (a.get_position().x0, -a.get_position().y0)):
        legend = ax.get_legend()
        if legend is None:
            continue
        labels = tuple(t.get_text() for t in legend.get_texts())
        seen = shown.setdefault(round(ax.get_position().x0, 3), set())
        if labels in seen:
            legend.remove()
        seen.add(labels)


def _stacked_figure(rows: int) -> Figure:
    """A figure for ``rows`` stacked subplots with fixed margins (in inches)."""
    height = 1.2 + 2.4 * rows
    fig = new_figure(figsize=(10, height))
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


def _summary_dict(summary) -> dict:
    if summary is None:
        return {}
    return summary.to_dict() if hasattr(summary, "to_dict") else dict(summary)


def _shade_outside_window(ax, summary: dict, x: np.ndarray) -> None:
    """Grey out the stretches outside the evaluation window (not assessed)."""
    win = summary.get("evaluation_window") or {}
    lo, hi = win.get("from_m"), win.get("to_m")
    if lo is not None and len(x) and lo > x[0]:
        ax.axvspan(x[0], lo, color="0.85", lw=0, zorder=0, label="not evaluated (start-up)")
    if hi is not None and len(x) and hi < x[-1]:
        ax.axvspan(hi, x[-1], color="0.85", lw=0, zorder=0)


def _mark_flange_contact(ax, x: np.ndarray, flange: np.ndarray, colour: str, label: str) -> None:
    """Shade the flange-contact spans and put a marker above each one, so that a 1 m contact is
    visible on a 500 m axis (a span alone would be thinner than a pixel)."""
    if not flange.any():
        return
    ax.fill_between(x, 0, 1, where=flange, transform=ax.get_xaxis_transform(), color=colour,
                    alpha=0.15, lw=0)  # fmt: skip
    starts = x[np.flatnonzero(np.diff(np.concatenate(([0], flange.astype(int)))) == 1)]
    ax.plot(starts, np.full(starts.shape, 0.97), "v", color=colour, ms=7,
            transform=ax.get_xaxis_transform(), clip_on=False, label=label)  # fmt: skip


def _limit_lines(ax, data_max: float, limits: list[tuple[float, str, str]]) -> None:
    """Horizontal limit lines; a limit far above the data (more than 3 times its maximum) is
    written in the corner instead, so that the data stay readable."""
    off_scale = []
    for value, label, style in limits:
        if value <= 3.0 * max(data_max, 0.0) or data_max <= 0.0:
            ax.axhline(value, color="k", ls=style, lw=1.0, label=label)
        else:
            off_scale.append(label)
    if off_scale:
        ax.text(0.01, 0.97, "above the axis: " + "; ".join(off_scale), transform=ax.transAxes,
                va="top", fontsize="small", color="0.2")  # fmt: skip


def _nanmax(*arrays: np.ndarray) -> float:
    values = [np.nanmax(a) for a in arrays if a.size and np.any(np.isfinite(a))]
    return float(max(values)) if values else 0.0


def run_figures(
    ts: TimeSeries, summary=None, title: str = "", names: Iterable[str] | None = None
) -> dict[str, Figure]:
    """Figures of a running simulation against the distance travelled (m).

    - ``"lateral_displacement"``: lateral displacement (mm, positive left) of every wheelset
      (solid) and of the other bodies (dashed), with the hunting verdict in the title;
    - ``"lateral_force"``: lateral contact force Y (kN) of the left and right wheel, one subplot
      per wheelset; flange contact (largest loaded contact angle above 45 deg) is shaded and
      marked by a triangle at its start, visible however short it is;
    - ``"y_over_q"``: Y/Q of every wheel, flanging wheel positive (raw thin, 2 m sliding mean
      thick), against EN 14363's limit 0.8 and Nadal's flange-climb value (information);
    - ``"wheel_load"``: wheel load Q (kN) and unloading ``Delta Q / Q0`` with its limit 0.6;
    - ``"sum_y"``: track-shifting force sum Y (kN) per axle (raw thin, 2 m mean thick) against
      the EN 14363 limit;
    - ``"accelerations"`` (when recorded): lateral and vertical accelerations (m/s^2) of each
      measurement point, with its ride comfort in the subplot title.

    Stretches outside the evaluation window are greyed. Samples where Q is below 5 % of the
    mean wheel load (unloaded wheel) have no Y/Q.

    Args:
        ts: the recorded time series.
        summary: the run's summary (:class:`railexu.results.RunSummary` or its dict), optional.
        title: figure title prefix (vehicle, speed...).
        names: the figures to draw (default: all of :func:`run_figure_names`).
    """
    available = run_figure_names(ts)
    wanted = available if names is None else list(names)
    unknown = [n for n in wanted if n not in RUN_FIGURES]
    if unknown:
        raise ValueError(f"unknown run figures {unknown}: expected some of {list(RUN_FIGURES)}")
    page = _page(ts, summary, title)
    return {n: RUN_FIGURES[n](page) for n in wanted if n in available}


def run_figure_names(ts: TimeSeries) -> list[str]:
    """The names of the run figures that ``ts`` has data for, in drawing order."""
    names = [n for n in RUN_FIGURES if n != "accelerations"]
    return names + (["accelerations"] if ts.measurement_points() else [])


class _Page(NamedTuple):
    """What every run figure needs: the data, the axes' common labels."""

    ts: TimeSeries
    summary: dict
    x: np.ndarray
    indices: list[int]
    labels: dict[int, str]
    prefix: str
    xlabel: str
    rows: int
    criteria: dict


def _page(ts: TimeSeries, summary, title: str) -> _Page:
    summary = _summary_dict(summary)
    indices = ts.wheelset_indices()
    return _Page(
        ts=ts,
        summary=summary,
        x=ts.distance_m,
        indices=indices,
        labels=_wheelset_labels(ts, summary),
        prefix=f"{title}: " if title else "",
        xlabel="distance travelled [m]",
        rows=max(1, len(indices)),
        criteria=(summary.get("assessment") or {}).get("criteria") or {},
    )


_SIDE_COLOUR = {"left": "tab:blue", "right": "tab:red"}


def _lateral_displacement(page: _Page) -> Figure:
    """Lateral displacement of the wheelsets and bodies."""
    ts, summary, x, indices, labels, prefix, xlabel, rows, criteria = page
    # run figures use fixed margins: the constrained layout engine costs ~40 % of the drawing
    fig = new_figure(figsize=(10, 5))
    # top margin for a title of two lines (a long vehicle name and the hunting verdict)
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.11, top=0.87)
    ax = fig.subplots()
    for i in indices:
        ax.plot(*_envelope(x, ts[f"ws{i}_lateral_m"] * 1e3), lw=1.2, label=labels[i])
    for body in ts.body_names():
        ax.plot(*_envelope(x, ts[f"{body}_lateral_m"] * 1e3), "--", lw=1.0,
                label=body.replace("_", " "))  # fmt: skip
    _shade_outside_window(ax, summary, x)
    title = _wrapped(f"{prefix}lateral displacement{_hunting_text(summary)}", 10 * 0.9)
    _finish_axes(ax, xlabel, "lateral displacement (positive left) [mm]", title)
    return fig


def _lateral_force(page: _Page) -> Figure:
    """Lateral force Y of each wheel with flange contact marked."""
    ts, summary, x, indices, labels, prefix, xlabel, rows, criteria = page
    fig = _stacked_figure(rows)
    axes = np.atleast_1d(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    for ax, i in zip(axes, indices, strict=False):
        for side in SIDES:
            name = f"ws{i}_{side}"
            if f"{name}_Y_N" not in ts:
                continue
            c = _SIDE_COLOUR[side]
            ax.plot(*_envelope(x, ts[f"{name}_Y_N"] * 1e-3), color=c, lw=1.0,
                    label=f"{side} wheel Y")  # fmt: skip
            if f"{name}_max_angle_rad" in ts:
                flange = ts[f"{name}_max_angle_rad"] > _FLANGE_ANGLE_PLOT_RAD
                _mark_flange_contact(ax, x, flange, c, f"{side} flange contact (> 45 deg)")
        ax.axhline(0.0, color="0.5", lw=0.6)
        _shade_outside_window(ax, summary, x)
        _finish_axes(ax, xlabel, "lateral force Y [kN]", f"{labels[i]}: lateral force on wheels")
    _suptitle(fig, f"{prefix}lateral wheel-rail force (on the wheel, positive left)")
    _deduplicate_legends(fig)
    return fig


def _y_over_q(page: _Page) -> Figure:
    """Y/Q of each wheel (flanging positive) against EN 14363's limit."""
    ts, summary, x, indices, labels, prefix, xlabel, rows, criteria = page
    q_cols = [ts[f"ws{i}_{s}_Q_N"] for i in indices for s in SIDES if f"ws{i}_{s}_Q_N" in ts]
    mean_q = float(np.nanmean(np.concatenate(q_cols))) if q_cols and len(ts) else 0.0
    yq_info = summary.get("max_Y_over_Q") or {}
    limit = yq_info.get("limit") or 0.8
    nadal = yq_info.get("nadal_limit")
    fig = _stacked_figure(rows)
    axes = np.atleast_1d(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    for ax, i in zip(axes, indices, strict=False):
        top = 0.0
        for side in SIDES:
            if f"ws{i}_{side}_Y_N" not in ts or f"ws{i}_{side}_Q_N" not in ts:
                continue
            c = _SIDE_COLOUR[side]
            yq = y_over_q(ts, i, side, MIN_LOAD_FRACTION * max(mean_q, 0.0))
            ax.plot(*_envelope(x, yq), color=c, lw=0.7, alpha=0.45, label=f"{side} wheel")
            top = max(top, _nanmax(yq))
            if len(ts) > 1 and x[-1] - x[0] >= SAFETY_WINDOW_M:
                ax.plot(*_envelope(x, sliding_mean(x, yq, SAFETY_WINDOW_M)), color=c, lw=1.6,
                        label=f"{side} wheel, {SAFETY_WINDOW_M:g} m mean")  # fmt: skip
        lines = [(limit, f"EN 14363 limit (Y/Q)_lim = {limit:.2f}", "--")]
        if nadal is not None:
            lines.append((nadal, f"Nadal flange-climb value {nadal:.2f} (information)", ":"))
        _limit_lines(ax, top, lines)
        ax.axhline(0.0, color="0.5", lw=0.6)
        _shade_outside_window(ax, summary, x)
        _finish_axes(ax, xlabel, "Y/Q (flanging positive) [-]", f"{labels[i]}: Y/Q")
    _suptitle(fig, f"{prefix}derailment quotient Y/Q against the EN 14363 limit")
    _deduplicate_legends(fig)
    return fig


def _wheel_load(page: _Page) -> Figure:
    """Wheel load Q and unloading against its limit."""
    ts, summary, x, indices, labels, prefix, xlabel, rows, criteria = page
    unloading = criteria.get("wheel_unloading") or {}
    static = unloading.get("static_wheel_load_N") or {}
    fig = _stacked_figure(rows)
    axes = fig.subplots(rows, 2, sharex=True, squeeze=False)
    for (ax_q, ax_d), i in zip(axes, indices, strict=False):
        for side in SIDES:
            col = f"ws{i}_{side}_Q_N"
            if col not in ts:
                continue
            c = _SIDE_COLOUR[side]
            q = ts[col]
            q0 = static.get(f"ws{i}_{side}") or (float(np.nanmean(q)) if len(q) else 1.0)
            ax_q.plot(*_envelope(x, q * 1e-3), color=c, lw=1.0, label=f"{side} wheel Q")
            ax_d.plot(*_envelope(x, (q0 - q) / q0), color=c, lw=1.0, label=f"{side} wheel")
        ax_d.axhline(unloading.get("limit") or 0.6, color="k", ls="--", lw=1.0,
                     label=f"limit {unloading.get('limit') or 0.6:g} (railexu)")  # fmt: skip
        for ax in (ax_q, ax_d):
            _shade_outside_window(ax, summary, x)
        _finish_axes(ax_q, xlabel, "wheel load Q [kN]", f"{labels[i]}: wheel load")
        _finish_axes(ax_d, xlabel, "unloading dQ/Q0 [-]", f"{labels[i]}: wheel unloading")
    _suptitle(fig, f"{prefix}vertical wheel load Q and unloading (Q0 - Q)/Q0")
    _deduplicate_legends(fig)
    return fig


def _sum_y(page: _Page) -> Figure:
    """Track-shifting force sum Y per axle against EN 14363's limit."""
    ts, summary, x, indices, labels, prefix, xlabel, rows, criteria = page
    shift = (summary.get("max_sum_Y_N") or {}).get("limit_N")
    fig = _stacked_figure(rows)
    axes = np.atleast_1d(fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0])
    for ax, i in zip(axes, indices, strict=False):
        if f"ws{i}_left_Y_N" not in ts or f"ws{i}_right_Y_N" not in ts:
            continue
        sum_y = (ts[f"ws{i}_left_Y_N"] + ts[f"ws{i}_right_Y_N"]) * 1e-3
        ax.plot(*_envelope(x, sum_y), color="0.4", lw=0.7, alpha=0.6, label="sum Y")
        if len(ts) > 1 and x[-1] - x[0] >= SAFETY_WINDOW_M:
            ax.plot(*_envelope(x, sliding_mean(x, sum_y, SAFETY_WINDOW_M)), color="tab:purple",
                    lw=1.6, label=f"sum Y, {SAFETY_WINDOW_M:g} m mean")  # fmt: skip
        if shift:
            top = _nanmax(np.abs(sum_y))
            _limit_lines(ax, top, [(shift * 1e-3, f"EN 14363 limit {shift * 1e-3:.1f} kN", "--"),
                                   (-shift * 1e-3, f"-{shift * 1e-3:.1f} kN", "--")])  # fmt: skip
        _shade_outside_window(ax, summary, x)
        _finish_axes(ax, xlabel, "sum Y [kN]", f"{labels[i]}: track-shifting force")
    _suptitle(fig, f"{prefix}track-shifting force sum Y = Y_left + Y_right (EN 14363)")
    _deduplicate_legends(fig)
    return fig


def _accelerations(page: _Page) -> Figure:
    """Accelerations of the measurement points with their ride comfort."""
    points = page.ts.measurement_points()
    return _acceleration_figure(page.ts, points, page.summary, page.prefix, page.xlabel)


#: the run figures by name, in drawing order
RUN_FIGURES: dict[str, Callable[[_Page], Figure]] = {
    "lateral_displacement": _lateral_displacement,
    "lateral_force": _lateral_force,
    "y_over_q": _y_over_q,
    "wheel_load": _wheel_load,
    "sum_y": _sum_y,
    "accelerations": _accelerations,
}


#: characters of a 12 pt title per inch (a wide character is about 0.6 of the font size)
_TITLE_CHARS_PER_INCH = 10


def _wrapped(title: str, width_in: float) -> str:
    """``title`` broken into lines that fit ``width_in`` inches, so that it stays inside the
    figure (issue 27: titles were cut at both edges)."""
    import textwrap

    return textwrap.fill(title, width=int(_TITLE_CHARS_PER_INCH * width_in))


#: the largest and smallest size of a figure's title [pt] (12: matplotlib's "large")
_SUPTITLE_PT = (12.0, 8.0)


def _suptitle(fig: Figure, title: str) -> None:
    """The figure's title in one line that fits its width: smaller type for a long title (a
    long vehicle name), down to 8 pt, and only then broken into lines (the stacked figures'
    fixed top margin holds one line of 12 pt)."""
    width_in = float(fig.get_figwidth())
    largest, smallest = _SUPTITLE_PT
    # characters that fit at size ``pt``: _TITLE_CHARS_PER_INCH is for 12 pt
    fits = _TITLE_CHARS_PER_INCH * width_in * largest
    size = min(largest, max(smallest, fits / max(len(title), 1)))
    fig.suptitle(_wrapped(title, width_in * largest / size), fontsize=size)


def _hunting_text(summary: dict) -> str:
    hunting = summary.get("hunting") or {}
    if not hunting:
        return ""
    state = "hunting" if hunting.get("detected") else "no hunting"
    verdict = hunting.get("verdict")
    text = f" ({state}" + (f": {verdict}" if verdict and verdict != state else "")
    if hunting.get("wavelength_m"):
        text += f", wavelength {hunting['wavelength_m']:.2f} m"
    if hunting.get("frequency_Hz"):
        text += f", {hunting['frequency_Hz']:.2f} Hz"
    return text + ")"


def _acceleration_figure(ts, points, summary, prefix, xlabel) -> Figure:
    comfort = ((summary.get("comfort") or {}).get("points")) or {}
    x = ts.distance_m
    fig = _stacked_figure(len(points))
    axes = np.atleast_1d(fig.subplots(len(points), 1, sharex=True, squeeze=False)[:, 0])
    for ax, p in zip(axes, points, strict=True):
        for axis, colour in (("y", "tab:blue"), ("z", "tab:green")):
            col = f"{p}_acc_{axis}_m_per_s2"
            if col in ts:
                label = "lateral" if axis == "y" else "vertical"
                ax.plot(*_envelope(x, ts[col]), color=colour, lw=0.8, label=label)
        c = comfort.get(p) or {}
        parts = []
        if c.get("N_MV") is not None:
            parts.append(f"N_MV {c['N_MV']:.2f}")
        if c.get("sperling_lateral_Wz") is not None:
            parts.append(f"Wz lateral {c['sperling_lateral_Wz']:.2f}")
        if c.get("sperling_vertical_Wz") is not None:
            parts.append(f"Wz vertical {c['sperling_vertical_Wz']:.2f}")
        _shade_outside_window(ax, summary, x)
        name = p.replace("_", " ")
        _finish_axes(
            ax, xlabel, "acceleration [m/s^2]", f"{name}: {', '.join(parts)}" if parts else name
        )
    _suptitle(fig, f"{prefix}accelerations and ride comfort (EN 12299 N_MV, Sperling Wz)")
    _deduplicate_legends(fig)
    return fig
