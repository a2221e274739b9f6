"""Figures of a parameter study: each result against the varied values."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

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
        import csv

        with Path(table).open(newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
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
