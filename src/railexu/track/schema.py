"""The track file's schema: every key declared once (unit, range, default, one line of doc).

:mod:`railexu.track.track` reads files with it; the tables of ``docs/track-format.md`` are generated
from it (``python -m railexu.schema --write-docs``).
"""

from __future__ import annotations

import math

from railexu.contact.standard_gauge import STANDARD_GAUGE_M
from railexu.inputs import OPTIONAL, REQUIRED, Field, Schema
from railexu.track.irregularities import COMPONENTS, available_spectra
from railexu.track.turnout_schema import CROSSING, DESIGN, SWITCH, TURNOUT
from railexu.track.variable_rails_schema import VARIABLE_RAILS
from railexu.track.vertical_schema import VERTICAL

FORMAT_VERSION = 1
#: Longest track a run or a synthetic record may cover [m]; a longer one is a unit mistake.
MAX_LENGTH_M = 200_000.0
#: Most samples a synthetic record may hold per signal (the grid step is wavelength_min / 16).
MAX_SAMPLES = 20_000_000
#: Steepest plausible rail inclination: 1:10 (0.0997 rad); usual ones are 1:20 and 1:40.
MAX_INCLINATION_RAD = 0.1

_FADE = Field("fade_length", "smooth (quintic) fade-in and fade-out at the ends of the record",
              unit="m", default=10.0, minimum=0.0, maximum=1000.0)  # fmt: skip

_MIRROR = Field("mirror", "the mirror image of the record: lateral alignment and cross level "
                "negated (the rails seen from the other side; a wear route's reverse cases)",
                "boolean", default=False)  # fmt: skip

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
            _MIRROR,
        ),
        "Random irregularities by the sum of cosines (docs/theory.md; ERRI B176 and FRA spectra).",
    ),
    "measured": Schema(
        "measured",
        (
            Field("file", "CSV file (relative to the track file): distance_m, lateral_m, "
                  "vertical_m, cross_level_m, gauge_m (or _mm)", "text"),
            _FADE,
            _MIRROR,
        ),
        "A measured record.",
    ),
}  # fmt: skip

# The geometry and the track model are read and checked by railexu.track.alignment and
# railexu.track.elastic (lists of sections, CSV files, a string or a mapping); these declarations
# give the allowed keys and the documentation (docs/curving.md has the details).
_CANT_BASE = Field("cant_base", "distance of the rail centres over which cant is measured",
                   unit="m", default=1.5, minimum=1.0, maximum=2.0)  # fmt: skip
GEOMETRY = {
    "straight": Schema("straight", (), "Straight track (the default)."),
    "sections": Schema(
        "sections",
        (
            Field("sections", "the sections along the centre line: {type: straight, length}, "
                  "{type: transition, length, shape: clothoid|bloss}, {type: curve, length, "
                  "radius, cant, direction: left|right}", "text_list"),
            _CANT_BASE,
        ),
        "Straights, transitions and curves in the order of travel (docs/curving.md).",
    ),
    "measured": Schema(
        "measured",
        (
            Field("file", "CSV of distance (m), curvature (1/m, signed, left positive) and cant "
                  "(m), relative to this file", "text"),
            _CANT_BASE,
        ),
        "Curvature and cant as track recording data give them.",
    ),
}  # fmt: skip
# Ranges of the elastic track (railexu's assumption, stated in docs/track-format.md): published
# rail-to-ground point stiffnesses lie between about 10 MN/m (soft subgrade) and 300 MN/m (slab
# track); below 1 MN/m a 100 kN wheel load would press a rail down 0.1 m, and above 10 GN/m the
# rail is stiffer than the Hertzian wheel-rail contact (about 1 GN/m): use the rigid track, as
# such a spring only forces a tiny time step. Dampings of 1e8 N s/m and masses of 5 t per wheel
# are 1000 times the published values.
MIN_TRACK_STIFFNESS_N_PER_M = 1.0e6
MAX_TRACK_STIFFNESS_N_PER_M = 1.0e10
MAX_TRACK_DAMPING_N_S_PER_M = 1.0e8
MAX_RAIL_MASS_KG = 5000.0

TRACK_MODEL = {
    "rigid": Schema("rigid", (), "Rigid rails (the default)."),
    "elastic": Schema(
        "elastic",
        (
            # 150 kg: between the kinetic-energy-equivalent vertical mass of the rail alone
            # (79 kg) and of rail and sleepers (166 kg) under the data of Zhai, Wang & Lin 2004
            Field("rail_mass", "co-running mass per rail and wheelset (rail and sleepers "
                  "moving with it)", unit="kg", default=150.0, positive=True,
                  maximum=MAX_RAIL_MASS_KG),
            # 32 MN/m, 80 kN s/m: the fastener of Huo & Dai (2019, Formulation of a linearized
            # model for vehicle-track interactions, Shock and Vibration 2019, 2015465, Table 2:
            # 15 MN/m, 50 kN s/m per fastener) on a 60 kg/m rail as a Winkler beam, seats 0.6 m
            # apart (tests/data/huo_dai2019_fastener.yaml; tests/test_elastic_track.py); a slab
            # track's: ballasted track is laterally softer
            Field("lateral_stiffness", "lateral stiffness of a rail to ground", unit="N/m",
                  default=32.0e6, minimum=MIN_TRACK_STIFFNESS_N_PER_M,
                  maximum=MAX_TRACK_STIFFNESS_N_PER_M),
            Field("lateral_damping", "lateral damping of a rail to ground", unit="N s/m",
                  default=8.0e4, minimum=0.0, maximum=MAX_TRACK_DAMPING_N_S_PER_M),
            # 81 MN/m: Winkler-beam point stiffness 2 s / beta of the ballasted track of Zhai,
            # Wang & Lin (2004, Modelling and experiment of railway ballast vibrations, J. Sound
            # Vib. 270, 673-683): pad, ballast and subgrade in series, sleepers 0.6 m apart
            # (tests/data/zhai2004_ballasted_track.yaml; tests/test_elastic_track.py)
            Field("vertical_stiffness", "vertical stiffness of a rail to ground (pad, ballast, "
                  "subgrade)", unit="N/m", default=81.0e6, minimum=MIN_TRACK_STIFFNESS_N_PER_M,
                  maximum=MAX_TRACK_STIFFNESS_N_PER_M),
            # 110 kN s/m: the fastener's vertical damping of Huo & Dai (2019; 50 kN s/m per
            # fastener) over the vertical deflection shape of the Zhai track (108 kN s/m)
            Field("vertical_damping", "vertical damping of a rail to ground", unit="N s/m",
                  default=1.1e5, minimum=0.0, maximum=MAX_TRACK_DAMPING_N_S_PER_M),
        ),
        "A co-running mass under each wheel with springs and dampers to ground; vertical "
        "stiffness from the ballasted track of Zhai, Wang & Lin (2004), lateral stiffness and "
        "the dampings from the fastener of Huo & Dai (2019), mapped by a Winkler beam "
        "(docs/curving.md gives the sources and the mapping).",
    ),
}  # fmt: skip

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
              unit="m", default=STANDARD_GAUGE_M, minimum=1.0, maximum=2.0),
        Field("geometry", "track geometry by `type`", "model", default={"type": "straight"},
              models=GEOMETRY, selector="type"),
        Field("vertical", "vertical alignment (gradients, vertical curves) by `type`", "model",
              default={"type": "level"}, models=VERTICAL, selector="type"),
        Field("start", "distance along the geometry where a run starts: the rearmost wheelset "
              "stands 1 m beyond it, on a curve placed on its local canted rails", unit="m",
              default=0.0, minimum=0.0, maximum=MAX_LENGTH_M),
        Field("track_model", "rigid, or elastic (`elastic` or {type: elastic, ...})", "model",
              default={"type": "rigid"}, models=TRACK_MODEL, selector="type"),
        Field("irregularities", "irregularities by `type`, their parameters nested", "model",
              default={"type": "none"}, models=IRREGULARITIES, selector="type"),
        Field("variable_rails", "a switch or crossing: rails that vary along a zone, by `type`",
              "model", default={"type": "none"}, models=VARIABLE_RAILS, selector="type"),
        Field("turnout", "a turnout's route as the track (generates `geometry` and "
              "`variable_rails`)", "section", default=OPTIONAL, schema=TURNOUT),
    ),
    "The top level of a track file.",
)  # fmt: skip

DOC_TABLES = (
    ("Top level", TRACK),
    ("`geometry` with `type: sections`", GEOMETRY["sections"]),
    ("`geometry` with `type: measured`", GEOMETRY["measured"]),
    ("`vertical` with `type: gradient`", VERTICAL["gradient"]),
    ("`vertical` with `type: stations`", VERTICAL["stations"]),
    ("`vertical` with `type: measured`", VERTICAL["measured"]),
    ("`track_model` with `type: elastic`", TRACK_MODEL["elastic"]),
    ("`irregularities` with `type: spectrum`", IRREGULARITIES["spectrum"]),
    ("`irregularities` with `type: measured`", IRREGULARITIES["measured"]),
    ("`variable_rails` with `type: slices`", VARIABLE_RAILS["slices"]),
    ("`turnout`", TURNOUT),
    ("Turnout design file (`tracks/turnouts/*.yaml`)", DESIGN),
    ("Turnout design: `switch`", SWITCH),
    ("Turnout design: `crossing`", CROSSING),
)


def synthetic_samples(length_m: float, wavelength_min_m: float) -> float:
    """Samples per signal of a synthetic record (grid step ``wavelength_min / 16``)."""
    return math.ceil(16.0 * length_m / wavelength_min_m) + 1


__all__ = ["FORMAT_VERSION", "MAX_LENGTH_M", "MAX_SAMPLES", "REQUIRED", "TRACK"]
