"""A wear route: track sections with the share of the mileage each stands for (docs/wear.md).

A route file (YAML)::

    format_version: 1
    name: curvy line
    rail_profile: UIC60          # optional (default UIC60), inclination "1:40", gauge 1.435 m
    sections:
      - {name: straight, share: 0.5, speed: 30 m/s, length: 60 m}
      - {name: R300, share: 0.5, speed: 15 m/s, length: 60 m, radius: 300 m, cant: 150 mm,
         directions: both}

Each section is one case per direction: a straight (no ``radius``) or a circular curve of
``length`` after a 10 m straight and a transition (clothoid with a linear cant ramp) of
:data:`TRANSITION_M`; the evaluation window is the curve (or the straight after
:data:`LEAD_M`). A curve ``forward`` turns left, ``reverse`` turns right (the same curve run the
other way); ``both`` (the default) runs both, each with half the section's share. A straight's
``reverse`` is its **mirrored case** (:attr:`RouteCase.mirrored`): the left and the right wheels
exchanged, i.e. each wheelset's two wheel profiles swapped and the initial lateral offset
negated (its irregularities, if any: below); the wear of the simulated left wheel is the real
right wheel's and the other way round (:mod:`.route_study`). The shares are normalised to sum to 1.

Irregularities (docs/wear.md, "Wear spreading"): an optional ``irregularities:`` mapping at the
route's top level, or in a section to replace the route's for that section, with the keys and
meaning of a track file's (docs/track-format.md), read by the same code
(:func:`railexu.track.track.irregularity_spec`); every case's track carries its section's.
Irregularities are a property of the rails: a section's two directions run the **same** record,
seen from the other side in the reverse direction, i.e. mirrored (``mirror`` toggled: lateral
alignment and cross level negated); the record is read in the same direction of travel (a
stationary random process read backwards is a sample of the same process). A curve's
``reverse`` (the vehicle as it is on the curve of the other hand) therefore runs the mirrored
record; a straight's ``reverse`` is simulated as its mirrored case (the wheels exchanged), the
mirror image of the vehicle as it is on the mirrored record, i.e. the record **unmirrored**
(the mirror of the mirror). So a route run both ways stays left/right symmetric as on ideal
track. A route-level ``seed`` is taken as ``seed + i`` for section ``i`` (each section its own
sample); a section's own block keeps its seed as written. A synthetic record's ``length``, if
given, must cover the case's run. A section whose evaluation window is shorter than the
spectrum's ``wavelength_max`` warns (:class:`RouteWarning`): the window sees the longest waves
at one phase only.
"""

from __future__ import annotations

import copy
import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

from railexu.errors import InputError
from railexu.inputs.reader import load_yaml
from railexu.inputs.section import Section, suggest
from railexu.units import to_si

#: straight lead-in before every section [m]
LEAD_M = 10.0
#: transition (clothoid, linear cant ramp) before a curve [m]
TRANSITION_M = 20.0
#: settling after the transition before the evaluation window starts [m]
SETTLE_M = 5.0
DIRECTIONS = ("forward", "reverse", "both")
_KEYS = ("name", "share", "speed", "length", "radius", "cant", "directions", "irregularities")
_NONE = {"type": "none"}
_MAX_SEED = 2**63 - 1


class RouteWarning(UserWarning):
    """A route that runs but samples its irregularities poorly (module doc)."""


@dataclass(frozen=True)
class RouteCase:
    """One section in one direction: its track, speed and share of the mileage."""

    name: str
    share: float
    speed_m_per_s: float
    length_m: float
    radius_m: float | None
    cant_m: float
    direction: str
    #: the section's ``irregularities:`` block as the track file gets it (module doc; the
    #: forward direction's: :meth:`irregularities` gives the case's own)
    section_irregularities: dict = field(default_factory=lambda: dict(_NONE), compare=False)

    def irregularities(self) -> dict:
        """The case's track ``irregularities:`` block: the section's, mirrored (``mirror``
        toggled) for a curve's ``reverse`` (module doc); a straight's ``reverse`` (its mirrored
        case) runs the section's record as it is."""
        block = copy.deepcopy(self.section_irregularities)
        if block.get("type", "none") != "none" and self.direction == "reverse" and self.radius_m:
            block["mirror"] = not block.get("mirror", False)
        return block

    @property
    def mirrored(self) -> bool:
        """A straight run ``reverse``: run as the mirrored case (module doc; a curve's
        ``reverse`` is the curve turning the other way, the wheels as they are)."""
        return self.direction == "reverse" and not self.radius_m

    @property
    def distance_m(self) -> float:
        """The run's distance: lead-in, transition (curves), the section."""
        return LEAD_M + (TRANSITION_M if self.radius_m else 0.0) + self.length_m

    @property
    def evaluate_from_m(self) -> float:
        """Start of the evaluation window (the curve after settling, or after the lead-in)."""
        return LEAD_M + (TRANSITION_M + SETTLE_M if self.radius_m else 0.0)

    def track_data(self, route: Route) -> dict:
        """The track file's data (docs/track-format.md)."""
        sections: list[dict] = [{"type": "straight", "length": f"{LEAD_M} m"}]
        if self.radius_m:
            sections.append({"type": "transition", "length": f"{TRANSITION_M} m"})
            sections.append({
                "type": "curve", "length": f"{self.length_m + 50.0} m",
                "radius": f"{self.radius_m} m", "cant": f"{self.cant_m * 1e3} mm",
                "direction": "left" if self.direction == "forward" else "right",
            })  # fmt: skip
        else:
            sections.append({"type": "straight", "length": f"{self.length_m + 50.0} m"})
        return {
            "format_version": 1,
            "name": f"{route.name}: {self.name} ({self.direction})",
            "rail_profile": route.rail_profile,
            "inclination": route.inclination,
            "gauge": f"{route.gauge_m} m",
            "geometry": {"type": "sections", "cant_base": "1.5 m", "sections": sections},
            "irregularities": self.irregularities(),
        }

    def write_track(self, route: Route, folder: Path) -> Path:
        """Write the case's track file into ``folder``; returns its path."""
        import yaml

        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{self.name}_{self.direction}.yaml"
        path.write_text(yaml.safe_dump(self.track_data(route), sort_keys=False), "utf-8")
        return path


@dataclass(frozen=True)
class Route:
    """A route: its cases (sections by direction) with normalised shares."""

    name: str
    rail_profile: str
    inclination: str
    gauge_m: float
    cases: tuple[RouteCase, ...]
    path: str = ""


def _number(value, unit: str, source: str, line, key: str, minimum: float, maximum: float):
    try:
        x = to_si(value, unit)
    except InputError as exc:
        raise InputError(exc.detail, source=source, line=line, key=key) from None
    if not (math.isfinite(x) and minimum <= x <= maximum):
        raise InputError(
            f"{value!r}: expected {minimum:g} .. {maximum:g} {unit}", source=source, line=line,
            key=key,
        )  # fmt: skip
    return x


def load_route(path: str | Path) -> Route:
    """Read a route file (module doc).

    Raises:
        InputError: naming the file, the line, the key and what was expected.
    """
    path = Path(path)
    data, lines = load_yaml(path)
    src = str(path)
    if not isinstance(data, dict):
        raise InputError("expected a mapping with format_version, name, sections", source=src)
    if data.get("format_version") != 1:
        raise InputError("expected 1", source=src, line=lines.get(("format_version",)),
                         key="format_version")  # fmt: skip
    unknown = set(data) - {"format_version", "name", "description", "rail_profile",
                           "inclination", "gauge", "sections", "irregularities"}  # fmt: skip
    if unknown:
        key = sorted(unknown)[0]
        raise InputError("unknown key", source=src, line=lines.get((key,)), key=key)
    sections = data.get("sections")
    if not isinstance(sections, list) or not sections:
        raise InputError("expected a list of sections", source=src,
                         line=lines.get(("sections",)), key="sections")  # fmt: skip
    gauge = _number(data.get("gauge", 1.435), "m", src, lines.get(("gauge",)), "gauge", 1.0, 1.7)
    top = Section(data, src, lines)
    route_block = _irregularities(top, path.parent, None) if "irregularities" in data else None
    cases: list[RouteCase] = []
    for i, sec in enumerate(sections):
        sec_cases = _section_cases(sec, i, src, lines)
        if isinstance(sec, dict) and "irregularities" in sec:
            here = Section(sec, src, lines, ("sections", i))
            block = _irregularities(here, path.parent, sec_cases[0])
        elif route_block is not None:
            block = _irregularities(top, path.parent, sec_cases[0], seed_offset=i)
        else:
            block = dict(_NONE)
        cases.extend(replace(c, section_irregularities=block) for c in sec_cases)
    total = sum(c.share for c in cases)
    if not total > 0.0:
        raise InputError("the shares sum to 0", source=src, key="sections")
    cases = [replace(c, share=c.share / total) for c in cases]
    names = [f"{c.name}_{c.direction}" for c in cases]
    if len(set(names)) != len(names):
        raise InputError("section names must differ", source=src, key="sections")
    return Route(
        name=str(data.get("name", path.stem)),
        rail_profile=str(data.get("rail_profile", "UIC60")),
        inclination=str(data.get("inclination", "1:40")),
        gauge_m=gauge,
        cases=tuple(cases),
        path=str(path.resolve()),
    )


def _section_cases(sec, i: int, src: str, lines) -> list[RouteCase]:
    here = ("sections", i)
    if not isinstance(sec, dict):
        raise InputError("expected a mapping", source=src, line=lines.get(here),
                         key=f"sections[{i}]")  # fmt: skip
    for k in sec:
        if k not in _KEYS:
            raise InputError(
                f"unknown key.{suggest(k, _KEYS)} A section has {', '.join(_KEYS)}",
                source=src, line=lines.get((*here, k)), key=f"sections[{i}].{k}",
            )  # fmt: skip

    def get(k, unit, lo, hi, default=None):
        if k not in sec:
            if default is None:
                raise InputError("required", source=src, line=lines.get(here),
                                 key=f"sections[{i}].{k}")  # fmt: skip
            return default
        return _number(sec[k], unit, src, lines.get((*here, k)), f"sections[{i}].{k}", lo, hi)

    name = str(sec.get("name", f"section{i}"))
    if not name.replace("_", "").replace("-", "").isalnum():
        raise InputError("letters, digits, _ and - only", source=src,
                         line=lines.get((*here, "name")), key=f"sections[{i}].name")  # fmt: skip
    share = get("share", "1", 0.0, 1e6)
    speed = get("speed", "m/s", 1.0, 100.0)
    length = get("length", "m", 5.0, 10_000.0)
    radius = get("radius", "m", 100.0, 100_000.0, default=0.0) or None
    cant = get("cant", "m", 0.0, 0.2, default=0.0)
    if radius is not None and not length > SETTLE_M:
        raise InputError(
            f"{sec['length']!r}: a curve must be longer than the {SETTLE_M:g} m of settling "
            "before its evaluation window",
            source=src, line=lines.get((*here, "length")), key=f"sections[{i}].length",
        )  # fmt: skip
    if cant and radius is None:
        raise InputError("cant needs a radius (a curve)", source=src,
                         line=lines.get((*here, "cant")), key=f"sections[{i}].cant")  # fmt: skip
    directions = str(sec.get("directions", "both"))
    if directions not in DIRECTIONS:
        raise InputError(f"{directions!r}: expected {', '.join(DIRECTIONS)}", source=src,
                         line=lines.get((*here, "directions")),
                         key=f"sections[{i}].directions")  # fmt: skip
    dirs = ("forward", "reverse") if directions == "both" else (directions,)
    return [RouteCase(name, share / len(dirs), speed, length, radius, cant, d) for d in dirs]


def _irregularities(
    parent: Section, base_dir: Path, case: RouteCase | None, seed_offset: int = 0
) -> dict:
    """``parent``'s ``irregularities:`` block read by the track file's code and written back as
    the case's track gets it (module doc): a measured file's path made absolute, the seed plus
    ``seed_offset``; the checks against ``case``'s run (None: the route level, read for its
    errors only)."""
    from railexu.track.track import irregularity_spec

    spec = irregularity_spec(parent, base_dir)
    raw = parent.data["irregularities"]
    block = {"type": raw} if isinstance(raw, str) else copy.deepcopy(raw or {})
    where = Section(block, parent.source, parent.lines, (*parent.path, "irregularities"))
    if spec.type == "measured":
        block["file"] = spec.file
    if spec.type != "spectrum" or case is None:
        return block
    block["seed"] = (spec.seed + seed_offset) % (_MAX_SEED + 1)
    if spec.length_m is not None and spec.length_m < case.distance_m:
        where.fail(
            f"a record of {spec.length_m:g} m does not cover the run of section "
            f"{case.name!r} ({case.distance_m:g} m): leave length out (the run's distance "
            "+ 50 m)",
            key="length",
        )  # fmt: skip
    window = case.distance_m - case.evaluate_from_m
    if window < spec.wavelength_max_m:
        line = where.line()
        warnings.warn(
            f"{parent.source}{f':{line}' if line else ''}: section {case.name!r}: its evaluation "
            f"window ({window:g} m) is shorter than the irregularities' wavelength_max "
            f"({spec.wavelength_max_m:g} m): the window sees the longest waves at one phase "
            "only (docs/wear.md, \"Wear spreading\")",
            RouteWarning,
            stacklevel=3,
        )  # fmt: skip
    return block
