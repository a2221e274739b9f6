"""The track file's ``turnout:`` section: a turnout's route as the track (issue 29).

Reads the section and the design file it names (:mod:`railexu.track.turnout_schema`), and
builds the route's geometry (:func:`railexu.track.turnout.route_layout`, as a ``sections``
geometry) and its variable rails: on the side of the route's switch and crossing a
:class:`~railexu.profiles.variable.zoned.ZonedProfile` with the switch panel (generated from the
track's rail, :mod:`railexu.profiles.variable.switch_panel`) and the crossing panel
(:func:`crossing_slices`: the whole crossing) and on the other side the check rail, the
track's rail between them. Every refusal names the file, the
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
from railexu.track.variable_rails import (
    FILE_CONTACT_FILTER_M,
    FILE_CROSSING_STATION_STEP_M,
    VariableRails,
)
from railexu.track.variable_rails_file import reversed_slices

#: Lateral spacing of the plain rail's points given to the slices [m].
RAIL_POINT_STEP_M = 5.0e-5


def _read_slices(file: Path, text_unit: str) -> ProfileSlices:
    """A slices file (CONTACT ``.slcs`` or railexu's YAML)."""
    if file.suffix.lower() == ".slcs":
        return read_slcs(file, scale_to_mm=1000.0 if text_unit == "m" else 1.0)
    return read_yaml_slices(file)


def crossing_slices(
    design: dict, route: str, direction: str
) -> tuple[ProfileSlices, ProfileSlices | None]:
    """The crossing's slices (wing rail and nose) and the check rail's (None: no check rail)
    for a route and a direction of travel.

    The shipped design names the whole crossing (``tracks/uk_crossing/uk_crossing_full.yaml``,
    plain rail to plain rail) and its check rail (``check_rail_thr.yaml``), given for the
    through route. The diverging route's crossing is its mirror image about the crossing's
    bisector (railexu's assumption, docs/switches-and-crossings.md "The turnout"): as each
    side's profile is in its own axes (field side positive), the mirror image is the same
    slices on the other side of the track, which :func:`route_layout` gives (``side``). Trailing
    runs them in reverse (``s -> -s``).

    Args:
        design: the design as read (:func:`read_design`), its ``crossing`` section resolved.
        route: ``through`` or ``diverging`` (the same slices, mirrored by the side).
        direction: ``facing`` or ``trailing``.
    """
    c = design["crossing"]
    del route  # the diverging route's crossing: the same slices on the other side
    crossing = _read_slices(Path(c["slices"]), c["text_unit"])
    check = None if c["check_rail"] is None else _read_slices(Path(c["check_rail"]), c["text_unit"])
    if direction == "trailing":
        crossing = reversed_slices(crossing)
        check = None if check is None else reversed_slices(check)
    return crossing, check


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
    for key, what in (("slices", "crossing slices"), ("check_rail", "check rail slices")):
        if d["crossing"][key] is None:
            continue
        slices = Path(resolve_file(d["crossing"][key], file.parent))
        if not slices.is_file():
            top.fail(f"{what} {str(slices)!r} not found", key="crossing")
        d["crossing"][key] = str(slices)
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
    except ProfileError as exc:
        dsec.fail(str(exc), key="crossing")
    reach = [(float(c.positions_m[0]), float(c.positions_m[-1])) for c in crossing if c]
    lo, hi = min(r[0] for r in reach), max(r[1] for r in reach)
    layout = route_layout(
        geometry, t["route"], t["direction"], design["hand"], approach_m=t["approach"],
        run_out_m=t["run_out"], s0_from_ip_m=design["crossing"]["s0_from_intersection"],
        crossing_range_m=(lo, hi) if t["direction"] == "facing" else (-hi, -lo),
    )  # fmt: skip
    pair = _placed_rail(rail, inclination, gauge_m, sec)
    side, start, spans = _zoned_profiles(design, t, layout, crossing, pair, geometry, sec)
    step = t["station_step"] if t["station_step"] is not None else design["station_step"]
    if t["crossing_station_step"] is None:  # fine enough for the contact filter
        t = {**t, "crossing_station_step": min(FILE_CROSSING_STATION_STEP_M, step)}
    rails = VariableRails(
        left=side.get("left"), right=side.get("right"), start_m=start,
        station_step_m=step,
        x_max_m=design["effective_length"],
        station_steps_m=panel_station_steps(spans, t, step),
        contact_filter_m=_or(t["contact_filter"], FILE_CONTACT_FILTER_M),
    )  # fmt: skip
    too_many = rails.too_many_stations()
    if too_many:
        sec.fail(f"{too_many} (station_step, switch_station_step, crossing_station_step)")
    geometry_section = {"type": "sections", "sections": [dict(p) for p in layout.sections]}
    return geometry_section, rails, layout


def panel_station_steps(
    spans: dict[str, list[tuple[float, float]]], t: dict, default_step_m: float
) -> tuple[tuple[float, float, float], ...]:
    """The parts of the zone with their own station step (``turnout.switch_station_step``,
    ``crossing_station_step``): ``(from, to, step)`` [m] over each panel's slices in track
    distances (``spans``: per panel kind its panels' ranges; the crossing's: its wing rail and
    nose and the check rail together). A panel's step equal to the zone's ``default_step_m``
    (``station_step``) is no part of its own: the zone stays uniform (the stations every
    ``station_step`` from its start)."""
    parts = []
    for kind, ranges in spans.items():
        step = t[f"{kind}_station_step"]
        if step is not None and ranges and step != default_step_m:
            parts.append((min(a for a, _ in ranges), max(b for _, b in ranges), step))
    return tuple(parts)


def _zoned_profiles(
    design, t, layout, crossing, pair, geometry, sec
) -> tuple[dict[str, ZonedProfile], float, dict[str, list[tuple[float, float]]]]:
    """Each side's panels along the zone, the plain rail between, the track distance of the
    zone's first slice [m] and per panel kind (``switch``, ``crossing``) the track distances of
    its panels' first and last slices [m]: on the route's side the switch panel (generated from
    the track's rail) and the crossing (wing rail and nose), on the other side the check rail
    beside the opposite running rail (:func:`crossing_slices`)."""
    y = np.arange(pair.rail.y_min, pair.rail.y_max, RAIL_POINT_STEP_M)
    head = np.column_stack([y, -pair.rail.height(y)])
    plain = extended_gauge_face(head)  # as the switch panel's slices continue it
    other = {"left": "right", "right": "left"}[layout.side]
    panels: dict[str, list[Panel]] = {layout.side: [], other: []}
    spans: dict[str, list[tuple[float, float]]] = {"switch": [], "crossing": []}
    if t["panels"] in ("both", "switch"):
        try:
            planing = SwitchPlaning(**{f"{k}_m": v for k, v in design["switch"].items()})
            sw = switch_panel_slices(head, geometry.switch_rail_radius_m(t["route"]), planing,
                                     f"{design['source']} (switch panel)")  # fmt: skip
        except ProfileError as exc:
            design["section"].fail(str(exc), key="switch")
        sw = reversed_slices(sw) if layout.reversed else sw
        panels[layout.side].append(Panel(VariableProfile(sw), layout.toe_m))
        spans["switch"].append(panels[layout.side][-1].range_m)
    if t["panels"] in ("both", "crossing"):
        origin = design["crossing"]["rail_origin"]
        y0, z0 = pair.rail_origin_track_m
        shift = (0.0, 0.0) if origin is None else (origin[0] - y0, z0 - origin[1])
        nose, check = crossing
        panels[layout.side].append(Panel(VariableProfile(nose), layout.crossing_s0_m, shift))
        spans["crossing"].append(panels[layout.side][-1].range_m)
        if check is not None:
            panels[other].append(Panel(VariableProfile(check), layout.crossing_s0_m, shift))
            spans["crossing"].append(panels[other][-1].range_m)
    start = min(p.range_m[0] for side in panels.values() for p in side)
    zoned = {}
    for name, side in panels.items():
        if not side:
            continue
        moved = [Panel(p.profile, p.s0_m - start, p.offset_m) for p in side]
        label = f"{design['source']} ({t['route']}, {t['direction']}, {name})"
        try:
            zoned[name] = ZonedProfile(moved, plain, label)
        except ProfileError as exc:
            sec.fail(str(exc), key="design")
    return zoned, start, spans


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


def _or(value: float | None, default: float) -> float:
    """``value`` if the file gives it, else ``default``."""
    return default if value is None else value
