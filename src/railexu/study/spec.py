"""The study file (``docs/study-format.md``): reading and validating it into a :class:`Study`,
its varied :class:`Parameter` objects and its :class:`Case` objects."""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from railexu.errors import did_you_mean
from railexu.inputs import (
    OPTIONAL,
    Field,
    InputError,
    KeyPath,
    Override,
    Schema,
    Section,
    apply_overrides,
    load_yaml,
)
from railexu.operation.run_settings import RUN_SCHEMA
from railexu.study.values import RANGE, RANGE_KEYS, _list_si, _range_values, _yaml_text
from railexu.track.schema import TRACK
from railexu.vehicle.schema import VEHICLE

FORMAT_VERSION = 1
ANALYSES = ("run", "critical_speed")
COMBINE = ("product", "zip")
TARGETS = ("vehicle", "track", "run", "critical_speed")

BASE = Schema(
    "base",
    (
        Field("vehicle", "vehicle file (relative to the study file) or shipped name", "text"),
        Field("track", "track file or shipped name (default: ideal straight track)", "text",
              default=OPTIONAL),
        Field("run", "run settings with units (docs/run-settings-format.md); analysis run only",
              "section", default={}, schema=RUN_SCHEMA),
        Field("critical_speed", "critical-speed settings (railexu.stability); analysis "
              "critical_speed only", "section", default=OPTIONAL),
        Field("set", "dotted.key=value overrides for every case (vehicle. or track. prefix)",
              "text_list", default=()),
    ),
    "What every case shares.",
)  # fmt: skip
VARY = Schema(
    "vary",
    (
        Field("combine", "product: every combination; zip: the i-th values together", "text",
              default="product", choices=COMBINE),
        Field("parameters", "path -> list of values, or a range {from, to, step}", "named"),
    ),
)  # fmt: skip
STUDY = Schema(
    "study",
    (
        Field("format_version", f"format of the file ({FORMAT_VERSION})", "integer",
              choices=(FORMAT_VERSION,)),
        Field("name", "a title, used in plots and messages", "text"),
        Field("description", "free text", "text", default=""),
        Field("analysis", "one run, or one critical-speed analysis, per case", "text",
              default="run", choices=ANALYSES),
        Field("base", "what every case shares", "section", schema=BASE),
        Field("vary", "the varied parameters", "section", schema=VARY),
        Field("collect", "result paths to tabulate (default depends on the analysis)",
              "text_list", default=OPTIONAL),
        Field("plots", "also write the plots of every case (slower)", "boolean", default=False),
    ),
    "The top level of a study file.",
)  # fmt: skip
TOP_KEYS = STUDY.keys()
BASE_KEYS = BASE.keys()
VARY_KEYS = VARY.keys()
DOC_TABLES = (("Top level", STUDY), ("`base`", BASE), ("`vary`", VARY), ("A range", RANGE))
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
MAX_CASES = 100_000

# SI units of the run and critical-speed keys whose values may be plain numbers
_KNOWN_UNITS = {
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
        "ramp_budget": "m",
        "time_step": "s",
        "branch_step": "m/s",
        "floor": "m",
        "limit_cycle_floor": "m",
    },
}
_COLLECT_PATH = re.compile(r"[A-Za-z0-9_]+(?:\.[A-Za-z0-9_]+)*")


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
    input_files: dict[str, str] = field(default_factory=dict, compare=False)

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
        return self._overrides(case, "vehicle")

    def _overrides(self, case: Case, target: str) -> list[str]:
        """Overrides of ``target``'s file for ``case``; each remembers its line in the study
        file, so that an invalid value is reported there, not in the vehicle or track file."""
        out = []
        for i, (t, item) in enumerate(_split_set(self.set)):
            if t == target:
                out.append(Override(item, self.source, _line(self.lines, ("base", "set", i))))
        for p in self.parameters:
            if p.target == target:
                text = f"{p.key}={_yaml_text(case.values[p.path])}"
                out.append(Override(text, f"{self.source} ({case.case_id})", p.line))
        return out

    def track_overrides(self, case: Case) -> list[str]:
        """``dotted.key=value`` overrides of the track file for ``case`` (base ones first)."""
        return self._overrides(case, "track")

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
        from railexu.version import __version__

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
            "input_files": dict(self.input_files),
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
    analysis = top.string("analysis", default="run", choices=ANALYSES)
    base = top.section("base", BASE_KEYS)
    inputs = _base_inputs(base, path.parent, source, lines)
    run_data, cs_data, cs_keys = _base_settings(top, base, analysis, source, lines)
    combine, parameters = _parameters(top, analysis, inputs, cs_keys)
    collect = _checked_collect(top, analysis, parameters, source, lines)
    return Study(
        source=source,
        name=top.string("name"),
        description=top.string("description", default=""),
        analysis=analysis,
        vehicle=inputs.vehicle_path,
        track=inputs.track_path,
        run=run_data,
        critical_speed=cs_data,
        set=inputs.set_items,
        combine=combine,
        parameters=parameters,
        collect=collect,
        plots=top.boolean("plots", default=False),
        fingerprint=_fingerprint(analysis, inputs, run_data, cs_data),
        lines=lines,
    )


@dataclass(frozen=True)
class _BaseInputs:
    """The base vehicle and track of a study: files, raw data with the base overrides applied,
    lines, and the overrides themselves."""

    vehicle_path: Path
    vehicle_raw: Any
    vehicle_lines: dict
    track_path: Path | None
    track_raw: Any
    track_lines: dict
    set_items: tuple[str, ...]


def _base_inputs(base: Section, here: Path, source: str, lines: dict) -> _BaseInputs:
    """Read the base vehicle and track files, apply the base overrides and validate both (an
    error in a key that an override set points at the override's line)."""
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
    inputs = _BaseInputs(
        vehicle_path, vehicle_raw, vehicle_lines, track_path, track_raw, track_lines,
        tuple(set_items),
    )  # fmt: skip
    _validate_base(inputs, split, source, lines)
    return inputs


def _validate_base(inputs: _BaseInputs, split: list, source: str, lines: dict) -> None:
    from railexu.track.track import track_from_dict
    from railexu.vehicle.vehicle import vehicle_from_dict

    checks = [("vehicle", vehicle_from_dict, inputs.vehicle_raw, inputs.vehicle_path,
               inputs.vehicle_lines)]  # fmt: skip
    if inputs.track_path is not None:
        checks.append(("track", track_from_dict, inputs.track_raw, inputs.track_path,
                       inputs.track_lines))  # fmt: skip
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


def _base_settings(
    top: Section, base: Section, analysis: str, source: str, lines: dict
) -> tuple[dict, dict, Sequence[str] | None]:
    """The base run settings (analysis ``run``) or critical-speed settings, validated; and the
    critical-speed keys a parameter may vary."""
    if analysis == "run":
        if base.has("critical_speed"):
            base.fail("only used with 'analysis: critical_speed'", key="critical_speed")
        from railexu.operation.run_settings import run_settings_from_dict

        run_data = _mapping(base, "run")
        run_settings_from_dict(run_data, source, lines, ("base", "run"))
        return run_data, {}, None
    if base.has("run"):
        base.fail(
            "not used by 'analysis: critical_speed': give the run options (distance, "
            "time_step, initial_lateral) in base.critical_speed",
            key="run",
        )
    stability = _stability_module(top)
    cs_data = _mapping(base, "critical_speed")
    stability.critical_speed_settings_from_dict(cs_data, source, lines, ("base", "critical_speed"))
    return {}, cs_data, getattr(stability, "CRITICAL_SPEED_KEYS", None)


def _parameters(
    top: Section, analysis: str, inputs: _BaseInputs, cs_keys: Sequence[str] | None
) -> tuple[str, tuple[Parameter, ...]]:
    """The varied parameters and how they combine; ``zip`` lengths and the number of cases
    checked."""
    vary = top.section("vary", VARY_KEYS)
    combine = vary.string("combine", default="product", choices=COMBINE)
    items = vary.items("parameters")
    if not items:
        vary.fail("no parameters: give at least one, e.g. 'run.speed: [10 m/s, 20 m/s]'",
                  key="parameters")  # fmt: skip
    context = {
        "analysis": analysis,
        "vehicle": (inputs.vehicle_raw, inputs.vehicle_path, inputs.vehicle_lines),
        "track": (inputs.track_raw, inputs.track_path, inputs.track_lines),
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
    return combine, parameters


def _checked_collect(
    top: Section, analysis: str, parameters: tuple[Parameter, ...], source: str, lines: dict
) -> tuple[str, ...]:
    """The results to collect, none collected twice or named like another column."""
    collect = _collect(top, analysis)
    columns = ["case_id"] + [c for p in parameters for c in p.columns]
    for i, c in enumerate(collect):
        clash = c in columns or c in ("status", "error", "run_time_s", "case_hash")
        if clash or collect.index(c) != i:
            what = "is collected twice" if not clash else "is also the name of another column"
            raise InputError(f"{c!r} {what}", source=source, line=_line(lines, ("collect", i)),
                             key=f"collect.{i}")  # fmt: skip
    return collect


def _fingerprint(analysis: str, inputs: _BaseInputs, run_data: dict, cs_data: dict) -> dict:
    """SHA-256 digests of what decides a case's result besides its parameter values."""
    track_raw = inputs.track_raw
    fingerprint = {
        "analysis": analysis,
        "vehicle": _sha256(_json_safe(inputs.vehicle_raw)),
        "track": _sha256(_json_safe(track_raw)) if track_raw is not None else "ideal straight",
        "run": _sha256(_json_safe(run_data)),
        "critical_speed": _sha256(_json_safe(cs_data)),
        "set": _sha256(list(inputs.set_items)),
    }
    fingerprint["digest"] = _sha256(fingerprint)
    return fingerprint


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
    hint = did_you_mean(name, list(candidates))
    return hint if hint.startswith(" Did you mean") else ""


def _mapping(sec: Section, key: str) -> dict:
    if not sec.has(key) or sec.data[key] is None:
        return {}
    return dict(sec.section(key).data)


def _study_file(sec: Section, key: str, here: Path) -> Path:
    """A file named by the study: a path relative to the study file, or a shipped name."""
    from railexu.inputs.catalog import find_input

    name = sec.string(key)
    p = Path(name).expanduser()
    if not p.is_absolute():
        p = here / p
    p = p.resolve()
    if p.is_dir():
        sec.fail(f"{p} is a folder; a {key} file was expected", key=key)
    if not p.is_file():
        if not (Path(name).suffix or "/" in name or "\\" in name):
            try:
                return find_input(key, name).resolve()
            except InputError as exc:
                sec.fail(exc.detail, key=key)
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
    from railexu import stability

    return stability


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
            from railexu.operation.run_settings import RUN_KEYS

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
    if not quantity and all(s is not None for s in si):
        unit = _schema_unit(target, key) or unit

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


def _schema_unit(target: str, key: str) -> str:
    """The SI unit of a parameter path from the schema of its target ("" if unknown)."""
    if target in _KNOWN_UNITS:
        return _KNOWN_UNITS[target].get(key, "")
    schema = {"run": RUN_SCHEMA, "vehicle": VEHICLE, "track": TRACK}[target]
    unit = schema.field_at(key.split("."))[1]
    return "" if unit == "1" else unit


def _check_new_key(target: str, key: str, applied: Any, file: Path, lines: dict, fail) -> None:
    """An override may add the last key of a mapping: refuse it here if the file reader does
    not know it (a misspelt key), leave every other problem to the cases."""
    from railexu.track.track import track_from_dict
    from railexu.vehicle.vehicle import vehicle_from_dict

    reader = vehicle_from_dict if target == "vehicle" else track_from_dict
    try:
        reader(applied, str(file), lines, file.parent)
    except InputError as exc:
        last = key.split(".")[-1]
        if "unknown key" in str(exc) and exc.key.split(".")[-1] == last and "*" not in last:
            fail(str(exc))
    except Exception:  # value problems are the cases' business
        pass


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
