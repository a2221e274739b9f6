"""``results.csv``: reading it, its rows and cells, and checking, repairing and appending to it
when a study runs or resumes."""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import warnings
from pathlib import Path
from typing import Any

from railexu.inputs import InputError
from railexu.study.errors import StudyError, StudyWarning
from railexu.study.folder import CASES_DIR, RESULTS_CSV, STUDY_JSON
from railexu.study.spec import RESULT_FILES, Case, Study, _did_you_mean

#: Status of a finished case; ``failed`` cases raised (bad override, solver crash, anything).
STATUSES = ("completed", "completed_with_exceedances", "derailed", "diverged", "failed")
#: Cases with these statuses are not run again when a study is resumed.
DONE_STATUSES = ("completed", "completed_with_exceedances", "derailed", "diverged")


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
    except UnicodeDecodeError:
        raise StudyError(f"{path}: not text (damaged); {_START_OVER}") from None
    try:
        records = list(csv.reader(text.splitlines(keepends=True)))
    except csv.Error as exc:
        raise StudyError(f"{path}: not a CSV table ({exc}); {_START_OVER}") from None
    if not records:
        return [], [], False
    header = records[0]
    body = records[1:]
    # every row is written with its line end and flushed: a last line without one was cut
    # (a power cut, a killed process), whatever it holds, even when its fields look complete
    # (a case hash cut short); it is dropped and its case runs again
    cut = bool(body) and not text.endswith("\n")
    if cut:
        body = body[:-1]
    # any other row of another length is not a cut write but damage: refused, not dropped
    for n, r in enumerate(body, start=2):
        if len(r) != len(header) and r:
            raise StudyError(
                f"{path}, line {n}: {len(r)} fields, expected {len(header)} (one per header "
                f"column): the table is damaged; {_START_OVER}"
            )
    rows = [r for r in body if len(r) == len(header)]
    damaged = cut or len(rows) != len(records) - 1
    return header, rows, damaged


_START_OVER = "repair it, or delete it to run every case again"


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
