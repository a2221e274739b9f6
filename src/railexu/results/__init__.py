"""Results of a running simulation: the time series, signal helpers and the typed summary.

- :mod:`.timeseries`: :class:`TimeSeries` (the recorded columns, CSV, pandas);
- :mod:`.summary`: the typed :class:`RunSummary` (``to_dict()`` is ``summary.json``),
  :func:`write_summary`, :func:`read_summary`;
- :mod:`.evaluate`: :func:`summarize`, a :class:`RunSummary` with every criterion of
  :mod:`railexu.assessment` over the evaluation window.

The signal helpers (sliding means and rms, windowed means, zero crossings, the one definition
of an oscillation's amplitude) live in :mod:`railexu.assessment.signals`, so that the assessment
does not import the results package (results -> assessment, never back). The names below stay
importable from ``railexu.results`` as before the split.

The names load on first access (PEP 562): reading a summary, or unpickling one that the warm
process of ``railexu run`` computed (:mod:`railexu.runtime.warm_process`), does not import the
assessment and ``scipy.signal`` (0.8 s) with it.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# public name -> module that defines it (imported on first access, PEP 562)
_EN14363 = "railexu.assessment.en14363"
_SIGNALS = "railexu.assessment.signals"
_PUBLIC = {
    **dict.fromkeys(
        (
            "ALPHA",
            "CATEGORIES",
            "FLANGE_SIGN",
            "SAFETY_WINDOW_M",
            "SIDES",
            "STABILITY_WINDOW_M",
            "Y_OVER_Q_LIMIT",
            "alpha_for",
            "nadal_limit",
            "track_shifting_limit_N",
        ),
        _EN14363,
    ),  # fmt: skip
    **dict.fromkeys(("FINAL_FRACTION", "HUNTING_DECAY_RATIO"), "railexu.assessment.hunting"),
    **dict.fromkeys(
        (
            "CROSSING_HYSTERESIS",
            "amplitude",
            "percentile",
            "sliding_mean",
            "sliding_rms",
            "window_means",
            "window_rms",
            "zero_crossing_wavelength",
            "zero_crossings",
        ),
        _SIGNALS,
    ),  # fmt: skip
    **dict.fromkeys(
        ("MIN_LOAD_FRACTION", "evaluation_window", "summarize", "y_over_q"),
        "railexu.results.evaluate",
    ),
    **dict.fromkeys(
        ("FORMAT_VERSION", "EvaluationWindow", "RunSummary", "read_summary", "write_summary"),
        "railexu.results.summary",
    ),
    **dict.fromkeys(("ResultsError", "TimeSeries"), "railexu.results.timeseries"),
}
#: EN 14363 track-shifting factor alpha (kept for older code: see ``ALPHA`` by category).
_ALPHA_BY_CATEGORY = {"ALPHA_LOCOMOTIVE": "locomotive", "ALPHA_FREIGHT_WAGON": "wagon"}

__all__ = [
    "ALPHA",
    "ALPHA_FREIGHT_WAGON",
    "ALPHA_LOCOMOTIVE",
    "CATEGORIES",
    "CROSSING_HYSTERESIS",
    "FINAL_FRACTION",
    "FLANGE_SIGN",
    "FORMAT_VERSION",
    "HUNTING_DECAY_RATIO",
    "MIN_LOAD_FRACTION",
    "SAFETY_WINDOW_M",
    "SIDES",
    "STABILITY_WINDOW_M",
    "Y_OVER_Q_LIMIT",
    "EvaluationWindow",
    "ResultsError",
    "RunSummary",
    "TimeSeries",
    "alpha_for",
    "amplitude",
    "evaluation_window",
    "nadal_limit",
    "percentile",
    "read_summary",
    "sliding_mean",
    "sliding_rms",
    "summarize",
    "track_shifting_limit_N",
    "window_means",
    "window_rms",
    "write_summary",
    "y_over_q",
    "zero_crossing_wavelength",
    "zero_crossings",
]

if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load lazily
    from railexu.assessment.en14363 import (
        ALPHA,
        CATEGORIES,
        FLANGE_SIGN,
        SAFETY_WINDOW_M,
        SIDES,
        STABILITY_WINDOW_M,
        Y_OVER_Q_LIMIT,
        alpha_for,
        nadal_limit,
        track_shifting_limit_N,
    )
    from railexu.assessment.hunting import FINAL_FRACTION, HUNTING_DECAY_RATIO
    from railexu.assessment.signals import (
        CROSSING_HYSTERESIS,
        amplitude,
        percentile,
        sliding_mean,
        sliding_rms,
        window_means,
        window_rms,
        zero_crossing_wavelength,
        zero_crossings,
    )
    from railexu.results.evaluate import MIN_LOAD_FRACTION, evaluation_window, summarize, y_over_q
    from railexu.results.summary import (
        FORMAT_VERSION,
        EvaluationWindow,
        RunSummary,
        read_summary,
        write_summary,
    )
    from railexu.results.timeseries import ResultsError, TimeSeries


def __getattr__(name: str) -> Any:
    if name in _ALPHA_BY_CATEGORY:
        value = __getattr__("ALPHA")[_ALPHA_BY_CATEGORY[name]]
    elif name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
    else:
        raise AttributeError(f"module 'railexu.results' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(list(globals()) + __all__)
