"""Track files: rail profile, inclination, gauge, geometry and irregularities.

A track file (``docs/track-format.md``) describes the rails a vehicle runs on::

    format_version: 1
    name: straight
    rail_profile: UIC60          # built-in name or a profile file (.prr, two-column text)
    inclination: 1:40            # a ratio (quoted or not), "none", or an angle with its unit
    gauge: 1.435 m
    geometry: {type: straight}   # curves are a planned extension of this section
    irregularities:
      type: spectrum             # none | spectrum | measured
      spectrum: german_low
      seed: 1
      wavelength_min: 3 m
      wavelength_max: 150 m

Only straight track is implemented; the geometry section exists so that curved track (radius,
transitions, cant) can be added without changing the format of straight-track files. Every key is
declared once in :mod:`railexu.track.schema`.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from railexu.contact.placement import parse_inclination
from railexu.inputs import InputError, LineMap, Section, load_yaml_with_overrides, resolve_file
from railexu.inputs.catalog import find_input
from railexu.inputs.reader import dotted
from railexu.profiles import ProfileError, rail_profile
from railexu.track.alignment import Alignment, alignment_from_dict
from railexu.track.elastic import ElasticTrack, track_model_from_dict
from railexu.track.irregularities import (
    COMPONENTS,
    IrregularityError,
    IrregularityProfile,
    read_measured_irregularities,
    synthesize_irregularities,
)
from railexu.track.schema import IRREGULARITIES, MAX_LENGTH_M, MAX_SAMPLES, TRACK, synthetic_samples
from railexu.track.turnout_file import turnout_from_dict
from railexu.track.variable_rails import VariableRails
from railexu.track.variable_rails_file import variable_rails_from_dict
from railexu.track.vertical import VerticalAlignment, vertical_from_dict

_SPECTRUM = IRREGULARITIES["spectrum"]


@dataclass(frozen=True)
class IrregularitySpec:
    """How to obtain the irregularities of a track (see :meth:`Track.irregularities`)."""

    type: str = "none"
    spectrum: str = ""
    seed: int = 0
    wavelength_min_m: float = _SPECTRUM.default("wavelength_min")
    wavelength_max_m: float = _SPECTRUM.default("wavelength_max")
    components: tuple[str, ...] = COMPONENTS
    amplitude_scale: float = _SPECTRUM.default("amplitude_scale")
    length_m: float | None = None
    fade_length_m: float = _SPECTRUM.default("fade_length")
    file: str = ""
    #: the mirror image: lateral alignment and cross level negated
    #: (:meth:`IrregularityProfile.mirrored`)
    mirror: bool = False


@dataclass(frozen=True)
class Track:
    """A validated track."""

    name: str
    rail_profile: str = TRACK.default("rail_profile")
    inclination: str | float = TRACK.default("inclination")
    gauge_m: float = TRACK.default("gauge")
    geometry: str = "straight"
    irregularity: IrregularitySpec = field(default_factory=IrregularitySpec)
    description: str = ""
    source: str = ""
    # design geometry (railexu.track.alignment); None: straight track
    alignment: Alignment | None = field(default=None, compare=False)
    # elastic track (railexu.track.elastic); None: rigid
    elastic: ElasticTrack | None = None
    # vertical alignment (railexu.track.vertical); None: level track
    vertical: VerticalAlignment | None = field(default=None, compare=False)
    # distance along the geometry where a run starts (the rearmost wheelset 1 m beyond) [m]
    start_m: float = 0.0
    # switches and crossings: rails that vary along a zone (railexu.track.variable_rails)
    variable_rails: VariableRails | None = field(default=None, compare=False)

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
        record = self._record(spec, length_m)
        return record.mirrored() if spec.mirror else record

    @staticmethod
    def _record(spec: IrregularitySpec, length_m: float) -> IrregularityProfile:
        if spec.type == "measured":
            return read_measured_irregularities(spec.file, fade_length_m=spec.fade_length_m)
        length = spec.length_m if spec.length_m is not None else length_m + 50.0
        check_record_length(spec, length, _refuse)
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


def _refuse(message: str) -> None:
    raise IrregularityError(f"track irregularities: {message}")


def ideal_straight_track() -> Track:
    """The default track: ideal straight track, UIC60 rails at 1:40, gauge 1.435 m."""
    return Track(name="straight (ideal)", description="ideal straight track")


def load_track(path: str | Path, overrides: str | Iterable[str] = ()) -> Track:
    """Read and validate a track file, or a shipped track by name (``"straight_irregular"``);
    overrides ``dotted.key=value`` are applied first (one string is one override).

    Raises:
        InputError: any problem, naming the file, the line and the key.
    """
    path = find_input("track", path)
    data, lines = load_yaml_with_overrides(path, overrides)
    return track_from_dict(data, source=str(path), lines=lines, base_dir=path.parent)


def track_from_dict(
    data: dict, source: str = "<track>", lines: dict | None = None, base_dir: Path | None = None
) -> Track:
    """Validate raw track data into a :class:`Track`."""
    top = TRACK.wrap(data, source, lines if lines is not None else LineMap())
    TRACK.read(top, "format_version")
    rail = resolve_file(TRACK.read(top, "rail_profile"), base_dir)
    try:
        rail_profile(rail)
    except ProfileError as exc:
        top.fail(str(exc), key="rail_profile")
    written, angle = TRACK.read(top, "inclination")
    turnout = _turnout(top, rail, written, base_dir)  # a turnout's route: geometry and zone
    # the geometry and the track model are checked by their own modules (sections, measured
    # CSV; rigid or elastic), with file, line and key
    geometry_data = top.data.get("geometry") if turnout is None else turnout[0]
    alignment = alignment_from_dict(geometry_data, source, top.lines, base_dir)
    geometry = "straight" if alignment.is_straight else str(geometry_data["type"])
    elastic = track_model_from_dict(top.data.get("track_model"), source, top.lines)
    vertical = vertical_from_dict(top.data.get("vertical"), source, top.lines, base_dir)
    start_m = TRACK.read(top, "start")
    end_m = alignment.end_m if alignment.end_m > 0.0 else None  # None: unbounded straight
    rails = variable_rails_from_dict(
        top.data.get("variable_rails"), source, top.lines, base_dir, end_m, start_m
    ) if turnout is None else turnout[1]  # fmt: skip
    if turnout is not None and rails.zone_m()[0] <= start_m + 1.0:
        first = rails.zone_m()[0]
        top.fail(f"the turnout's first rail at {first:g} m is not beyond the run's start "
                 f"({start_m:g} m + 1 m): lengthen turnout.approach", key="turnout")  # fmt: skip
    spec = irregularity_spec(top, base_dir)
    return Track(
        name=TRACK.read(top, "name"),
        rail_profile=rail,
        inclination=_inclination_value(written, angle),
        gauge_m=TRACK.read(top, "gauge"),
        geometry=geometry,
        irregularity=spec,
        description=TRACK.read(top, "description"),
        source=source,
        alignment=alignment,
        elastic=elastic,
        vertical=vertical,
        start_m=start_m,
        variable_rails=rails,
    )


def _turnout(top: Section, rail: str, inclination, base_dir: Path | None):
    """``(geometry section, variable rails)`` of a ``turnout:`` section, or None without one
    (``railexu.track.turnout_file``); it excludes ``geometry`` and ``variable_rails``."""
    if top.data.get("turnout") is None:
        return None
    for key in ("geometry", "variable_rails"):
        if key in top.data:
            top.fail("given with 'turnout', which generates it: remove one of them", key=key)
    gauge = TRACK.read(top, "gauge")
    geometry, rails, _ = turnout_from_dict(
        top.data["turnout"], top.source, top.lines, base_dir, rail, inclination, gauge
    )
    return geometry, rails


def _inclination_value(written: object, angle_rad: float) -> str | float:
    """The inclination as written if the model's parser reads it to the same angle (a ratio,
    ``"none"``: kept for display), else the angle in rad."""
    if isinstance(written, str):
        try:
            if parse_inclination(written) == angle_rad:
                return written
        except ValueError:
            pass
    return angle_rad


def irregularity_spec(parent: Section, base_dir: Path | None = None) -> IrregularitySpec:
    """The ``irregularities:`` mapping of ``parent`` (a track file's top level, or any mapping
    that holds one with the same keys and meaning, e.g. a wear route's,
    :mod:`railexu.study.wear.route`), read and checked.

    Raises:
        InputError: naming ``parent``'s file, the line and the key.
    """
    kind, params = TRACK.read(parent, "irregularities")
    if kind not in ("spectrum", "measured"):  # written as a mapping or as the type alone
        return IrregularitySpec(type=kind)
    irr = Section(parent.data.get("irregularities", {}), parent.source, parent.lines,
                  (*parent.path, "irregularities"))  # fmt: skip
    if kind == "spectrum":
        return _spectrum_spec(irr, params)
    return _measured_spec(irr, params, base_dir, parent.source)


def _spectrum_spec(irr: Section, p: dict) -> IrregularitySpec:
    components = p["components"]
    if len(set(components)) != len(components):
        irr.fail(f"components listed twice: {list(components)}", key="components")
    spec = IrregularitySpec(
        type="spectrum",
        spectrum=p["spectrum"],
        seed=p["seed"],
        wavelength_min_m=p["wavelength_min"],
        wavelength_max_m=p["wavelength_max"],
        components=components,
        amplitude_scale=p["amplitude_scale"],
        length_m=p["length"],
        fade_length_m=p["fade_length"],
        mirror=p["mirror"],
    )
    if spec.wavelength_min_m >= spec.wavelength_max_m:
        irr.fail("wavelength_min must be below wavelength_max", key="wavelength_min")
    if spec.length_m is not None:
        check_record_length(spec, spec.length_m, lambda m: irr.fail(m, key="length"))
    try:  # fail early on spectrum/component combinations the spectrum does not have
        synthesize_irregularities(
            spec.spectrum, 4.0 * spec.fade_length_m + 100.0, 0, spec.wavelength_min_m,
            spec.wavelength_max_m, n_components=4, components=components,
            fade_length_m=spec.fade_length_m,
        )  # fmt: skip
    except (IrregularityError, NotImplementedError) as exc:
        irr.fail(str(exc))
    return spec


def check_record_length(spec: IrregularitySpec, length_m: float, fail) -> None:
    """Refuse a synthetic record too long for memory or time (``fail(message)`` raises)."""
    if not length_m <= MAX_LENGTH_M:
        fail(f"a record of {length_m:g} m is longer than {MAX_LENGTH_M:g} m: is a unit wrong?")
    n = synthetic_samples(length_m, spec.wavelength_min_m)
    if n > MAX_SAMPLES:
        fail(
            f"a record of {length_m:g} m at wavelength_min {spec.wavelength_min_m:g} m needs "
            f"{n:.3g} samples per signal, more than {MAX_SAMPLES:.3g}: shorten it or raise "
            "wavelength_min"
        )
    if 2.0 * spec.fade_length_m > length_m:
        fail(f"fade_length {spec.fade_length_m:g} m is more than half the record ({length_m:g} m)")


def _measured_spec(irr: Section, p: dict, base_dir: Path | None, source: str) -> IrregularitySpec:
    file = Path(p["file"])
    if not file.is_absolute() and base_dir is not None:
        file = base_dir / file
    if not file.is_file():
        what = "is a folder, not a file" if file.is_dir() else "not found"
        irr.fail(f"irregularity file {str(file)!r} {what}", key="file")
    spec = IrregularitySpec(type="measured", file=str(file), fade_length_m=p["fade_length"],
                            mirror=p["mirror"])  # fmt: skip
    try:
        read_measured_irregularities(spec.file)
    except IrregularityError as exc:
        raise InputError(str(exc), source=source, key=f"{dotted(irr.path)}.file") from exc
    except (OSError, UnicodeDecodeError) as exc:
        irr.fail(f"cannot read {str(file)!r}: {exc}", key="file")
    return spec
