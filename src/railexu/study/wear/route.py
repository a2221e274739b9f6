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
negated (the route's tracks have no irregularities, so there are none to mirror); the wear of
the simulated left wheel is the real right wheel's and the other way round
(:mod:`.route_study`). The shares are normalised to sum to 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from railexu.errors import InputError
from railexu.inputs.reader import load_yaml
from railexu.inputs.section import suggest
from railexu.units import to_si

#: straight lead-in before every section [m]
LEAD_M = 10.0
#: transition (clothoid, linear cant ramp) before a curve [m]
TRANSITION_M = 20.0
#: settling after the transition before the evaluation window starts [m]
SETTLE_M = 5.0
DIRECTIONS = ("forward", "reverse", "both")
_KEYS = ("name", "share", "speed", "length", "radius", "cant", "directions")


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
            "irregularities": {"type": "none"},
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
                           "inclination", "gauge", "sections"}  # fmt: skip
    if unknown:
        key = sorted(unknown)[0]
        raise InputError("unknown key", source=src, line=lines.get((key,)), key=key)
    sections = data.get("sections")
    if not isinstance(sections, list) or not sections:
        raise InputError("expected a list of sections", source=src,
                         line=lines.get(("sections",)), key="sections")  # fmt: skip
    gauge = _number(data.get("gauge", 1.435), "m", src, lines.get(("gauge",)), "gauge", 1.0, 1.7)
    cases: list[RouteCase] = []
    for i, sec in enumerate(sections):
        cases.extend(_section_cases(sec, i, src, lines))
    total = sum(c.share for c in cases)
    if not total > 0.0:
        raise InputError("the shares sum to 0", source=src, key="sections")
    cases = [
        RouteCase(c.name, c.share / total, c.speed_m_per_s, c.length_m, c.radius_m, c.cant_m,
                  c.direction)
        for c in cases
    ]  # fmt: skip
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
