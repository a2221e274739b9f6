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


#: SI unit -> (factor, engineering unit) for the axes of study figures.
_ENGINEERING = {
    "m/s": (3.6, "km/h"),
    "N": (1e-3, "kN"),
    "N/m": (1e-6, "MN/m"),
    "N s/m": (1e-3, "kN s/m"),
    "Pa": (1e-6, "MPa"),
    "kg": (1e-3, "t"),
}


def engineering_unit(unit: str, values: np.ndarray) -> tuple[float, str]:
    """The factor from SI to the engineering unit of an axis, and that unit: km/h, kN, MN/m,
    kN s/m, MPa, t; lengths in mm and angles in mrad when every value is below 0.5 m (0.1 rad),
    else m (rad); other units as they are."""
    if unit in _ENGINEERING:
        return _ENGINEERING[unit]
    finite = np.abs(values[np.isfinite(values)]) if values.size else values
    largest = float(np.max(finite)) if finite.size else 0.0
    if unit == "m" and largest < 0.5:
        return 1e3, "mm"
    if unit == "rad" and largest < 0.1:
        return 1e3, "mrad"
    return 1.0, unit


def readable(path: str) -> str:
    """A title from a result or parameter path: dots and underscores as spaces, the unit
    suffix left out (``max_abs_lateral_force_N`` -> ``max abs lateral force``,
    ``hunting.wavelength_m`` -> ``hunting wavelength``)."""
    parts = path.split(".")
    last = parts[-1]
    for suffix, _ in _RESULT_SUFFIX_UNITS:
        if last.endswith(suffix) and len(last) > len(suffix):
            last = last[: -len(suffix)]
            break
    return " ".join(p.replace("_", " ").strip() for p in [*parts[:-1], last])


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


class _Result:
    """A collected result in engineering units: values, title, unit, whether boolean."""

    def __init__(self, name: str, values: np.ndarray, boolean: bool) -> None:
        self.name = name
        self.boolean = boolean
        factor, unit = (1.0, "") if boolean else engineering_unit(result_unit(name), values)
        self.values = values * factor
        self.unit = unit
        self.title = readable(name) + (" (true / false)" if boolean else "")

    @property
    def ylabel(self) -> str:
        return "" if self.boolean else f"[{self.unit or '-'}]"


def _parameter_axes(params, rows) -> dict[str, tuple[np.ndarray, list[str] | None, str]]:
    """Per parameter: positions (engineering units, or indices of text values), the text
    labels (None for numbers) and the axis label."""
    axis: dict[str, tuple[np.ndarray, list[str] | None, str]] = {}
    for p in params:
        path = p["path"]
        si_col = f"{path}_si"
        cells = [str(r.get(si_col if si_col in r else path, "")) for r in rows]
        nums = np.array([_study_number(c) for c in cells])
        if cells and np.all(np.isfinite(nums)):
            factor, unit = engineering_unit(p.get("unit") or "", nums)
            axis[path] = (
                nums * factor,
                None,
                f"{readable(path)} [{unit}]" if unit else readable(path),
            )
            continue
        written = [str(v) if not isinstance(v, bool) else str(v).lower()
                   for v in p.get("values", [])]  # fmt: skip
        labels = list(dict.fromkeys([*written, *(str(r.get(path, "")) for r in rows)]))
        labels = [v for v in labels if any(str(r.get(path, "")) == v for r in rows)]
        pos = np.array([labels.index(str(r.get(path, ""))) for r in rows], dtype=float)
        axis[path] = (pos, labels, readable(path))
    return axis


def _collected(collect, rows) -> dict[str, _Result]:
    results: dict[str, _Result] = {}
    for name in collect:
        cells = [str(r.get(name, "")) for r in rows]
        filled = [c for c in cells if c.strip()]
        if not filled or not all(_is_number_cell(c) for c in filled):
            continue
        values = np.array([_study_number(c) for c in cells])
        if not np.any(np.isfinite(values)):
            continue
        boolean = all(c.strip().lower() in ("true", "false") for c in filled)
        results[name] = _Result(name, values, boolean)
    return results


def _boolean_markers(ax, x, y, colour, label=None) -> None:
    """True as a filled marker at 1, false as an open one at 0 (no line, no colour map)."""
    yes, no = y == 1.0, y == 0.0
    ax.plot(x[yes], y[yes], "o", ms=8, color=colour, label=label)
    ax.plot(x[no], y[no], "o", ms=8, mfc="none", color=colour)
    ax.set_yticks([0, 1], ["false", "true"])
    ax.set_ylim(-0.4, 1.4)


def study_figures(table: str | Path | Iterable[Mapping[str, str]], study: Any) -> dict[str, Figure]:
    """Figures of a parameter study's results (``railexu study``), in engineering units.

    - ``"study_vs_<parameter>"``, one per varied parameter: every numeric collected result
      against the parameter (one subplot per result, titled by the result's name in words).
      With other varied parameters, one line per combination of their values. Boolean results
      are markers (filled = true, open = false), not lines; derailed or diverged cases are
      marked with a cross; failed cases have no value.
    - ``"study_map_<result>"``, one per numeric result when exactly two parameters vary: the
      result over the two parameters, as a ``pcolormesh`` with each cell's value written in it
      when the cases fill a grid (a product study), else as coloured points labelled with their
      values; a boolean result as filled / open markers instead of colours.

    Units: the SI values are shown in engineering units (km/h, kN, MN/m, kN s/m, MPa, t; mm and
    mrad for small lengths and angles), the unit taken from the parameter's SI unit and from the
    suffix of the result's path (``_m``, ``_N``, ``_m_per_s``, ...). Parameters with text values
    are drawn at equally spaced positions, labelled by value.

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
    if not rows or not params:
        return {}
    results = _collected(list(meta.get("collect") or []), rows)
    if not results:
        return {}
    title = meta.get("name") or "study"
    marked = np.array([r.get("status", "") in ("derailed", "diverged") for r in rows])
    axis = _parameter_axes(params, rows)
    figs: dict[str, Figure] = {}

    def add(name: str, fig: Figure) -> None:
        key, k = name, 2
        while key in figs:
            key, k = f"{name}_{k}", k + 1
        figs[key] = fig

    for p in params:
        add(f"study_vs_{_slug(p['path'])}",
            _against_figure(p["path"], params, rows, axis, results, marked, title))  # fmt: skip
    if len(params) == 2:
        for name, result in results.items():
            add(f"study_map_{_slug(name)}", _map_figure(params, axis, result, marked, title))
    return figs


def _set_ticks(ax, which: str, labels: list[str] | None) -> None:
    if labels is None:
        return
    ticks = list(range(len(labels)))
    if which == "x":
        ax.set_xticks(ticks, labels)
    else:
        ax.set_yticks(ticks, labels)


def _against_figure(path, params, rows, axis, results, marked, title) -> Figure:
    import contextlib

    from matplotlib import colormaps

    x, labels, xlabel = axis[path]
    others = [q["path"] for q in params if q["path"] != path]
    groups: dict[tuple, list[int]] = {}
    for i, r in enumerate(rows):
        groups.setdefault(tuple(str(r.get(o, "")) for o in others), []).append(i)
    legend = 1 < len(groups) <= _MAX_LEGEND_GROUPS
    cmap = colormaps["tab10" if len(groups) <= _MAX_LEGEND_GROUPS else "viridis"]
    n = len(results)
    fig = Figure(figsize=(8.5, 1.3 + 2.5 * n), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0])
    for ax, result in zip(axes, results.values(), strict=True):
        y = result.values
        for g, (key, idx) in enumerate(groups.items()):
            idx = np.array(sorted(idx, key=lambda i: x[i]))
            small = len(groups) <= _MAX_LEGEND_GROUPS
            colour = cmap(g % 10) if small else cmap(g / max(1, len(groups) - 1))
            text = ", ".join(f"{_short_path(o)} = {v}" for o, v in zip(others, key, strict=True))
            label = text if legend and np.any(np.isfinite(y[idx])) else None
            if result.boolean:
                _boolean_markers(ax, x[idx], y[idx], colour, label)
            else:
                ax.plot(x[idx], y[idx], "o-", ms=4, lw=1.2, color=colour, label=label)
        bad = marked & np.isfinite(y)
        if bad.any():
            ax.plot(x[bad], y[bad], "x", color="k", ms=8, mew=1.5, label="derailed/diverged")
        ax.set_title(result.title, fontsize="small", loc="left")
        ax.set_ylabel(result.ylabel)
        if not result.boolean:
            with contextlib.suppress(AttributeError):  # only for the default formatter
                ax.ticklabel_format(axis="y", useOffset=False)
        ax.grid(True, alpha=0.4)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize="x-small", loc="best")
    axes[-1].set_xlabel(xlabel)
    _set_ticks(axes[-1], "x", labels)
    note = "" if legend or len(groups) == 1 else f" ({len(groups)} lines, dark to light)"
    fig.suptitle(f"{title}: results against {readable(path)}{note}", fontsize="medium")
    return fig


def _map_figure(params, axis, result: _Result, marked, title) -> Figure:
    px, py = params[0]["path"], params[1]["path"]
    x, xlabels, xlabel = axis[px]
    y, ylabels, ylabel = axis[py]
    z = result.values
    fig = Figure(figsize=(8, 5.8), layout="constrained")
    ax = fig.subplots()
    xu, yu = np.unique(x), np.unique(y)
    pairs = set(zip(x.tolist(), y.tolist(), strict=True))
    grid = len(xu) >= 2 and len(yu) >= 2 and len(pairs) == len(xu) * len(yu)
    ok = np.isfinite(z)
    if result.boolean:
        yes, no = ok & (z == 1.0), ok & (z == 0.0)
        ax.plot(x[yes], y[yes], "o", ms=12, color="tab:red", label="true")
        ax.plot(x[no], y[no], "o", ms=12, mfc="none", color="tab:blue", label="false")
    elif grid:
        Z = np.full((len(yu), len(xu)), np.nan)
        Z[np.searchsorted(yu, y), np.searchsorted(xu, x)] = z
        mappable = ax.pcolormesh(xu, yu, np.ma.masked_invalid(Z), shading="nearest",
                                 cmap="viridis")  # fmt: skip
        fig.colorbar(mappable, ax=ax, label=f"{result.title} {result.ylabel}")
    else:
        mappable = ax.scatter(x[ok], y[ok], c=z[ok], cmap="viridis", s=70, edgecolors="k")
        fig.colorbar(mappable, ax=ax, label=f"{result.title} {result.ylabel}")
    if not result.boolean:
        for xi, yi, zi in zip(x[ok], y[ok], z[ok], strict=True):
            ax.annotate(f"{zi:.3g}", (xi, yi), xytext=(0, 7), textcoords="offset points",
                        ha="center", fontsize="small",
                        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.7,
                              "lw": 0})  # fmt: skip
    if (~ok).any():
        ax.plot(x[~ok], y[~ok], "s", mfc="none", color="0.5", ms=8, label="no value (failed)")
    bad = marked & ok
    if bad.any():
        ax.plot(x[bad], y[bad], "x", color="r", ms=9, mew=2, label="derailed/diverged")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    _set_ticks(ax, "x", xlabels)
    _set_ticks(ax, "y", ylabels)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize="small", loc="best")
    unit = f" [{result.unit}]" if result.unit else ""
    ax.set_title(f"{title}: {result.title}{unit}", fontsize="medium")
    return fig
