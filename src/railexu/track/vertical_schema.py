"""Declarations of the track file's ``vertical:`` section (keys, units, one line of doc each).

:mod:`railexu.track.vertical` reads and checks the section (lists of stations, CSV files); these
declarations give the allowed keys and the generated tables of ``docs/track-format.md``
(``python -m railexu.schema --write-docs``).
"""

from __future__ import annotations

from railexu.inputs import Field, Schema

_RACK = Field("rack", "a rack railway: gradients up to 480 per mille instead of 100",
              "boolean", default=False)  # fmt: skip

VERTICAL = {
    "level": Schema("level", (), "A level track (the default)."),
    "gradient": Schema(
        "gradient",
        (
            Field("gradient", "constant gradient: a number in per mille (positive rising in the "
                  "direction of travel), or with its unit ('1.25 %')", "text"),
            _RACK,
        ),
        "One gradient along the whole track.",
    ),
    "stations": Schema(
        "stations",
        (
            Field("stations", "the points of intersection of the gradients in the order of "
                  "travel: {position (m), elevation (m), radius (m): the vertical curve's "
                  "radius, >= 250 m, at every station but the first and the last}",
                  "text_list"),
            _RACK,
        ),
        "Gradients between stations joined by parabolic vertical curves (docs/curving.md).",
    ),
    "measured": Schema(
        "measured",
        (
            Field("file", "CSV of distance (m) and elevation (m) of the top of rail, or of "
                  "distance (m) and gradient (per mille), relative to this file", "text"),
            Field("column", "what the file's second column is: elevation (m) or gradient "
                  "(per mille, integrated from elevation 0)", "text", default="elevation",
                  choices=("elevation", "gradient")),
            _RACK,
        ),
        "A surveyed profile, smoothed over 5 m (docs/curving.md).",
    ),
}  # fmt: skip
