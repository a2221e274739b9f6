"""A self-contained ``report.html`` for a run folder or a study folder.

The page needs no network and no other file: figures are PNG images embedded as base64 data,
the animations (``contact.gif``, ``plan.gif`` or their MP4s) likewise, the case table of a study
sorts with a few lines of inline JavaScript. It opens from the file system in any browser.

- **Run** (``timeseries.csv``, ``summary.json``, ``state.npz``): vehicle and track with the
  SHA-256 of their files, the settings, the status, the key results with the limits they are
  held against (Nadal's Y/Q, EN 14363's sum of Y), an assessment table when the summary holds
  one, the animations when present and the figures of ``railexu plot``.
- **Study** (``study.json``, ``results.csv``, ``cases/<id>/``): the table of cases (values,
  results, status; click a heading to sort), the study figures and a link to each case's own
  report, which is written too.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from railexu.errors import InputError
from railexu.report.state_file import STATE_FILE, file_sha256

REPORT_FILE = "report.html"
ANIMATIONS = ("contact", "plan")

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:1.5em auto;max-width:1100px;
padding:0 1em;color:#222}
h1{font-size:1.5em;margin-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid
#ccc}
table{border-collapse:collapse;margin:.5em 0;font-size:.92em}
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:left;vertical-align:top}
th{background:#f0f3f7}td.num{text-align:right;font-variant-numeric:tabular-nums}
.pass{color:#17692b;font-weight:600}.fail{color:#b00020;font-weight:600}
.status{display:inline-block;padding:.1em .6em;border-radius:.3em;color:#fff}
.completed{background:#17692b}.derailed,.diverged,.failed,.interrupted{background:#b00020}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:.9em;color:#555}code{font-size:.9em}.foot{color:#777;font-size:.85em}
table.sortable th{cursor:pointer}table.sortable th:after{content:" \\2195";color:#999}
"""

_SORT_JS = """
document.querySelectorAll("table.sortable").forEach(function (table) {
  table.querySelectorAll("th").forEach(function (th, col) {
    th.addEventListener("click", function () {
      var body = table.tBodies[0], rows = Array.prototype.slice.call(body.rows);
      var dir = th.dataset.dir === "asc" ? -1 : 1; th.dataset.dir = dir > 0 ? "asc" : "desc";
      rows.sort(function (a, b) {
        var x = a.cells[col].dataset.v || a.cells[col].textContent;
        var y = b.cells[col].dataset.v || b.cells[col].textContent;
        var nx = parseFloat(x), ny = parseFloat(y);
        if (!isNaN(nx) && !isNaN(ny)) return dir * (nx - ny);
        return dir * x.localeCompare(y);
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
});
"""


def _e(text: object) -> str:
    return html.escape(str(text), quote=True)


def figure_png_base64(fig: Figure, dpi: int = 100) -> str:
    """A figure as base64 PNG data."""
    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    # "tight": titles and labels inside the picture (a suptitle wider than the axes was cut)
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _img(data_b64: str, alt: str, caption: str = "", mime: str = "image/png") -> str:
    cap = f"<figcaption>{_e(caption)}</figcaption>" if caption else ""
    return f'<figure><img alt="{_e(alt)}" src="data:{mime};base64,{data_b64}">{cap}</figure>'


def _table(rows: list[tuple], header: tuple | None = None, cls: str = "") -> str:
    out = [f'<table class="{cls}">' if cls else "<table>"]
    if header:
        out.append("<thead><tr>" + "".join(f"<th>{_e(h)}</th>" for h in header) + "</tr></thead>")
    out.append("<tbody>")
    for row in rows:
        out.append("<tr>" + "".join(_cell(c) for c in row) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)


class Raw(str):
    """HTML that goes into a table cell as it is."""


def _cell(value: object) -> str:
    if isinstance(value, Raw):
        return f"<td>{value}</td>"
    if isinstance(value, bool):
        return f"<td>{'yes' if value else 'no'}</td>"
    if isinstance(value, int | float):
        return f'<td class="num" data-v="{value!r}">{_e(_fmt(value))}</td>'
    return f"<td>{_e(value)}</td>"


def _fmt(value: float) -> str:
    if isinstance(value, int):
        return str(value)
    return f"{value:.6g}"


def _verdict(ok: bool) -> Raw:
    return Raw('<span class="pass">pass</span>' if ok else '<span class="fail">fail</span>')


def _page(title: str, body: list[str]) -> str:
    import datetime

    from railexu.version import __version__

    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    body = [*body, f'<p class="foot">Written {when} by railexu {_e(__version__)} '
            "(railexu report).</p>"]  # fmt: skip
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f"<title>{_e(title)}</title><link rel=\"icon\" href=\"data:,\">"
        f"<style>{_CSS}</style></head><body>\n" + "\n".join(body)
        + f"\n<script>{_SORT_JS}</script>\n</body></html>\n"
    )  # fmt: skip


# ----------------------------------------------------------------------------------------------
# run
# ----------------------------------------------------------------------------------------------


def run_report_html(folder: str | Path, figures: bool = True) -> str:
    """The HTML text of a run folder's report.

    Raises:
        InputError: the folder holds no ``summary.json``; it is incomplete or damaged
            (:func:`railexu.report.run_folder.read_run_summary`).
    """
    from railexu.report.run_folder import TIMESERIES, read_run_summary
    from railexu.results import TimeSeries

    folder = Path(folder)
    if not (folder / "summary.json").is_file():
        raise InputError(f"{folder}: no summary.json (not an output folder of railexu run)")
    summary = read_run_summary(folder, ("summary.json", TIMESERIES, STATE_FILE))
    meta = _state_meta(folder)
    status = summary.get("status", {})
    state = str(status.get("state", "unknown"))
    speed = (summary.get("settings") or {}).get("speed_m_per_s")
    title = f"{summary.get('vehicle', '')}" + (f" at {speed:g} m/s" if speed else "")
    body = [
        f"<h1>{_e(title)} on {_e(summary.get('track', ''))}</h1>",
        f'<p>Status: <span class="status {_e(state)}">{_e(state)}</span> at '
        f"{status.get('distance_m', float('nan')):.1f} m"
        + (f" ({_e(status['reason'])})" if status.get("reason") else "")
        + f". Folder: <code>{_e(folder.resolve())}</code></p>",
        "<h2>Inputs</h2>",
        _table(_input_rows(summary, meta), ("input", "name", "file", "SHA-256")),
        "<h2>Settings</h2>",
        _table(_settings_rows(summary), ("setting", "value")),
        "<h2>Results</h2>",
        _table(_result_rows(summary), ("result", "value", "limit", "verdict")),
        "<h2>Solver</h2>",
        _table(_solver_rows(summary), ("solver", "value")),
    ]
    warnings = summary.get("warnings") or []
    if warnings:
        body += ["<h2>Warnings</h2>", "<ul>" + "".join(f"<li>{_e(w)}</li>" for w in warnings)
                 + "</ul>"]  # fmt: skip
    wear = _wear_html(summary.get("wear"))
    if wear:
        body += ["<h2>Wear and rolling contact fatigue</h2>", wear]
    assessment = _assessment_html(summary.get("assessment"))
    if assessment:
        body += ["<h2>Assessment</h2>", assessment]
    comfort = _comfort_html(summary.get("comfort"))
    if comfort:
        body += ["<h2>Ride comfort</h2>", comfort]
    anims = _animations_html(folder)
    if anims:
        body += ["<h2>Animations</h2>", anims]
    if figures and (folder / "timeseries.csv").is_file():
        from railexu.report.run_figures import run_figures

        ts = TimeSeries.from_csv(folder / "timeseries.csv")
        body.append("<h2>Figures</h2>")
        for name, fig in run_figures(ts, summary, title).items():
            body.append(_img(figure_png_base64(fig), name, name.replace("_", " ")))
    return _page(f"railexu run: {title}", body)


def _state_meta(folder: Path) -> dict:
    path = folder / STATE_FILE
    if not path.is_file():
        return {}
    import numpy as np

    try:
        with np.load(path, allow_pickle=False) as z:
            return json.loads(str(z["meta_json"])) if "meta_json" in z.files else {}
    except (OSError, ValueError, KeyError):
        return {}


def _input_rows(summary: dict, meta: dict) -> list[tuple]:
    rows = []
    for what in ("vehicle", "track"):
        path = summary.get(f"{what}_file") or meta.get(f"{what}_file") or ""
        digest = summary.get(f"{what}_sha256") or meta.get(f"{what}_sha256") or ""
        if path and Path(path).is_file():
            now = file_sha256(path)
            if digest and now != digest:
                digest = f"{digest} (the file has changed since the run: now {now})"
            digest = digest or now
        rows.append((what, summary.get(what, ""), path or "(built in)", digest or "-"))
    return rows


def _solver_rows(summary: dict) -> list[tuple]:
    """The solver block of ``summary.json`` (steps, the steps the solver cut, the smallest step;
    docs/performance.md) as settings are shown: names in words, values with their units."""
    return [_setting_row(k, v) for k, v in (summary.get("solver") or {}).items()]


#: the wear block's per-wheel and per-rail columns: (key, heading with its unit)
_WEAR_WHEEL = (
    ("removed_area_per_km_mm2", "removed area [mm²/km]"),
    ("max_depth_per_km_um", "largest depth [µm/km]"),
    ("max_depth_at_mm", "at s [mm]"),
    ("fi_surf_max", "FI_surf max [-]"),
    ("fi_surf_max_at_mm", "at s [mm]"),
    ("wlrm_damage_per_km", "WLRM damage [1/km]"),
)
_WEAR_RAIL = (("removed_area_per_axle_um2", "removed area [µm²/axle]"),
              ("max_depth_per_axle_nm", "largest depth [nm/axle]"),
              ("max_depth_at_mm", "at y [mm]"), ("fi_surf_max", "FI_surf max [-]"),
              ("wlrm_damage_per_axle", "WLRM damage [1/axle]"))  # fmt: skip


def _wear_html(block: dict | None) -> str:
    """The ``wear`` block of a run asked for its wear (docs/wear.md, "Per run"): the law and its
    sources, then one table for the wheels and one for the rails."""
    if not block:
        return ""
    head = (
        f"<p>Law {_e(block.get('law', ''))}, coefficients {_e(block.get('coefficients_file', ''))}"
    )
    if block.get("note"):
        head += f"; {_e(block['note'])}"
    if not block.get("computed", True):
        return head + f"; not computed: {_e(block.get('reason', ''))}</p>"
    window = block.get("window_m") or []
    if window:
        head += f"; window {window[0]:.1f}-{window[1]:.1f} m ({_e(block.get('window_rule', ''))})"
    out = [head + "</p>"]
    for what, cols in (("wheels", _WEAR_WHEEL), ("rails", _WEAR_RAIL)):
        rows = [(f"ws{r.get('wheelset')} {r.get('side')}",
                 *("-" if r.get(k) is None else float(r[k]) for k, _ in cols))
                for r in block.get(what) or []]  # fmt: skip
        if rows:
            out.append(_table(rows, (what[:-1], *(h for _, h in cols))))
    return "".join(out)


def _settings_rows(summary: dict) -> list[tuple]:
    rows = [_setting_row(k, v) for k, v in (summary.get("settings") or {}).items()]
    timings = summary.get("timings_s") or {}
    rows += [(f"time: {k}", float(v)) for k, v in timings.items()]
    return rows


#: a setting's name suffix -> the unit shown (the longest suffix first)
_SETTING_UNITS = (("_m_per_s2", "m/s²"), ("_m_per_s", "m/s"), ("_m", "m"), ("_s", "s"))


def _setting_row(key: str, value: object) -> tuple[str, str]:
    """A setting as a reader takes it: its name in words, its value with its unit (``speed``,
    ``10 m/s``), ``default`` for an unset value, text without JSON quoting."""
    name, unit = key, ""
    for suffix, shown in _SETTING_UNITS:
        if key.endswith(suffix):
            name, unit = key[: -len(suffix)], shown
            break
    name = name.replace("_", " ")
    if value is None:
        return (name, "none" if key == "wear_law" else "default (not set)")
    if isinstance(value, bool):
        return (name, "yes" if value else "no")
    if isinstance(value, int | float):
        return (name, f"{value:.6g} {unit}".strip())
    if isinstance(value, str):
        return (name, value.replace("_", "-") if key == "solver" else value)
    if isinstance(value, dict):
        return (name, "; ".join(f"{k}: {_setting_row(str(k), v)[1]}" for k, v in value.items()))
    if isinstance(value, list | tuple):
        return (name, ", ".join(str(_setting_row("", v)[1]) for v in value))
    return (name, str(value))


def _result_rows(summary: dict) -> list[tuple]:
    rows: list[tuple] = []
    if summary.get("realtime_factor") is not None:
        rows.append(("real-time factor [-]", float(summary["realtime_factor"]), "", ""))
    for ws in summary.get("wheelsets", []):
        rows.append((f"{ws['name']}: max |lateral| [mm]", ws["max_abs_lateral_m"] * 1e3, "", ""))
        rows.append((f"{ws['name']}: final amplitude [mm]", ws["final_amplitude_m"] * 1e3, "", ""))
    fc = summary.get("flange_contact") or {}
    rows.append(("flange contact", bool(fc.get("occurred")), "", ""))
    if fc.get("occurred"):
        rows.append(("first flange contact at [m]", float(fc["first_distance_m"]), "", ""))
    h = summary.get("hunting") or {}
    rows.append(("hunting", bool(h.get("detected")), "", ""))
    if h.get("detected"):
        rows.append(("hunting wavelength [m]", float(h["wavelength_m"]), "", ""))
        rows.append(("hunting frequency [Hz]", float(h["frequency_Hz"]), "", ""))
    if "max_abs_lateral_force_N" in summary:
        rows.append(("max |Y|, raw samples [kN]", summary["max_abs_lateral_force_N"] / 1e3, "", ""))
    yq = summary.get("max_Y_over_Q") or {}
    if "pass" in yq and yq.get("value_en14363") is not None:  # the assessment's EN 14363 form
        rows.append(("max Y/Q (EN 14363) [-]", float(yq["value_en14363"]),
                     _or_blank(yq.get("limit")), _verdict(bool(yq["pass"]))))  # fmt: skip
    elif yq.get("value") is not None:
        limit = yq.get("nadal_limit")
        value = yq.get("value_2m")
        value = yq["value"] if value is None else value
        rows.append(("max Y/Q (2 m mean) [-]", float(value), limit if limit else "",
                     _verdict(value <= limit) if limit else ""))  # fmt: skip
    if yq.get("nadal_limit") is not None and "pass" in yq:
        rows.append(("Nadal's flange-climb limit [-]", float(yq["nadal_limit"]), "", ""))
    sy = summary.get("max_sum_Y_N") or {}
    if sy.get("value") is not None:
        limit = sy.get("limit_N")
        ok = bool(sy["pass"]) if "pass" in sy else (sy["value"] <= limit if limit else None)
        rows.append(("max sum Y (2 m mean) [kN]", sy["value"] / 1e3,
                     limit / 1e3 if limit else "", "" if ok is None else _verdict(ok)))  # fmt: skip
    rs = summary.get("running_stability") or {}
    if rs.get("rms_sum_Y_N") is not None:
        limit = rs.get("limit_N")
        ok = bool(rs["pass"]) if "pass" in rs else (rs["rms_sum_Y_N"] <= limit if limit else None)
        rows.append(("running stability, rms sum Y [kN]", rs["rms_sum_Y_N"] / 1e3,
                     limit / 1e3 if limit else "", "" if ok is None else _verdict(ok)))  # fmt: skip
    return rows


def _or_blank(value: object) -> object:
    return "" if value is None else value


#: the columns of a criterion of the assessment, in this order (the rest are details)
_CRITERION_KEYS = ("value", "limit", "unit", "where", "distance_m", "window", "rule")


def _assessment_html(assessment: object) -> str:
    """The assessment of a run: its category and exceedances, and a table of its criteria
    (``{"criteria": {name: {value, limit, pass, unit, where, distance_m, window, rule, ...}}}``;
    a bare mapping or list of criteria works too), ``pass`` as the verdict."""
    if not assessment:
        return ""
    head = ""
    criteria: object = assessment
    if isinstance(assessment, dict) and "criteria" in assessment:
        criteria = assessment.get("criteria") or {}
        parts = []
        if assessment.get("category"):
            parts.append(f"category: <b>{_e(assessment['category'])}</b>")
        exceeded = assessment.get("exceedances") or []
        parts.append(
            '<span class="fail">exceeded: ' + _e(", ".join(exceeded)) + "</span>"
            if exceeded
            else '<span class="pass">no safety criterion exceeded</span>'
        )
        head = "<p>" + "; ".join(parts) + "</p>"
    items = (
        [{"criterion": k, **(v if isinstance(v, dict) else {"value": v})}
         for k, v in criteria.items()]
        if isinstance(criteria, dict) else [i for i in criteria if isinstance(i, dict)]
    )  # fmt: skip
    if not items:
        return head
    keys = ["criterion"] + [k for k in _CRITERION_KEYS if any(k in i for i in items)]
    if not any(k in i for i in items for k in _CRITERION_KEYS):
        keys = list(dict.fromkeys(k for i in items for k in i if k not in _VERDICT_KEYS))
    rows = []
    for item in items:
        verdict = next((item[k] for k in _VERDICT_KEYS if k in item), None)
        cells = [_plain(item.get(k, "")) for k in keys]
        rows.append((*cells, "" if verdict is None else _verdict(bool(verdict))))
    return head + _table(rows, (*keys, "verdict"))


_VERDICT_KEYS = ("pass", "passed", "ok")


def _plain(value: object) -> object:
    if value is None:
        return ""
    return value if isinstance(value, int | float | str | bool) else json.dumps(value)


def _comfort_html(comfort: object) -> str:
    """Ride comfort per measurement point (EN 12299 N_MV, Sperling's Wz), when assessed."""
    points = (comfort or {}).get("points") if isinstance(comfort, dict) else None
    if not points:
        return ""
    rows = [
        (name, _plain(p.get("N_MV")), _plain(p.get("sperling_lateral_Wz")),
         _plain(p.get("sperling_vertical_Wz")))
        for name, p in points.items() if isinstance(p, dict)
    ]  # fmt: skip
    note = comfort.get("note")
    return _table(rows, ("point", "N_MV", "Wz lateral", "Wz vertical")) + (
        f"<p>{_e(note)}</p>" if note else ""
    )


def _animations_html(folder: Path) -> str:
    parts = []
    for name in ANIMATIONS:
        gif, mp4 = folder / f"{name}.gif", folder / f"{name}.mp4"
        caption = f"{name} view (railexu animate)"
        if gif.is_file():
            data = base64.b64encode(gif.read_bytes()).decode("ascii")
            parts.append(_img(data, f"{name} animation", caption, mime="image/gif"))
        elif mp4.is_file():
            data = base64.b64encode(mp4.read_bytes()).decode("ascii")
            parts.append(
                f'<figure><video controls loop muted src="data:video/mp4;base64,{data}">'
                f"</video><figcaption>{_e(caption)}</figcaption></figure>"
            )
    return "\n".join(parts)


# ----------------------------------------------------------------------------------------------
# study
# ----------------------------------------------------------------------------------------------


def study_report_html(folder: str | Path, case_reports: dict[str, str] | None = None) -> str:
    """The HTML text of a study folder's report; ``case_reports`` maps case ids to the relative
    paths of their reports (links).

    Raises:
        InputError: the folder holds no ``study.json`` and ``results.csv``.
    """
    from railexu.report.study_figures import study_figures

    folder = Path(folder)
    if not ((folder / "study.json").is_file() and (folder / "results.csv").is_file()):
        raise InputError(f"{folder}: no study.json and results.csv (not a study's folder)")
    try:
        meta = json.loads((folder / "study.json").read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"{folder / 'study.json'}: cannot read: {exc}") from None
    rows = sorted(read_study_rows(folder / "results.csv"), key=lambda r: r["case_id"])
    case_reports = case_reports or {}
    name = meta.get("name") or folder.name
    counts: dict[str, int] = {}
    for r in rows:
        counts[r.get("status", "")] = counts.get(r.get("status", ""), 0) + 1
    n_cases = len(meta.get("cases", [])) or len(rows)
    body = [
        f"<h1>Study: {_e(name)}</h1>",
        f"<p>{len(rows)} of {n_cases} cases finished: "
        + ", ".join(f"{v} {_e(k)}" for k, v in sorted(counts.items()))
        + f". Folder: <code>{_e(folder.resolve())}</code></p>",
    ]
    if meta.get("description"):
        body.append(f"<p>{_e(meta['description'])}</p>")
    body += [
        "<h2>Cases</h2><p>Click a column heading to sort.</p>",
        _case_table(rows, case_reports),
    ]
    figs = study_figures(folder / "results.csv", meta) if rows else {}
    if figs:
        body.append("<h2>Figures</h2>")
        for fname, fig in figs.items():
            body.append(_img(figure_png_base64(fig), fname, fname.replace("_", " ")))
    return _page(f"railexu study: {name}", body)


_HIDDEN = ("case_hash", "error")


def read_study_rows(path: Path) -> list[dict[str, str]]:
    """The rows of a study's ``results.csv`` (a last line cut short by an interrupted write is
    left out, as the study's resume does).

    Raises:
        DamagedFolderError: not text, no ``case_id`` and ``status`` columns, or a row (other
            than a cut last one) with another number of fields than the header.
    """
    from railexu.report.folder_check import DamagedFolderError

    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise DamagedFolderError(f"{path}: cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise DamagedFolderError(f"{path}: not text; the study's folder is damaged") from None
    try:
        records = list(csv.reader(text.splitlines(keepends=True)))
    except csv.Error as exc:
        raise DamagedFolderError(f"{path}: not a CSV table ({exc})") from None
    if not records or not {"case_id", "status"} <= set(records[0]):
        raise DamagedFolderError(
            f"{path}: no header with case_id and status columns; the study's folder is damaged"
        )
    header, body = records[0], records[1:]
    if body and not text.endswith("\n"):  # cut by an interrupted write: that case is not done
        body = body[:-1]
    for n, row in enumerate(body, start=2):
        if len(row) != len(header):
            raise DamagedFolderError(
                f"{path}, line {n}: {len(row)} fields, expected {len(header)} (one per header "
                "column); the study's folder is damaged"
            )
    return [dict(zip(header, row, strict=True)) for row in body]


def _case_table(rows: list[dict], case_reports: dict[str, str]) -> str:
    if not rows:
        return "<p>No case has finished yet.</p>"
    columns = [c for c in rows[0] if c not in _HIDDEN and not c.endswith("_si")]
    out = []
    for r in rows:
        cells: list[object] = []
        for c in columns:
            text = r.get(c, "") or ""
            if c == "case_id" and text in case_reports:
                cells.append(Raw(f'<a href="{_e(case_reports[text])}">{_e(text)}</a>'))
            elif c == "status":
                cells.append(Raw(f'<span class="status {_e(text)}">{_e(text)}</span>'))
            else:
                cells.append(_number_or_text(text))
        if r.get("error"):
            cells[-1] = Raw(
                f'{_cell_text(cells[-1])} <span title="{_e(r["error"])}">(error)</span>'
            )
        out.append(tuple(cells))
    return _table(out, tuple(columns), cls="sortable")


def _cell_text(value: object) -> str:
    return str(value) if isinstance(value, Raw) else _e(value)


def _number_or_text(text: str) -> object:
    try:
        return float(text)
    except ValueError:
        return text


# ----------------------------------------------------------------------------------------------
# writing
# ----------------------------------------------------------------------------------------------


def write_report(folder: str | Path, cases: bool = True, progress=None) -> list[Path]:
    """Write ``report.html`` into a run folder or a study folder (and, for a study with
    ``cases``, into each case folder that holds a run's output); returns the files written.

    Raises:
        InputError: the folder holds neither a run's nor a study's output.
    """
    from railexu.report.acceptance_page import acceptance_report_html, is_acceptance_folder
    from railexu.report.folder import add_to_manifest

    folder = Path(folder)
    written: list[Path] = []
    if is_acceptance_folder(folder):
        text = acceptance_report_html(folder, _page, _e, _table, Raw)
        return [_write(folder, text)]
    if (folder / "study.json").is_file() and (folder / "results.csv").is_file():
        links: dict[str, str] = {}
        # the cases with a row: a case folder without one is being written or was stopped
        finished = {r["case_id"] for r in read_study_rows(folder / "results.csv")}
        case_dirs = sorted(
            p for p in (folder / "cases").glob("*") if p.is_dir() and p.name in finished
        )
        for n, case in enumerate(case_dirs):
            if cases and (case / "summary.json").is_file():
                written.append(_write(case, run_report_html(case)))
            if (case / REPORT_FILE).is_file():
                links[case.name] = f"cases/{case.name}/{REPORT_FILE}"
            if progress is not None:
                progress(n + 1, len(case_dirs))
        written.append(_write(folder, study_report_html(folder, links)))
        return written
    if not (folder / "summary.json").is_file():
        raise InputError(
            f"{folder}: neither a run's output (summary.json) nor a study's (study.json, "
            "results.csv)"
        )
    path = _write(folder, run_report_html(folder))
    add_to_manifest(folder, [REPORT_FILE])
    return [path]


def _write(folder: Path, text: str) -> Path:
    from railexu.report.folder import atomic_path

    path = folder / REPORT_FILE
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path
