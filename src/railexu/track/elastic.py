"""The track's own dynamics: rigid (default) or elastic with co-running rail masses.

``track_model: {type: elastic, ...}`` in a track file gives every rail under every wheelset a
mass that runs along with the wheelset, held to the ground by a lateral and a vertical spring
and damper: the simplest elastic track, as GENSYS and SIMPACK offer it (the "moving track
section" of Knothe & Grassie 1993, Modelling of railway track and vehicle/track interaction at
high frequencies, Vehicle System Dynamics 22, 209-262, reduced to one mass per rail and
wheel). The rail masses' coordinates are measured from their statically loaded position.

Defaults (per rail and wheelset; docs/curving.md gives the sources and the mapping):

- vertical stiffness 81 MN/m: the static point stiffness of the ballasted track of Zhai, Wang &
  Lin (2004, Modelling and experiment of railway ballast vibrations, J. Sound Vib. 270,
  673-683) as a beam on a Winkler foundation (Hetenyi 1946): ``2 s / beta``;
- mass 150 kg: between the kinetic-energy-equivalent masses of that track's rail (79 kg) and of
  its rail and sleepers (166 kg);
- lateral 32 MN/m and 80 kN s/m, vertical damping 110 kN s/m: the fastener of Huo & Dai (2019,
  Formulation of a linearized model for vehicle-track interactions, Shock and Vibration 2019,
  2015465, Table 2) on a 60 kg/m rail by the same mapping (a slab track's fastener: ballasted
  track is laterally softer); set measured or published values for a project.
"""

from __future__ import annotations

from dataclasses import dataclass

from railexu.inputs import Section
from railexu.track.schema import TRACK_MODEL

# defaults: declared once, in the track file's schema
_D = TRACK_MODEL["elastic"].default

TRACK_MODELS = ("rigid", "elastic")
ELASTIC_KEYS = (
    "type",
    "rail_mass",
    "lateral_stiffness",
    "lateral_damping",
    "vertical_stiffness",
    "vertical_damping",
)


@dataclass(frozen=True)
class ElasticTrack:
    """Co-running rail masses, per rail and wheelset (SI units)."""

    rail_mass_kg: float = _D("rail_mass")
    lateral_stiffness_N_per_m: float = _D("lateral_stiffness")
    lateral_damping_N_s_per_m: float = _D("lateral_damping")
    vertical_stiffness_N_per_m: float = _D("vertical_stiffness")
    vertical_damping_N_s_per_m: float = _D("vertical_damping")


def track_model_from_dict(
    data: dict | str | None, source: str = "<track>", lines: dict | None = None
) -> ElasticTrack | None:
    """Validate a track file's ``track_model`` entry: ``rigid`` (or absent) gives None,
    ``elastic`` (a string or a mapping with ``type: elastic`` and optional values) an
    :class:`ElasticTrack`.

    Raises:
        railexu.errors.InputError: naming file, line and key.
    """
    if data is None:
        return None
    if isinstance(data, str):
        data = {"type": data}
    sec = Section(data, source, lines, ("track_model",))
    kind = sec.string("type", default="rigid", choices=TRACK_MODELS)
    if kind == "rigid":
        Section(data, source, lines, ("track_model",), ("type",))
        return None
    sec = Section(data, source, lines, ("track_model",), ELASTIC_KEYS)
    schema = TRACK_MODEL["elastic"]  # units, defaults and ranges (track/schema.py)
    return ElasticTrack(
        rail_mass_kg=schema.read(sec, "rail_mass"),
        lateral_stiffness_N_per_m=schema.read(sec, "lateral_stiffness"),
        lateral_damping_N_s_per_m=schema.read(sec, "lateral_damping"),
        vertical_stiffness_N_per_m=schema.read(sec, "vertical_stiffness"),
        vertical_damping_N_s_per_m=schema.read(sec, "vertical_damping"),
    )
