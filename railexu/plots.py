"""Plots: matplotlib figures, saved as PNG and SVG, with units on every axis.

Figures are built with :class:`matplotlib.figure.Figure` directly (no pyplot state), so they work
on any backend, in threads and in worker processes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

if TYPE_CHECKING:
    from .contact.check import ContactCheckResult

SIDES = ("left", "right")


def save_figure(fig: Figure, stem: str | Path, dpi: int = 130) -> list[Path]:
    """Save ``fig`` as ``stem.png`` and ``stem.svg``; returns both paths."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".png"), stem.with_suffix(".svg")]
    fig.savefig(paths[0], dpi=dpi)
    fig.savefig(paths[1])
    return paths


def _colour_for(values: np.ndarray):
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    lo, hi = float(np.min(values)), float(np.max(values))
    span = hi - lo if hi > lo else 1.0
    return lambda v: cmap((v - lo) / span)


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

if TYPE_CHECKING:
    from .results import TimeSeries

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
    from .results import MIN_LOAD_FRACTION, SAFETY_WINDOW_M, sliding_mean, y_over_q

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

_RESULT_SUFFIX_UNITS = (
    ("_m_per_s2", "m/s^2"),
    ("_m_per_s", "m/s"),
    ("_N_s_per_m", "N s/m"),
    ("_N_per_m", "N/m"),
    ("_Hz", "Hz"),
    ("_rad", "rad"),
    ("_kg", "kg"),
    ("_Pa", "Pa"),
    ("_N", "N"),
    ("_m", "m"),
    ("_s", "s"),
)
_MAX_LEGEND_GROUPS = 10


def result_unit(path: str) -> str:
    """The SI unit a result path states by its suffix (``hunting.wavelength_m`` -> ``"m"``,
    ``linear_m_per_s`` -> ``"m/s"``, ``max_abs_lateral_force_N`` -> ``"N"``), else ``""``."""
    last = path.rsplit(".", 1)[-1]
    for suffix, unit in _RESULT_SUFFIX_UNITS:
        if last.endswith(suffix):
            return unit
    return ""


def _study_number(text: object) -> float:
    """A results.csv cell as a number: ``true``/``false`` as 1/0, empty or text as NaN."""
    s = str(text if text is not None else "").strip().lower()
    if s == "true":
        return 1.0
    if s == "false":
        return 0.0
    try:
        return float(s)
    except ValueError:
        return float("nan")


def _is_number_cell(text: str) -> bool:
    s = text.strip().lower()
    if s in ("true", "false"):
        return True
    try:
        float(s)
    except ValueError:
        return False
    return True


def _slug(text: str) -> str:
    import re

    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_") or "value"


def _short_path(path: str, limit: int = 28) -> str:
    if len(path) <= limit:
        return path
    return "..." + ".".join(path.split(".")[-2:])


def _labelled(path: str, unit: str) -> str:
    return f"{path} [{unit}]" if unit else path


if TYPE_CHECKING:
    from collections.abc import Iterable, Mapping
    from typing import Any


def study_figures(table: str | Path | Iterable[Mapping[str, str]], study: Any) -> dict[str, Figure]:
    """Figures of a parameter study's results (``railexu study``), in SI units.

    - ``"study_vs_<parameter>"``, one per varied parameter: every numeric collected result
      against the parameter (one subplot per result). With other varied parameters, one line
      per combination of their values. Booleans are drawn as 0/1; derailed or diverged cases
      are marked with a cross; failed cases have no value.
    - ``"study_map_<result>"``, one per numeric result when exactly two parameters vary: the
      result over the two parameters, as a ``pcolormesh`` when the cases fill a grid (a
      product study), else as coloured points, with a colour bar.

    Parameter axes use the ``<path>_si`` column of a quantity and the parameter's SI unit;
    result axes state the unit their path ends with (``_m``, ``_N``, ``_m_per_s``, ...).
    Parameters with text values are drawn at equally spaced positions, labelled by value.

    Args:
        table: the path of a ``results.csv``, or its rows (column -> text, as
            :func:`railexu.study.read_results` returns them).
        study: a :class:`railexu.study.Study` or the content of ``study.json`` (a mapping).

    Returns:
        Figures by name (empty if there are no rows or no numeric results).
    """
    meta = study.to_dict() if hasattr(study, "to_dict") else dict(study)
    if isinstance(table, str | Path):
        from .study import read_results

        rows = read_results(table)
    else:
        rows = [dict(r) for r in table]
    rows.sort(key=lambda r: str(r.get("case_id", "")))
    params = list(meta.get("parameters") or [])
    collect = list(meta.get("collect") or [])
    if not rows or not params:
        return {}
    title = meta.get("name") or "study"
    statuses = [r.get("status", "") for r in rows]
    marked = np.array([s in ("derailed", "diverged") for s in statuses])

    # parameter axes: SI numbers, or positions of text values
    axis: dict[str, tuple[np.ndarray, list[str] | None, str]] = {}
    for p in params:
        path = p["path"]
        si_col = f"{path}_si"
        cells = [str(r.get(si_col if si_col in r else path, "")) for r in rows]
        nums = np.array([_study_number(c) for c in cells])
        unit = p.get("unit") or ""
        if cells and np.all(np.isfinite(nums)):
            axis[path] = (nums, None, _labelled(path, unit))
        else:
            written = [str(v) if not isinstance(v, bool) else str(v).lower()
                       for v in p.get("values", [])]  # fmt: skip
            labels = list(dict.fromkeys([*written, *(str(r.get(path, "")) for r in rows)]))
            labels = [v for v in labels if any(str(r.get(path, "")) == v for r in rows)]
            pos = np.array([labels.index(str(r.get(path, ""))) for r in rows], dtype=float)
            axis[path] = (pos, labels, path)

    # numeric results
    results: dict[str, tuple[np.ndarray, str]] = {}
    for name in collect:
        cells = [str(r.get(name, "")) for r in rows]
        filled = [c for c in cells if c.strip()]
        if not filled or not all(_is_number_cell(c) for c in filled):
            continue
        values = np.array([_study_number(c) for c in cells])
        if not np.any(np.isfinite(values)):
            continue
        label = _labelled(name, result_unit(name))
        if all(c.strip().lower() in ("true", "false") for c in filled):
            label += " (1 = true)"
        results[name] = (values, label)
    if not results:
        return {}

    figs: dict[str, Figure] = {}

    def add(name: str, fig: Figure) -> None:
        key, k = name, 2
        while key in figs:
            key, k = f"{name}_{k}", k + 1
        figs[key] = fig

    def set_ticks(ax, which: str, labels: list[str] | None) -> None:
        if labels is None:
            return
        ticks = list(range(len(labels)))
        if which == "x":
            ax.set_xticks(ticks, labels)
        else:
            ax.set_yticks(ticks, labels)

    import contextlib

    from matplotlib import colormaps

    # 1. every result against every parameter
    for p in params:
        path = p["path"]
        x, labels, xlabel = axis[path]
        others = [q["path"] for q in params if q["path"] != path]
        groups: dict[tuple, list[int]] = {}
        for i, r in enumerate(rows):
            groups.setdefault(tuple(str(r.get(o, "")) for o in others), []).append(i)
        legend = 1 < len(groups) <= _MAX_LEGEND_GROUPS
        cmap = colormaps["tab10" if len(groups) <= _MAX_LEGEND_GROUPS else "viridis"]
        n = len(results)
        height = 1.3 + 2.5 * n
        fig = Figure(figsize=(8.5, height), layout="constrained")
        axes = np.atleast_1d(fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0])
        for ax, (name, (y, ylabel)) in zip(axes, results.items(), strict=True):
            for g, (key, idx) in enumerate(groups.items()):
                idx = sorted(idx, key=lambda i: x[i])
                if len(groups) <= _MAX_LEGEND_GROUPS:
                    colour = cmap(g % 10)
                else:
                    colour = cmap(g / max(1, len(groups) - 1))
                text = ", ".join(
                    f"{_short_path(o)} = {v}" for o, v in zip(others, key, strict=True)
                )
                has_data = bool(np.any(np.isfinite(y[idx])))
                ax.plot(x[idx], y[idx], "o-", ms=4, lw=1.2, color=colour,
                        label=text if legend and has_data else None)  # fmt: skip
            bad = marked & np.isfinite(y)
            if bad.any():
                ax.plot(x[bad], y[bad], "x", color="k", ms=8, mew=1.5, label="derailed/diverged")
            # the result's path as the subplot title, its unit on the axis (long paths do not
            # fit along a short axis)
            ax.set_title(ylabel, fontsize="small", loc="left")
            unit = result_unit(name)
            ax.set_ylabel("0 / 1" if ylabel.endswith("(1 = true)") else f"[{unit or '-'}]")
            with contextlib.suppress(AttributeError):  # only for the default formatter
                ax.ticklabel_format(axis="y", useOffset=False)
            ax.grid(True, alpha=0.4)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize="x-small", loc="best")
        axes[-1].set_xlabel(xlabel)
        set_ticks(axes[-1], "x", labels)
        note = "" if legend or len(groups) == 1 else f" ({len(groups)} lines, dark to light)"
        fig.suptitle(f"{title}: results against {path}{note}", fontsize="medium")
        add(f"study_vs_{_slug(path)}", fig)

    # 2. maps over two parameters
    if len(params) == 2:
        px, py = params[0]["path"], params[1]["path"]
        x, xlabels, xlabel = axis[px]
        y, ylabels, ylabel = axis[py]
        xu, yu = np.unique(x), np.unique(y)
        pairs = set(zip(x.tolist(), y.tolist(), strict=True))
        grid = len(xu) >= 2 and len(yu) >= 2 and len(pairs) == len(xu) * len(yu)
        for name, (z, zlabel) in results.items():
            fig = Figure(figsize=(8, 5.8), layout="constrained")
            ax = fig.subplots()
            if grid:
                Z = np.full((len(yu), len(xu)), np.nan)
                Z[np.searchsorted(yu, y), np.searchsorted(xu, x)] = z
                mappable = ax.pcolormesh(
                    xu, yu, np.ma.masked_invalid(Z), shading="nearest", cmap="viridis"
                )
                ax.plot(x, y, ".", color="k", alpha=0.5, ms=3)
                missing = ~np.isfinite(z)
                if missing.any():
                    ax.plot(x[missing], y[missing], "s", mfc="none", color="0.5", ms=8,
                            label="no value (failed)")  # fmt: skip
            else:
                ok = np.isfinite(z)
                mappable = ax.scatter(x[ok], y[ok], c=z[ok], cmap="viridis", s=70, edgecolors="k")
                if (~ok).any():
                    ax.plot(x[~ok], y[~ok], "s", mfc="none", color="0.5", label="no value")
            bad = marked & np.isfinite(z)
            if bad.any():
                ax.plot(x[bad], y[bad], "x", color="r", ms=9, mew=2, label="derailed/diverged")
            fig.colorbar(mappable, ax=ax, label=zlabel)
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            set_ticks(ax, "x", xlabels)
            set_ticks(ax, "y", ylabels)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize="small", loc="best")
            ax.set_title(f"{title}: {name}", fontsize="medium")
            add(f"study_map_{_slug(name)}", fig)
    return figs
