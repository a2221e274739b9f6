"""The track file's ``turnout:`` section: a turnout's route as the track (issue 29).

Reads the section and the design file it names (:mod:`railexu.track.turnout_schema`), and
builds the route's geometry (:func:`railexu.track.turnout.route_layout`, as a ``sections``
geometry) and its variable rails: on the side of the route's switch and crossing a
:class:`~railexu.profiles.variable.zoned.ZonedProfile` with the switch panel (generated from the
track's rail, :mod:`railexu.profiles.variable.switch_panel`) and the crossing panel
(:func:`crossing_slices`), the track's rail between them. Every refusal names the file, the
line and the key.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from railexu.contact.placement import place_wheel_rail
from railexu.inputs import InputError, Section, load_yaml, resolve_file
from railexu.profiles import ProfileError, rail_profile
from railexu.profiles.variable import ProfileSlices, VariableProfile, read_slcs, read_yaml_slices
from railexu.profiles.variable.switch_panel import (
    SwitchPlaning,
    extended_gauge_face,
    switch_panel_slices,
)
from railexu.profiles.variable.zoned import Panel, ZonedProfile
from railexu.track.turnout import RouteLayout, TurnoutGeometry, parse_crossing_rate, route_layout
from railexu.track.turnout_schema import DESIGN, TURNOUT
from railexu.track.variable_rails import VariableRails
from railexu.track.variable_rails_file import reversed_slices

#: Lateral spacing of the plain rail's points given to the slices [m].
RAIL_POINT_STEP_M = 5.0e-5


def crossing_slices(design: dict, route: str, direction: str) -> ProfileSlices:
    """The crossing's slices for a route and a direction of travel.

    Today the slices main ships (the S&C benchmark's UK crossing, slices 41-60: CONTACT's
    ``uk_interrupt_v2.slcs``) for both routes: each side's profile is in its own axes, so the
    diverging route's crossing (on the other side) is the same slices. Trailing runs them in
    reverse (``s -> -s``). The whole crossing with its check rail replaces the slice set here.

    Args:
        design: the design as read (:func:`read_design`), its ``crossing`` section resolved.
        route: ``through`` or ``diverging`` (the same slices today).
        direction: ``facing`` or ``trailing``.
    """
    c = design["crossing"]
    file = Path(c["slices"])
    if file.suffix.lower() == ".slcs":
        slices = read_slcs(file, scale_to_mm=1000.0 if c["text_unit"] == "m" else 1.0)
    else:
        slices = read_yaml_slices(file)
    del route  # one slice set serves both routes until the whole crossing ships
    return reversed_slices(slices) if direction == "trailing" else slices


def read_design(name: str, base_dir: Path | None, sec: Section) -> dict:
    """The design file named by the track's ``turnout.design`` (refusals at that key)."""
    file = Path(resolve_file(name, base_dir))
    if not file.is_file():
        sec.fail(f"turnout design {str(file)!r} not found", key="design")
    data, lines = load_yaml(file)
    top = DESIGN.wrap(data, str(file), lines)
    d = DESIGN.read_all(top)
    try:
        d["crossing_n"] = parse_crossing_rate(d["crossing_angle"])
    except ValueError as exc:
        top.fail(str(exc), key="crossing_angle")
    slices = Path(resolve_file(d["crossing"]["slices"], file.parent))
    if not slices.is_file():
        top.fail(f"crossing slices {str(slices)!r} not found", key="crossing")
    d["crossing"]["slices"] = str(slices)
    d["source"] = str(file)
    d["section"] = top
    return d


def turnout_from_dict(
    data, source: str, lines: dict, base_dir: Path | None, rail: str, inclination, gauge_m: float
) -> tuple[dict, VariableRails, RouteLayout]:
    """The geometry section (``{type: sections, ...}``), the variable rails and the layout of
    a track file's ``turnout:`` section.

    Raises:
        InputError: naming the file, the line and the key.
    """
    sec = TURNOUT.wrap(data, source, lines, ("turnout",))
    t = TURNOUT.read_all(sec)
    design = read_design(t["design"], base_dir, sec)
    dsec = design["section"]
    geometry = TurnoutGeometry(design["radius"], design["crossing_n"], gauge_m)
    try:
        crossing = crossing_slices(design, t["route"], t["direction"])
        facing = crossing if t["direction"] == "facing" else reversed_slices(crossing)
    except ProfileError as exc:
        dsec.fail(str(exc), key="crossing")
    layout = route_layout(
        geometry, t["route"], t["direction"], design["hand"], approach_m=t["approach"],
        run_out_m=t["run_out"], s0_from_ip_m=design["crossing"]["s0_from_intersection"],
        crossing_range_m=(float(facing.positions_m[0]), float(facing.positions_m[-1])),
    )  # fmt: skip
    pair = _placed_rail(rail, inclination, gauge_m, sec)
    zoned, start = _zoned_profile(design, t, layout, crossing, pair, geometry, sec)
    step = t["station_step"] if t["station_step"] is not None else design["station_step"]
    side = {layout.side: zoned}
    rails = VariableRails(
        left=side.get("left"), right=side.get("right"), start_m=start,
        station_step_m=step,
        x_max_m=design["effective_length"],
    )  # fmt: skip
    geometry_section = {"type": "sections", "sections": [dict(p) for p in layout.sections]}
    return geometry_section, rails, layout


def _zoned_profile(design, t, layout, crossing, pair, geometry, sec) -> tuple[ZonedProfile, float]:
    """The route side's panels (switch from the track's rail, crossing slices) along the
    zone, the plain rail between, and the track distance of the zone's first slice [m]."""
    y = np.arange(pair.rail.y_min, pair.rail.y_max, RAIL_POINT_STEP_M)
    head = np.column_stack([y, -pair.rail.height(y)])
    plain = extended_gauge_face(head)  # as the switch panel's slices continue it
    panels = []
    if t["panels"] in ("both", "switch"):
        try:
            planing = SwitchPlaning(**{f"{k}_m": v for k, v in design["switch"].items()})
            sw = switch_panel_slices(head, geometry.switch_rail_radius_m(t["route"]), planing,
                                     f"{design['source']} (switch panel)")  # fmt: skip
        except ProfileError as exc:
            design["section"].fail(str(exc), key="switch")
        sw = reversed_slices(sw) if layout.reversed else sw
        panels.append(Panel(VariableProfile(sw), layout.toe_m))
    if t["panels"] in ("both", "crossing"):
        oy, oz = design["crossing"]["rail_origin"]
        y0, z0 = pair.rail_origin_track_m
        panels.append(Panel(VariableProfile(crossing), layout.crossing_s0_m, (oy - y0, z0 - oz)))
    start = min(p.range_m[0] for p in panels)
    panels = [Panel(p.profile, p.s0_m - start, p.offset_m) for p in panels]
    try:
        zoned = ZonedProfile(panels, plain, f"{design['source']} ({t['route']}, {t['direction']})")
    except ProfileError as exc:
        sec.fail(str(exc), key="design")
    return zoned, start


def _placed_rail(rail: str, inclination, gauge_m: float, sec: Section):
    """The track's rail placed as the dynamics places it (its origin in track axes); refused
    if the placement turns it (the crossing's slices are pre-canted like MBench_UIC60 at 1:40,
    and the panels are shifted, not turned, into the rail's axes)."""
    try:
        pair = place_wheel_rail("S1002", rail_profile(rail), nominal_radius_m=0.46,
                                inclination=inclination, gauge_m=gauge_m)  # fmt: skip
    except InputError as exc:
        sec.fail(str(exc))
    if abs(pair.rail_cant_rad) > 1e-12:
        sec.fail(f"the track's rail {rail!r} is turned by {pair.rail_cant_rad:.4f} rad at this "
                 "inclination: a turnout needs a rail profile given at its inclination (the "
                 "crossing's slices are pre-canted: MBench_UIC60 at 1:40)")  # fmt: skip
    return pair


__all__ = ["crossing_slices", "read_design", "turnout_from_dict"]
