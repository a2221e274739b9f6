"""One test zone of an acceptance programme as a study: its sections' tracks and runs.

Every section of a zone (:meth:`railexu.assessment.acceptance.programme.Zone.sections`) is one
case of a study (``docs/study-format.md``) whose cases vary the section's conditions together
(``combine: zip``): on curves the radius, the direction and the speed (cant deficiency), on
every zone the irregularities' seed and amplitude scale (the section's track quality). The
study file and its base track file are written into the zone's folder, so that a zone can be
inspected, re-run or resumed like any study (``railexu study DIR/zones/NAME/study.yaml``).

The section's track (railexu's choice, stated in ``docs/acceptance.md``):

- straight zones: straight track with the section's irregularities;
- curve zones: the section's entry transition (clothoid with a linear cant ramp, its length
  ``SectionSpec.transition_m`` from the zone's cant-gradient and cant-rate limits, varied per
  case), then one curve of the section's radius, cant and direction, long enough for the run
  and the vehicle; the zone's ``run_in`` of full curve lets the vehicle settle before the
  evaluation window. (A vehicle started inside the curve starts away from its curving
  equilibrium: its wheel loads start transferred the wrong way, and in R 150 m it derails.);
- the rail profile, inclination and gauge of the programme's base track (UIC60 1:40, 1435 mm by
  default).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

if TYPE_CHECKING:
    from railexu.assessment.acceptance.programme import SectionSpec, Zone

#: Track beyond the run's distance, for the wheelsets ahead of the reference point [m].
TRACK_MARGIN_M = 150.0
#: Distance run beyond the evaluation window's end, so that the window lies inside the record [m].
RUN_MARGIN_M = 1.0
#: The rails and gauge of every section's track (a programme does not change them).
BASE_RAILS = {"rail_profile": "UIC60", "inclination": "1:40", "gauge": "1.435 m"}


def section_distance_m(section: SectionSpec) -> float:
    """The run's distance: run-in, evaluation window and a margin [m]."""
    return section.evaluate_to_m + RUN_MARGIN_M


def start_lead_m(vehicle: Any) -> float:
    """The straight before a curve section's transition: the vehicle's wheelbase plus the 1 m
    by which a run starts its rearmost wheelset past the track's start, so that the whole
    vehicle starts (in its static equilibrium) on straight track and its leading wheelset
    enters the transition at distance 0; every measurement point passes the transition's start
    (EN 12299 P_CT)."""
    xs = [w.position_x_m for w in vehicle.wheelsets]
    return max(xs) - min(xs) + 1.0


def curve_key(lead_m: float = 0.0) -> str:
    """The study key of the curve piece of :func:`zone_track` (after the lead, if any)."""
    return f"track.geometry.sections.{2 if lead_m > 0.0 else 1}"


def transition_key(lead_m: float = 0.0) -> str:
    """The study key of the entry transition of :func:`zone_track`."""
    return f"track.geometry.sections.{1 if lead_m > 0.0 else 0}"


def zone_track(zone: Zone, sections: list[SectionSpec], lead_m: float = 0.0) -> dict[str, Any]:
    """The base track of the zone's study (the first section's conditions; the cases vary
    them); with ``lead_m`` (:func:`start_lead_m`) a straight of that length before a curve
    section's transition."""
    first = sections[0]
    length = max(section_distance_m(s) for s in sections) + TRACK_MARGIN_M
    if zone.kind == "curve":
        lead = [{"type": "straight", "length": f"{lead_m:.3f} m"}] if lead_m > 0.0 else []
        geometry: dict[str, Any] = {
            "type": "sections",
            "cant_base": "1.5 m",
            "sections": [
                *lead,
                {"type": "transition", "length": f"{first.transition_m:.3f} m"},
                {
                    "type": "curve",
                    "length": f"{length:.3f} m",
                    "radius": f"{first.radius_m:.6g} m",
                    "cant": f"{first.cant_m * 1000.0:.6g} mm",
                    "direction": first.direction,
                },
            ],
        }
    else:
        geometry = {"type": "straight"}
    return {
        "format_version": 1,
        "name": f"acceptance zone {zone.name}",
        "description": f"the sections of test zone {zone.name} (written by railexu acceptance)",
        **BASE_RAILS,
        "geometry": geometry,
        "irregularities": dict(first.irregularities),
    }


def zone_study(
    zone: Zone,
    sections: list[SectionSpec],
    vehicle_file: Path,
    vehicle_overrides: tuple[str, ...] = (),
    name: str = "",
    run_settings: dict[str, str] | None = None,
    lead_m: float = 0.0,
) -> dict[str, Any]:
    """The study mapping of a zone: one case per section, conditions varied together;
    ``run_settings`` adds keys of the run file's ``run:`` section to every case (e.g.
    ``{"time_step": "1 ms"}`` for a step-size study); ``lead_m`` as :func:`zone_track`'s."""
    parameters: dict[str, list] = {}
    if zone.kind == "curve":
        key = curve_key(lead_m)
        parameters[f"{key}.radius"] = [f"{s.radius_m:.6g} m" for s in sections]
        parameters[f"{key}.direction"] = [s.direction for s in sections]
        parameters[f"{transition_key(lead_m)}.length"] = [
            f"{s.transition_m:.3f} m" for s in sections
        ]
    irr = "track.irregularities"
    parameters[f"{irr}.seed"] = [int(s.irregularities["seed"]) for s in sections]
    parameters[f"{irr}.amplitude_scale"] = [
        float(s.irregularities.get("amplitude_scale", 1.0)) for s in sections
    ]
    parameters["run.speed"] = [f"{s.speed_m_per_s:.6g} m/s" for s in sections]
    parameters["run.distance"] = [f"{section_distance_m(s):.3f} m" for s in sections]
    distance = max(section_distance_m(s) for s in sections)
    base: dict[str, Any] = {
        "vehicle": str(vehicle_file),
        "track": "track.yaml",
        "run": {"distance": f"{distance:.3f} m", "initial_lateral": "0 mm"}
        | dict(run_settings or {}),
    }
    if vehicle_overrides:
        base["set"] = [f"vehicle.{item}" for item in vehicle_overrides]
    return {
        "format_version": 1,
        "name": name or f"acceptance zone {zone.name}",
        "description": f"EN 14363 test zone {zone.name}: one case per section",
        "analysis": "run",
        "base": base,
        "vary": {"combine": "zip", "parameters": parameters},
        "collect": ["max_Y_over_Q.value", "hunting.detected"],
    }


def write_zone_files(folder: Path, track: dict, study: dict) -> Path:
    """Write ``track.yaml`` and ``study.yaml`` into ``folder`` (created); returns the study
    file. Files are replaced only if their content changes (a resumed zone keeps its cases)."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in (("track.yaml", track), ("study.yaml", study)):
        text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True)
        path = folder / name
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            tmp = path.with_suffix(".tmp")
            tmp.write_text(text, encoding="utf-8")
            tmp.replace(path)
    return folder / "study.yaml"
