"""Declarations of the track file's ``variable_rails:`` section (switches and crossings, issue 29).

:mod:`railexu.track.variable_rails_file` reads and checks the section (the slices files, the
zone against the track); these declarations give the allowed keys and the generated tables of
``docs/track-format.md`` (``python -m railexu.schema --write-docs``).
"""

from __future__ import annotations

from railexu.inputs import OPTIONAL, Field, Schema

#: Longest zone of variable rails accepted [m] (railexu's assumption): a 1:9.25 crossing panel
#: is about 10 m, a long switch panel 40-60 m; the station tables of a longer zone would not fit
#: in memory (~ 70 MB per metre at 10 mm stations, docs/switches-and-crossings.md).
MAX_ZONE_LENGTH_M = 100.0

#: Keys of one part of a zone with its own station step (``station_steps:``).
STATION_STEP_KEYS = ("from", "to", "step")

#: Bounds of a station step [m] (``station_step`` and a part's ``step``), those
#: :class:`~railexu.track.variable_rails.VariableRails` applies (railexu's choice): 0.1 mm is
#: 100 times the distance at which two stations are one, 1 m is 20 times the turnout's default
#: 50 mm (a part coarser than that is no refinement a zone of slices needs).
MIN_STATION_STEP_M, MAX_STATION_STEP_M = 1.0e-4, 1.0

_SIDE = ("the {side} rail's variable profile: a CONTACT `.slcs` file or railexu's YAML slices "
         "(`.yaml`), relative to this file; absent: the track's rail on that side")  # fmt: skip

VARIABLE_RAILS = {
    "none": Schema("none", (), "No switch or crossing (the default)."),
    "slices": Schema(
        "slices",
        (
            Field("start", "track distance of the slices' s = 0 (facing) or of their s = 0 "
                  "met in reverse (trailing)", unit="m", minimum=0.0, maximum=200_000.0),
            Field("direction", "facing: the slices' s increases in the direction of travel; "
                  "trailing: the zone is run in the other direction (s -> -s)", "text",
                  default="facing", choices=("facing", "trailing")),
            Field("left", _SIDE.format(side="left"), "text", default=OPTIONAL),
            Field("right", _SIDE.format(side="right"), "text", default=OPTIONAL),
            Field("text_unit", "unit of two-column text profiles named by a `.slcs` file "
                  "(CONTACT's SCALE): mm or m", "text", default="mm", choices=("mm", "m")),
            Field("station_step", "distance between the stations whose kernel tables are "
                  "blended", unit="m", default=0.01, minimum=MIN_STATION_STEP_M,
                  maximum=MAX_STATION_STEP_M),
            Field("rail_origin", "(y, z) of the slices' origin in the track's left-type axes "
                  "(y from the track centre, z down); absent: the placed rail profile's own "
                  "origin", "vector", unit="m", default=OPTIONAL, components=("y", "z"),
                  minimum=-2.0, maximum=2.0),
            Field("station_steps", "parts of the zone with their own station step: a list of "
                  "{from, to, step}, from and to in the slices' own s (as `start` places it; "
                  "trailing too: the slices file's s), in order, not overlapping, within the "
                  "zone's slices; step 0.1 mm .. 1 m; each part's stations every step from its "
                  "first slice met, its ends included; elsewhere every station_step",
                  "text_list", default=OPTIONAL),
            Field("effective_length", "half-length of the effective section (a wheel touches "
                  "a rising nose ahead of its axle)", unit="m", default=0.06, minimum=0.0,
                  maximum=0.2),
            Field("contact_filter", "the station tables averaged along the track over this "
                  "length (a contact patch's, railexu's assumption; 0: not filtered; default: "
                  "12 mm, railexu.track.variable_rails.FILE_CONTACT_FILTER_M, applied at the "
                  "wheelset: with stations of 5 mm or finer a crossing's peaks converge)",
                  unit="m", default=OPTIONAL, minimum=0.0, maximum=0.1),
        ),
        "A zone whose rails vary along the track: slices per side interpolated between them "
        "(docs/switches-and-crossings.md).",
    ),
}  # fmt: skip
