"""Declarations of a turnout: the track file's ``turnout:`` section and the turnout design file.

:mod:`railexu.track.turnout_file` reads them; :mod:`railexu.track.turnout` builds the route's
geometry and its variable rails. The generated tables of ``docs/track-format.md`` come from
here (``python -m railexu.schema --write-docs``). Every default marked "railexu's assumption"
is not public for the design shipped (docs/switches-and-crossings.md, "The turnout").
"""

from __future__ import annotations

from railexu.inputs import OPTIONAL, Field, Schema

#: The track file's ``turnout:`` section.
TURNOUT = Schema(
    "turnout",
    (
        Field("design", "the turnout design file (YAML, e.g. tracks/turnouts/), relative to "
              "this file", "text"),
        Field("route", "through (straight) or diverging (the switch curve)", "text",
              choices=("through", "diverging")),
        Field("direction", "facing: switch toe first; trailing: crossing first", "text",
              choices=("facing", "trailing")),
        Field("approach", "straight track from the track's start to the first rail of the "
              "turnout met (the toe facing, the crossing's last slice trailing)", unit="m",
              default=40.0, minimum=2.0, maximum=10_000.0),
        Field("run_out", "straight track beyond the last rail of the turnout met", unit="m",
              default=30.0, minimum=1.0, maximum=10_000.0),
        Field("panels", "which panels vary along the track: both, switch or crossing (the "
              "other one is plain rail: a shorter zone, fewer tables)", "text", default="both",
              choices=("both", "switch", "crossing")),
        Field("station_step", "distance between the stations whose kernel tables are blended "
              "(default: the design's)", unit="m", default=OPTIONAL, minimum=1e-3, maximum=1.0),
        Field("switch_station_step", "the stations' distance over the switch panel's slices "
              "(default: station_step)", unit="m", default=OPTIONAL, minimum=1e-4, maximum=1.0),
        Field("crossing_station_step", "the stations' distance over the crossing panel's slices "
              "(wing rail, nose, check rail; default: 5 mm, or station_step if finer: "
              "railexu.track.variable_rails.FILE_CROSSING_STATION_STEP_M, fine enough for the "
              "contact filter): finer stations where the rails move laterally fastest",
              unit="m", default=OPTIONAL, minimum=1e-4, maximum=1.0),
        Field("contact_filter", "the station tables averaged along the track over this length "
              "(a contact patch's, railexu's assumption; 0: not filtered; default: 12 mm, "
              "railexu.track.variable_rails.FILE_CONTACT_FILTER_M, applied at the wheelset: "
              "the crossing's peaks converge with 5 mm stations or finer)", unit="m",
              default=OPTIONAL, minimum=0.0, maximum=0.1),
    ),
    "A turnout as the track: its route and direction (docs/switches-and-crossings.md, "
    "'The turnout'). Generates `geometry` and `variable_rails`: give neither with it.",
)  # fmt: skip

#: The design file's switch panel (``switch:``): the planing rule, railexu's assumptions.
SWITCH = Schema(
    "switch",
    (
        Field("tip_width", "the blade's head width at the toe (railexu's assumption)", unit="m",
              default=0.006, minimum=0.0005, maximum=0.05),
        Field("tip_drop", "the blade's top below the stock rail's at the toe (railexu's "
              "assumption)", unit="m", default=0.010, minimum=0.0, maximum=0.05),
        Field("rise_length", "length over which the blade rises linearly to full height "
              "(railexu's assumption)", unit="m", default=3.5, minimum=0.1, maximum=30.0),
        Field("runout", "how far ahead of the toe the switch panel's slices begin (the plain "
              "rail there)", unit="m", default=0.2, minimum=0.01, maximum=5.0),
        Field("stock_reach", "divergence beyond which the other route's rail is dropped "
              "(beyond any wheel's field face; railexu's assumption)", unit="m", default=0.13,
              minimum=0.02, maximum=1.0),
        Field("slice_step", "spacing of the generated slices", unit="m", default=0.025,
              minimum=0.01, maximum=2.0),
    ),
    "The switch panel's blade and stock rail, generated from the track's rail "
    "(railexu.profiles.variable.switch_panel).",
)  # fmt: skip

#: The design file's crossing panel (``crossing:``).
CROSSING = Schema(
    "crossing",
    (
        Field("slices", "the crossing's slices (.slcs or YAML), relative to the design file",
              "text"),
        Field("text_unit", "unit of the slices' text profiles", "text", default="mm",
              choices=("mm", "m")),
        Field("check_rail", "the check rail's slices beside the opposite running rail (.slcs "
              "or YAML, relative to the design file; default none)", "text", default=OPTIONAL),
        Field("rail_origin", "(y, z) of the slices' origin in the track's left-type axes "
              "(default: the track's rail's own origin: the slices in its axes)", "vector",
              unit="m", components=("y", "z"), minimum=-2.0, maximum=2.0, default=OPTIONAL),
        Field("s0_from_intersection", "track distance from the intersection of the gauge lines "
              "to the slices' s = 0 (railexu's assumption)", unit="m", default=0.0,
              minimum=-5.0, maximum=5.0),
    ),
    "The crossing panel: the crossing's slices (wing rail and nose) on the route's crossing "
    "side, the check rail's beside the opposite running rail.",
)  # fmt: skip

#: The turnout design file (``tracks/turnouts/*.yaml``).
DESIGN = Schema(
    "turnout design",
    (
        Field("format_version", "format of the file (1)", "integer", choices=(1,)),
        Field("name", "the design's name", "text"),
        Field("description", "its sources", "text", default=""),
        Field("radius", "radius of the diverging route's centre line through the switch and "
              "the closure (tangential at the toe)", unit="m", minimum=50.0, maximum=10_000.0),
        Field("crossing_angle", "crossing rate 1:N (the tangent of the crossing angle), "
              "written '1:9.25'", "text"),
        Field("hand", "the side the diverging route leaves to, seen from the toe", "text",
              choices=("left", "right")),
        Field("station_step", "distance between the stations whose kernel tables are blended",
              unit="m", default=0.05, minimum=1e-3, maximum=1.0),
        Field("effective_length", "half-length of the effective section", unit="m",
              default=0.06, minimum=0.0, maximum=0.2),
        Field("switch", "the switch panel's planing rule", "section", default={},
              schema=SWITCH),
        Field("crossing", "the crossing panel", "section", schema=CROSSING),
    ),
    "A turnout design: radius, crossing angle, hand, the switch panel's planing rule and the "
    "crossing's slices.",
)  # fmt: skip
