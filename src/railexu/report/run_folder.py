"""Reading a run's folder for ``railexu report``, ``plot`` and ``animate``: checked first.

:func:`read_run_summary` checks the folder (complete, not damaged:
:func:`railexu.report.folder_check.check_output_folder`) and the types of the ``summary.json``
entries the commands read, so that a damaged or hand-edited summary gets one clear line naming the
file and the entry (exit code 2), never a traceback.
"""

from __future__ import annotations

from pathlib import Path

from railexu.report.folder_check import DamagedFolderError, check_output_folder

SUMMARY = "summary.json"
TIMESERIES = "timeseries.csv"

_NUMBER = "a number"
_TEXT = "a text"
_OBJECT = "an object"
_LIST = "a list"

#: entries of summary.json the commands read (dotted path -> type); absent entries and nulls are
#: allowed (older summaries lack some); ``*`` stands for every key of a mapping or item of a list
_TYPES = {
    "status": _OBJECT,
    "status.state": _TEXT,
    "status.distance_m": _NUMBER,
    "status.reason": _TEXT,
    "vehicle": _TEXT,
    "track": _TEXT,
    "vehicle_file": _TEXT,
    "track_file": _TEXT,
    "vehicle_sha256": _TEXT,
    "track_sha256": _TEXT,
    "settings": _OBJECT,
    "settings.speed_m_per_s": _NUMBER,
    "timings_s": _OBJECT,
    "timings_s.*": _NUMBER,
    "realtime_factor": _NUMBER,
    "wheelsets": _LIST,
    "wheelsets.*": _OBJECT,
    "wheelsets.*.name": _TEXT,
    "wheelsets.*.max_abs_lateral_m": _NUMBER,
    "wheelsets.*.final_amplitude_m": _NUMBER,
    "flange_contact": _OBJECT,
    "flange_contact.first_distance_m": _NUMBER,
    "hunting": _OBJECT,
    "hunting.amplitude_m": _NUMBER,
    "hunting.frequency_Hz": _NUMBER,
    "hunting.wavelength_m": _NUMBER,
    "hunting.verdict": _TEXT,
    "max_abs_lateral_force_N": _NUMBER,
    "max_Y_over_Q": _OBJECT,
    "max_Y_over_Q.value": _NUMBER,
    "max_Y_over_Q.value_2m": _NUMBER,
    "max_Y_over_Q.value_en14363": _NUMBER,
    "max_Y_over_Q.nadal_limit": _NUMBER,
    "max_Y_over_Q.limit": _NUMBER,
    "max_sum_Y_N": _OBJECT,
    "max_sum_Y_N.value": _NUMBER,
    "max_sum_Y_N.limit_N": _NUMBER,
    "running_stability": _OBJECT,
    "running_stability.rms_sum_Y_N": _NUMBER,
    "running_stability.limit_N": _NUMBER,
    "evaluation_window": _OBJECT,
    "evaluation_window.from_m": _NUMBER,
    "evaluation_window.to_m": _NUMBER,
    "assessment": _OBJECT,
    "assessment.criteria": _OBJECT,
    "assessment.exceedances": _LIST,
    "assessment.exceedances.*": _TEXT,
    "comfort": _OBJECT,
    "comfort.points": _OBJECT,
    "comfort.points.*": _OBJECT,
    "curving": _OBJECT,
    "curving.geometry": _OBJECT,
    "warnings": _LIST,
    "warnings.*": _TEXT,
    "wear": _OBJECT,
    "wear.law": _TEXT,
    "wear.wheels": _LIST,
    "wear.wheels.*": _OBJECT,
    "wear.rails": _LIST,
    "wear.rails.*": _OBJECT,
}


def read_run_summary(folder: str | Path, reads: tuple[str, ...] = (SUMMARY,)) -> dict:
    """The checked ``summary.json`` of a complete run folder.

    Args:
        reads: the files the caller will read (their sizes are checked against the manifest).

    Raises:
        IncompleteFolderError: the folder is being written or its writing was stopped.
        DamagedFolderError: a file is missing, cut short, not JSON, or an entry has a wrong
            type.
        InputError: the folder holds no ``summary.json``.
    """
    from railexu.results import read_summary
    from railexu.results.summary import ResultsError

    folder = Path(folder)
    check_output_folder(folder, "run", reads)
    path = folder / SUMMARY
    if not path.is_file():
        raise DamagedFolderError(f"{folder}: no {SUMMARY} (not an output folder of railexu run)")
    try:
        summary = read_summary(path)
    except ResultsError as exc:
        raise DamagedFolderError(str(exc)) from None
    check_summary_types(summary, path)
    return summary


def check_summary_types(summary: dict, path: str | Path = SUMMARY) -> None:
    """Check the types of the entries of a run's summary that the commands read.

    Raises:
        DamagedFolderError: naming the file, the entry, what it holds and what was expected.
    """
    for key, expected in _TYPES.items():
        for where, value in _values(summary, key.split(".")):
            if value is not None and not _is(value, expected):
                raise DamagedFolderError(
                    f"{path}: {where} is {_shown(value)}, expected {expected} (the file is "
                    "damaged or was edited)"
                )


def _values(node: object, parts: list[str], where: str = "") -> list[tuple[str, object]]:
    """The values at a dotted path (``*``: every key or item); none where a parent is absent or
    of another type (that parent's own entry reports it)."""
    if not parts:
        return [(where, node)]
    head, rest = parts[0], parts[1:]
    prefix = f"{where}." if where else ""
    if head == "*":
        if isinstance(node, dict):
            items = [(f"{prefix}{k}", v) for k, v in node.items()]
        elif isinstance(node, list):
            items = [(f"{where}[{i}]", v) for i, v in enumerate(node)]
        else:
            return []
    elif isinstance(node, dict) and head in node:
        items = [(f"{prefix}{head}", node[head])]
    else:
        return []
    out: list[tuple[str, object]] = []
    for name, value in items:
        out += _values(value, rest, name)
    return out


def _is(value: object, expected: str) -> bool:
    if expected == _NUMBER:
        return isinstance(value, int | float) and not isinstance(value, bool)
    if expected == _TEXT:
        return isinstance(value, str)
    if expected == _OBJECT:
        return isinstance(value, dict)
    return isinstance(value, list)


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
