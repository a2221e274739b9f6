"""The track file's schema: every key declared once (unit, range, default, one line of doc).

:mod:`railexu.track` reads files with it; the tables of ``docs/track-format.md`` are generated
from it (``python -m railexu.schema --write-docs``).
"""

from __future__ import annotations

import math

from .inputs import OPTIONAL, REQUIRED, Field, Schema
from .irregularities import COMPONENTS, available_spectra

FORMAT_VERSION = 1
#: Longest track a run or a synthetic record may cover [m]; a longer one is a unit mistake.
MAX_LENGTH_M = 200_000.0
#: Most samples a synthetic record may hold per signal (the grid step is wavelength_min / 16).
MAX_SAMPLES = 20_000_000
#: Steepest plausible rail inclination: 1:10 (0.0997 rad); usual ones are 1:20 and 1:40.
MAX_INCLINATION_RAD = 0.1

_FADE = Field("fade_length", "smooth (quintic) fade-in and fade-out at the ends of the record",
              unit="m", default=10.0, minimum=0.0, maximum=1000.0)  # fmt: skip

IRREGULARITIES = {
    "none": Schema("none", (), "Ideal rails."),
    "spectrum": Schema(
        "spectrum",
        (
            Field("spectrum", "power spectral density the signals are synthesised from", "text",
                  choices=available_spectra),
            Field("seed", "seed of the random phases: the same seed gives the same track",
                  "integer", minimum=0, maximum=2**63 - 1),
            Field("wavelength_min", "shortest wavelength synthesised", unit="m", default=3.0,
                  minimum=0.1, maximum=1000.0),
            Field("wavelength_max", "longest wavelength synthesised", unit="m", default=150.0,
                  minimum=0.1, maximum=5000.0),
            Field("components", "signals to synthesise (the others are zero)", "text_list",
                  default=COMPONENTS, choices=COMPONENTS),
            Field("amplitude_scale", "factor on every signal", unit="1", default=1.0,
                  minimum=0.0, maximum=100.0),
            Field("length", "length of the record (default: the run's distance + 50 m)",
                  unit="m", default=OPTIONAL, positive=True, maximum=MAX_LENGTH_M),
            _FADE,
        ),
        "Random irregularities by the sum of cosines (docs/theory.md; ERRI B176 and FRA spectra).",
    ),
    "measured": Schema(
        "measured",
        (
            Field("file", "CSV file (relative to the track file): distance_m, lateral_m, "
                  "vertical_m, cross_level_m, gauge_m (or _mm)", "text"),
            _FADE,
        ),
        "A measured record.",
    ),
}  # fmt: skip

GEOMETRY = {"straight": Schema("straight", (), "Straight track (curves will extend this).")}

TRACK = Schema(
    "track",
    (
        Field("format_version", f"format of the file ({FORMAT_VERSION})", "integer",
              choices=(FORMAT_VERSION,)),
        Field("name", "short name", "text"),
        Field("description", "one paragraph", "text", default=""),
        Field("rail_profile", "built-in name (UIC60, MBench_UIC60, round:<R>, flat) or a file",
              "text", default="UIC60"),
        Field("inclination", "rail cant towards the track centre: '1:40', '1:20', 'none', or an "
              "angle ('0.025 rad', '1.43 deg'); an unquoted 1:40 is read as the ratio",
              "inclination", default="1:40", minimum=0.0, maximum=MAX_INCLINATION_RAD),
        Field("gauge", "track gauge, measured 14 mm below the top of rail (EN 13848-1)",
              unit="m", default=1.435, minimum=1.0, maximum=2.0),
        Field("geometry", "track geometry by `type`", "model", default={"type": "straight"},
              models=GEOMETRY, selector="type"),
        Field("irregularities", "irregularities by `type`, their parameters nested", "model",
              default={"type": "none"}, models=IRREGULARITIES, selector="type"),
    ),
    "The top level of a track file.",
)  # fmt: skip

DOC_TABLES = (
    ("Top level", TRACK),
    ("`irregularities` with `type: spectrum`", IRREGULARITIES["spectrum"]),
    ("`irregularities` with `type: measured`", IRREGULARITIES["measured"]),
)


def synthetic_samples(length_m: float, wavelength_min_m: float) -> float:
    """Samples per signal of a synthetic record (grid step ``wavelength_min / 16``)."""
    return math.ceil(16.0 * length_m / wavelength_min_m) + 1


__all__ = ["FORMAT_VERSION", "MAX_LENGTH_M", "MAX_SAMPLES", "REQUIRED", "TRACK"]
