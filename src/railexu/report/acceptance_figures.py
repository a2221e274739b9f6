"""Figures of an acceptance (``railexu acceptance``): per test zone, each criterion's section
values with the zone's statistical estimate and the limit, as EN 14363:2016's evaluation of the
test zones plots them.

Curve zones evaluated two-dimensionally show the section values against the zone's first
regressor (cant deficiency in mm, or curvature in 1/km) with the regression line (the other
regressor at its mean) and the estimate at the zone's limit conditions; straight zones and
one-dimensional evaluations show the values per section with the mean and ``mean + k s``. The
figures read ``acceptance.json``'s mapping only (no study or simulation import).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from railexu.report.figures import new_figure, save_figure

#: per quantity: axis label and the factor from SI to the unit shown
SHOWN = {
    "N": ("kN", 1.0e-3),
    "m/s^2": ("m/s$^2$", 1.0),
    "1": ("-", 1.0),
}
REGRESSOR_AXES = {
    "cant_deficiency": ("cant deficiency [mm]", "cant_deficiency_m", 1.0e3),
    "curvature": ("curvature [1/km]", "radius_m", None),
}
COLUMNS = 3
#: characters of the 10 pt title per inch of the figure's width (a wide character is about
#: 0.6 of the font size, 6 pt, so 12 per inch; 10 leaves a margin)
TITLE_CHARS_PER_INCH = 10


def draw_acceptance_figures(data: dict, folder: Path) -> list[Path]:
    """One PNG per zone with one panel per criterion that has section values; returns the
    files."""
    files: list[Path] = []
    for name, zone in data.get("zones", {}).items():
        criteria = {k: c for k, c in zone.get("criteria", {}).items() if c.get("sections")}
        if not criteria or not zone.get("sections"):
            continue
        files += save_figure(_zone_figure(name, zone, criteria, data), folder / f"zone_{name}",
                             formats=("png",))  # fmt: skip
    return files


def _zone_figure(name: str, zone: dict, criteria: dict, data: dict):
    n = len(criteria)
    rows = math.ceil(n / COLUMNS)
    fig = new_figure(figsize=(4.2 * COLUMNS, 3.2 * rows + 0.8), layout="constrained")
    quick = " (quick programme: a trend, not an acceptance verdict)" if (
        data.get("programme", {}).get("quick")) else ""  # fmt: skip
    title = (f"{data.get('vehicle', {}).get('name', '')}: zone {name}, "
             f"{zone.get('method', '').replace('_', '-')}{quick}")  # fmt: skip
    # wrapped to the figure's width, so that a long vehicle name stays inside the figure
    fig.suptitle(textwrap.fill(title, width=int(TITLE_CHARS_PER_INCH * 4.2 * COLUMNS)),
                 fontsize=10)  # fmt: skip
    axes = fig.subplots(rows, COLUMNS, squeeze=False).ravel()
    for ax, (crit, c) in zip(axes, criteria.items(), strict=False):
        _panel(ax, crit, c, zone)
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig


def _panel(ax, crit: str, c: dict, zone: dict) -> None:
    unit, factor = SHOWN.get(c.get("unit", "1"), (c.get("unit", ""), 1.0))
    sections = {s["section"]: s for s in zone["sections"]}
    used = [sections[s] for s in c["sections"] if s in sections]
    y = [s["values"].get(crit) for s in used]
    details = c.get("details", {})
    regressors = zone.get("conditions", {}).get("regressors") or []
    two_d = c.get("method") == "two_dimensional" and regressors
    if two_d:
        label, key, scale = REGRESSOR_AXES[regressors[0]]
        x = [_regressor(s, key, scale) for s in used]
    else:
        label = "section"
        x = list(range(1, len(used) + 1))
    pts = [(a, b * factor) for a, b in zip(x, y, strict=True) if a is not None and b is not None]
    if pts:
        ax.plot(*zip(*pts, strict=True), "o", ms=4, color="tab:blue", label="sections")
    if two_d and "coefficients" in details and pts:
        _regression_line(ax, details, regressors, [p[0] for p in pts], scale, factor,
                         used)  # fmt: skip
    elif "mean" in details:
        ax.axhline(details["mean"] * factor, color="tab:blue", lw=0.8, ls=":", label="mean")
    if c.get("value") is not None:
        what = "largest" if c.get("method") == "largest_section_value" else "estimate"
        ax.axhline(c["value"] * factor, color="tab:green", lw=1.2,
                   label=f"{what} {c['value'] * factor:.3g}")  # fmt: skip
    if c.get("limit") is not None:
        ax.axhline(c["limit"] * factor, color="tab:red", lw=1.2, ls="--",
                   label=f"limit {c['limit'] * factor:.3g}")  # fmt: skip
    verdict = {True: "pass", False: "FAIL", None: "-"}[c.get("pass")]
    if c.get("pass") is None and details.get("within_limit") is not None:
        verdict = "informative"  # the other measuring method's criterion: not judged
    ax.set_title(f"{crit}: {verdict}", fontsize=9)
    ax.set_xlabel(label, fontsize=8)
    ax.set_ylabel(f"{crit} [{unit}]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, loc="best")


def _regressor(section: dict, key: str, scale: float | None) -> float | None:
    value = section.get("conditions", {}).get(key)
    if value is None:
        return None
    if scale is None:  # curvature from the radius, 1/km
        return 1.0e3 / float(value) if value else 0.0
    return float(value) * scale


def _regression_line(ax, details, regressors, xs, scale, factor, used) -> None:
    coef = details["coefficients"]
    lo, hi = min(xs), max(xs)
    at = details.get("at") or []
    if at:  # extend the line to the evaluation point
        x0 = at[0] * (scale if scale is not None else 1.0e3)
        lo, hi = min(lo, x0), max(hi, x0)
    others = 0.0
    if len(coef) > 2:  # the second regressor at its mean over the sections
        label, key, sc = REGRESSOR_AXES[regressors[1]]
        vals = [_regressor(s, key, sc) for s in used]
        vals = [v for v in vals if v is not None]
        si = 1.0 / (sc if sc is not None else 1.0e3)
        others = coef[2] * (sum(vals) / len(vals)) * si if vals else 0.0
    si_x = 1.0 / (scale if scale is not None else 1.0e3)
    line_x = [lo, hi]
    line_y = [(coef[0] + coef[1] * v * si_x + others) * factor for v in line_x]
    ax.plot(line_x, line_y, color="tab:blue", lw=1.0, label="regression")
