"""The track file's ``variable_rails:`` section: a switch-and-crossing zone (issue 29).

Reads the keys declared in :mod:`railexu.track.variable_rails_schema` into a
:class:`~railexu.track.variable_rails.VariableRails`: per side a CONTACT ``.slcs`` file or
railexu's YAML slices (:mod:`railexu.profiles.variable`), resolved relative to the track file;
``direction: trailing`` runs the slices in reverse (``s -> -s``); ``station_steps:`` gives
parts of the zone their own station step (in the slices' own ``s``, mapped to track distances;
a trailing zone's grids run backwards so its stations mirror the facing zone's). Every refusal is an
:class:`~railexu.errors.InputError` naming the track file, the line and the key (and, for a bad
slices file, that file's own message: its line and slice).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from railexu.inputs import Section, resolve_file
from railexu.profiles.core import ProfileError
from railexu.profiles.variable import ProfileSlices, VariableProfile, read_slcs, read_yaml_slices
from railexu.track.variable_rails import FILE_CONTACT_FILTER_M, VariableRails
from railexu.track.variable_rails_schema import (
    MAX_STATION_STEP_M,
    MAX_ZONE_LENGTH_M,
    MIN_STATION_STEP_M,
    STATION_STEP_KEYS,
    VARIABLE_RAILS,
)

_SLICES = VARIABLE_RAILS["slices"]
_KEYS = ("type", *_SLICES.keys())
_READ_APART = ("rail_origin", "station_steps")


def variable_rails_from_dict(
    data, source: str, lines: dict, base_dir: Path | None, track_end_m: float | None,
    track_start_m: float = 0.0,
) -> VariableRails | None:  # fmt: skip
    """Validate a track file's ``variable_rails:`` section (absent or ``type: none``: None).

    Args:
        data: the section as read (a mapping, ``"none"`` or None).
        source, lines: the track file and its line numbers (for messages).
        base_dir: folder of the track file (slices files are relative to it).
        track_end_m: end of the track's geometry [m] (None: unbounded, a straight track).
        track_start_m: the track's ``start`` [m]: a run starts 1 m beyond it, outside the zone.

    Raises:
        InputError: naming the file, the line and the key.
    """
    if data is None or data == "none":
        return None
    if isinstance(data, str):
        data = {"type": data}
    top = Section(data, source, lines, ("variable_rails",))
    kind = top.string("type", choices=tuple(VARIABLE_RAILS))
    if kind == "none":
        Section(data, source, lines, ("variable_rails",), ("type",))
        return None
    sec = Section(data, source, lines, ("variable_rails",), _KEYS)
    p = _SLICES.read_all(sec, [k for k in _SLICES.by_key if k not in _READ_APART])
    origin = _SLICES.read(sec, "rail_origin") if sec.has("rail_origin") else None
    if p["left"] is None and p["right"] is None:
        sec.fail("expected a slices file for the left or the right rail (or both)")
    scale = 1000.0 if p["text_unit"] == "m" else 1.0
    sides = [
        None if p[side] is None else _profile(sec, side, p[side], base_dir, scale, p["direction"])
        for side in ("left", "right")
    ]
    rails = VariableRails(
        left=sides[0], right=sides[1], start_m=p["start"], station_step_m=p["station_step"],
        rail_origin_m=None if origin is None else (origin[0], origin[1]),
        x_max_m=p["effective_length"],
        contact_filter_m=_or(p["contact_filter"], FILE_CONTACT_FILTER_M),
    )  # fmt: skip
    _check_zone(sec, rails, track_start_m, track_end_m)
    if sec.has("station_steps"):
        trailing = p["direction"] == "trailing"
        parts = station_step_parts(sec, rails, trailing)
        rails = replace(rails, station_steps_m=parts, grids_from_end=trailing and bool(parts))
    too_many = rails.too_many_stations()
    if too_many:
        sec.fail(too_many, key="station_steps" if sec.has("station_steps") else "station_step")
    return rails


def station_step_parts(
    sec: Section, rails: VariableRails, trailing: bool
) -> tuple[tuple[float, float, float], ...]:
    """The zone's ``station_steps:`` as ``(from, to, step)`` in track distances [m].

    Each part is written ``{from, to, step}``, ``from < to`` in the slices' own ``s`` (the
    slices file's, trailing too), the parts in increasing ``s`` and not overlapping (touching
    allowed), within the zone's slices (both sides together). A facing part maps to
    ``(start + from, start + to)``; a trailing one (``s -> -s``) to ``(start - to, start -
    from)``. Refusals name the part (``variable_rails.station_steps.<k>.<key>``) and its line.
    """
    raw = sec.data["station_steps"]
    if raw is None:
        return ()
    if not isinstance(raw, list):
        sec.fail("expected a list of parts {from: ..., to: ..., step: ...}, got "
                 f"{type(raw).__name__} {raw!r}", key="station_steps")  # fmt: skip
    start = rails.start_m
    lo, hi = rails.zone_m()
    s_lo, s_hi = (start - hi, start - lo) if trailing else (lo - start, hi - start)
    parts, previous = [], None
    for k, item in enumerate(raw):
        part = Section(item, sec.source, sec.lines, (*sec.path, "station_steps", k),
                       STATION_STEP_KEYS)  # fmt: skip
        a = part.quantity("from", "m")
        b = part.quantity("to", "m")
        step = part.quantity("step", "m", minimum=MIN_STATION_STEP_M, maximum=MAX_STATION_STEP_M)
        if not a < b:
            part.fail(f"from {a:g} m is not before to {b:g} m: expected from < to (in the "
                      "slices' own s)", key="to")  # fmt: skip
        tol = 1e-9  # the slices' positions as read: metres rounded in a text file
        if a < s_lo - tol or b > s_hi + tol:
            key = "from" if a < s_lo - tol else "to"
            part.fail(f"the part {a:g} .. {b:g} m lies outside the zone's slices ({s_lo:g} .. "
                      f"{s_hi:g} m in the slices' s)", key=key)  # fmt: skip
        if previous is not None and a < previous[1]:
            what = "overlaps" if a > previous[0] else "comes before"
            part.fail(f"the part {a:g} .. {b:g} m {what} the part before it ({previous[0]:g} .. "
                      f"{previous[1]:g} m): expected parts in increasing s, not overlapping",
                      key="from")  # fmt: skip
        previous = (a, b)
        parts.append((start - b, start - a, step) if trailing else (start + a, start + b, step))
    return tuple(parts)


def _profile(
    sec: Section, side: str, name: str, base_dir: Path | None, scale: float, direction: str
) -> VariableProfile:
    """One side's variable profile, read, checked and (trailing) reversed."""
    file = Path(resolve_file(name, base_dir))
    if not file.is_file():
        what = "is a folder, not a file" if file.is_dir() else "not found"
        sec.fail(f"slices file {str(file)!r} {what}", key=side)
    suffix = file.suffix.lower()
    if suffix not in (".slcs", ".yaml", ".yml"):
        sec.fail(f"slices file {str(file)!r}: expected a CONTACT .slcs file or railexu's YAML "
                 "slices (.yaml)", key=side)  # fmt: skip
    try:
        slices = read_slcs(file, scale_to_mm=scale) if suffix == ".slcs" else read_yaml_slices(file)
        if direction == "trailing":
            slices = reversed_slices(slices)
        return VariableProfile(slices)
    except ProfileError as exc:
        sec.fail(str(exc), key=side)


def reversed_slices(slices: ProfileSlices) -> ProfileSlices:
    """The slices met in the other direction of travel: ``s -> -s``, in reverse order.

    The profiles themselves are unchanged (a rail's section does not depend on the direction of
    travel; the lateral axis stays the side's field side).
    """
    order = slice(None, None, -1)
    features = None if slices.features_m is None else slices.features_m[order].copy()
    return replace(
        slices,
        positions_m=-slices.positions_m[order],
        points_m=slices.points_m[order],
        features_m=features,
        lines=slices.lines[order],
        names=slices.names[order],
    )


def _check_zone(sec: Section, rails: VariableRails, start_m: float, end_m: float | None) -> None:
    """The zone lies on the track, after the run's start and not too long."""
    lo, hi = rails.zone_m()
    if hi - lo > MAX_ZONE_LENGTH_M:
        sec.fail(f"the zone is {hi - lo:g} m long: expected at most {MAX_ZONE_LENGTH_M:g} m "
                 "(a unit wrong in the slices file?)", key="start")  # fmt: skip
    if lo <= start_m + 1.0:
        sec.fail(f"the zone begins at {lo:g} m, not beyond the run's start ({start_m:g} m + 1 m, "
                 "where the rearmost wheelset stands): a run must start outside the zone "
                 "(its static equilibrium uses the plain rail)", key="start")  # fmt: skip
    if end_m is not None and hi > end_m:
        sec.fail(f"the zone ({lo:g} .. {hi:g} m) overlaps the track's end at {end_m:g} m",
                 key="start")  # fmt: skip


__all__ = ["reversed_slices", "station_step_parts", "variable_rails_from_dict"]


def _or(value: float | None, default: float) -> float:
    """``value`` if the file gives it, else ``default``."""
    return default if value is None else value
