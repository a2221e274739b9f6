"""``acceptance.json``: what was run, every criterion per zone, the quasi-static tests, the
verdict.

The verdict (railexu's rule, ``docs/acceptance.md``):

- ``fail``: a criterion of a zone or a quasi-static test exceeds its limit (the criteria that
  decide it are listed);
- ``incomplete``: nothing failed, but the verdict cannot be signed: the quick (reduced)
  programme was run, a zone could not be evaluated or had fewer sections than its minimum, or a
  quasi-static test was not run or its run stopped numerically (diverged, failed, interrupted)
  before it measured a value (a derailment fails it);
- ``pass``: every criterion of every zone and every quasi-static test within its limit.

Criteria whose limit or statistics rest on a value railexu could not confirm in a public text
are listed under ``verdict.assumptions``: a verdict that rests on one says so.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, is_dataclass
from pathlib import Path
from typing import Any

from railexu.jsonable import jsonable
from railexu.version import __version__

STANDARD = "EN 14363:2016"


def build_acceptance(
    programme, vehicle_file: Path, vehicle_sha256: str, vehicle_overrides: tuple[str, ...],
    vehicle, zone_results: dict, section_values: dict, zone_errors: dict, studies: dict,
    tests: dict,
) -> dict[str, Any]:  # fmt: skip
    """The content of ``acceptance.json`` (a JSON-ready mapping)."""
    zones = {}
    for zone in programme.zones:
        zones[zone.name] = _zone_entry(
            zone,
            zone_results.get(zone.name),
            section_values.get(zone.name, []),
            zone_errors.get(zone.name),
            studies.get(zone.name),
        )
    data = {
        "standard": STANDARD,
        "railexu_version": __version__,
        "vehicle": {
            "name": vehicle.name,
            "file": str(vehicle_file),
            "sha256": vehicle_sha256,
            "overrides": list(vehicle_overrides),
        },
        "category": vehicle.category,
        "programme": {
            "name": programme.name,
            "file": programme.source,
            "quick": programme.quick,
            "sources": list(programme.sources),
            "zones": [_conditions(z) for z in programme.zones],
        },
        "zones": zones,
        "twist_test": tests.get("twist_test", {"status": "not_run", "reason": "not asked for"}),
        "yaw_resistance_test": tests.get(
            "yaw_resistance_test", {"status": "not_run", "reason": "not asked for"}
        ),
    }
    data["verdict"] = decide(data)
    return jsonable(data)


def decide(data: dict) -> dict[str, Any]:
    """The verdict of an acceptance mapping (see the module doc)."""
    failed, missing, assumptions = [], [], []
    for name, zone in data["zones"].items():
        if zone.get("error"):
            missing.append(f"zone {name}: not evaluated ({zone['error']})")
            continue
        if zone.get("reduced"):
            missing.append(f"zone {name}: fewer sections than the programme's minimum")
        for crit, c in zone.get("criteria", {}).items():
            where = f"{name}: {crit}"
            if c.get("pass") is False:
                unit = c.get("unit", "")
                value, limit = _quantity(c.get("value"), unit), _quantity(c.get("limit"), unit)
                failed.append(f"{where} {value} > {limit} ({c.get('clause', '')})")
            if c.get("assumption") and c.get("pass") is not None:
                assumptions.append(where)
    for test in ("twist_test", "yaw_resistance_test"):
        entry = data.get(test, {})
        status = entry.get("status")
        if status == "completed" and entry.get("pass") is False:
            stop = _numerical_stop(entry)
            if stop:
                missing.append(f"{test}: {stop}")
            else:
                failed.append(_test_failure(test, entry))
        elif status not in ("completed", "not_applicable"):
            missing.append(f"{test}: {status or 'not run'} ({entry.get('reason', '')})")
    if data["programme"]["quick"]:
        missing.insert(0, "the quick (reduced) programme: a trend, not an acceptance verdict")
    if failed:
        result, reason = "fail", f"{len(failed)} criteria exceed their limits"
    elif missing:
        result, reason = "incomplete", missing[0]
    else:
        result, reason = "pass", "every criterion within its limit"
    return {"result": result, "reason": reason, "failed": failed, "missing": missing,
            "assumptions": assumptions}  # fmt: skip


#: The quantities of a quasi-static test's mapping with the key of their limit: the twist
#: test's Y/Q and wheel unloading (``assessment/acceptance/twist.py``), the yaw-resistance
#: test's X factor (``assessment/acceptance/yaw_resistance.py``), or a plain value.
TEST_QUANTITIES = (
    ("y_over_q", "y_over_q_limit"),
    ("unloading", "unloading_limit"),
    ("x_factor", "limit"),
    ("value", "limit"),
)


#: run states that stop a quasi-static test without a physical verdict: the integration
#: failed or the run was stopped (a derailment is a physical failure and fails the test)
NUMERICAL_STOPS = ("diverged", "failed", "interrupted", "terminated")


def _numerical_stop(entry: dict) -> str:
    """Why a failed quasi-static test measured nothing (its run stopped numerically before a
    quantity exceeded its limit), or "" when it failed physically. railexu's rule: such a test
    leaves the verdict incomplete, as one not run; it is no evidence that the vehicle fails."""
    if any(
        isinstance(entry.get(k), int | float) and isinstance(entry.get(lim), int | float)
        and entry[k] > entry[lim]
        for k, lim in TEST_QUANTITIES
    ):  # fmt: skip
        return ""
    run = entry.get("run_status")
    if not isinstance(run, dict) or run.get("state") not in NUMERICAL_STOPS:
        return ""
    where = run.get("distance_m")
    at = f" at {where:.1f} m" if isinstance(where, int | float) else ""
    return (f"its run {run['state']}{at} ({run.get('reason') or 'no reason given'}): no value, "
            "not a failure of the vehicle")  # fmt: skip


def _test_failure(test: str, entry: dict) -> str:
    """What failed in a quasi-static test: each quantity above its own limit, or, when none
    is (a run that did not reach its end), the test's run status."""
    exceeded = []
    for key, limit_key in TEST_QUANTITIES:
        value, limit = entry.get(key), entry.get(limit_key)
        if isinstance(value, int | float) and isinstance(limit, int | float) and value > limit:
            exceeded.append(f"{key} {_num(value)} > {_num(limit)}")
    if not exceeded:
        run = entry.get("run_status") or {}
        state = run.get("state") if isinstance(run, dict) else run
        exceeded.append(f"did not pass (run: {state or 'unknown'})")
    return f"{test}: {'; '.join(exceeded)} ({entry.get('clause', '')})"


def write_acceptance(path: Path, data: dict) -> None:
    """Write ``acceptance.json`` atomically (a temporary file renamed into place)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n", encoding="utf-8")
    tmp.replace(path)


def _zone_entry(zone, result, svs: list, error: str | None, study: dict | None) -> dict:
    entry: dict[str, Any] = {
        "conditions": _conditions(zone),
        "method": zone.method,
        "sections_run": len(svs),
        "sections": [sv.to_dict() for sv in svs],
        "study": dict(study or {}),
    }
    if "curve_transition_comfort" in entry["study"]:  # EN 12299 P_CT of the sections' runs
        entry["curve_transition_comfort"] = entry["study"].pop("curve_transition_comfort")
    if error:
        entry["error"] = error
    if result is not None:
        entry.update(result.to_dict())
    return entry


def _conditions(zone) -> dict:
    d = asdict(zone) if is_dataclass(zone) else dict(zone)
    return {k: v for k, v in d.items() if k != "description"} | {
        "description": getattr(zone, "description", "")
    }


def _quantity(value: Any, unit: str) -> str:
    """A value with its unit as an engineer reads it: forces in kN (``42.41 kN``), others with
    four significant digits."""
    if unit == "N" and isinstance(value, int | float) and math.isfinite(value):
        return f"{value / 1e3:.2f} kN"
    return f"{_num(value)} {unit}".rstrip() if unit not in ("", "1") else _num(value)


def _num(value: Any) -> str:
    if isinstance(value, float) and math.isfinite(value):
        return f"{value:.4g}"
    return str(value)
