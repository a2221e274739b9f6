"""Track vertical alignment: elevation, gradient and vertical curvature along the track.

A track's ``vertical:`` section (``docs/track-format.md``) gives the design profile or a
measured one::

    vertical: {type: gradient, gradient: 12.5}      # constant, per mille, positive rising

    vertical:
      type: stations                               # points of intersection of the gradients
      stations:
        - {position: 0 m, elevation: 0 m}
        - {position: 400 m, elevation: 4 m, radius: 5000 m}   # vertical curve there
        - {position: 900 m, elevation: -1 m}

    vertical: {type: measured, file: profile.csv}   # distance [m], elevation [m]
    vertical: {type: measured, file: g.csv, column: gradient}   # distance [m], gradient [per mille]

Conventions (``docs/curving.md``, "Vertical alignment"): distance ``s`` along the track as in
:mod:`railexu.track.alignment`; elevation ``z(s)`` [m], gradient ``g = dz/ds`` (positive rising
in the direction of travel), pitch angle of the track ``theta = atan(g)``, vertical curvature
``kappa_v = d theta / ds`` (positive in a sag, negative on a crest). Before the first and after
the last station the gradient continues unchanged.

A vertical curve is the parabola of civil engineering practice (EN 13803:2017 uses the radius
``R_v`` of the osculating circle of this parabola): centred on its station, of length
``L = R_v |g_2 - g_1|``, with ``z'' = (g_2 - g_1) / L = +-1 / R_v`` constant, tangent to both
gradients (so elevation and gradient are continuous and the curvature jumps at its ends).
Measured profiles are smoothed by a Gaussian of :data:`MEASURED_SMOOTHING_M` before they are
differentiated (a surveyed elevation's second difference is mostly noise).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from railexu.errors import InputError
from railexu.inputs import Section

#: Steepest gradient of an adhesion railway accepted [m/m]: 100 per mille; the steepest
#: adhesion lines (Lisbon and Porto trams, the Pöstlingbergbahn) reach about 90-116 per mille,
#: main lines stay below 40 (railexu's assumption: more is a unit mistake or a rack railway).
MAX_GRADIENT = 0.100
#: Steepest gradient with ``rack: true`` [m/m]: the Pilatus railway's 480 per mille.
MAX_RACK_GRADIENT = 0.480
#: Smallest vertical curve radius [m] (railexu's assumption): hump crests in marshalling yards
#: are about 250-500 m, main lines use 2000 m and more. Below 250 m the vertical curvature's
#: terms that railexu neglects (of order height / R_v, ``docs/curving.md``) exceed 0.4 %.
MIN_VERTICAL_RADIUS_M = 250.0
#: Sample step of the profile tables [m].
STEP_M = 0.25
#: Rounding of the curvature's jumps at the ends of vertical curves (Gaussian standard deviation)
#: [m], as the cant's kinks (:data:`railexu.track.alignment.CANT_ROUNDING_M`): keeps the pitch
#: acceleration of a body entering a vertical curve finite.
CURVATURE_ROUNDING_M = 1.0
#: Smoothing of a measured elevation before it is differentiated (Gaussian standard deviation)
#: [m] (railexu's assumption: removes survey noise, keeps vertical curves of 50 m and more).
MEASURED_SMOOTHING_M = 5.0
#: Largest elevation accepted [m] (the highest railways run at about 5000 m): more is a unit
#: mistake.
MAX_ELEVATION_M = 1.0e4

VERTICAL_KEYS = {
    "level": ("type",),
    "gradient": ("type", "gradient", "rack"),
    "stations": ("type", "stations", "rack"),
    "measured": ("type", "file", "column", "rack"),
}
STATION_KEYS = ("position", "elevation", "radius")


@dataclass(frozen=True)
class VerticalCurve:
    """A vertical curve of the design profile (for figures and statistics)."""

    start_m: float
    end_m: float
    radius_m: float  # signed: positive in a sag, negative on a crest


@dataclass
class VerticalAlignment:
    """The track's vertical profile, sampled every ``step_m`` from ``start_m``: elevation [m],
    gradient [m/m] and vertical curvature [1/m] (rounded at its jumps); beyond the samples the
    end gradients continue (see the module docstring for conventions)."""

    start_m: float
    step_m: float
    elevation_m: np.ndarray
    gradient: np.ndarray
    curvature_1_per_m: np.ndarray
    kind: str = "gradient"
    curves: list[VerticalCurve] = field(default_factory=list)
    source: str = ""
    curvature_slope: np.ndarray = field(init=False)
    grid_m: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        n = self.elevation_m.size
        self.grid_m = self.start_m + self.step_m * np.arange(n)
        self.curvature_slope = np.gradient(self.curvature_1_per_m, self.step_m)

    @property
    def end_m(self) -> float:
        return float(self.grid_m[-1])

    @property
    def is_level(self) -> bool:
        """True when the track has neither gradient nor vertical curvature anywhere."""
        return not (np.any(self.gradient) or np.any(self.curvature_1_per_m))

    def elevation(self, s) -> np.ndarray:
        """Elevation of the top of rail on the centre line [m]."""
        s = np.asarray(s, dtype=float)
        z = np.interp(s, self.grid_m, self.elevation_m)
        before = np.minimum(s - self.grid_m[0], 0.0) * self.gradient[0]
        after = np.maximum(s - self.grid_m[-1], 0.0) * self.gradient[-1]
        inside = (s >= self.grid_m[0]) & (s <= self.grid_m[-1])
        # between samples the parabola: linear elevation plus the curvature's sag
        i = np.clip(((s - self.start_m) / self.step_m).astype(int), 0, self.grid_m.size - 2)
        u = s - self.grid_m[i]
        chord = np.where(inside, 0.5 * self.curvature_1_per_m[i] * u * (u - self.step_m), 0.0)
        return z + before + after + chord

    def gradient_at(self, s) -> np.ndarray:
        """Gradient dz/ds [m/m], positive rising in the direction of travel."""
        return np.interp(np.asarray(s, dtype=float), self.grid_m, self.gradient)

    def pitch(self, s) -> np.ndarray:
        """Pitch angle of the track [rad]: ``atan(gradient)``, positive rising."""
        return np.arctan(self.gradient_at(s))

    def curvature(self, s) -> np.ndarray:
        """Vertical curvature ``d theta / ds`` [1/m]: positive in a sag; zero beyond the ends."""
        s = np.asarray(s, dtype=float)
        return np.interp(s, self.grid_m, self.curvature_1_per_m, left=0.0, right=0.0)

    def curvature_slope_at(self, s) -> np.ndarray:
        """d(vertical curvature)/ds [1/m^2]."""
        s = np.asarray(s, dtype=float)
        return np.interp(s, self.grid_m, self.curvature_slope, left=0.0, right=0.0)

    def to_dict(self) -> dict:
        """The profile as plain lists (JSON), rebuilt by :func:`vertical_from_record`."""
        return {
            "kind": self.kind, "start_m": float(self.start_m), "step_m": float(self.step_m),
            "elevation_m": [float(v) for v in self.elevation_m],
            "gradient": [float(v) for v in self.gradient],
            "curvature_1_per_m": [float(v) for v in self.curvature_1_per_m],
            "curves": [[c.start_m, c.end_m, c.radius_m] for c in self.curves],
            "source": self.source,
        }  # fmt: skip


def vertical_from_record(record: dict) -> VerticalAlignment:
    """Rebuild a :class:`VerticalAlignment` from :meth:`VerticalAlignment.to_dict`'s output.

    Raises:
        InputError: a missing or bad field.
    """
    try:
        arrays = [np.asarray(record[k], dtype=float)
                  for k in ("elevation_m", "gradient", "curvature_1_per_m")]  # fmt: skip
        curves = [VerticalCurve(float(a), float(b), float(c)) for a, b, c in record["curves"]]
        start, step = float(record["start_m"]), float(record["step_m"])
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"track vertical profile record: missing or bad field ({exc})") from None
    if len({a.size for a in arrays}) != 1 or arrays[0].size < 2 or not step > 0.0:
        raise InputError("track vertical profile record: arrays of different lengths")
    return VerticalAlignment(start, step, *arrays, str(record.get("kind", "")), curves,
                             str(record.get("source", "")))  # fmt: skip


# ---------------------------------------------------------------------------------------------
def constant_gradient(gradient: float, source: str = "") -> VerticalAlignment:
    """A constant gradient [m/m] everywhere (elevation 0 at distance 0)."""
    s = np.array([0.0, STEP_M])
    return VerticalAlignment(0.0, STEP_M, gradient * s, np.full(2, gradient), np.zeros(2),
                             "gradient", [], source)  # fmt: skip


def vertical_from_stations(
    position_m, elevation_m, radius_m, source: str = "", where=None
) -> VerticalAlignment:
    """The design profile through stations (points of intersection of the gradients) with a
    parabolic vertical curve of radius ``radius_m[i]`` at every interior station.

    Args:
        position_m, elevation_m: the stations, positions increasing [m].
        radius_m: radius of the vertical curve at each station [m] (the ends' are ignored).
        where: ``where(index, message)`` raises a located error (default: a plain InputError).

    Raises:
        InputError: overlapping vertical curves.
    """
    p = np.asarray(position_m, float)
    z = np.asarray(elevation_m, float)
    r = np.asarray(radius_m, float)
    fail = where or (lambda i, msg: (_ for _ in ()).throw(InputError(f"station {i + 1}: {msg}")))
    g = np.diff(z) / np.diff(p)  # gradient between stations
    # vertical curve at station i: from p_i - L/2 to p_i + L/2, L = R |g_i - g_{i-1}|
    half = np.zeros(p.size)
    curves = []
    for i in range(1, p.size - 1):
        dg = g[i] - g[i - 1]
        half[i] = 0.5 * r[i] * abs(dg)
        if dg != 0.0:
            curves.append(
                VerticalCurve(
                    float(p[i] - half[i]), float(p[i] + half[i]), math.copysign(float(r[i]), dg)
                )
            )
    for i in range(p.size - 1):
        room = p[i + 1] - p[i]
        if half[i] + half[i + 1] > room + 1e-9:
            fail(i + 1, f"the vertical curves at stations {i + 1} and {i + 2} overlap: they need "
                 f"{half[i] + half[i + 1]:.1f} m and the stations are {room:.1f} m apart "
                 "(smaller radii or stations further apart)")  # fmt: skip
    s = np.arange(p[0], p[-1] + STEP_M, STEP_M)
    if s[-1] < p[-1]:
        s = np.append(s, s[-1] + STEP_M)
    k = np.clip(np.searchsorted(p, s, side="right") - 1, 0, p.size - 2)
    zs = z[k] + g[k] * (s - p[k])
    gs = g[k].copy()
    ks = np.zeros_like(s)
    for i in range(1, p.size - 1):
        if half[i] == 0.0:
            continue
        a = p[i] - half[i]
        on = (s >= a) & (s <= p[i] + half[i])
        u = s[on] - a
        c = (g[i] - g[i - 1]) / (2.0 * half[i])
        zs[on] = z[i] - g[i - 1] * half[i] + g[i - 1] * u + 0.5 * c * u * u
        gs[on] = g[i - 1] + c * u
        ks[on] = c
    kappa = ks / (1.0 + gs * gs) ** 1.5
    kappa = _rounded(kappa, CURVATURE_ROUNDING_M)
    return VerticalAlignment(float(s[0]), STEP_M, zs, gs, kappa, "stations", curves, source)


def vertical_from_samples(
    distance_m, elevation_m, smoothing_m: float = MEASURED_SMOOTHING_M, source: str = ""
) -> VerticalAlignment:
    """A measured profile: elevation samples (linear between them), resampled every
    :data:`STEP_M`, smoothed by a Gaussian of ``smoothing_m`` and differentiated; beyond its
    ends the record is continued point-symmetrically about its end points while it is
    smoothed, so that the end elevations and a constant gradient are kept."""
    d = np.asarray(distance_m, float)
    s = np.arange(d[0], d[-1] + 0.5 * STEP_M, STEP_M)
    z = np.interp(s, d, np.asarray(elevation_m, float))
    zs = _smoothed_point_symmetric(z, smoothing_m)
    g = np.gradient(zs, STEP_M)
    kappa = np.gradient(g, STEP_M) / (1.0 + g * g) ** 1.5
    return VerticalAlignment(float(s[0]), STEP_M, zs, g, kappa, "measured", [], source)


def _smoothed_point_symmetric(values: np.ndarray, sigma_m: float) -> np.ndarray:
    """``values`` (samples every :data:`STEP_M`) smoothed by a Gaussian of ``sigma_m``, the
    record continued beyond each end by its point reflection about the end sample (the mean of
    every symmetric pair is the end value: ends and straight lines are kept)."""
    from scipy.ndimage import gaussian_filter1d

    n = values.size
    if sigma_m <= 0.0 or n < 3:
        return values
    pad = min(n - 1, int(math.ceil(4.0 * sigma_m / STEP_M)))
    head = 2.0 * values[0] - values[pad:0:-1]
    tail = 2.0 * values[-1] - values[-2 : -pad - 2 : -1]
    full = np.concatenate([head, values, tail])
    return gaussian_filter1d(full, sigma_m / STEP_M, mode="nearest")[pad : pad + n]


def _rounded(values: np.ndarray, sigma_m: float) -> np.ndarray:
    """``values`` (samples every :data:`STEP_M`) smoothed by a Gaussian of ``sigma_m``."""
    from scipy.ndimage import gaussian_filter1d

    if sigma_m <= 0.0 or values.size < 3:
        return values
    return gaussian_filter1d(values, sigma_m / STEP_M, mode="nearest")


def read_measured_profile(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a CSV of distance [m] and elevation [m]; lines starting with ``#`` and a header line
    are skipped.

    Raises:
        InputError: unreadable or non-finite numbers, fewer than 2 rows, distances not
            increasing, absurd values; with the file and line.
    """
    rows: list[list[float]] = []
    source = str(path)
    with open(path, newline="") as fh:
        for lineno, row in enumerate(csv.reader(fh), start=1):
            if not row or row[0].lstrip().startswith("#"):
                continue
            try:
                values = [float(v) for v in row]
            except ValueError:
                if rows:
                    raise InputError(f"expected two numbers (distance, elevation), got {row!r}",
                                     source=source, line=lineno) from None  # fmt: skip
                continue  # header
            if len(values) != 2:
                raise InputError("expected two columns: distance [m], elevation [m]",
                                 source=source, line=lineno)  # fmt: skip
            if not all(math.isfinite(v) for v in values):
                raise InputError(f"expected finite numbers, got {values}", source=source,
                                 line=lineno)  # fmt: skip
            if abs(values[0]) > 1.0e6 or abs(values[1]) > MAX_ELEVATION_M:
                raise InputError(f"distance {values[0]:g} m or elevation {values[1]:g} m out of "
                                 f"range (|distance| <= 1000 km, |elevation| <= "
                                 f"{MAX_ELEVATION_M:g} m): is a unit wrong?",
                                 source=source, line=lineno)  # fmt: skip
            if rows and not values[0] > rows[-1][0]:
                raise InputError(f"distance {values[0]:g} m is not beyond the previous row's "
                                 f"{rows[-1][0]:g} m: distances must increase",
                                 source=source, line=lineno)  # fmt: skip
            rows.append(values)
    if len(rows) < 2:
        raise InputError("needs at least two rows (distance [m], elevation [m])", source=source)
    data = np.array(rows)
    return data[:, 0], data[:, 1]


# ---------------------------------------------------------------------------------------------
def vertical_from_dict(
    data: dict | None, source: str = "<track>", lines: dict | None = None, path=None
) -> VerticalAlignment | None:
    """Validate a track file's ``vertical:`` section (``None`` or ``type: level``: a level
    track, returned as None).

    Raises:
        InputError: naming file, line and key.
    """
    if data is None:
        return None
    top = Section(data, source, lines, ("vertical",))
    kind = top.string("type", choices=tuple(VERTICAL_KEYS))
    top = Section(data, source, lines, ("vertical",), VERTICAL_KEYS[kind])
    if kind == "level":
        return None
    rack = top.boolean("rack", default=False)
    steepest = MAX_RACK_GRADIENT if rack else MAX_GRADIENT
    if kind == "gradient":
        g = _gradient(top, "gradient", steepest, rack)
        return constant_gradient(g, source)
    if kind == "measured":
        return _measured(top, path, steepest, rack, source)
    raw = top.data.get("stations")
    if not isinstance(raw, list) or len(raw) < 2:
        top.fail("expected a list of at least two stations ({position, elevation, radius})",
                 key="stations")  # fmt: skip
    pos, elev, rad = [], [], []
    for j, item in enumerate(raw):
        st = Section(item, source, lines, ("vertical", "stations", j), STATION_KEYS)
        p = st.quantity("position", "m", minimum=-1.0e6, maximum=1.0e6)
        if pos and not p > pos[-1]:
            st.fail(f"position {p:g} m is not beyond the previous station's {pos[-1]:g} m: "
                    "stations must be in the order of travel", key="position")  # fmt: skip
        pos.append(p)
        elev.append(st.quantity("elevation", "m", minimum=-MAX_ELEVATION_M,
                                maximum=MAX_ELEVATION_M))  # fmt: skip
        interior = 0 < j < len(raw) - 1
        if interior:
            rad.append(st.quantity("radius", "m", minimum=MIN_VERTICAL_RADIUS_M, maximum=1.0e7))
        else:
            if st.has("radius"):
                st.fail("the first and the last station have no vertical curve (they continue "
                        "their gradient): remove radius", key="radius")  # fmt: skip
            rad.append(0.0)
    grads = np.diff(elev) / np.diff(pos)
    for j, g in enumerate(grads):
        if abs(g) > steepest:
            Section(raw[j + 1], source, lines, ("vertical", "stations", j + 1)).fail(
                f"the gradient from station {j + 1} to {j + 2} is {1e3 * g:.1f} per mille, "
                f"steeper than {1e3 * steepest:g} per mille" + _rack_hint(rack),
                key="elevation",
            )

    def where(i: int, message: str):
        Section(raw[i], source, lines, ("vertical", "stations", i)).fail(message)

    return vertical_from_stations(pos, elev, rad, source, where)


def _rack_hint(rack: bool) -> str:
    return "" if rack else " (an adhesion railway's limit; set rack: true for a rack railway)"


def _gradient(sec: Section, key: str, steepest: float, rack: bool) -> float:
    """A gradient: a plain number is per mille, a string may carry its unit ('1.2 %')."""
    raw = sec.data.get(key)
    if isinstance(raw, bool) or raw is None:
        sec.fail("expected a gradient in per mille (a number, positive rising) or with its "
                 "unit ('1.25 %')", key=key)  # fmt: skip
    value = 1e-3 * float(raw) if isinstance(raw, int | float) else sec.quantity(key, "1")
    if not math.isfinite(value):
        sec.fail(f"expected a finite gradient, got {raw!r}", key=key)
    if abs(value) > steepest:
        sec.fail(f"{1e3 * value:g} per mille is steeper than {1e3 * steepest:g} per mille"
                 + _rack_hint(rack), key=key)  # fmt: skip
    return value


def _measured(top: Section, path, steepest: float, rack: bool, source: str) -> VerticalAlignment:
    file = Path(top.string("file"))
    if not file.is_absolute() and path is not None:
        file = Path(path) / file
    if not file.is_file():
        top.fail(f"vertical profile file {str(file)!r} not found", key="file")
    column = top.string("column", default="elevation", choices=("elevation", "gradient"))
    try:
        d, z = read_measured_profile(file)
    except InputError as exc:  # the track file's line too, then the data file's
        top.fail(str(exc), key="file")
    except (OSError, UnicodeDecodeError) as exc:
        top.fail(f"cannot read {str(file)!r}: {exc}", key="file")
    if column == "gradient":  # per mille: integrated (trapezoids) from elevation 0
        g = 1e-3 * z
        if np.max(np.abs(g)) > steepest:
            top.fail(f"{file.name}: a gradient of {1e3 * np.max(np.abs(g)):.1f} per mille is "
                     f"steeper than {1e3 * steepest:g} per mille" + _rack_hint(rack),
                     key="file")  # fmt: skip
        z = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(d))])
    profile = vertical_from_samples(d, z, source=source)
    steep = float(np.max(np.abs(profile.gradient)))
    if steep > steepest:
        at = float(profile.grid_m[int(np.argmax(np.abs(profile.gradient)))])
        top.fail(f"{file.name}: the profile's gradient reaches {1e3 * steep:.1f} per mille at "
                 f"{at:.1f} m, "
                 f"steeper than {1e3 * steepest:g} per mille" + _rack_hint(rack),
                 key="file")  # fmt: skip
    radius = 1.0 / max(float(np.max(np.abs(profile.curvature_1_per_m))), 1e-12)
    if radius < MIN_VERTICAL_RADIUS_M:
        top.fail(f"{file.name}: the smoothed profile has a vertical curve of radius "
                 f"{radius:.0f} m, below "
                 f"{MIN_VERTICAL_RADIUS_M:g} m: check the elevation's unit or the survey",
                 key="file")  # fmt: skip
    return profile


def vertical_columns(vertical: VerticalAlignment, s_m: np.ndarray) -> dict[str, np.ndarray]:
    """Time-series columns of the vertical profile at the distances ``s_m`` (the leading
    wheelset's): elevation [m], gradient [per mille, positive rising] and vertical curvature
    [1/m, positive in a sag]."""
    s = np.asarray(s_m, dtype=float)
    return {
        "track_elevation_m": vertical.elevation(s),
        "track_gradient_per_mille": 1e3 * vertical.gradient_at(s),
        "track_vertical_curvature_1_per_m": vertical.curvature(s),
    }
