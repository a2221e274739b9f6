"""Parameter studies: one vehicle run (or critical-speed analysis) per combination of inputs.

A study file (``docs/study-format.md``) names a base vehicle, track and run settings, the
parameters to vary (vehicle, track, run or critical-speed settings, with units) and the results to
collect from each case's ``summary.json`` (or ``critical_speed.json``)::

    study = load_study("studies/eu07_lateral_force_vs_speed.yaml")
    result = run_study(study, "out/lateral_force", workers=4)
    result.rows            # the rows of out/lateral_force/results.csv
    plot_study("out/lateral_force")

Execution: every case runs in a worker process (``concurrent.futures.ProcessPoolExecutor`` with
the ``spawn`` start method: Exudyn and numba are not fork-safe), or as a task on a Dask
distributed cluster (``scheduler="tcp://host:port"``). The main process is the only writer of
``results.csv``: one row is appended, flushed and synced to disk as each case finishes, so an
interrupted study keeps every finished case, and running the same study again into the same
folder resumes it (cases are identified by ``case_id`` and a hash of everything that decides
their result).

Files written into the output folder ``DIR``:

- ``study.json``: the study as read (base, parameters with their values, collect list) and its
  cases, written at the start;
- ``results.csv``: one row per finished case (see :meth:`Study.columns`);
- ``cases/<case_id>/``: the case's ``case.json`` (its parameter values and overrides), the run's
  ``timeseries.csv`` and ``summary.json`` (or ``critical_speed.json``), plots if the study asks
  for them, and ``error.txt`` (the traceback) for a failed case;
- ``plots/``: the study plots of :func:`plot_study` (PNG and SVG).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import hashlib
import importlib
import itertools
import json
import math
import os
import re
import shutil
import sys
import tempfile
import time
import traceback
import uuid
import warnings
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from .inputs import InputError, KeyPath, Section, apply_overrides, load_yaml
from .units import UnitError, to_si, unit_dimension

__all__ = [
    "Case",
    "Parameter",
    "Study",
    "StudyError",
    "StudyProgress",
    "StudyResult",
    "StudyWarning",
    "add_study_parser",
    "is_study_folder",
    "load_study",
    "plot_study",
    "print_study_progress",
    "read_results",
    "run_study",
]

FORMAT_VERSION = 1
ANALYSES = ("run", "critical_speed")
COMBINE = ("product", "zip")
TOP_KEYS = ("format_version", "name", "description", "analysis", "base", "vary", "collect", "plots")
BASE_KEYS = ("vehicle", "track", "run", "critical_speed", "set")
VARY_KEYS = ("combine", "parameters")
RANGE_KEYS = ("from", "to", "step")
TARGETS = ("vehicle", "track", "run", "critical_speed")
#: Status of a finished case; ``failed`` cases raised (bad override, solver crash, anything).
STATUSES = ("completed", "derailed", "diverged", "failed")
#: Cases with these statuses are not run again when a study is resumed.
DONE_STATUSES = ("completed", "derailed", "diverged")
#: Results collected when a study gives no ``collect`` list.
DEFAULT_COLLECT = {
    "run": (
        "max_abs_lateral_force_N",
        "max_Y_over_Q.value",
        "hunting.detected",
        "hunting.wavelength_m",
        "wheelsets.0.max_abs_lateral_m",
    ),
    "critical_speed": (
        "linear_m_per_s",
        "nonlinear_bisection_m_per_s",
        "nonlinear_ramp_m_per_s",
    ),
}
#: The result file of a case, per analysis, that ``collect`` paths refer to.
RESULT_FILES = {"run": "summary.json", "critical_speed": "critical_speed.json"}
MAX_VALUES = 10_000
MAX_CASES = 100_000
RESULTS_CSV = "results.csv"
STUDY_JSON = "study.json"
CASES_DIR = "cases"
PLOTS_DIR = "plots"
_LOCK_FILE = ".railexu-study.lock"
#: Test hook: a worker process exits abruptly (as on a crash in native code) before running the
#: case whose id this environment variable names. Never set it outside the tests.
_CRASH_ENV = "RAILEXU_STUDY_TEST_CRASH"

# SI units of the run and critical-speed keys whose values may be plain numbers
_KNOWN_UNITS = {
    "run": {
        "speed": "m/s",
        "distance": "m",
        "initial_lateral": "m",
        "time_step": "s",
        "output_interval": "s",
    },
    "critical_speed": {
        "speed_min": "m/s",
        "speed_max": "m/s",
        "tolerance": "m/s",
        "initial_lateral": "m",
        "threshold": "m",
        "distance": "m",
        "conicity_amplitude": "m",
        "ramp_deceleration": "m/s^2",
        "ramp_settle": "m",
        "time_step": "s",
    },
}
# readable SI units of dimensions (kg, m, s)
_DIMENSION_NAMES = {
    (0, 0, 0): "-",
    (0, 1, 0): "m",
    (1, 0, 0): "kg",
    (0, 0, 1): "s",
    (0, 1, -1): "m/s",
    (0, 1, -2): "m/s^2",
    (1, 1, -2): "N",
    (1, 0, -2): "N/m",
    (1, 0, -1): "N s/m",
    (1, 2, -2): "N m",
    (1, 2, -1): "N m s",
    (1, 2, 0): "kg m^2",
    (1, -1, -2): "Pa",
    (0, 0, -1): "1/s",
    (1, 2, -3): "W",
}
_NUMBER_UNIT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*")
_COLLECT_PATH = re.compile(r"[A-Za-z0-9_]+(?:\.[A-Za-z0-9_]+)*")


class StudyError(ValueError):
    """A study cannot run as asked: its output folder holds another study's results, another
    study is running in it, bad worker settings."""


class StudyWarning(UserWarning):
    """Something in a study's results to look at (a ``collect`` path missing from a result)."""


# ----------------------------------------------------------------------------------------------
# The study file
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Parameter:
    """One varied parameter of a study.

    Attributes:
        path: the dotted path as written in the study, with its target prefix
            (``run.speed``, ``vehicle.suspension.primary_ws*.stiffness.x``); the column name.
        target: ``vehicle``, ``track``, ``run`` or ``critical_speed``.
        key: the path inside the target (``speed``, ``suspension.primary_ws*.stiffness.x``).
        values: the values as written (a range is expanded into values in the unit of its
            ``from``, e.g. ``"15 m/s"``).
        si_values: each value in SI (None where a value is not a number).
        quantity: some value carries a unit: ``results.csv`` has a ``<path>_si`` column.
        unit: the SI unit of the values (``"m/s"``, ``"N/m"``), ``""`` if unknown.
        line: the line of the parameter in the study file.
    """

    path: str
    target: str
    key: str
    values: tuple[Any, ...]
    si_values: tuple[float | None, ...]
    quantity: bool
    unit: str
    line: int | None = None

    @property
    def numeric(self) -> bool:
        """Every value is a number (with or without unit)."""
        return all(v is not None for v in self.si_values)

    @property
    def columns(self) -> tuple[str, ...]:
        """The parameter's columns in ``results.csv``: the path, and ``<path>_si`` for a
        quantity."""
        return (self.path, f"{self.path}_si") if self.quantity else (self.path,)

    def to_dict(self) -> dict:
        return {
            "path": self.path,
            "target": self.target,
            "key": self.key,
            "values": list(self.values),
            "si_values": list(self.si_values),
            "quantity": self.quantity,
            "unit": self.unit,
        }


@dataclass(frozen=True)
class Case:
    """One case of a study: one value of every parameter.

    Attributes:
        index: position in the study's case list (0-based).
        case_id: stable name, ``case_0007`` (the index, zero-padded to at least 4 digits).
        hash: 16 hex digits of SHA-256 over the study's base fingerprint (analysis, the parsed
            vehicle and track files, base run/critical-speed settings, base overrides) and this
            case's parameter values as written: equal hashes mean equal inputs.
        values: parameter path -> value as written.
        si_values: parameter path -> SI value (None if not a number).
    """

    index: int
    case_id: str
    hash: str
    values: dict[str, Any]
    si_values: dict[str, float | None]

    def to_dict(self) -> dict:
        return {
            "case_id": self.case_id,
            "hash": self.hash,
            "values": dict(self.values),
            "si_values": dict(self.si_values),
        }


@dataclass(frozen=True)
class Study:
    """A validated study file (see ``docs/study-format.md``); :func:`load_study` reads one.

    Attributes:
        source: the study file as given (for messages).
        name, description: from the file.
        analysis: ``run`` or ``critical_speed``.
        vehicle: the vehicle file (absolute).
        track: the track file (absolute), or None for the ideal straight track.
        run: the base run settings as written (``run_settings_from_dict`` keys).
        critical_speed: the base critical-speed settings as written.
        set: base overrides as written (``vehicle.`` / ``track.`` prefix; none means vehicle).
        combine: ``product`` (full factorial) or ``zip`` (element-wise).
        parameters: the varied parameters, in file order.
        collect: dotted paths into each case's result file.
        plots: write the plots of every case (``write_run(..., plots=True)``).
        fingerprint: SHA-256 digests of what decides the results besides the parameters
            (``analysis``, ``vehicle``, ``track``, ``run``, ``critical_speed``, ``set``) and
            ``digest``, over all of them.
        lines: the line of each key in the study file.
    """

    source: str
    name: str
    description: str
    analysis: str
    vehicle: Path
    track: Path | None
    run: dict
    critical_speed: dict
    set: tuple[str, ...]
    combine: str
    parameters: tuple[Parameter, ...]
    collect: tuple[str, ...]
    plots: bool
    fingerprint: dict[str, str]
    lines: dict = field(default_factory=dict, repr=False, compare=False)

    # -- cases ----------------------------------------------------------------------------------
    def cases(self) -> list[Case]:
        """Every case, in a stable order: ``product`` varies the last parameter fastest,
        ``zip`` takes the i-th value of every parameter."""
        ranges = [range(len(p.values)) for p in self.parameters]
        combos = (
            itertools.product(*ranges) if self.combine == "product" else zip(*ranges, strict=True)
        )
        combos = list(combos)
        width = max(4, len(str(len(combos) - 1)))
        out = []
        for index, combo in enumerate(combos):
            values = {p.path: p.values[i] for p, i in zip(self.parameters, combo, strict=True)}
            si = {p.path: p.si_values[i] for p, i in zip(self.parameters, combo, strict=True)}
            digest = _sha256(
                {
                    "base": self.fingerprint["digest"],
                    "parameters": [[k, v] for k, v in values.items()],
                }
            )
            out.append(Case(index, f"case_{index:0{width}d}", digest[:16], values, si))
        return out

    def vehicle_overrides(self, case: Case) -> list[str]:
        """``dotted.key=value`` overrides of the vehicle file for ``case`` (base ones first)."""
        base = [item for target, item in _split_set(self.set) if target == "vehicle"]
        return base + [
            f"{p.key}={_yaml_text(case.values[p.path])}"
            for p in self.parameters
            if p.target == "vehicle"
        ]

    def track_overrides(self, case: Case) -> list[str]:
        """``dotted.key=value`` overrides of the track file for ``case`` (base ones first)."""
        base = [item for target, item in _split_set(self.set) if target == "track"]
        return base + [
            f"{p.key}={_yaml_text(case.values[p.path])}"
            for p in self.parameters
            if p.target == "track"
        ]

    def settings_data(self, case: Case) -> dict:
        """The run settings (analysis ``run``) or critical-speed settings of ``case``: the base
        mapping with the case's values of ``run.*`` / ``critical_speed.*`` parameters."""
        data = dict(self.run if self.analysis == "run" else self.critical_speed)
        for p in self.parameters:
            if p.target == self.analysis:
                data[p.key] = case.values[p.path]
        return data

    # -- table ----------------------------------------------------------------------------------
    def columns(self) -> list[str]:
        """The header of ``results.csv``: ``case_id``, the parameter columns (path, and
        ``<path>_si`` for quantities), the collected results, ``status``, ``error``,
        ``run_time_s``, ``case_hash``."""
        cols = ["case_id"]
        for p in self.parameters:
            cols.extend(p.columns)
        cols.extend(self.collect)
        cols.extend(["status", "error", "run_time_s", "case_hash"])
        return cols

    def to_dict(self) -> dict:
        """The study as stored in ``study.json`` (without the cases)."""
        from . import __version__

        return {
            "format_version": FORMAT_VERSION,
            "railexu_version": __version__,
            "source": str(Path(self.source).resolve()),
            "name": self.name,
            "description": self.description,
            "analysis": self.analysis,
            "plots": self.plots,
            "base": {
                "vehicle": str(self.vehicle),
                "track": None if self.track is None else str(self.track),
                "run": dict(self.run),
                "critical_speed": dict(self.critical_speed),
                "set": list(self.set),
            },
            "combine": self.combine,
            "parameters": [p.to_dict() for p in self.parameters],
            "collect": list(self.collect),
            "fingerprint": dict(self.fingerprint),
        }

    def collect_line(self, index: int) -> int | None:
        return self.lines.get(("collect", index)) or self.lines.get(("collect",))


def load_study(path: str | Path) -> Study:
    """Read and validate a study file.

    Checked here, each error naming the file, the line and the key (with did-you-mean): the
    keys of every section, the analysis, the base vehicle and track files (loaded and validated
    with the base overrides), the base run or critical-speed settings, every parameter path
    (prefix, run/critical-speed key, and that the path exists in the vehicle or track file;
    wildcards must match), ranges (``step > 0``, ``to >= from``, units of one dimension), lists
    (not empty), ``zip`` lengths and the ``collect`` paths' syntax. The parameter *values* are
    checked when each case runs: a value that makes a case invalid fails that case only.

    Raises:
        InputError: any problem in the study file or in the base vehicle/track.
    """
    path = Path(path)
    data, lines = load_yaml(path)
    source = str(path)
    top = Section(data, source, lines, (), TOP_KEYS)
    version = top.integer("format_version")
    if version != FORMAT_VERSION:
        top.fail(
            f"format_version {version} is not supported (this railexu reads {FORMAT_VERSION})",
            key="format_version",
        )
    name = top.string("name")
    description = top.string("description", default="")
    analysis = top.string("analysis", default="run", choices=ANALYSES)
    plots = top.boolean("plots", default=False)
    base = top.section("base", BASE_KEYS)
    here = path.parent

    # base files and overrides
    vehicle_path = _study_file(base, "vehicle", here)
    track_path = _study_file(base, "track", here) if base.has("track") else None
    set_items = base.string_list("set")
    if base.has("set") and not set_items:
        base.fail("empty list: give overrides like 'bodies.car_body.mass=50 t' or leave out", "set")
    split = []
    for i, item in enumerate(set_items):
        try:
            split.append(_split_set([item])[0])
        except InputError as exc:
            raise InputError(str(exc), source=source, line=_line(lines, ("base", "set", i)),
                             key=f"base.set.{i}") from None  # fmt: skip
    vehicle_raw, vehicle_lines = load_yaml(vehicle_path)
    vehicle_raw = _apply_base_set(vehicle_raw, split, "vehicle", vehicle_path, source, lines)
    track_raw: Any = None
    track_lines: dict = {}
    if track_path is not None:
        track_raw, track_lines = load_yaml(track_path)
        track_raw = _apply_base_set(track_raw, split, "track", track_path, source, lines)
    elif any(target == "track" for target, _ in split):
        i = next(i for i, (t, _) in enumerate(split) if t == "track")
        raise InputError(
            "track overrides need a track file: add base.track",
            source=source,
            line=_line(lines, ("base", "set", i)),
            key=f"base.set.{i}",
        )
    from .track import track_from_dict
    from .vehicle import vehicle_from_dict

    checks = [("vehicle", vehicle_from_dict, vehicle_raw, vehicle_path, vehicle_lines)]
    if track_path is not None:
        checks.append(("track", track_from_dict, track_raw, track_path, track_lines))
    for target, reader, raw, file, file_lines in checks:
        try:
            reader(raw, str(file), file_lines, file.parent)
        except InputError as exc:
            # an error in a key that a base override set: point at the override
            for i, (t, item) in enumerate(split):
                key = item.partition("=")[0].strip()
                if t == target and _same_key(exc.key, key):
                    raise InputError(str(exc), source=source, line=_line(lines, ("base", "set", i)),
                                     key=f"base.set.{i}") from None  # fmt: skip
            raise

    # base settings of the analysis
    run_data: dict = {}
    cs_data: dict = {}
    cs_keys: Sequence[str] | None = None
    if analysis == "run":
        if base.has("critical_speed"):
            base.fail("only used with 'analysis: critical_speed'", key="critical_speed")
        from .simulation import run_settings_from_dict

        run_data = _mapping(base, "run")
        run_settings_from_dict(run_data, source, lines, ("base", "run"))
    else:
        if base.has("run"):
            base.fail(
                "not used by 'analysis: critical_speed': give the run options (distance, "
                "time_step, initial_lateral) in base.critical_speed",
                key="run",
            )
        stability = _stability_module(top)
        cs_data = _mapping(base, "critical_speed")
        stability.critical_speed_settings_from_dict(
            cs_data, source, lines, ("base", "critical_speed")
        )
        cs_keys = getattr(stability, "CRITICAL_SPEED_KEYS", None)

    # parameters
    vary = top.section("vary", VARY_KEYS)
    combine = vary.string("combine", default="product", choices=COMBINE)
    items = vary.items("parameters")
    if not items:
        vary.fail("no parameters: give at least one, e.g. 'run.speed: [10 m/s, 20 m/s]'",
                  key="parameters")  # fmt: skip
    context = {
        "analysis": analysis,
        "vehicle": (vehicle_raw, vehicle_path, vehicle_lines),
        "track": (track_raw, track_path, track_lines),
        "cs_keys": cs_keys,
    }
    parameters = tuple(_parameter(str(key), raw, vary, context) for key, raw in items)
    if combine == "zip":
        lengths = {len(p.values) for p in parameters}
        if len(lengths) > 1:
            detail = ", ".join(f"{p.path} has {len(p.values)} (line {p.line})" for p in parameters)
            vary.fail(f"zip needs lists of equal length: {detail}", key="combine")
    n_cases = (
        math.prod(len(p.values) for p in parameters) if combine == "product"
        else len(parameters[0].values)
    )  # fmt: skip
    if n_cases > MAX_CASES:
        vary.fail(f"{n_cases} cases is more than {MAX_CASES}: is a step or a unit wrong?",
                  key="parameters")  # fmt: skip

    # results to collect
    collect = _collect(top, analysis)
    columns = ["case_id"] + [c for p in parameters for c in p.columns]
    for i, c in enumerate(collect):
        clash = c in columns or c in ("status", "error", "run_time_s", "case_hash")
        if clash or collect.index(c) != i:
            what = "is collected twice" if not clash else "is also the name of another column"
            raise InputError(f"{c!r} {what}", source=source, line=_line(lines, ("collect", i)),
                             key=f"collect.{i}")  # fmt: skip

    fingerprint = {
        "analysis": analysis,
        "vehicle": _sha256(_json_safe(vehicle_raw)),
        "track": _sha256(_json_safe(track_raw)) if track_raw is not None else "ideal straight",
        "run": _sha256(_json_safe(run_data)),
        "critical_speed": _sha256(_json_safe(cs_data)),
        "set": _sha256(list(set_items)),
    }
    fingerprint["digest"] = _sha256(fingerprint)
    return Study(
        source=source,
        name=name,
        description=description,
        analysis=analysis,
        vehicle=vehicle_path,
        track=track_path,
        run=run_data,
        critical_speed=cs_data,
        set=tuple(set_items),
        combine=combine,
        parameters=parameters,
        collect=collect,
        plots=plots,
        fingerprint=fingerprint,
        lines=lines,
    )


def _line(lines: dict, path: KeyPath) -> int | None:
    while path and path not in lines:
        path = path[:-1]
    return lines.get(path)


def _same_key(concrete: str, pattern: str) -> bool:
    """``concrete`` (``suspension.primary_ws1.stiffness.x``) is a key that ``pattern`` (an
    override path, maybe with wildcards) sets."""
    from fnmatch import fnmatchcase

    a, b = concrete.split("."), pattern.split(".")
    return len(a) == len(b) and all(fnmatchcase(x, y) for x, y in zip(a, b, strict=True))


def _did_you_mean(name: str, candidates: Iterable[str]) -> str:
    import difflib

    close = difflib.get_close_matches(str(name), [str(c) for c in candidates], n=1, cutoff=0.6)
    return f" Did you mean {close[0]!r}?" if close else ""


def _mapping(sec: Section, key: str) -> dict:
    if not sec.has(key) or sec.data[key] is None:
        return {}
    return dict(sec.section(key).data)


def _study_file(sec: Section, key: str, here: Path) -> Path:
    name = sec.string(key)
    p = Path(name).expanduser()
    if not p.is_absolute():
        p = here / p
    p = p.resolve()
    if not p.is_file():
        sec.fail(f"file not found: {p} (paths are relative to the study file)", key=key)
    return p


def _split_set(items: Iterable[str]) -> list[tuple[str, str]]:
    """``(target, "key=value")`` of base overrides: ``vehicle.``/``track.`` prefix, none means
    the vehicle (as ``railexu run --set``)."""
    out = []
    for item in items:
        if "=" not in item:
            raise InputError(f"expected dotted.key=value, got {item!r}")
        head = item.split(".", 1)[0]
        if head in ("run", "critical_speed"):
            raise InputError(f"{item!r}: give base {head} settings in base.{head}, not in set")
        if head in ("vehicle", "track") and "." in item.partition("=")[0]:
            out.append((head, item.split(".", 1)[1]))
        else:
            out.append(("vehicle", item))
    return out


def _apply_base_set(
    raw: Any, split: list[tuple[str, str]], target: str, file: Path, source: str, lines: dict
) -> Any:
    for i, (t, item) in enumerate(split):
        if t != target:
            continue
        try:
            raw = apply_overrides(raw, [item], source=str(file))
        except InputError as exc:
            raise InputError(str(exc), source=source, line=_line(lines, ("base", "set", i)),
                             key=f"base.set.{i}") from None  # fmt: skip
    return raw


def _stability_module(top: Section):
    try:
        return importlib.import_module("railexu.stability")
    except ImportError as exc:
        top.fail(
            f"analysis critical_speed needs railexu.stability, which cannot be imported: {exc}",
            key="analysis",
        )


def _yaml_text(value: Any) -> str:
    """``value`` as YAML text that reads back as the same value (for ``key=value`` overrides)."""
    text = yaml.safe_dump(value, default_flow_style=True, width=10**9, allow_unicode=True)
    text = text.strip()
    if text.endswith("\n..."):
        text = text[: -len("\n...")].strip()
    elif text.endswith("..."):
        text = text[:-3].strip()
    return text


def _split_quantity(value: Any) -> tuple[float, str] | None:
    """``(number, unit text)`` of a number or a ``"<number> <unit>"`` string; None otherwise."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return float(value), ""
    if isinstance(value, str):
        m = _NUMBER_UNIT.fullmatch(value)
        if m:
            return float(m.group(1)), m.group(2)
    return None


def _dimension_unit(dim: tuple[int, int, int]) -> str:
    """A unit string of dimension ``dim`` (kg, m, s) with factor 1, for :func:`to_si`."""
    parts = [f"{s}^{e}" for s, e in zip(("kg", "m", "s"), dim, strict=True) if e]
    return " ".join(parts) or "1"


def _unit_label(dim: tuple[int, int, int], units: Iterable[str]) -> str:
    if dim == (0, 0, 0):
        return "rad" if any("rad" in u or "deg" in u for u in units) else "-"
    return _DIMENSION_NAMES.get(dim, _dimension_unit(dim))


def _number_text(x: float, integer: bool = False) -> Any:
    """A value of a range as written: 12 significant digits, an int if ``integer``."""
    x = float(f"{x:.12g}")
    if integer and x.is_integer():
        return int(x)
    return x


def _parameter(name: str, raw: Any, vary: Section, ctx: dict) -> Parameter:
    source, lines = vary.source, vary.lines
    path = (*vary.path, "parameters", name)
    line = _line(lines, path)

    def fail(message: str, sub: Any = None) -> None:
        key = ".".join(str(p) for p in (*path[:-1], name, *(() if sub is None else (sub,))))
        sub_line = line if sub is None else _line(lines, (*path, sub))
        raise InputError(message, source=source, line=sub_line, key=key)

    analysis = ctx["analysis"]
    allowed = ("vehicle", "track", "run") if analysis == "run" else (
        "vehicle", "track", "critical_speed"
    )  # fmt: skip
    target, _, key = name.partition(".")
    if target not in allowed or not key:
        hint = _did_you_mean(target, allowed)
        if target in TARGETS and key:
            hint = f" {target}.* parameters need 'analysis: {target}'."
        fail(
            f"unknown parameter path: it must start with {', '.join(t + '.' for t in allowed)}"
            f" followed by a key.{hint}"
        )
    if target in ("run", "critical_speed"):
        if target == "run":
            from .simulation import RUN_KEYS

            keys: Sequence[str] | None = RUN_KEYS
        else:
            keys = ctx["cs_keys"]
        if "." in key:
            fail(f"{target} settings have no sections: expected {target}.<key>")
        if keys is not None and key not in keys:
            fail(f"unknown {target} key {key!r}.{_did_you_mean(key, keys)} "
                 f"Allowed: {', '.join(keys)}")  # fmt: skip
    if target == "track" and ctx["track"][1] is None:
        fail("track.* parameters need a track file: add base.track")

    # values
    if isinstance(raw, dict):
        values, si, quantity, unit = _range_values(
            raw, Section(raw, source, lines, path, RANGE_KEYS)
        )
    elif isinstance(raw, list):
        if not raw:
            fail("empty list: give at least one value")
        for i, v in enumerate(raw):
            if v is None:
                fail("empty value", sub=i)
        values = tuple(raw)
        si, quantity, unit = _list_si(values, fail)
    else:
        fail(
            f"expected a list of values ([10 m/s, 20 m/s]) or a range ({{from: 10 m/s, to: "
            f"40 m/s, step: 5 m/s}}), got {raw!r}"
        )
    if not quantity and target in _KNOWN_UNITS and all(s is not None for s in si):
        unit = _KNOWN_UNITS[target].get(key, unit)

    # the path must exist in the vehicle or track file
    if target in ("vehicle", "track"):
        raw_data, file, file_lines = ctx[target]
        item = f"{key}={_yaml_text(values[0])}"
        try:
            applied = apply_overrides(raw_data, [item], source=str(file))
        except InputError as exc:
            fail(str(exc))
        _check_new_key(target, key, applied, file, file_lines, fail)
    for v in values:
        text = _yaml_text(v)
        if not (isinstance(v, float) and math.isnan(v)) and yaml.safe_load(text) != v:
            fail(f"value {v!r} cannot be passed on as an override")  # pragma: no cover
    return Parameter(name, target, key, tuple(values), tuple(si), quantity, unit, line)


def _check_new_key(target: str, key: str, applied: Any, file: Path, lines: dict, fail) -> None:
    """An override may add the last key of a mapping: refuse it here if the file reader does
    not know it (a misspelt key), leave every other problem to the cases."""
    from .track import track_from_dict
    from .vehicle import vehicle_from_dict

    reader = vehicle_from_dict if target == "vehicle" else track_from_dict
    try:
        reader(applied, str(file), lines, file.parent)
    except InputError as exc:
        last = key.split(".")[-1]
        if "unknown key" in str(exc) and exc.key.split(".")[-1] == last and "*" not in last:
            fail(str(exc))
    except Exception:  # value problems are the cases' business
        pass


def _range_values(raw: dict, sec: Section) -> tuple[tuple, tuple, bool, str]:
    for k in RANGE_KEYS:
        if k not in raw:
            sec.fail(f"missing key {k!r}: a range needs from, to and step")
    parsed = {}
    for k in RANGE_KEYS:
        q = _split_quantity(raw[k])
        if q is None:
            sec.fail(f"expected a number or '<number> <unit>', got {raw[k]!r}", key=k)
        parsed[k] = q
    units = {k: q[1] for k, q in parsed.items()}
    dims = {}
    for k, u in units.items():
        if u:
            try:
                dims[k] = unit_dimension(u)
            except UnitError as exc:
                sec.fail(str(exc), key=k)
    if dims and (len(dims) != 3 or len(set(dims.values())) != 1):
        sec.fail(
            "from, to and step must all carry units of the same kind (or all be plain numbers), "
            f"got {raw['from']!r}, {raw['to']!r}, {raw['step']!r}"
        )
    dim = next(iter(dims.values())) if dims else (0, 0, 0)
    si_unit = _dimension_unit(dim)
    si = {k: to_si(raw[k], si_unit) if dims else parsed[k][0] for k in RANGE_KEYS}
    if not si["step"] > 0.0:
        sec.fail(f"step must be > 0, got {raw['step']!r}", key="step")
    if si["to"] < si["from"]:
        sec.fail(f"to ({raw['to']!r}) must be >= from ({raw['from']!r})", key="to")
    n = int(math.floor((si["to"] - si["from"]) / si["step"] + 0.5)) + 1
    if n > MAX_VALUES:
        sec.fail(f"{n} values is more than {MAX_VALUES}: is the step or a unit wrong?", key="step")
    unit = units["from"]
    if dims:
        factor = to_si(f"1 {unit}", si_unit)
        numbers = [_number_text((si["from"] + i * si["step"]) / factor) for i in range(n)]
        values = tuple(f"{x:.12g} {unit}" for x in numbers)
        si_values = tuple(to_si(v, si_unit) for v in values)
        return values, si_values, True, _unit_label(dim, [unit])
    integer = all(
        isinstance(raw[k], int) and not isinstance(raw[k], bool) for k in ("from", "step")
    )
    values = tuple(_number_text(si["from"] + i * si["step"], integer) for i in range(n))
    return values, tuple(float(v) for v in values), False, ""


def _list_si(values: tuple, fail) -> tuple[tuple, bool, str]:
    parsed = [_split_quantity(v) for v in values]
    if any(p is None for p in parsed):
        return tuple(None for _ in values), False, ""
    units = [p[1] for p in parsed if p[1]]
    if not units:
        return tuple(p[0] for p in parsed), False, ""
    dims = {}
    for u in units:
        try:
            dims[u] = unit_dimension(u)
        except UnitError:
            return tuple(None for _ in values), False, ""  # not a quantity ("1:40")
    if len(set(dims.values())) > 1:
        fail(f"the values carry units of different kinds: {', '.join(dims)}")
    dim = next(iter(dims.values()))
    si_unit = _dimension_unit(dim)
    return tuple(to_si(v, si_unit) for v in values), True, _unit_label(dim, units)


def _collect(top: Section, analysis: str) -> tuple[str, ...]:
    if not top.has("collect"):
        return DEFAULT_COLLECT[analysis]
    raw = top.data["collect"]
    if not isinstance(raw, list) or not raw:
        top.fail(
            "expected a non-empty list of result paths, e.g. [max_abs_lateral_force_N, "
            "hunting.detected, wheelsets.0.max_abs_lateral_m]",
            key="collect",
        )
    out = []
    for i, item in enumerate(raw):
        if isinstance(item, int) and not isinstance(item, bool):
            item = str(item)
        if not isinstance(item, str) or not _COLLECT_PATH.fullmatch(item):
            raise InputError(
                f"expected a dotted path of names and list indices (hunting.wavelength_m, "
                f"wheelsets.0.max_abs_lateral_m), got {item!r}",
                source=top.source,
                line=_line(top.lines, ("collect", i)),
                key=f"collect.{i}",
            )
        out.append(item)
    return tuple(out)


def _json_safe(obj: Any) -> Any:
    return json.loads(json.dumps(obj, sort_keys=True, default=str))


def _sha256(obj: Any) -> str:
    text = json.dumps(obj, sort_keys=True, default=str, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


# ----------------------------------------------------------------------------------------------
# One case (runs in a worker process)
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Task:
    """What a worker needs to run one case (plain, picklable data)."""

    case_id: str
    hash: str
    analysis: str
    source: str
    vehicle: str
    track: str | None
    vehicle_overrides: tuple[str, ...]
    track_overrides: tuple[str, ...]
    settings: dict
    values: dict
    case_dir: str | None  # None: write into a temporary folder and return the files
    plots: bool
    in_worker: bool


def _make_task(study: Study, case: Case, case_dir: Path | None, in_worker: bool) -> _Task:
    return _Task(
        case_id=case.case_id,
        hash=case.hash,
        analysis=study.analysis,
        source=study.source,
        vehicle=str(study.vehicle),
        track=None if study.track is None else str(study.track),
        vehicle_overrides=tuple(study.vehicle_overrides(case)),
        track_overrides=tuple(study.track_overrides(case)),
        settings=study.settings_data(case),
        values=dict(case.values),
        case_dir=None if case_dir is None else str(case_dir),
        plots=study.plots,
        in_worker=in_worker,
    )


def _worker_init() -> None:
    """Worker processes ignore Ctrl-C: the main process cancels and ends them cleanly."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _error_text(exc: BaseException) -> str:
    msg = str(exc).strip() or type(exc).__name__
    if not isinstance(exc, ValueError):
        msg = f"{type(exc).__name__}: {msg}"
    return " ".join(msg.split())


def _outcome(task: _Task, status: str, error: str = "", run_time_s: float = math.nan) -> dict:
    return {
        "case_id": task.case_id,
        "hash": task.hash,
        "status": status,
        "error": error,
        "run_time_s": run_time_s,
        "result": None,
        "files": None,
    }


def _run_case(task: _Task) -> dict:
    """Run one case and return its outcome: status, error, run time, the content of its result
    file (for ``collect``) and, when ``task.case_dir`` is None, its files (name -> bytes).
    Never raises for a failing case: the error is part of the outcome."""
    t0 = time.perf_counter()
    if task.in_worker and os.environ.get(_CRASH_ENV) == task.case_id:
        os._exit(70)  # test hook: a worker dying as on a crash in native code
    temporary = task.case_dir is None
    outcome = _outcome(task, "failed")
    try:
        if temporary:
            case_dir = Path(tempfile.mkdtemp(prefix=f"railexu-{task.case_id}-"))
        else:
            case_dir = Path(task.case_dir)
            if case_dir.exists():
                shutil.rmtree(case_dir)
            case_dir.mkdir(parents=True)
    except OSError as exc:
        outcome["error"] = _error_text(exc)
        outcome["run_time_s"] = time.perf_counter() - t0
        return outcome
    try:
        _write_json(
            case_dir / "case.json",
            {
                "case_id": task.case_id,
                "hash": task.hash,
                "values": task.values,
                "vehicle": task.vehicle,
                "vehicle_overrides": list(task.vehicle_overrides),
                "track": task.track,
                "track_overrides": list(task.track_overrides),
                task.analysis: task.settings,
            },
        )
        status, result = _execute(task, case_dir)
        outcome.update(status=status, result=result)
    except Exception as exc:  # any failure of a case is recorded, not raised
        outcome["error"] = _error_text(exc)
        with contextlib.suppress(OSError):
            (case_dir / "error.txt").write_text(traceback.format_exc(), encoding="utf-8")
    outcome["run_time_s"] = time.perf_counter() - t0
    if temporary:
        files = {}
        for p in sorted(case_dir.rglob("*")):
            if p.is_file():
                files[p.relative_to(case_dir).as_posix()] = p.read_bytes()
        outcome["files"] = files
        shutil.rmtree(case_dir, ignore_errors=True)
    return outcome


def _execute(task: _Task, case_dir: Path) -> tuple[str, dict]:
    from .track import ideal_straight_track, load_track
    from .vehicle import load_vehicle

    source = f"{task.source} ({task.case_id})"
    if task.analysis == "run":
        from .results import read_summary
        from .simulation import run, run_settings_from_dict, write_run

        settings = run_settings_from_dict(task.settings, source, None, ("run",))
        vehicle = load_vehicle(task.vehicle, task.vehicle_overrides)
        track = load_track(task.track, task.track_overrides) if task.track else None
        result = run(vehicle, track or ideal_straight_track(), settings)
        write_run(result, case_dir, plots=task.plots)
        return str(result.status["state"]), read_summary(case_dir / RESULT_FILES["run"])
    stability = importlib.import_module("railexu.stability")
    settings = stability.critical_speed_settings_from_dict(
        task.settings, source, None, ("critical_speed",)
    )
    vehicle = load_vehicle(task.vehicle, task.vehicle_overrides)
    track = load_track(task.track, task.track_overrides) if task.track else None
    result = stability.critical_speed(vehicle, track or ideal_straight_track(), settings)
    stability.write_critical_speed(result, case_dir, plots=task.plots)
    path = case_dir / RESULT_FILES["critical_speed"]
    return "completed", json.loads(path.read_text(encoding="utf-8"))


def _write_json(path: Path, data: Any) -> None:
    text = json.dumps(data, indent=2, default=str, allow_nan=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text + "\n", encoding="utf-8")
    os.replace(tmp, path)


# ----------------------------------------------------------------------------------------------
# Executors: local processes, Dask, or this process
# ----------------------------------------------------------------------------------------------


def _run_inline(tasks: Sequence[_Task]) -> Iterator[dict]:
    for task in tasks:
        yield _run_case(task)


def _run_local(tasks: Sequence[_Task], workers: int) -> Iterator[dict]:
    """Run tasks on a spawn-context process pool, at most ``workers`` in flight. If a worker
    process dies (a crash in native code, out of memory), the cases that were in flight are run
    again one at a time, so that only the case that kills its worker is recorded as failed."""
    import multiprocessing
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from concurrent.futures.process import BrokenProcessPool

    ctx = multiprocessing.get_context("spawn")
    queue: deque[_Task] = deque(tasks)
    suspects: deque[_Task] = deque()
    isolated: set[str] = set()  # suspects in flight: nothing else runs beside them
    inflight: dict[Any, _Task] = {}
    pool: ProcessPoolExecutor | None = None
    clean = False

    def collect(futures) -> Iterator[tuple[_Task, dict | None]]:
        for fut in futures:
            task = inflight.pop(fut)
            isolated.discard(task.case_id)
            try:
                yield task, fut.result()
            except BrokenProcessPool:
                yield task, None
            except Exception as exc:  # e.g. a result that cannot be pickled
                yield task, _outcome(task, "failed", _error_text(exc))

    try:
        while queue or suspects or inflight:
            if pool is None:
                n = max(1, min(workers, len(queue) + len(suspects)))
                pool = ProcessPoolExecutor(n, mp_context=ctx, initializer=_worker_init)
            limit = 1 if suspects or isolated else workers
            pool_broken = False
            while len(inflight) < limit and (suspects or queue):
                source = suspects if suspects else queue
                task = source.popleft()
                try:
                    fut = pool.submit(_run_case, task)
                except BrokenProcessPool:  # a worker died since the last look
                    source.appendleft(task)
                    pool_broken = True
                    break
                if source is suspects:
                    isolated.add(task.case_id)
                inflight[fut] = task
            alone = len(inflight) == 1
            done, _ = wait(list(inflight), return_when=FIRST_COMPLETED)
            broken: list[_Task] = []
            for task, outcome in collect(done):
                if outcome is None:
                    broken.append(task)
                else:
                    yield outcome
            if not (broken or pool_broken):
                continue
            # the pool is unusable: the other cases in flight end with it
            rest, _ = wait(list(inflight))
            for task, outcome in collect(rest):
                if outcome is None:
                    broken.append(task)
                else:
                    yield outcome
            pool.shutdown(wait=True)
            pool = None
            if alone and broken:
                yield _outcome(
                    broken[0],
                    "failed",
                    "the worker process died while running this case (a crash in native code, "
                    "or out of memory)",
                )
            else:
                suspects.extend(broken)  # run each alone to find the one that kills its worker
        clean = True
    finally:
        if pool is not None:
            _stop_pool(pool, list(inflight), terminate=not clean)


def _stop_pool(pool, futures: list, terminate: bool) -> None:
    for fut in futures:
        fut.cancel()
    if terminate:
        stop = getattr(pool, "terminate_workers", None)  # Python >= 3.14
        if stop is not None:
            stop()
        else:
            for proc in list((getattr(pool, "_processes", None) or {}).values()):
                if proc.is_alive():
                    proc.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def _dask_client(scheduler: Any):
    """``(client, owned)``: a ``distributed.Client`` for an address, or the client given."""
    if not isinstance(scheduler, str):
        return scheduler, False
    try:
        import distributed
    except ImportError as exc:
        raise ImportError(
            f"running a study on a Dask cluster ({scheduler}) needs dask.distributed, which is "
            "not installed: pip install railexu[dask]"
        ) from exc
    try:
        return distributed.Client(scheduler, timeout="20s"), True
    except (OSError, TimeoutError) as exc:
        raise StudyError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from exc


def _run_dask(tasks: Sequence[_Task], client) -> Iterator[dict]:
    """Submit every task to the cluster and yield outcomes as they complete."""
    from distributed import as_completed

    futures = {}
    for task in tasks:
        key = f"railexu-study-{task.case_id}-{uuid.uuid4().hex[:8]}"
        futures[client.submit(_run_case, task, key=key, pure=False)] = task
    try:
        for fut in as_completed(list(futures)):
            task = futures.pop(fut)
            try:
                outcome = fut.result()
            except (KeyboardInterrupt, SystemExit, GeneratorExit):
                raise
            except BaseException as exc:  # KilledWorker, CancelledError, ...
                outcome = _outcome(task, "failed", f"the Dask task failed: {_error_text(exc)}")
            yield outcome
    finally:
        if futures:
            with contextlib.suppress(Exception):
                client.cancel(list(futures))


# ----------------------------------------------------------------------------------------------
# results.csv
# ----------------------------------------------------------------------------------------------


def _cell(value: Any) -> str:
    """A value as a cell of results.csv: booleans true/false, floats with full precision
    (``repr``), None empty, lists and mappings as JSON."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return value
    return json.dumps(value, default=str)


_MISSING = object()


def _lookup(data: Any, path: str) -> tuple[Any, str]:
    """The value at a dotted path (list items by index), or ``(_MISSING, why)``."""
    node = data
    done: list[str] = []
    for part in path.split("."):
        if isinstance(node, dict):
            if part not in node:
                where = ".".join(done) or "the top level"
                return _MISSING, f"no {part!r} in {where}.{_did_you_mean(part, node)}"
            node = node[part]
        elif isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                return _MISSING, f"{'.'.join(done)} is a list of {len(node)} items"
            node = node[int(part)]
        else:
            return _MISSING, f"{'.'.join(done)} is a value, not a section"
        done.append(part)
    return node, ""


def read_results(path: str | Path) -> list[dict[str, str]]:
    """The rows of a ``results.csv`` as dicts of column -> text (empty cells are ``""``);
    incomplete lines (an interrupted write) are left out.

    Raises:
        StudyError: the file cannot be read.
    """
    header, rows, _ = _read_table(Path(path))
    return [dict(zip(header, r, strict=True)) for r in rows]


def _read_table(path: Path) -> tuple[list[str], list[list[str]], bool]:
    """Header, complete rows, and whether something was left out."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise StudyError(f"{path}: cannot read: {exc.strerror or exc}") from None
    records = list(csv.reader(text.splitlines(keepends=True)))
    if not records:
        return [], [], False
    header = records[0]
    rows = [r for r in records[1:] if len(r) == len(header)]
    damaged = len(rows) != len(records) - 1 or (bool(text) and not text.endswith("\n"))
    return header, rows, damaged


class _Table:
    """``results.csv`` of one study: checks and repairs it on resume, appends rows durably."""

    def __init__(self, out: Path, study: Study, cases: list[Case]):
        self.out = out
        self.path = out / RESULTS_CSV
        self.study = study
        self.cases = {c.case_id: c for c in cases}
        self.header = study.columns()
        self.fh = None
        self.writer = None
        self.warned: set[str] = set()

    # -- rows -----------------------------------------------------------------------------------
    def row(self, case: Case, outcome: dict) -> dict[str, str]:
        row = {"case_id": case.case_id}
        for p in self.study.parameters:
            row[p.path] = _cell(case.values[p.path])
            if p.quantity:
                row[f"{p.path}_si"] = _cell(case.si_values[p.path])
        result = outcome.get("result")
        for i, c in enumerate(self.study.collect):
            row[c] = "" if result is None else self._collect(result, i, case.case_id)
        rt = outcome.get("run_time_s")
        row.update(
            status=outcome["status"],
            error=outcome.get("error") or "",
            run_time_s="" if rt is None or not math.isfinite(rt) else f"{rt:.3f}",
            case_hash=case.hash,
        )
        return row

    def _collect(self, result: Any, index: int, case_id: str) -> str:
        path = self.study.collect[index]
        value, why = _lookup(result, path)
        if value is _MISSING:
            if path not in self.warned:
                self.warned.add(path)
                file = RESULT_FILES[self.study.analysis]
                msg = InputError(
                    f"not found in {file} of {case_id} ({why}): recorded as empty",
                    source=self.study.source,
                    line=self.study.collect_line(index),
                    key=f"collect.{index} {path!r}",
                )
                warnings.warn(str(msg), StudyWarning, stacklevel=4)
            return ""
        return _cell(value)

    # -- resume ---------------------------------------------------------------------------------
    def prepare(self, retry_failed: bool) -> dict[str, dict[str, str]]:
        """Check an existing results.csv against the study; return the rows to keep (case_id ->
        row) and rewrite the file if it needs it (duplicates, an incomplete last line, failed
        rows to retry, a changed ``collect`` list)."""
        if not self.path.exists() or self.path.stat().st_size == 0:
            return {}
        header, records, damaged = _read_table(self.path)
        if not {"case_id", "case_hash", "status"} <= set(header):
            raise StudyError(
                f"{self.path} is not the results table of a railexu study (no case_id, "
                "case_hash and status columns): use another output folder"
            )
        rows: dict[str, dict[str, str]] = {}
        duplicates = False
        for r in records:
            d = dict(zip(header, r, strict=True))
            duplicates |= d["case_id"] in rows
            rows[d["case_id"]] = d
        conflicts = [
            d for d in rows.values()
            if d["case_id"] not in self.cases or self.cases[d["case_id"]].hash != d["case_hash"]
        ]  # fmt: skip
        if conflicts:
            raise StudyError(self._conflict_message(conflicts))
        keep = {
            cid: d for cid, d in rows.items()
            if d["status"] in DONE_STATUSES or (d["status"] == "failed" and not retry_failed)
        }  # fmt: skip
        if damaged or duplicates or len(keep) != len(rows) or header != self.header:
            new = {}
            for cid in sorted(keep, key=lambda c: self.cases[c].index):
                new[cid] = self._rebuild(keep[cid])
            self._rewrite(list(new.values()))
            keep = new
        return keep

    def _rebuild(self, old: dict[str, str]) -> dict[str, str]:
        case = self.cases[old["case_id"]]
        missing = [c for c in self.study.collect if c not in old]
        result = None
        if missing and old["status"] != "failed":
            path = self.out / CASES_DIR / case.case_id / RESULT_FILES[self.study.analysis]
            with contextlib.suppress(OSError, ValueError):
                result = json.loads(path.read_text(encoding="utf-8"))
        outcome = {"status": old["status"], "error": old.get("error", ""), "result": result}
        row = self.row(case, outcome)
        for c in self.study.collect:
            if c in old:
                row[c] = old[c]
        row["run_time_s"] = old.get("run_time_s", "")
        return row

    def _rewrite(self, rows: list[dict[str, str]]) -> None:
        tmp = self.path.with_name(f".{self.path.name}.tmp")
        with tmp.open("w", encoding="utf-8", newline="") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(self.header)
            for row in rows:
                w.writerow([row.get(c, "") for c in self.header])
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, self.path)

    def _conflict_message(self, conflicts: list[dict[str, str]]) -> str:
        out = self.out
        details = ""
        old_study = None
        with contextlib.suppress(OSError, ValueError):
            old_study = json.loads((out / STUDY_JSON).read_text(encoding="utf-8"))
        if isinstance(old_study, dict):
            old_fp = old_study.get("fingerprint") or {}
            names = {
                "analysis": "the analysis",
                "vehicle": "the vehicle file's content",
                "track": "the track file's content",
                "run": "base.run",
                "critical_speed": "base.critical_speed",
                "set": "base.set",
            }
            changed = [
                text for k, text in names.items() if old_fp.get(k) != self.study.fingerprint.get(k)
            ]
            if changed:
                details = (
                    f"{', '.join(changed)} differ(s) from study {old_study.get('name')!r} there"
                )
        if not details:
            d = conflicts[0]
            cid = d["case_id"]
            if cid not in self.cases:
                details = f"it has {cid}, which this study does not have"
            else:
                there = ", ".join(f"{p.path}={d.get(p.path, '?')}" for p in self.study.parameters)
                here = ", ".join(
                    f"{p.path}={_cell(self.cases[cid].values[p.path])}"
                    for p in self.study.parameters
                )
                details = f"{cid} there is {there or 'another case'}; here it is {here}"
            if len(conflicts) > 1:
                details += f" ({len(conflicts) - 1} more cases differ)"
        return (
            f"{out} holds the results of a different study: {details}. Rows of two studies "
            f"cannot be mixed: use another output folder, or delete {out / RESULTS_CSV} to start "
            "over."
        )

    # -- appending ------------------------------------------------------------------------------
    def open(self) -> None:
        new = not self.path.exists() or self.path.stat().st_size == 0
        self.fh = self.path.open("a", encoding="utf-8", newline="")
        self.writer = csv.writer(self.fh, lineterminator="\n")
        if new:
            self.writer.writerow(self.header)
            self._sync()

    def append(self, row: dict[str, str]) -> None:
        self.writer.writerow([row.get(c, "") for c in self.header])
        self._sync()

    def _sync(self) -> None:
        self.fh.flush()
        os.fsync(self.fh.fileno())

    def close(self) -> None:
        if self.fh is not None:
            self.fh.close()
            self.fh = None


@contextlib.contextmanager
def _locked(out: Path):
    """Hold an exclusive lock on the output folder (POSIX; released if the process dies)."""
    try:
        import fcntl
    except ImportError:  # Windows: no lock
        yield
        return
    fh = (out / _LOCK_FILE).open("w")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fh.close()
        raise StudyError(f"{out}: another railexu study is running in this folder") from None
    try:
        yield
    finally:
        fcntl.flock(fh, fcntl.LOCK_UN)
        fh.close()


# ----------------------------------------------------------------------------------------------
# Running a study
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class StudyProgress:
    """State of a running study, passed to the progress callback after each case.

    Attributes:
        total: cases in the study.
        done: cases with a row in results.csv (finished now or before).
        skipped: of these, rows kept from before (resume).
        failed: failed cases among ``done``.
        elapsed_s: wall-clock time since the start [s].
        eta_s: estimated time left [s]: cases left x mean run time of this call's cases /
            workers; ``inf`` until a case has finished.
        case_id: the case that just finished (None for the first call, before any case).
        status: its status.
    """

    total: int
    done: int
    skipped: int
    failed: int
    elapsed_s: float
    eta_s: float
    case_id: str | None = None
    status: str | None = None


StudyProgressCallback = Callable[[StudyProgress], None]


@dataclass
class StudyResult:
    """Outcome of :func:`run_study`.

    Attributes:
        study: the study.
        out_dir: its output folder.
        rows: every row of results.csv after the run (column -> text), in case order.
        ran: cases run by this call.
        skipped: cases already in results.csv (resume).
        elapsed_s: wall-clock time of this call [s].
    """

    study: Study
    out_dir: Path
    rows: list[dict[str, str]]
    ran: int
    skipped: int
    elapsed_s: float

    @property
    def results_csv(self) -> Path:
        return self.out_dir / RESULTS_CSV

    @property
    def counts(self) -> dict[str, int]:
        """Number of cases per status."""
        out = dict.fromkeys(STATUSES, 0)
        for r in self.rows:
            out[r["status"]] = out.get(r["status"], 0) + 1
        return out

    @property
    def failed(self) -> list[dict[str, str]]:
        return [r for r in self.rows if r["status"] == "failed"]

    @property
    def ok(self) -> bool:
        """No case failed (derailed and diverged runs are results, not failures)."""
        return not self.failed


def run_study(
    study: Study | str | Path,
    out_dir: str | Path,
    workers: int | None = None,
    scheduler: Any = None,
    progress: StudyProgressCallback | None = None,
    retry_failed: bool = False,
) -> StudyResult:
    """Run every case of ``study`` not yet in ``out_dir/results.csv``.

    Args:
        study: a :class:`Study` or the path of a study file.
        out_dir: the output folder (created if needed).
        workers: local worker processes (default ``os.cpu_count()``); ``0`` runs the cases one
            after the other in this process (debugging: no isolation from crashes). Ignored
            with ``scheduler``.
        scheduler: a Dask scheduler address (``"tcp://host:port"``) or a
            ``distributed.Client``: the cases run as tasks on that cluster. The workers must be
            able to read the vehicle and track files (and the profile files they name) at the
            same absolute paths; each case's files are sent back and written here.
        progress: called with a :class:`StudyProgress` at the start and after each case.
        retry_failed: run the cases recorded as ``failed`` again.

    Resume: a case whose ``case_id`` and ``case_hash`` are in results.csv with status
    completed, derailed or diverged is not run again (nor a failed one, unless
    ``retry_failed``). A results.csv with rows that do not match this study's cases is refused.

    Raises:
        InputError: a bad study file (when given as a path).
        StudyError: the output folder holds another study's results or is in use, bad
            ``workers``, no connection to the scheduler.
        ImportError: ``scheduler`` given but dask.distributed is not installed.
        KeyboardInterrupt: after cancelling the pending cases (finished rows are kept).
    """
    t0 = time.perf_counter()
    if not isinstance(study, Study):
        study = load_study(study)
    if workers is None:
        workers = os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise StudyError(f"workers must be an integer >= 0, got {workers!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cases = study.cases()
    with _locked(out):
        table = _Table(out, study, cases)
        kept = table.prepare(retry_failed)
        _write_json(out / STUDY_JSON, {**study.to_dict(), "cases": [c.to_dict() for c in cases]})
        pending = [c for c in cases if c.case_id not in kept]
        by_id = {c.case_id: c for c in cases}
        failed = sum(1 for r in kept.values() if r["status"] == "failed")
        run_times: list[float] = []
        state = {"done": len(kept), "failed": failed}

        client, owned = (None, False)
        if pending and scheduler is not None:
            client, owned = _dask_client(scheduler)
        try:
            if client is not None:
                parallel = max(1, sum(client.nthreads().values()))
                tasks = [_make_task(study, c, None, True) for c in pending]
                outcomes = _run_dask(tasks, client)
            elif workers == 0:
                parallel = 1
                tasks = [_make_task(study, c, out / CASES_DIR / c.case_id, False) for c in pending]
                outcomes = _run_inline(tasks)
            else:
                parallel = workers
                tasks = [_make_task(study, c, out / CASES_DIR / c.case_id, True) for c in pending]
                outcomes = _run_local(tasks, workers)

            def report(case_id: str | None = None, status: str | None = None) -> None:
                if progress is None:
                    return
                left = len(cases) - state["done"]
                if left == 0:
                    eta = 0.0
                elif run_times:
                    eta = left * (sum(run_times) / len(run_times)) / max(1, min(parallel, left))
                else:
                    eta = math.inf
                progress(
                    StudyProgress(
                        total=len(cases),
                        done=state["done"],
                        skipped=len(kept),
                        failed=state["failed"],
                        elapsed_s=time.perf_counter() - t0,
                        eta_s=eta,
                        case_id=case_id,
                        status=status,
                    )
                )

            table.open()
            try:
                report()
                with contextlib.closing(outcomes):
                    for outcome in outcomes:
                        case = by_id[outcome["case_id"]]
                        if outcome.get("files") is not None:
                            _write_files(out / CASES_DIR / case.case_id, outcome["files"])
                        table.append(table.row(case, outcome))
                        state["done"] += 1
                        state["failed"] += outcome["status"] == "failed"
                        rt = outcome.get("run_time_s")
                        if rt is not None and math.isfinite(rt):
                            run_times.append(rt)
                        report(case.case_id, outcome["status"])
            finally:
                table.close()
        finally:
            if owned:
                with contextlib.suppress(Exception):
                    client.close()
        rows = read_results(table.path) if table.path.exists() else []
    order = {c.case_id: c.index for c in cases}
    rows.sort(key=lambda r: order.get(r["case_id"], len(order)))
    return StudyResult(
        study=study,
        out_dir=out,
        rows=rows,
        ran=len(pending),
        skipped=len(kept),
        elapsed_s=time.perf_counter() - t0,
    )


def _write_files(case_dir: Path, files: Mapping[str, bytes]) -> None:
    if case_dir.exists():
        shutil.rmtree(case_dir)
    for name, data in files.items():
        path = case_dir / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    case_dir.mkdir(parents=True, exist_ok=True)


def _format_duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "--"
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}h{m:02d}m{s:02d}s" if h else (f"{m}m{s:02d}s" if m else f"{s}s")


def print_study_progress(stream=sys.stderr) -> StudyProgressCallback:
    """A progress callback printing cases done / total, failures, elapsed time and the time
    left on one updating line of ``stream``."""

    def report(p: StudyProgress) -> None:
        failed = f", {p.failed} failed" if p.failed else ""
        before = f" ({p.skipped} from before)" if p.skipped else ""
        left = "" if p.done >= p.total else f", about {_format_duration(p.eta_s)} left"
        end = "\n" if p.done >= p.total else ""
        stream.write(
            f"\r  {p.done}/{p.total} cases{before}{failed}, elapsed "
            f"{_format_duration(p.elapsed_s)}{left}    {end}"
        )
        stream.flush()

    return report


# ----------------------------------------------------------------------------------------------
# Plots and the command line
# ----------------------------------------------------------------------------------------------


def is_study_folder(path: str | Path) -> bool:
    """``path`` holds a study's output (``study.json`` and ``results.csv``)."""
    p = Path(path)
    return (p / STUDY_JSON).is_file() and (p / RESULTS_CSV).is_file()


def plot_study(out_dir: str | Path) -> list[Path]:
    """Draw the study plots of an output folder from its ``study.json`` and ``results.csv``
    into ``out_dir/plots/`` (PNG and SVG; see :func:`railexu.plots.study_figures`).

    Returns:
        The files written (none if no case has a numeric result yet).

    Raises:
        StudyError: the folder holds no study output.
    """
    from .plots import save_figure, study_figures

    out = Path(out_dir)
    if not is_study_folder(out):
        raise StudyError(f"{out}: no study.json and results.csv (not an output folder of a study)")
    try:
        meta = json.loads((out / STUDY_JSON).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise StudyError(f"{out / STUDY_JSON}: cannot read: {exc}") from None
    written: list[Path] = []
    for name, fig in study_figures(out / RESULTS_CSV, meta).items():
        written.extend(save_figure(fig, out / PLOTS_DIR / name))
    return written


def add_study_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``study`` sub-command to the ``railexu`` parser's sub-parsers; its function
    returns the exit status: 0 when every case completed, derailed or diverged, 1 when a case
    failed."""
    p = subparsers.add_parser(
        "study",
        help="run a parameter study (many runs over varied inputs)",
        description=(
            "Run every case of a study file (docs/study-format.md) in parallel worker processes "
            "or on a Dask cluster. Writes OUT/study.json, OUT/results.csv (one row per case, "
            "appended as cases finish), OUT/cases/<case_id>/ and the study plots OUT/plots/. "
            "Running the same study into the same folder again resumes it."
        ),
    )
    p.add_argument("study", help="study file (YAML), e.g. studies/eu07_lateral_force_vs_speed.yaml")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help="local worker processes (default: the number of CPUs; 0: run in this process)",
    )
    p.add_argument(
        "--scheduler",
        help="run the cases on a Dask cluster: scheduler address tcp://host:port "
        "(needs pip install railexu[dask])",
    )
    p.add_argument("--retry-failed", action="store_true", help="run failed cases again")
    p.add_argument("--no-plots", action="store_true", help="do not draw the study plots")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=_cmd_study)
    return p


def _cmd_study(args: argparse.Namespace) -> int:
    study = load_study(args.study)
    n = len(study.cases())
    err = sys.stderr

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        err.write(f"\nrailexu study: warning: {message}\n")

    if not args.quiet:
        where = f"Dask cluster {args.scheduler}" if args.scheduler else (
            "this process" if args.workers == 0
            else f"{args.workers or os.cpu_count()} worker processes"
        )  # fmt: skip
        err.write(f"railexu study: {study.name}: {n} cases ({study.analysis}) on {where}\n")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", StudyWarning)
            warnings.showwarning = show
            result = run_study(
                study,
                args.out,
                workers=args.workers,
                scheduler=args.scheduler,
                progress=None if args.quiet else print_study_progress(err),
                retry_failed=args.retry_failed,
            )
    except KeyboardInterrupt:
        path = Path(args.out) / RESULTS_CSV
        kept = len(read_results(path)) if path.exists() else 0
        err.write(
            f"\nrailexu study: interrupted; {kept} finished case(s) are kept in {path}. Run the "
            "same command again to resume.\n"
        )
        return 130
    except ImportError as exc:
        err.write(f"railexu study: error: {exc}\n")
        return 2
    counts = result.counts
    summary = ", ".join(f"{counts[s]} {s}" for s in STATUSES if counts.get(s))
    print(
        f"railexu study: {study.name}: {len(result.rows)} of {n} cases ({summary}); ran "
        f"{result.ran}, {result.skipped} from before, {result.elapsed_s:.1f} s"
    )
    for r in result.failed[:10]:
        print(f"  {r['case_id']} failed: {r['error']}")
    if len(result.failed) > 10:
        print(f"  ... {len(result.failed) - 10} more failed cases in {result.results_csv}")
    print(f"  results: {result.results_csv}")
    if not args.no_plots:
        written = plot_study(args.out)
        if written:
            print(f"  plots: {len(written)} files in {Path(args.out) / PLOTS_DIR}")
    return 1 if result.failed else 0
