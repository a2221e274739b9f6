"""The report page of an acceptance folder (``railexu report DIR`` after ``railexu
acceptance``): the verdict and what decides it, the vehicle and programme, one table per test
zone (each criterion's estimate against its limit, with its method and clause), the quasi-static
tests, and the figures of ``DIR/figures/`` embedded. Reads ``acceptance.json`` only."""

from __future__ import annotations

import base64
import json
from pathlib import Path

from railexu.errors import InputError

ACCEPTANCE_JSON = "acceptance.json"
#: unit shown per SI unit, and the factor from SI
SHOWN = {"N": ("kN", 1.0e-3), "m/s^2": ("m/s²", 1.0), "1": ("", 1.0)}


def is_acceptance_folder(folder: Path) -> bool:
    return (Path(folder) / ACCEPTANCE_JSON).is_file()


def read_acceptance(folder: Path) -> dict:
    """``acceptance.json`` of ``folder``.

    Raises:
        InputError: not JSON, or not an acceptance's mapping (naming the file).
    """
    path = Path(folder) / ACCEPTANCE_JSON
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{path}: not a readable acceptance file ({exc})") from None
    if not isinstance(data, dict) or not isinstance(data.get("zones"), dict) or not (
        isinstance(data.get("verdict"), dict)
    ):  # fmt: skip
        raise InputError(f"{path}: expected an acceptance mapping with 'zones' and 'verdict'")
    return data


def acceptance_report_html(folder: Path, page, escape, table, raw) -> str:
    """The page's HTML (``page``, ``escape``, ``table`` and ``raw`` are the report module's
    helpers, passed in so that both pages look alike)."""
    data = read_acceptance(folder)
    verdict = data["verdict"]
    vehicle = data.get("vehicle", {})
    programme = data.get("programme", {})
    body = [
        f"<h1>Acceptance: {escape(vehicle.get('name', ''))} ({escape(data.get('category', ''))})"
        f", {escape(data.get('standard', ''))}</h1>",
        f'<p class="{"pass" if verdict["result"] == "pass" else "fail"}"><b>Verdict: '
        f"{escape(verdict['result'])}</b>: {escape(verdict.get('reason', ''))}</p>",
    ]
    if programme.get("quick"):
        body.append("<p><b>Quick (reduced) programme: a trend, not an acceptance verdict.</b></p>")
    for title, key in (("Exceeded", "failed"), ("Missing for a verdict", "missing"),
                       ("Criteria resting on railexu's assumptions", "assumptions")):  # fmt: skip
        if verdict.get(key):
            items = "".join(f"<li>{escape(x)}</li>" for x in verdict[key])
            body.append(f"<h3>{title}</h3><ul>{items}</ul>")
    body.append("<h2>Inputs</h2>")
    body.append(table([
        ("vehicle", vehicle.get("file", "")), ("SHA-256", vehicle.get("sha256", "")),
        ("vehicle changes", ", ".join(vehicle.get("overrides", [])) or "none"),
        ("programme", f"{programme.get('name', '')} ({programme.get('file', '')})"),
        *_admissible_rows(programme.get("admissible") or {}),
        ("railexu", data.get("railexu_version", "")),
    ]))  # fmt: skip
    for name, zone in data["zones"].items():
        body.append(_zone_html(name, zone, escape, table, raw))
    body.append("<h2>Quasi-static tests</h2>")
    for key, title in (("twist_test", "Safety against derailment on twisted track"),
                       ("yaw_resistance_test", "Bogie yaw resistance")):  # fmt: skip
        rows = _test_rows(data.get(key, {}))
        body.append(f"<h3>{escape(title)}</h3>" + table(rows, ("quantity", "value")))
    for rel in data.get("figures", []):
        path = Path(folder) / rel
        if path.is_file():
            b64 = base64.b64encode(path.read_bytes()).decode("ascii")
            body.append(f'<figure><img alt="{escape(rel)}" src="data:image/png;base64,{b64}">'
                        f"<figcaption>{escape(rel)}</figcaption></figure>")  # fmt: skip
    return page(f"Acceptance {vehicle.get('name', '')}", body)


def _admissible_rows(admissible: dict) -> list[tuple[str, str]]:
    """The admissible speed (km/h) and cant deficiency (mm) the programme ran with, each with
    where it came from (the command line, the vehicle file, or none: the programme's own)."""
    rows = []
    source = admissible.get("source", {})
    for key, label, unit, factor in (("speed_m_per_s", "admissible speed", "km/h", 3.6),
                                     ("cant_deficiency_m", "admissible cant deficiency", "mm",
                                      1.0e3)):  # fmt: skip
        value = admissible.get(key)
        if value is None and key not in source:
            continue
        text = "-" if value is None else f"{_text(float(value) * factor)} {unit}"
        rows.append((label, f"{text} ({source.get(key, 'command line')})"))
    return rows


#: a quasi-static test's key suffix -> (unit shown, factor from SI), the longest suffix first
_TEST_UNITS = (
    ("_rad_per_s", "rad/s", 1.0), ("_per_mille", "‰", 1.0), ("_m_per_s", "m/s", 1.0),
    ("_N_m", "kN m", 1.0e-3), ("_rad", "rad", 1.0), ("_N", "kN", 1.0e-3), ("_m", "m", 1.0),
    ("_s", "s", 1.0),
)  # fmt: skip


def _test_rows(entry: dict, prefix: str = "") -> list[tuple[str, str]]:
    """A quasi-static test's rows, each a quantity in words with its value and unit
    (``radius 150 m``, ``pass yes``; not raw JSON): its plain values, its lists of numbers
    joined, and one level of nested mappings (the run's status; a yaw-resistance test outside
    the wagon category keeps its X factor under ``informative``) with the mapping's name before
    each key, so that a reader sees the value that was not judged."""
    rows = []
    for k, v in entry.items():
        if isinstance(v, dict):
            if not prefix:
                rows += _test_rows(v, prefix=f"{k.replace('_', ' ')}: ")
            continue
        if isinstance(v, list) and not all(isinstance(x, int | float | str) for x in v):
            continue
        name, unit, factor = k, "", 1.0
        for suffix, shown, scale in _TEST_UNITS:
            if k.endswith(suffix):
                name, unit, factor = k[: -len(suffix)], shown, scale
                break
        values = v if isinstance(v, list) else [v]
        text = ", ".join(_test_value(x, factor) for x in values)
        rows.append((f"{prefix}{name.replace('_', ' ')}", f"{text} {unit}".strip()))
    return rows


def _test_value(value, factor: float) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int | float):
        return _text(float(value) * factor)
    return _text(value)


def _zone_html(name: str, zone: dict, escape, table, raw) -> str:
    cond = zone.get("conditions", {})
    head = (f"<h2>Zone {escape(name)}</h2><p>{escape(cond.get('description', ''))}; "
            f"{zone.get('sections_run', 0)} sections run, method "
            f"{escape(zone.get('method', ''))}</p>")  # fmt: skip
    if zone.get("error"):
        return head + f'<p class="fail">Not evaluated: {escape(zone["error"])}</p>'
    rows = []
    for crit, c in zone.get("criteria", {}).items():
        unit, factor = SHOWN.get(c.get("unit", ""), (c.get("unit", ""), 1.0))
        verdict = {
            True: raw('<span class="pass">pass</span>'),
            False: raw('<span class="fail">fail</span>'),
            None: "-",
        }[c.get("pass")]
        within = (c.get("details") or {}).get("within_limit")
        if c.get("pass") is None and within is not None:  # reported, not judged
            verdict = "informative: " + ("within the limit" if within else "above the limit")
        rows.append((
            crit, _scaled(c.get("value"), factor), _scaled(c.get("limit"), factor), unit,
            verdict, c.get("method", ""), "yes" if c.get("assumption") else "",
            c.get("clause", ""), c.get("note", ""),
        ))  # fmt: skip
    header = ("criterion", "estimate", "limit", "unit", "verdict", "method", "assumption",
              "clause", "note")  # fmt: skip
    return head + table(rows, header) + _transition_comfort_html(zone, escape)


def _transition_comfort_html(zone: dict, escape) -> str:
    """EN 12299 P_CT of the zone's sections' transitions (reported, not judged)."""
    pct = zone.get("curve_transition_comfort") or {}
    if not pct.get("sections"):
        return ""
    return (f"<p>Comfort on the sections' entry transitions ({escape(pct.get('clause') or '')}"
            f"{', railexu assumption' if pct.get('assumption') else ''}): largest P_CT "
            f"{_text(pct.get('max_P_CT_standing_percent'))} % standing, "
            f"{_text(pct.get('max_P_CT_seated_percent'))} % seated over "
            f"{len(pct['sections'])} sections (no limit).</p>")  # fmt: skip


def _scaled(value, factor: float):
    return "-" if value is None else round(float(value) * factor, 6)


def _text(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)
