"""Track files: rail profile, inclination, gauge, geometry and irregularities.

A track file (``docs/track-format.md``) describes the rails a vehicle runs on::

    format_version: 1
    name: straight
    rail_profile: UIC60          # built-in name or a profile file (.prr, two-column text)
    inclination: "1:40"
    gauge: 1.435 m
    geometry: {type: straight}   # curves are a planned extension of this section
    irregularities:
      type: spectrum             # none | spectrum | measured
      spectrum: german_low
      seed: 1
      wavelength_min: 3 m
      wavelength_max: 150 m

Only straight track is implemented; the geometry section exists so that curved track (radius,
transitions, cant) can be added without changing the format of straight-track files.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from .alignment import Alignment, alignment_from_dict
from .contact.placement import PlacementError, parse_inclination
from .inputs import InputError, Section, load_yaml_with_overrides, resolve_file
from .irregularities import (
    COMPONENTS,
    IrregularityError,
    IrregularityProfile,
    available_spectra,
    read_measured_irregularities,
    synthesize_irregularities,
)
from .profiles import ProfileError, rail_profile
from .track_model import ElasticTrack, track_model_from_dict

FORMAT_VERSION = 1
TOP_KEYS = (
    "format_version",
    "name",
    "description",
    "rail_profile",
    "inclination",
    "gauge",
    "geometry",
    "track_model",
    "irregularities",
)
IRREGULARITY_KEYS = {
    "none": ("type",),
    "spectrum": (
        "type",
        "spectrum",
        "seed",
        "wavelength_min",
        "wavelength_max",
        "components",
        "amplitude_scale",
        "length",
        "fade_length",
    ),
    "measured": ("type", "file", "fade_length"),
}


@dataclass(frozen=True)
class IrregularitySpec:
    """How to obtain the irregularities of a track (see :meth:`Track.irregularities`)."""

    type: str = "none"
    spectrum: str = ""
    seed: int = 0
    wavelength_min_m: float = 3.0
    wavelength_max_m: float = 150.0
    components: tuple[str, ...] = COMPONENTS
    amplitude_scale: float = 1.0
    length_m: float | None = None
    fade_length_m: float = 10.0
    file: str = ""


@dataclass(frozen=True)
class Track:
    """A validated track."""

    name: str
    rail_profile: str = "UIC60"
    inclination: str | float = "1:40"
    gauge_m: float = 1.435
    geometry: str = "straight"
    irregularity: IrregularitySpec = field(default_factory=IrregularitySpec)
    description: str = ""
    source: str = ""
    # design geometry (railexu.alignment); None: straight track
    alignment: Alignment | None = field(default=None, compare=False)
    # elastic track (railexu.track_model); None: rigid
    elastic: ElasticTrack | None = None

    @property
    def inclination_rad(self) -> float:
        return parse_inclination(self.inclination)

    def irregularities(self, length_m: float) -> IrregularityProfile:
        """The irregularity record covering at least ``[0, length_m]`` of track (m).

        Synthetic records are generated for the file's ``length`` or, if none is given, for the
        requested length plus 50 m; the same seed always gives the same track.
        """
        spec = self.irregularity
        if spec.type == "none":
            return IrregularityProfile.zeros(max(length_m, 1.0) + 50.0)
        if spec.type == "measured":
            return read_measured_irregularities(spec.file, fade_length_m=spec.fade_length_m)
        length = spec.length_m if spec.length_m is not None else length_m + 50.0
        return synthesize_irregularities(
            spec.spectrum,
            length_m=length,
            seed=spec.seed,
            wavelength_min_m=spec.wavelength_min_m,
            wavelength_max_m=spec.wavelength_max_m,
            amplitude_scale=spec.amplitude_scale,
            components=spec.components,
            fade_length_m=spec.fade_length_m,
        )


def ideal_straight_track() -> Track:
    """The default track: ideal straight track, UIC60 rails at 1:40, gauge 1.435 m."""
    return Track(name="straight (ideal)", description="ideal straight track")


def load_track(path: str | Path, overrides: Iterable[str] = ()) -> Track:
    """Read and validate a track file (overrides ``dotted.key=value`` applied first).

    Raises:
        InputError: any problem, naming the file, the line and the key.
    """
    path = Path(path)
    data, lines = load_yaml_with_overrides(path, overrides)
    return track_from_dict(data, source=str(path), lines=lines, base_dir=path.parent)


def track_from_dict(
    data: dict, source: str = "<track>", lines: dict | None = None, base_dir: Path | None = None
) -> Track:
    """Validate raw track data into a :class:`Track`."""
    top = Section(data, source, lines, (), TOP_KEYS)
    version = top.integer("format_version")
    if version != FORMAT_VERSION:
        top.fail(f"format_version {version} is not supported (this railexu reads {FORMAT_VERSION})")
    rail = resolve_file(top.string("rail_profile", default="UIC60"), base_dir)
    try:
        rail_profile(rail)
    except ProfileError as exc:
        top.fail(str(exc), key="rail_profile")
    inclination = top.data.get("inclination", "1:40")
    try:
        parse_inclination(inclination)
    except PlacementError as exc:
        top.fail(str(exc), key="inclination")
    gauge = top.quantity("gauge", "m", default=1.435, minimum=1.0, maximum=2.0)
    alignment = alignment_from_dict(top.data.get("geometry"), source, lines, base_dir)
    geometry_type = "straight" if alignment.is_straight else "sections"
    irr = top.section("irregularities", None, required=False)
    kind = irr.string("type", default="none", choices=tuple(IRREGULARITY_KEYS))
    irr = top.section("irregularities", IRREGULARITY_KEYS[kind], required=False)
    spec = IrregularitySpec(type=kind)
    if kind == "spectrum":
        spectrum = irr.string("spectrum", choices=available_spectra())
        components = irr.string_list("components", default=COMPONENTS)
        for c in components:
            if c not in COMPONENTS:
                irr.fail(f"unknown component {c!r}; expected some of {', '.join(COMPONENTS)}",
                         key="components")  # fmt: skip
        length = irr.quantity("length", "m", required=False, positive=True)
        spec = IrregularitySpec(
            type=kind,
            spectrum=spectrum,
            seed=irr.integer("seed", minimum=0),
            wavelength_min_m=irr.quantity("wavelength_min", "m", default=3.0, positive=True),
            wavelength_max_m=irr.quantity("wavelength_max", "m", default=150.0, positive=True),
            components=components,
            amplitude_scale=irr.quantity("amplitude_scale", "1", default=1.0, minimum=0.0),
            length_m=None if length != length else length,
            fade_length_m=irr.quantity("fade_length", "m", default=10.0, minimum=0.0),
        )
        if spec.wavelength_min_m >= spec.wavelength_max_m:
            irr.fail("wavelength_min must be below wavelength_max", key="wavelength_min")
        try:  # fail early on spectrum/component combinations the spectrum does not have
            synthesize_irregularities(
                spectrum, 4.0 * spec.fade_length_m + 100.0, 0, spec.wavelength_min_m,
                spec.wavelength_max_m, n_components=4, components=components,
                fade_length_m=spec.fade_length_m,
            )  # fmt: skip
        except (IrregularityError, NotImplementedError) as exc:
            irr.fail(str(exc))
    elif kind == "measured":
        name = irr.string("file")
        file = Path(name)
        if not file.is_absolute() and base_dir is not None:
            file = base_dir / file
        if not file.exists():
            irr.fail(f"irregularity file {str(file)!r} not found", key="file")
        spec = IrregularitySpec(
            type=kind,
            file=str(file),
            fade_length_m=irr.quantity("fade_length", "m", default=10.0, minimum=0.0),
        )
        try:
            read_measured_irregularities(spec.file)
        except IrregularityError as exc:
            raise InputError(str(exc), source=source, key="irregularities.file") from exc
    return Track(
        name=top.string("name"),
        rail_profile=rail,
        inclination=inclination,
        gauge_m=gauge,
        geometry=geometry_type,
        irregularity=spec,
        description=top.string("description", default=""),
        source=source,
        alignment=alignment,
        elastic=track_model_from_dict(top.data.get("track_model"), source, lines),
    )
