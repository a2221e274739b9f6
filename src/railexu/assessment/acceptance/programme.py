"""Acceptance programme files: the EN 14363:2016 test zones of one vehicle category.

A programme (YAML, ``programmes/*.yaml``; every key: ``docs/acceptance-programme-format.md``)
names the vehicle category, the statistics' parameters and its test zones: straight track at a
speed, or curves of a radius range at a cant and a range of cant deficiencies (or a speed), each
made of ``n_sections`` sections of ``section_length`` with a track quality, evaluated by a
statistical ``method``. :func:`load_programme` reads and checks it (unknown keys refused, errors
name the file, the line and the key); :meth:`Zone.sections` gives each section's concrete
conditions (:class:`SectionSpec`) from which a track and run settings are built.

How the sections of a zone are spread (railexu's rule, stated in ``docs/acceptance.md``): the
radius of curve section ``i`` of ``n`` steps evenly from ``radius_min`` to ``radius_max``; the
cant deficiency (or the track quality) of section ``i`` is taken at the fraction
``u_i = frac(0.5 + i phi)`` (``phi`` the golden ratio's conjugate 0.618...) of its range, so that
radius and cant deficiency are not collinear and the regression over both has a spread. The
speed follows from ``V = sqrt(g R (I + D) / b)`` (EN 13803: ``b`` = 1.5 m), capped at the
zone's ``speed_max`` (EN 14363:2016's maximum test speed, 1.1 times the admissible speed): a
capped section runs at ``speed_max`` with the cant deficiency ``I = b V^2 / (g R) - D`` that
speed gives, recorded as the section's. Curves alternate left (even ``i``) and right. The random
seed of section ``i`` is ``seed + i``. Each curve section starts with an entry transition whose
length follows from the zone's cant-gradient and cant-rate limits (:func:`transition_length_m`),
then ``run_in`` of full curve before the evaluation window.

Track quality: EN 14363:2016 asks for test sections of stated track quality (QN levels of
EN 13848-6: standard deviations of the longitudinal level and the alignment in the wavelength
band D1, 3 m to 25 m). railexu synthesises each section from a spectrum
(:mod:`railexu.track.irregularities`) scaled so that the spectrum's standard deviation in that
band reaches the section's target for **both** alignment and level: ``amplitude_scale =
max(sd_alignment / rms_alignment, sd_level / rms_level)``, rms of the unscaled spectrum over the
band (:meth:`~railexu.track.irregularities.TrackSpectrum.band_rms`); the other component is then
at or above its target (the spectrum's own ratio). The QN values themselves are parameters of the
programme file, marked there as railexu's assumption where not public.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path

from railexu.assessment.en14363 import CATEGORIES
from railexu.errors import InputError
from railexu.inputs import OPTIONAL, Field, Schema, Section, load_yaml_with_overrides
from railexu.inputs.catalog import find_input

FORMAT_VERSION = 1
GRAVITY_M_PER_S2 = 9.81
#: EN 13803: cant base, the distance of the rail centres over which cant is measured (m).
CANT_BASE_M = 1.5
#: Shortest entry transition of a curve section [m] (railexu's floor for a curve without cant).
TRANSITION_MIN_M = 10.0
#: The golden ratio's conjugate: the low-discrepancy step of the spread of conditions.
PHI = (math.sqrt(5.0) - 1.0) / 2.0
METHODS = ("one_dimensional", "two_dimensional")
REGRESSORS = ("cant_deficiency", "curvature")
#: EN 14363's measuring methods whose running-stability criteria a programme judges: the
#: normal method (rms of sum Y) and the simplified method (the bogie frame's acceleration).
STABILITY_METHODS = ("normal", "simplified", "both")
#: Units of the limits a programme may set (``limits:``), by quantity name.
LIMIT_UNITS = {
    "sum_Y_2m": "N", "Y_over_Q_2m": "1", "Q_max": "N", "Y_qst": "N", "Q_qst": "N",
    "car_body_acc_y_max": "m/s^2", "car_body_acc_z_max": "m/s^2",
    "car_body_acc_y_rms": "m/s^2", "car_body_acc_z_rms": "m/s^2",
    "car_body_acc_y_qst": "m/s^2", "bogie_frame_acc_y_max": "m/s^2",
    "bogie_frame_acc_y_rms": "m/s^2",
}  # fmt: skip

QUALITY = Schema(
    "track_quality",
    (
        Field("level", "name of the quality level (EN 13848-6: QN1, QN2) for the reports", "text"),
        Field("spectrum", "spectrum the irregularities are synthesised from", "text",
              default="german_low"),
        Field("band_min", "shortest wavelength of the band the standard deviations refer to "
              "(EN 13848-1 D1: 3 m)", unit="m", default=3.0, positive=True, maximum=70.0),
        Field("band_max", "longest wavelength of that band (D1: 25 m)", unit="m", default=25.0,
              positive=True, maximum=200.0),
        Field("alignment_sd_min", "lowest standard deviation of the alignment over the sections",
              unit="m", positive=True, maximum=0.02),
        Field("alignment_sd_max", "highest standard deviation of the alignment", unit="m",
              positive=True, maximum=0.02),
        Field("level_sd_min", "lowest standard deviation of the longitudinal level", unit="m",
              positive=True, maximum=0.02),
        Field("level_sd_max", "highest standard deviation of the longitudinal level", unit="m",
              positive=True, maximum=0.02),
    ),
    "Track quality of a zone's sections: target standard deviations in a wavelength band.",
)  # fmt: skip

EVALUATE_AT = Schema(
    "evaluate_at",
    (
        Field("cant_deficiency", "cant deficiency the regression is evaluated at", unit="m",
              default=OPTIONAL, minimum=-0.2, maximum=0.3),
        Field("radius", "radius the regression is evaluated at (curvature 1/radius)", unit="m",
              default=OPTIONAL, minimum=100.0, maximum=100_000.0),
    ),
    "The zone's limit conditions at which the two-dimensional regression is evaluated.",
)  # fmt: skip

ZONE = Schema(
    "zone",
    (
        Field("kind", "straight or curve", "text", choices=("straight", "curve")),
        Field("description", "one line", "text", default=""),
        Field("n_sections", "number of sections", "integer", minimum=1, maximum=500),
        Field("quick_sections", "number of sections of the --quick variant (default: the "
              "statistical minimum of the method)", "integer", default=OPTIONAL, minimum=1,
              maximum=500),
        Field("min_sections", "least number of sections the evaluation accepts", "integer",
              minimum=2, maximum=500),
        Field("section_length", "length of each section's evaluation window", unit="m",
              positive=True, maximum=5000.0),
        Field("run_in", "track run before each section's window to settle (curves: full "
              "curve after the entry transition)", unit="m",
              default=50.0, minimum=0.0, maximum=2000.0),
        Field("speed", "test speed (straight track; curves: instead of cant deficiency)",
              unit="m/s", default=OPTIONAL, positive=True, maximum=150.0),
        Field("speed_max", "curves: the maximum test speed (EN 14363: 1.1 x the admissible "
              "speed); a section whose speed from its cant deficiency would exceed it runs at "
              "it, with the cant deficiency it gives", unit="m/s", default=OPTIONAL,
              positive=True, maximum=150.0),
        Field("radius_min", "smallest radius of the zone's curves", unit="m", default=OPTIONAL,
              minimum=150.0, maximum=100_000.0),
        Field("radius_max", "largest radius of the zone's curves", unit="m", default=OPTIONAL,
              minimum=150.0, maximum=100_000.0),
        Field("cant", "cant of the curves", unit="m", default=0.0, minimum=0.0, maximum=0.2),
        Field("cant_deficiency_min", "lowest cant deficiency of the sections", unit="m",
              default=OPTIONAL, minimum=-0.2, maximum=0.3),
        Field("cant_deficiency_max", "highest cant deficiency of the sections", unit="m",
              default=OPTIONAL, minimum=-0.2, maximum=0.3),
        Field("transition_cant_gradient_max", "curves: largest cant gradient of the entry "
              "transition (EN 13803 recommended limit 2.25 mm/m; railexu assumption)", unit="1",
              default=2.25e-3, positive=True, maximum=0.02),
        Field("transition_cant_rate_max", "curves: largest rate of change of cant dD/dt at "
              "the section's speed (EN 13803; not applied if absent)", unit="m/s",
              default=OPTIONAL, positive=True, maximum=0.5),
        Field("transition_cant_deficiency_rate_max", "curves: largest rate of change of cant "
              "deficiency dI/dt at the section's speed (EN 13803; not applied if absent)",
              unit="m/s", default=OPTIONAL, positive=True, maximum=0.5),
        Field("method", "statistical evaluation", "text", choices=METHODS),
        Field("regressors", "two-dimensional: the section conditions regressed on", "text_list",
              default=("cant_deficiency",), choices=REGRESSORS),
        Field("evaluate_at", "two-dimensional: the limit conditions", "section",
              default={}, schema=EVALUATE_AT),
        Field("track_quality", "track quality of the sections", "section", schema=QUALITY),
        Field("seed", "random seed of the first section's irregularities (section i: seed + i)",
              "integer", default=1, minimum=0),
    ),
    "One test zone.",
)  # fmt: skip

STATISTICS = Schema(
    "statistics",
    (
        Field("k_safety", "one-dimensional factor k of running safety and track loading",
              unit="1", minimum=0.0, maximum=5.0),
        Field("k_ride", "one-dimensional factor k of the ride characteristics", unit="1",
              minimum=0.0, maximum=5.0),
        Field("prediction_quantile", "two-dimensional: one-sided quantile of Student's t",
              unit="1", minimum=0.5, maximum=0.999),
        Field("assumption", "the statistics' parameters are railexu's assumption", "boolean",
              default=True),
        Field("y_qst_limit_radius", "radius of the Y_qst limit 30 + 10500/R kN: `mean` (the "
              "zone's mean radius R_m) or `evaluation` (the radius of `evaluate_at`, where the "
              "estimate is taken); railexu could not confirm the 2016 edition's reading",
              "text", default="mean", choices=("mean", "evaluation")),
        Field("stability_method", "the measuring method whose criteria judge running "
              "stability: `normal` (the rms of sum Y), `simplified` (the bogie frame's lateral "
              "acceleration, peak and rms) or `both`; the other method's values are reported, "
              "not judged", "text", default="normal", choices=STABILITY_METHODS),
    ),
    "Parameters of the statistical evaluation.",
)  # fmt: skip

LIMIT = Schema(
    "limit",
    (
        Field("value", "the limit (unit of the quantity: N, 1 or m/s^2)", "text"),
        Field("note", "why, and where the value comes from", "text"),
    ),
    "A limit set by the programme (a railexu assumption).",
)  # fmt: skip

PROGRAMME = Schema(
    "programme",
    (
        Field("format_version", f"format of the file ({FORMAT_VERSION})", "integer",
              choices=(FORMAT_VERSION,)),
        Field("name", "short name", "text"),
        Field("description", "one paragraph", "text", default=""),
        Field("category", "EN 14363 vehicle category", "text", choices=CATEGORIES),
        Field("sources", "where the values come from", "text_list", default=()),
        Field("statistics", "parameters of the statistical evaluation", "section",
              schema=STATISTICS),
        Field("limits", "limits replaced by the programme, by quantity name", "named",
              default={}, schema=LIMIT),
        Field("zones", "the test zones, by name", "named", schema=ZONE),
    ),
    "An EN 14363 acceptance programme: its test zones and statistics.",
)  # fmt: skip


@dataclass(frozen=True)
class TrackQuality:
    """Target standard deviations (m) of the sections' alignment and level in a band (m)."""

    level: str
    spectrum: str
    band_m: tuple[float, float]
    alignment_sd_m: tuple[float, float]
    level_sd_m: tuple[float, float]


@dataclass(frozen=True)
class SectionSpec:
    """The concrete conditions of one section (SI).

    ``radius_m`` is None on straight track; ``direction`` is ``"left"``/``"right"`` in curves;
    the evaluation window is ``[evaluate_from_m, evaluate_to_m]`` of the distance travelled (the
    run starts ``run_in_m`` before it); ``irregularities`` is the track file's
    ``irregularities`` mapping (SI numbers); ``quality`` the targets and the scale used.
    In curves the run-in is the entry transition (``transition_m``, :func:`transition_length_m`)
    followed by the zone's ``run_in`` of full curve; ``speed_capped`` says that the section runs
    at the zone's maximum test speed with the cant deficiency that speed gives (lower than its
    share of the zone's range).
    """

    zone: str
    index: int
    name: str
    kind: str
    radius_m: float | None
    direction: str | None
    cant_m: float
    speed_m_per_s: float
    cant_deficiency_m: float
    length_m: float
    run_in_m: float
    seed: int
    quality: dict
    irregularities: dict
    transition_m: float = 0.0
    speed_capped: bool = False

    @property
    def evaluate_from_m(self) -> float:
        return self.run_in_m

    @property
    def evaluate_to_m(self) -> float:
        return self.run_in_m + self.length_m

    @property
    def curvature_1_per_m(self) -> float:
        """Unsigned curvature 1/R (0 on straight track)."""
        return 0.0 if self.radius_m is None else 1.0 / self.radius_m


@dataclass(frozen=True)
class Zone:
    """One test zone of a programme (SI units); see :data:`ZONE` for each field."""

    name: str
    kind: str
    n_sections: int
    section_length_m: float
    run_in_m: float
    method: str
    min_sections: int
    track_quality: TrackQuality
    speed_m_per_s: float | None = None
    speed_max_m_per_s: float | None = None
    radius_m: tuple[float, float] | None = None
    cant_m: float = 0.0
    cant_deficiency_m: tuple[float, float] | None = None
    regressors: tuple[str, ...] = ("cant_deficiency",)
    evaluate_at: tuple[float, ...] = ()
    k_safety: float = 2.2
    k_ride: float = 3.0
    prediction_quantile: float = 0.95
    statistics_assumption: bool = True
    y_qst_limit_radius: str = "mean"
    stability_method: str = "normal"
    seed: int = 1
    reduced: bool = False
    description: str = ""
    transition_cant_gradient_max: float = 2.25e-3
    transition_cant_rate_max_m_per_s: float | None = None
    transition_cant_deficiency_rate_max_m_per_s: float | None = None

    def sections(self) -> list[SectionSpec]:
        """Each section's conditions (see the module doc for the spread)."""
        return [self._section(i) for i in range(self.n_sections)]

    def _section(self, i: int) -> SectionSpec:
        u = math.fmod(0.5 + i * PHI, 1.0)
        w = math.fmod(0.25 + i * PHI * PHI, 1.0)  # another order for the track quality
        radius = direction = None
        cd, speed, capped, transition = 0.0, self.speed_m_per_s, False, 0.0
        if self.kind == "curve":
            assert self.radius_m is not None
            lo, hi = self.radius_m
            radius = lo + (hi - lo) * (i / (self.n_sections - 1) if self.n_sections > 1 else 0.5)
            direction = "left" if i % 2 == 0 else "right"
            if self.cant_deficiency_m is not None:
                cd = self.cant_deficiency_m[0] + u * (self.cant_deficiency_m[1]
                                                      - self.cant_deficiency_m[0])  # fmt: skip
                speed = speed_for(radius, self.cant_m, cd)
            assert speed is not None
            if self.speed_max_m_per_s is not None and speed > self.speed_max_m_per_s:
                speed, capped = self.speed_max_m_per_s, True
            if capped or self.cant_deficiency_m is None:
                cd = cant_deficiency_for(radius, self.cant_m, speed)
            transition = transition_length_m(self, speed, cd)
        assert speed is not None
        quality, irregularities = _quality(self.track_quality, w, self.seed + i)
        return SectionSpec(
            zone=self.name, index=i, name=f"{self.name}_{i + 1:03d}", kind=self.kind,
            radius_m=radius, direction=direction, cant_m=self.cant_m if radius else 0.0,
            speed_m_per_s=speed, cant_deficiency_m=cd, length_m=self.section_length_m,
            run_in_m=self.run_in_m + transition, seed=self.seed + i, quality=quality,
            irregularities=irregularities, transition_m=transition, speed_capped=capped,
        )  # fmt: skip


@dataclass(frozen=True)
class Programme:
    """An acceptance programme: ``name``, ``category``, ``source`` (the file), ``quick`` (the
    reduced variant), ``zones``, the limits it sets (``limits``: name -> (value SI, note)),
    ``sources`` and ``description``."""

    name: str
    category: str
    source: str
    quick: bool
    zones: tuple[Zone, ...]
    limits: dict[str, tuple[float, str]] = field(default_factory=dict)
    sources: tuple[str, ...] = ()
    description: str = ""

    def zone(self, name: str) -> Zone:
        for z in self.zones:
            if z.name == name:
                return z
        raise KeyError(f"no zone {name!r} in programme {self.name!r}")


def speed_for(radius_m: float, cant_m: float, cant_deficiency_m: float) -> float:
    """``V = sqrt(g R (I + D) / b)`` (m/s), EN 13803 with ``b`` = 1.5 m."""
    return math.sqrt(GRAVITY_M_PER_S2 * radius_m * (cant_deficiency_m + cant_m) / CANT_BASE_M)


def cant_deficiency_for(radius_m: float, cant_m: float, speed_m_per_s: float) -> float:
    """``I = b V^2 / (g R) - D`` (m), EN 13803."""
    return CANT_BASE_M * speed_m_per_s**2 / (GRAVITY_M_PER_S2 * radius_m) - cant_m


def transition_length_m(zone: Zone, speed_m_per_s: float, cant_deficiency_m: float) -> float:
    """Length of a curve section's entry transition [m] (railexu's rule, after EN 13803's
    limits on transitions): the shortest clothoid with a linear cant ramp that keeps the cant
    gradient ``D / L``, and, where the zone gives them, the rates ``V D / L`` and ``V |I| / L``
    within the zone's limits, rounded up to 0.1 m; at least :data:`TRANSITION_MIN_M`."""
    cant, v = zone.cant_m, speed_m_per_s
    lengths = [TRANSITION_MIN_M, cant / zone.transition_cant_gradient_max]
    if zone.transition_cant_rate_max_m_per_s is not None:
        lengths.append(v * cant / zone.transition_cant_rate_max_m_per_s)
    rate_i = zone.transition_cant_deficiency_rate_max_m_per_s
    if rate_i is not None:
        lengths.append(v * abs(cant_deficiency_m) / rate_i)
    return math.ceil(max(lengths) * 10.0 - 1e-9) / 10.0


def load_programme(
    name_or_path: str | Path, quick: bool = False, overrides: str | Iterable[str] = ()
) -> Programme:
    """Read and check a programme file (a path, or the name of a shipped programme).

    Args:
        name_or_path: a file, or a name of ``programmes/`` (``shipped_names("programme")``).
        quick: the reduced variant: each zone's ``quick_sections`` (default: the method's
            statistical minimum) sections, marked ``reduced``; not an acceptance verdict.
        overrides: ``dotted.key=value`` items applied before the checks (``--set``).

    Raises:
        InputError: naming the file, the line and the key.
    """
    path = find_input("programme", name_or_path)
    data, lines = load_yaml_with_overrides(path, overrides)
    source = str(path)
    top = PROGRAMME.wrap(data, source, lines)
    PROGRAMME.read(top, "format_version")
    stats = PROGRAMME.read(top, "statistics")
    zones = []
    for name, _ in PROGRAMME.read(top, "zones"):
        sec = top.child("zones", name, ZONE.keys())
        zones.append(_zone(str(name), sec, stats, quick))
    if not zones:
        top.fail("expected at least one zone", key="zones")
    return Programme(
        name=PROGRAMME.read(top, "name"), category=PROGRAMME.read(top, "category"),
        source=source, quick=quick, zones=tuple(zones), limits=_limits(top),
        sources=PROGRAMME.read(top, "sources"), description=PROGRAMME.read(top, "description"),
    )  # fmt: skip


def _zone(name: str, sec: Section, stats: dict, quick: bool) -> Zone:
    v = ZONE.read_all(sec)
    kind, method = v["kind"], v["method"]
    if kind == "straight" and method == "two_dimensional":
        sec.fail("a straight zone has no cant deficiency or curvature to regress on: use "
                 "one_dimensional", key="method")  # fmt: skip
    regressors = tuple(dict.fromkeys(v["regressors"]))
    needed = 2 if method == "one_dimensional" else len(regressors) + 2
    if v["min_sections"] < needed:
        sec.fail(f"the {method} evaluation needs at least {needed} sections, got "
                 f"{v['min_sections']}", key="min_sections")  # fmt: skip
    if v["n_sections"] < v["min_sections"]:
        sec.fail(f"must be >= min_sections ({v['min_sections']}), got {v['n_sections']}",
                 key="n_sections")  # fmt: skip
    zone = Zone(
        name=name, kind=kind, n_sections=v["n_sections"], description=v["description"],
        section_length_m=v["section_length"], run_in_m=v["run_in"], method=method,
        min_sections=v["min_sections"], track_quality=_track_quality(sec),
        speed_m_per_s=v["speed"], speed_max_m_per_s=v["speed_max"], cant_m=v["cant"],
        regressors=regressors, seed=v["seed"],
        radius_m=_range(sec, v, "radius", kind == "curve"),
        cant_deficiency_m=_range(sec, v, "cant_deficiency", False),
        evaluate_at=_evaluate_at(sec, v, method, regressors),
        k_safety=stats["k_safety"], k_ride=stats["k_ride"],
        prediction_quantile=stats["prediction_quantile"],
        statistics_assumption=stats["assumption"],
        y_qst_limit_radius=stats["y_qst_limit_radius"],
        stability_method=stats["stability_method"],
        transition_cant_gradient_max=v["transition_cant_gradient_max"],
        transition_cant_rate_max_m_per_s=v["transition_cant_rate_max"],
        transition_cant_deficiency_rate_max_m_per_s=v["transition_cant_deficiency_rate_max"],
    )  # fmt: skip
    _check_conditions(sec, zone)
    if quick:
        n = v["quick_sections"] or needed
        zone = replace(zone, n_sections=max(n, needed), min_sections=needed, reduced=True)
    return zone


def _range(sec: Section, v: dict, key: str, required: bool) -> tuple[float, float] | None:
    lo, hi = v[f"{key}_min"], v[f"{key}_max"]
    if lo is None and hi is None:
        if required:
            sec.fail(f"missing key '{key}_min' (and '{key}_max'): a curve zone needs its range")
        return None
    if lo is None or hi is None:
        missing = f"{key}_min" if lo is None else f"{key}_max"
        sec.fail(f"missing key {missing!r}: give both ends of the range")
    if hi < lo:
        sec.fail(f"must be >= {key}_min ({lo:g}), got {hi:g}", key=f"{key}_max")
    return (lo, hi)


def _evaluate_at(sec: Section, v: dict, method: str, regressors: tuple[str, ...]) -> tuple:
    if method != "two_dimensional":
        return ()
    at = v["evaluate_at"]
    values = []
    for r in regressors:
        key = "radius" if r == "curvature" else r
        if at.get(key) is None:
            sec.fail(f"missing key 'evaluate_at.{key}': the two-dimensional evaluation over "
                     f"{r} needs the limit condition", key="evaluate_at")  # fmt: skip
        values.append(1.0 / at[key] if r == "curvature" else at[key])
    return tuple(values)


def _check_conditions(sec: Section, zone: Zone) -> None:
    if zone.kind == "straight":
        if zone.speed_m_per_s is None:
            sec.fail("missing key 'speed': a straight zone runs at a speed")
        if zone.speed_max_m_per_s is not None:
            sec.fail("a straight zone runs at its 'speed' (the maximum test speed): "
                     "'speed_max' is for curve zones", key="speed_max")  # fmt: skip
        return
    if (zone.speed_m_per_s is None) == (zone.cant_deficiency_m is None):
        sec.fail("give either 'speed' or 'cant_deficiency_min'/'cant_deficiency_max' for a "
                 "curve zone (one of them)")  # fmt: skip
    assert zone.radius_m is not None
    low_i = zone.cant_deficiency_m[0] if zone.cant_deficiency_m else None
    if low_i is not None and low_i + zone.cant_m <= 0.0:
        sec.fail(f"cant deficiency {low_i:g} m with cant {zone.cant_m:g} m means standstill",
                 key="cant_deficiency_min")  # fmt: skip
    curvature = zone.method == "two_dimensional" and "curvature" in zone.regressors
    if curvature and zone.radius_m[1] <= zone.radius_m[0]:
        sec.fail("regression over curvature needs a radius range", key="radius_max")
    for spec in zone.sections():
        if not 0.0 < spec.speed_m_per_s <= 150.0:
            sec.fail(f"section {spec.name}: speed {spec.speed_m_per_s:.1f} m/s is outside "
                     "(0, 150] m/s")  # fmt: skip


def _track_quality(sec: Section) -> TrackQuality:
    q = QUALITY.read_all(QUALITY.section(sec, "track_quality", required=True))
    where = Section(sec.data.get("track_quality", {}), sec.source, sec.lines,
                    (*sec.path, "track_quality"))  # fmt: skip
    for part in ("alignment_sd", "level_sd", "band"):
        if q[f"{part}_max"] < q[f"{part}_min"]:
            where.fail(f"must be >= {part}_min", key=f"{part}_max")
    from railexu.track.irregularities import get_spectrum

    try:
        spectrum = get_spectrum(q["spectrum"])
        spectrum.require("lateral")
        spectrum.require("vertical")
    except (InputError, NotImplementedError) as exc:
        where.fail(str(exc).split(": ", 1)[-1], key="spectrum")
    return TrackQuality(
        level=q["level"], spectrum=q["spectrum"], band_m=(q["band_min"], q["band_max"]),
        alignment_sd_m=(q["alignment_sd_min"], q["alignment_sd_max"]),
        level_sd_m=(q["level_sd_min"], q["level_sd_max"]),
    )  # fmt: skip


def _quality(q: TrackQuality, w: float, seed: int) -> tuple[dict, dict]:
    """The section's targets at fraction ``w`` of the ranges and the irregularities for them."""
    from railexu.track.irregularities import get_spectrum

    spectrum = get_spectrum(q.spectrum)
    sd_a = q.alignment_sd_m[0] + w * (q.alignment_sd_m[1] - q.alignment_sd_m[0])
    sd_v = q.level_sd_m[0] + w * (q.level_sd_m[1] - q.level_sd_m[0])
    rms_a = spectrum.band_rms("lateral", *q.band_m)
    rms_v = spectrum.band_rms("vertical", *q.band_m)
    scale = max(sd_a / rms_a, sd_v / rms_v)
    quality = {
        "level": q.level, "band_m": list(q.band_m), "alignment_sd_m": sd_a, "level_sd_m": sd_v,
        "amplitude_scale": scale, "alignment_sd_achieved_m": scale * rms_a,
        "level_sd_achieved_m": scale * rms_v,
        "rule": "amplitude_scale = max(sd_alignment / rms_alignment, sd_level / rms_level), "
        "rms of the spectrum over the band",
    }  # fmt: skip
    irregularities = {"type": "spectrum", "spectrum": q.spectrum, "seed": seed,
                      "amplitude_scale": scale}  # fmt: skip
    return quality, irregularities


def _limits(top: Section) -> dict[str, tuple[float, str]]:
    out = {}
    for name, _ in PROGRAMME.read(top, "limits"):
        sec = top.child("limits", name, LIMIT.keys())
        if name not in LIMIT_UNITS:
            sec.fail(f"unknown quantity {name!r}; known: {', '.join(LIMIT_UNITS)}")
        value = sec.quantity("value", LIMIT_UNITS[name], positive=True)
        out[str(name)] = (value, LIMIT.read(sec, "note"))
    return out


#: The tables of ``docs/acceptance-programme-format.md`` (``python -m railexu.schema``).
DOC_TABLES = (
    ("Top level", PROGRAMME),
    ("`statistics`", STATISTICS),
    ("`limits.<quantity>`", LIMIT),
    ("`zones.<name>`", ZONE),
    ("`zones.<name>.track_quality`", QUALITY),
    ("`zones.<name>.evaluate_at`", EVALUATE_AT),
)
