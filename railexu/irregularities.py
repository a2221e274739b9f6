"""Track irregularities: spectra, synthesis, measured records and rail offsets.

Model
-----
A track carries four irregularity signals, functions of the distance ``x`` along the track (m),
in the track frame of ``docs/conventions.md`` (``y`` lateral positive to the **left**, ``z`` up):

- ``lateral`` -- alignment ``y_a(x)``: lateral position of the mean of the two rails, m, positive
  to the left;
- ``vertical`` -- vertical profile (longitudinal level) ``z_v(x)``: height of the mean of the two
  rails, m, positive up;
- ``cross_level`` -- ``c(x)``: height of the left rail minus height of the right rail, **a height
  difference in metres** (not an angle). It is the deviation from the design cant, not the cant
  itself. The corresponding roll angle of the track is ``c / RAIL_DISTANCE_M`` rad, with
  ``RAIL_DISTANCE_M = 2 b = 1.5 m`` the distance between the nominal contact points;
- ``gauge`` -- ``g(x)``: actual gauge minus nominal gauge, m (positive = wide gauge).

The rails are displaced from their nominal positions by

    left rail:   dy = y_a + g/2,   dz = z_v + c/2
    right rail:  dy = y_a - g/2,   dz = z_v - c/2

so that ``dy_left - dy_right = g`` and ``dz_left - dz_right = c``. The rail velocities seen by a
vehicle running at speed ``V`` are ``V * d(dy, dz)/dx``, available through ``derivative=1``.

Units: everything is SI. Spectra are one-sided power spectral densities over the spatial angular
frequency ``Omega = 2 pi / wavelength`` in rad/m, in m^2/(rad/m), so that the variance of a signal
is the integral of its PSD over ``Omega`` (m^2).

Spectra (``get_spectrum(name)``)
--------------------------------
``german_low``, ``german_high`` -- the German spectra of ERRI (ORE) B176, low and high level, as
given in railexu's ``physics.md`` section 6, with ``Oc = 0.8246``, ``Or = 0.0206``,
``Os = 0.4380`` rad/m and ``b = 0.75`` m (half the distance between the rails' contact points)::

    S_a(O) = A_a Oc^2 / ((O^2 + Or^2)(O^2 + Oc^2))                        alignment
    S_v(O) = A_v Oc^2 / ((O^2 + Or^2)(O^2 + Oc^2))                        vertical
    S_t(O) = (A_v / b^2) Oc^2 O^2 / ((O^2 + Or^2)(O^2 + Oc^2)(O^2 + Os^2))  cross-level ANGLE
    S_g(O) = A_g Oc^2 O^2 / ((O^2 + Or^2)(O^2 + Oc^2)(O^2 + Os^2))         gauge

with ``A`` in m rad (low: ``A_a = 2.119e-7``, ``A_v = 4.032e-7``, ``A_g = 5.32e-8``; high:
``A_a = 6.125e-7``, ``A_v = 1.080e-6``, ``A_g = 1.032e-7``). Units: ``Oc^2/((O^2+Or^2)(O^2+Oc^2))``
is in (rad/m)^-2 = m^2/rad^2, so ``S_a``, ``S_v`` and ``S_g`` come out in
m rad * m^2/rad^2 = m^2/(rad/m). ``S_t`` is the PSD of the cross-level *angle*: ``A_v/b^2`` is
in rad/m, so ``S_t`` is in 1/(rad/m), i.e. rad^2 of angle per rad/m. railexu's cross level is the
height difference ``c = 2 b * angle``, so its PSD is ``(2 b)^2 S_t = 4 A_v Oc^2 O^2 / (...)`` in
m^2/(rad/m).

``fra_class_1`` ... ``fra_class_6`` -- the US FRA (Federal Railroad Administration) vertical
profile spectrum for track classes 1-6, as in ``physics.md`` section 6::

    S_v(O) = k A_v Oc^2 / (O^2 (O^2 + Oc^2)),   k = 0.25, Oc = 0.8245 rad/m

with ``A_v`` = 1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339 cm^2 rad/m for classes 1-6, converted
to SI (times 1e-4 m^2/cm^2), giving m^2/(rad/m). The formula is stated valid for wavelengths
1.524-304.8 m (5-1000 ft); synthesizing outside that band warns. Only the vertical spectrum is
implemented: the FRA alignment, cross-level and gauge formulas circulate in secondary literature
with coefficients railexu could not check against a citable source, so asking for them raises
``NotImplementedError`` (synthesize FRA track with ``components=("vertical",)``).

Synthesis (``synthesize_irregularities``)
-----------------------------------------
Sum of cosines (``physics.md`` section 6): the band ``[2 pi/wavelength_max, 2 pi/wavelength_min]``
is cut into ``N`` equal intervals of width ``dO`` with midpoints ``O_k``; each signal is

    q(x) = sum_k a_k cos(O_k x + phi_k),   a_k = amplitude_scale * sqrt(2 S(O_k) dO)

with phases ``phi`` drawn as ``numpy.random.default_rng(seed).uniform(0, 2 pi, size=(4, N))``, one
row per signal in the order of ``COMPONENTS`` (the rows are drawn whether or not a signal is
selected, so the selection does not change the other signals). The four signals are therefore
independent. The ensemble variance of ``q`` is ``sum a_k^2 / 2``, the midpoint-rule integral of
``S`` over the band; over one whole period ``2 pi/dO`` sampled uniformly the mean square equals it
exactly when ``2 pi/wavelength_max`` is a multiple of ``dO/2`` (and approximately otherwise), while
a shorter record scatters around it like any finite sample of a random process. The sum is
evaluated with a chirp-z transform (exact up to rounding; the record is cut into blocks to keep it
so).

Reference values: over the band 3-150 m the German low level gives rms values of 2.08 mm
(lateral), 2.86 mm (vertical), 1.82 mm (cross level as a height difference, i.e. 1.22 mrad) and
0.33 mm (gauge); see :meth:`TrackSpectrum.band_rms`.

Evaluation, fade and sampling
-----------------------------
An :class:`IrregularityProfile` stores the raw signals on a uniform grid. Between grid points they
are interpolated with a not-a-knot cubic spline (``scipy.interpolate.CubicSpline``), which is C2,
so the rail offsets and their slopes are continuous. The offsets returned by
:meth:`IrregularityProfile.left_rail_offsets` and friends are the raw signals multiplied by a
window ``w(x)`` that rises from 0 to 1 over the first ``fade_length_m`` metres of the record and
falls back to 0 over the last ``fade_length_m`` metres, with the quintic smoothstep
``s(t) = 6 t^5 - 15 t^4 + 10 t^3`` (value, slope and curvature continuous). Before the start and
beyond the end of the record the irregularities are zero. The stored signals are not faded, so a
CSV round trip returns the data unchanged.

:meth:`IrregularityProfile.sampled` resamples the faded rail offsets and their exact slopes
``d/dx`` onto a uniform grid for a compiled kernel, which must interpolate them with the cubic
Hermite polynomial from values and slopes (reference implementation:
:meth:`SampledIrregularities.evaluate`) and use zero outside the grid.
"""

from __future__ import annotations

import csv
import difflib
import math
import re
import warnings
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline

from .errors import InputError

__all__ = [
    "COMPONENTS",
    "RAIL_DISTANCE_M",
    "IrregularityError",
    "IrregularityProfile",
    "SampledIrregularities",
    "TrackSpectrum",
    "available_spectra",
    "component_amplitudes",
    "get_spectrum",
    "psd_estimate",
    "read_measured_irregularities",
    "rms",
    "synthesize_irregularities",
]

FloatArray = NDArray[np.float64]

#: The four irregularity signals, in the order used for random phases and stacked arrays.
COMPONENTS: tuple[str, ...] = ("lateral", "vertical", "cross_level", "gauge")

#: Distance between the nominal contact points of the two rails, ``2 b`` (m).
RAIL_DISTANCE_M = 1.5

# German (ERRI B176) spectrum constants, physics.md section 6.
GERMAN_OMEGA_C = 0.8246  # rad/m
GERMAN_OMEGA_R = 0.0206  # rad/m
GERMAN_OMEGA_S = 0.4380  # rad/m
GERMAN_HALF_RAIL_DISTANCE_M = 0.75  # b, m

# US FRA vertical spectrum constants, physics.md section 6.
FRA_K = 0.25
FRA_OMEGA_C = 0.8245  # rad/m
FRA_A_V_CM2 = (1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339)  # cm^2 rad/m, classes 1..6
FRA_VALID_WAVELENGTH_M = (1.524, 304.8)

_FADE_DEFAULT_M = 10.0
_CZT_BLOCK = 1 << 15
_UNIFORM_RTOL = 1e-6


class IrregularityError(InputError):
    """Invalid irregularity data or arguments (bad CSV file, unknown name, bad grid)."""


def _did_you_mean(name: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.5)
    if not close:
        return ""
    return " Did you mean " + " or ".join(repr(c) for c in close) + "?"


def _check_component(component: str) -> str:
    if component not in COMPONENTS:
        raise IrregularityError(
            f"unknown irregularity component {component!r}; expected one of "
            f"{', '.join(COMPONENTS)}.{_did_you_mean(str(component), COMPONENTS)}"
        )
    return component


# ----------------------------------------------------------------------------------------------
# Spectra
# ----------------------------------------------------------------------------------------------

PsdFunction = Callable[[FloatArray], FloatArray]


@dataclass(frozen=True)
class TrackSpectrum:
    """A set of one-sided track irregularity PSDs, one per signal.

    Attributes:
        name: registry name (``"german_low"``, ...).
        description: one-line description.
        source: where the formula and coefficients come from.
        valid_wavelength_m: ``(min, max)`` wavelength range (m) the source states the formula is
            valid for, or ``None`` if it states none.
        formulas: ``component -> PSD(Omega)`` for the implemented components; Omega in rad/m,
            PSD in m^2/(rad/m).
        unavailable_reason: message for the components that are not implemented.
    """

    name: str
    description: str
    source: str
    valid_wavelength_m: tuple[float, float] | None
    formulas: Mapping[str, PsdFunction] = field(repr=False)
    unavailable_reason: str = ""

    @property
    def components(self) -> tuple[str, ...]:
        """The implemented components, in the order of ``COMPONENTS``."""
        return tuple(c for c in COMPONENTS if c in self.formulas)

    def require(self, component: str) -> None:
        """Raise if ``component`` is unknown (``IrregularityError``) or not implemented here
        (``NotImplementedError``)."""
        _check_component(component)
        if component not in self.formulas:
            raise NotImplementedError(
                f"spectrum {self.name!r} has no {component!r} PSD: {self.unavailable_reason} "
                f"Available components: {', '.join(self.components)}."
            )

    def psd(self, component: str, omega: ArrayLike) -> FloatArray:
        """One-sided PSD of ``component`` at spatial angular frequency ``omega`` (rad/m).

        Returns m^2/(rad/m) for every component; for ``cross_level`` this is the PSD of the
        height difference between the rails (m), see the module docstring.
        """
        self.require(component)
        om = np.asarray(omega, dtype=float)
        return np.asarray(self.formulas[component](om), dtype=float)

    def band_variance(
        self, component: str, wavelength_min_m: float, wavelength_max_m: float
    ) -> float:
        """Integral of the PSD over the wavelength band (m^2): the variance of a signal
        containing exactly these wavelengths."""
        lo, hi = _band(wavelength_min_m, wavelength_max_m)
        self.require(component)
        from scipy import integrate  # lazy: keeps `import railexu` fast

        value, _ = integrate.quad(
            lambda o: float(self.psd(component, o)), lo, hi, limit=200, epsrel=1e-10
        )
        return float(value)

    def band_rms(self, component: str, wavelength_min_m: float, wavelength_max_m: float) -> float:
        """Root mean square (m) of ``component`` restricted to the wavelength band."""
        return math.sqrt(self.band_variance(component, wavelength_min_m, wavelength_max_m))


def _german_plain(a: float) -> PsdFunction:
    oc2, or2 = GERMAN_OMEGA_C**2, GERMAN_OMEGA_R**2

    def psd(om: FloatArray) -> FloatArray:
        o2 = om * om
        return a * oc2 / ((o2 + or2) * (o2 + oc2))

    return psd


def _german_band(a: float) -> PsdFunction:
    oc2, or2, os2 = GERMAN_OMEGA_C**2, GERMAN_OMEGA_R**2, GERMAN_OMEGA_S**2

    def psd(om: FloatArray) -> FloatArray:
        o2 = om * om
        return a * oc2 * o2 / ((o2 + or2) * (o2 + oc2) * (o2 + os2))

    return psd


def _german(name: str, level: str, a_a: float, a_v: float, a_g: float) -> TrackSpectrum:
    b = GERMAN_HALF_RAIL_DISTANCE_M
    # Cross-level angle PSD uses A_v / b^2; height difference c = (2b) * angle.
    a_cross_height = RAIL_DISTANCE_M**2 * a_v / b**2
    return TrackSpectrum(
        name=name,
        description=f"German (ERRI B176) {level}-level track spectrum",
        source=(
            "ERRI (ORE) B176 German spectra as given in railexu physics.md section 6; "
            f"A_a = {a_a:g}, A_v = {a_v:g}, A_g = {a_g:g} m rad; cross level converted from "
            f"angle to height difference with 2b = {RAIL_DISTANCE_M} m"
        ),
        valid_wavelength_m=None,
        formulas={
            "lateral": _german_plain(a_a),
            "vertical": _german_plain(a_v),
            "cross_level": _german_band(a_cross_height),
            "gauge": _german_band(a_g),
        },
    )


def _fra_vertical(a_v_si: float) -> PsdFunction:
    oc2 = FRA_OMEGA_C**2

    def psd(om: FloatArray) -> FloatArray:
        o2 = om * om
        with np.errstate(divide="ignore"):
            return FRA_K * a_v_si * oc2 / (o2 * (o2 + oc2))

    return psd


def _fra(track_class: int) -> TrackSpectrum:
    a_cm2 = FRA_A_V_CM2[track_class - 1]
    return TrackSpectrum(
        name=f"fra_class_{track_class}",
        description=f"US FRA class {track_class} track spectrum (vertical profile only)",
        source=(
            "US FRA vertical-profile spectrum as given in railexu physics.md section 6; "
            f"k = {FRA_K}, Oc = {FRA_OMEGA_C} rad/m, A_v = {a_cm2} cm^2 rad/m "
            f"= {a_cm2 * 1e-4:g} m^2 rad/m; valid for wavelengths 1.524-304.8 m"
        ),
        valid_wavelength_m=FRA_VALID_WAVELENGTH_M,
        formulas={"vertical": _fra_vertical(a_cm2 * 1e-4)},
        unavailable_reason=(
            "only the FRA vertical-profile spectrum is implemented; the FRA alignment, "
            "cross-level and gauge formulas could not be verified against a citable source."
        ),
    )


_SPECTRA: dict[str, TrackSpectrum] = {
    "german_low": _german("german_low", "low", 2.119e-7, 4.032e-7, 5.32e-8),
    "german_high": _german("german_high", "high", 6.125e-7, 1.080e-6, 1.032e-7),
    **{f"fra_class_{i}": _fra(i) for i in range(1, 7)},
}


def available_spectra() -> tuple[str, ...]:
    """Names accepted by :func:`get_spectrum`."""
    return tuple(_SPECTRA)


def get_spectrum(name: str) -> TrackSpectrum:
    """The spectrum registered as ``name`` (case and surrounding blanks ignored).

    Raises:
        IrregularityError: unknown name, with close matches suggested.
    """
    key = str(name).strip().lower()
    try:
        return _SPECTRA[key]
    except KeyError:
        raise IrregularityError(
            f"unknown track spectrum {name!r}; available: {', '.join(_SPECTRA)}."
            f"{_did_you_mean(key, _SPECTRA)}"
        ) from None


def _resolve_spectrum(spectrum: str | TrackSpectrum) -> TrackSpectrum:
    return spectrum if isinstance(spectrum, TrackSpectrum) else get_spectrum(spectrum)


def _band(wavelength_min_m: float, wavelength_max_m: float) -> tuple[float, float]:
    lmin, lmax = float(wavelength_min_m), float(wavelength_max_m)
    if not (math.isfinite(lmin) and math.isfinite(lmax) and 0.0 < lmin < lmax):
        raise IrregularityError(
            f"wavelength band must satisfy 0 < wavelength_min_m < wavelength_max_m, "
            f"got {wavelength_min_m!r} and {wavelength_max_m!r} m"
        )
    return 2.0 * math.pi / lmax, 2.0 * math.pi / lmin


# ----------------------------------------------------------------------------------------------
# Synthesis
# ----------------------------------------------------------------------------------------------


def component_amplitudes(
    spectrum: str | TrackSpectrum,
    component: str,
    wavelength_min_m: float,
    wavelength_max_m: float,
    n_components: int,
    amplitude_scale: float = 1.0,
) -> tuple[FloatArray, FloatArray]:
    """Frequencies ``O_k`` (rad/m) and amplitudes ``a_k`` (m) of the sum-of-cosines synthesis.

    ``O_k`` are the midpoints of ``n_components`` equal intervals ``dO`` covering
    ``[2 pi/wavelength_max_m, 2 pi/wavelength_min_m]``; ``a_k = amplitude_scale *
    sqrt(2 S(O_k) dO)``, so ``sum(a_k**2) / 2`` is the midpoint-rule integral of the PSD (times
    ``amplitude_scale**2``).
    """
    spec = _resolve_spectrum(spectrum)
    spec.require(component)
    lo, hi = _band(wavelength_min_m, wavelength_max_m)
    n = int(n_components)
    if n < 1 or n != n_components:
        raise IrregularityError(f"n_components must be a positive integer, got {n_components!r}")
    d_omega = (hi - lo) / n
    omega = lo + (np.arange(n) + 0.5) * d_omega
    amplitude = float(amplitude_scale) * np.sqrt(2.0 * spec.psd(component, omega) * d_omega)
    return omega, amplitude


def _sum_of_cosines(
    x0: float, step: float, n_points: int, omega: FloatArray, amp: FloatArray, phase: FloatArray
) -> FloatArray:
    """``sum_k amp_k cos(omega_k x_j + phase_k)`` at ``x_j = x0 + j step``, for equally spaced
    ``omega``, by chirp-z transform in blocks (the error grows with the block length)."""
    if omega.size == 1:
        x = x0 + step * np.arange(n_points)
        return amp[0] * np.cos(omega[0] * x + phase[0])
    d_omega = omega[1] - omega[0]
    w = np.exp(1j * d_omega * step)
    out = np.empty(n_points)
    for start in range(0, n_points, _CZT_BLOCK):
        m = min(_CZT_BLOCK, n_points - start)
        xb = x0 + start * step
        coeff = amp * np.exp(1j * (omega * xb + phase))
        from scipy import signal as sp_signal  # lazy: keeps `import railexu` fast

        z = sp_signal.czt(coeff, m=m, w=w, a=1.0)
        out[start : start + m] = np.real(np.exp(1j * omega[0] * step * np.arange(m)) * z)
    return out


def synthesize_irregularities(
    spectrum: str | TrackSpectrum,
    length_m: float,
    seed: int,
    wavelength_min_m: float,
    wavelength_max_m: float,
    n_components: int | None = None,
    amplitude_scale: float = 1.0,
    components: Iterable[str] = COMPONENTS,
    *,
    step_m: float | None = None,
    start_m: float = 0.0,
    fade_length_m: float = _FADE_DEFAULT_M,
) -> IrregularityProfile:
    """Random track irregularities following a spectrum, by the sum-of-cosines method.

    Args:
        spectrum: registry name (see :func:`available_spectra`) or a :class:`TrackSpectrum`.
        length_m: length of the record (m); the grid runs from ``start_m`` to
            ``start_m + length_m`` inclusive.
        seed: seed of ``numpy.random.default_rng``; same arguments and seed give the same
            profile.
        wavelength_min_m, wavelength_max_m: wavelength band (m) of the synthesized signals.
        n_components: number of cosines per signal. Default: enough for the sum's period
            ``2 pi/dO`` to be at least twice the record length, and at least 256.
        amplitude_scale: factor on every signal (the PSD is multiplied by its square).
        components: signals to synthesize, among ``COMPONENTS``; the others are zero.
        step_m: grid step (m); default ``wavelength_min_m / 16``. The actual step is the largest
            one not above it that divides ``length_m``.
        start_m: distance (m) where the record starts.
        fade_length_m: fade-in/fade-out length (m) of the returned profile.

    Raises:
        IrregularityError: unknown spectrum or component, or invalid arguments.
        NotImplementedError: a selected component has no PSD in this spectrum (FRA: only
            ``vertical``).
    """
    spec = _resolve_spectrum(spectrum)
    selected = tuple(components) if not isinstance(components, str) else (components,)
    for comp in selected:
        spec.require(comp)
    if len(set(selected)) != len(selected):
        raise IrregularityError(f"components listed twice: {selected}")
    length = float(length_m)
    if not (math.isfinite(length) and length > 0.0):
        raise IrregularityError(f"length_m must be positive, got {length_m!r}")
    lo, hi = _band(wavelength_min_m, wavelength_max_m)
    if not math.isfinite(float(amplitude_scale)) or amplitude_scale < 0.0:
        raise IrregularityError(f"amplitude_scale must be >= 0, got {amplitude_scale!r}")
    if spec.valid_wavelength_m is not None:
        vmin, vmax = spec.valid_wavelength_m
        if wavelength_min_m < vmin or wavelength_max_m > vmax:
            warnings.warn(
                f"spectrum {spec.name!r} is stated valid for wavelengths {vmin}-{vmax} m; "
                f"synthesizing {wavelength_min_m}-{wavelength_max_m} m extrapolates it",
                UserWarning,
                stacklevel=2,
            )
    if n_components is None:
        n_components = max(256, math.ceil((hi - lo) * length / math.pi))
    step_target = float(wavelength_min_m) / 16.0 if step_m is None else float(step_m)
    if not (math.isfinite(step_target) and step_target > 0.0):
        raise IrregularityError(f"step_m must be positive, got {step_m!r}")
    n_intervals = max(1, math.ceil(length / step_target - 1e-9))
    step = length / n_intervals
    n_points = n_intervals + 1

    rng = np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2.0 * math.pi, size=(len(COMPONENTS), int(n_components)))
    signals = {c: np.zeros(n_points) for c in COMPONENTS}
    for comp in selected:
        omega, amp = component_amplitudes(
            spec, comp, wavelength_min_m, wavelength_max_m, n_components, amplitude_scale
        )
        signals[comp] = _sum_of_cosines(
            float(start_m), step, n_points, omega, amp, phases[COMPONENTS.index(comp)]
        )
    distance = float(start_m) + step * np.arange(n_points)
    distance[-1] = float(start_m) + length
    return IrregularityProfile(
        distance_m=distance,
        lateral_m=signals["lateral"],
        vertical_m=signals["vertical"],
        cross_level_m=signals["cross_level"],
        gauge_m=signals["gauge"],
        fade_length_m=fade_length_m,
        description=(
            f"synthesized: {spec.name}, seed {seed}, {wavelength_min_m}-{wavelength_max_m} m, "
            f"{n_components} cosines, scale {amplitude_scale}, components {', '.join(selected)}"
        ),
    )


# ----------------------------------------------------------------------------------------------
# Profile
# ----------------------------------------------------------------------------------------------


def _smootherstep(t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Quintic smoothstep on [0, 1] (clamped outside) and its derivative d/dt."""
    t = np.clip(t, 0.0, 1.0)
    s = t * t * t * (t * (6.0 * t - 15.0) + 10.0)
    ds = 30.0 * t * t * (1.0 - t) ** 2
    return s, ds


def _readonly(a: ArrayLike, name: str) -> FloatArray:
    arr = np.array(a, dtype=float, copy=True)
    if arr.ndim != 1:
        raise IrregularityError(f"{name} must be a 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise IrregularityError(f"{name} contains non-finite values")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class IrregularityProfile:
    """The four irregularity signals of a track on a uniform grid (SI units).

    Attributes:
        distance_m: uniform, strictly increasing grid of distances along the track (m).
        lateral_m: alignment ``y_a`` (m, positive left).
        vertical_m: vertical profile ``z_v`` (m, positive up).
        cross_level_m: height of the left rail minus the right rail ``c`` (m).
        gauge_m: gauge minus nominal gauge ``g`` (m).
        fade_length_m: length (m) of the smooth fade-in at the start and fade-out at the end
            applied to the rail offsets (0 disables it; then the offsets jump at the ends).
        description: free text on where the data comes from.

    The stored arrays are the raw (unfaded) signals; see the module docstring for the
    interpolation, the fade and the rail offsets. The arrays are read-only copies; use
    ``dataclasses.replace(profile, fade_length_m=...)`` for another fade length.
    """

    distance_m: FloatArray
    lateral_m: FloatArray
    vertical_m: FloatArray
    cross_level_m: FloatArray
    gauge_m: FloatArray
    fade_length_m: float = _FADE_DEFAULT_M
    description: str = ""
    _spline: CubicSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        names = ("distance_m", "lateral_m", "vertical_m", "cross_level_m", "gauge_m")
        arrays = {n: _readonly(getattr(self, n), n) for n in names}
        for n, a in arrays.items():
            object.__setattr__(self, n, a)
        x = arrays["distance_m"]
        if x.size < 2:
            raise IrregularityError("an irregularity profile needs at least 2 grid points")
        for n in names[1:]:
            if arrays[n].shape != x.shape:
                raise IrregularityError(
                    f"{n} has {arrays[n].size} values but distance_m has {x.size}"
                )
        dx = np.diff(x)
        if np.any(dx <= 0.0):
            i = int(np.argmax(dx <= 0.0))
            raise IrregularityError(
                f"distance_m must increase strictly; index {i + 1} ({x[i + 1]} m) follows {x[i]} m"
            )
        h = (x[-1] - x[0]) / (x.size - 1)
        if np.max(np.abs(dx - h)) > _UNIFORM_RTOL * h:
            raise IrregularityError(
                f"distance_m must be a uniform grid; steps range from {dx.min()} to {dx.max()} m"
            )
        fade = float(self.fade_length_m)
        if not (math.isfinite(fade) and fade >= 0.0):
            raise IrregularityError(f"fade_length_m must be >= 0, got {self.fade_length_m!r}")
        if 2.0 * fade > x[-1] - x[0] + 1e-12:
            raise IrregularityError(
                f"fade_length_m = {fade} m is longer than half the record "
                f"({x[-1] - x[0]} m); use a shorter fade or a longer record"
            )
        object.__setattr__(self, "fade_length_m", fade)
        stacked = np.stack([arrays[f"{c}_m"] for c in COMPONENTS], axis=-1)
        object.__setattr__(self, "_spline", CubicSpline(x, stacked, axis=0))

    # -- grid ----------------------------------------------------------------------------------

    @property
    def start_m(self) -> float:
        """First grid distance (m)."""
        return float(self.distance_m[0])

    @property
    def end_m(self) -> float:
        """Last grid distance (m)."""
        return float(self.distance_m[-1])

    @property
    def length_m(self) -> float:
        """Length of the record (m)."""
        return self.end_m - self.start_m

    @property
    def step_m(self) -> float:
        """Grid step (m)."""
        return self.length_m / (self.distance_m.size - 1)

    # -- evaluation ----------------------------------------------------------------------------

    def window(self, x: ArrayLike, derivative: int = 0) -> FloatArray:
        """The fade window ``w(x)`` (``derivative=0``, dimensionless) or ``dw/dx`` (1/m)."""
        w, dw = self._window(np.asarray(x, dtype=float))
        return w if _check_derivative(derivative) == 0 else dw

    def _window(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        inside = (x >= self.start_m) & (x <= self.end_m)
        fade = self.fade_length_m
        if fade == 0.0:
            return inside.astype(float), np.zeros_like(x)
        s_in, ds_in = _smootherstep((x - self.start_m) / fade)
        s_out, ds_out = _smootherstep((self.end_m - x) / fade)
        w = np.where(inside, s_in * s_out, 0.0)
        dw = np.where(inside, (ds_in * s_out - s_in * ds_out) / fade, 0.0)
        return w, dw

    def _faded(self, x: ArrayLike, derivative: int) -> FloatArray:
        """Faded signals, shape ``x.shape + (4,)`` in ``COMPONENTS`` order."""
        derivative = _check_derivative(derivative)
        xa = np.asarray(x, dtype=float)
        xc = np.clip(xa, self.start_m, self.end_m)
        w, dw = self._window(xa)
        q = self._spline(xc)
        if derivative == 0:
            return w[..., None] * q
        return dw[..., None] * q + w[..., None] * self._spline(xc, 1)

    def signals(self, x: ArrayLike, derivative: int = 0) -> dict[str, FloatArray]:
        """The four faded signals at ``x`` (m): values in m (``derivative=0``) or slopes d/dx
        (``derivative=1``, m/m), keyed by ``COMPONENTS``; arrays shaped like ``x``."""
        q = self._faded(x, derivative)
        return {c: q[..., i] for i, c in enumerate(COMPONENTS)}

    def left_rail_offsets(self, x: ArrayLike, derivative: int = 0) -> tuple[FloatArray, FloatArray]:
        """Displacement ``(dy, dz)`` (m) of the left rail at ``x`` (m): ``(y_a + g/2,
        z_v + c/2)`` times the fade window; with ``derivative=1`` its slope d/dx (multiply by the
        speed for the rail velocity). Vectorised; arrays shaped like ``x``."""
        q = self._faded(x, derivative)
        return q[..., 0] + 0.5 * q[..., 3], q[..., 1] + 0.5 * q[..., 2]

    def right_rail_offsets(
        self, x: ArrayLike, derivative: int = 0
    ) -> tuple[FloatArray, FloatArray]:
        """Displacement ``(dy, dz)`` (m) of the right rail at ``x`` (m): ``(y_a - g/2,
        z_v - c/2)`` times the fade window; with ``derivative=1`` its slope d/dx."""
        q = self._faded(x, derivative)
        return q[..., 0] - 0.5 * q[..., 3], q[..., 1] - 0.5 * q[..., 2]

    def rail_offsets(self, x: ArrayLike, derivative: int = 0) -> FloatArray:
        """Left dy, left dz, right dy, right dz stacked on a last axis of length 4 (m or m/m),
        the column order of :class:`SampledIrregularities`."""
        ly, lz = self.left_rail_offsets(x, derivative)
        ry, rz = self.right_rail_offsets(x, derivative)
        return np.stack([ly, lz, ry, rz], axis=-1)

    def sampled(self, step_m: float) -> SampledIrregularities:
        """Faded rail offsets and their slopes on a uniform grid for a compiled kernel.

        The grid covers the record with the largest step not above ``step_m`` that divides the
        length. Values and slopes at the nodes are exact (spline times window); between nodes
        the kernel interpolates with the cubic Hermite polynomial, whose error relative to this
        profile is ``O(step^4)``.
        """
        step_target = float(step_m)
        if not (math.isfinite(step_target) and step_target > 0.0):
            raise IrregularityError(f"step_m must be positive, got {step_m!r}")
        n_intervals = max(1, math.ceil(self.length_m / step_target - 1e-9))
        x = self.start_m + (self.length_m / n_intervals) * np.arange(n_intervals + 1)
        x[-1] = self.end_m
        return SampledIrregularities(
            start_m=self.start_m,
            step_m=self.length_m / n_intervals,
            values=self.rail_offsets(x, 0),
            slopes=self.rail_offsets(x, 1),
        )

    # -- construction and output ---------------------------------------------------------------

    @classmethod
    def zeros(
        cls, length_m: float, step_m: float = 1.0, start_m: float = 0.0
    ) -> IrregularityProfile:
        """Ideal track: all signals zero over ``[start_m, start_m + length_m]`` (m)."""
        length = float(length_m)
        if not (math.isfinite(length) and length > 0.0):
            raise IrregularityError(f"length_m must be positive, got {length_m!r}")
        if not (math.isfinite(float(step_m)) and step_m > 0.0):
            raise IrregularityError(f"step_m must be positive, got {step_m!r}")
        n = max(1, math.ceil(length / float(step_m) - 1e-9)) + 1
        x = float(start_m) + np.linspace(0.0, length, n)
        z = np.zeros(n)
        return cls(x, z, z, z, z, fade_length_m=0.0, description="ideal track (zeros)")

    def to_csv(self, path: str | Path, units: str = "m") -> None:
        """Write the raw signals as CSV with a header row ``distance_m, lateral_m, vertical_m,
        cross_level_m, gauge_m`` (``units="mm"``: the same names with ``_mm``, values in mm).
        The fade length is not stored."""
        if units not in ("m", "mm"):
            raise IrregularityError(f"units must be 'm' or 'mm', got {units!r}")
        scale = 1.0 if units == "m" else 1000.0
        cols = [self.distance_m, self.lateral_m, self.vertical_m, self.cross_level_m, self.gauge_m]
        with open(path, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow([f"{base}_{units}" for base in _CSV_BASES])
            for row in zip(*cols, strict=True):
                writer.writerow([f"{v * scale:.17g}" for v in row])


def _check_derivative(derivative: int) -> int:
    if derivative not in (0, 1):
        raise IrregularityError(f"derivative must be 0 or 1, got {derivative!r}")
    return int(derivative)


@dataclass(frozen=True, eq=False)
class SampledIrregularities:
    """Faded rail offsets on a uniform grid, for a compiled kernel.

    Attributes:
        start_m: distance of the first node (m).
        step_m: node spacing (m).
        values: ``(n, 4)`` C-contiguous float64: left dy, left dz, right dy, right dz (m).
        slopes: ``(n, 4)`` their derivatives with respect to ``x`` (m/m).

    Between nodes ``i`` and ``i+1``, with ``t = (x - x_i)/h``, the offsets are the cubic Hermite
    polynomial ``p = h00 p_i + h h10 m_i + h01 p_{i+1} + h h11 m_{i+1}`` (``h00 = 2t^3 - 3t^2 +
    1``, ``h10 = t^3 - 2t^2 + t``, ``h01 = -2t^3 + 3t^2``, ``h11 = t^3 - t^2``); outside
    ``[start_m, end_m]`` they are zero.
    """

    start_m: float
    step_m: float
    values: FloatArray
    slopes: FloatArray

    columns: ClassVar[tuple[str, ...]] = ("left_dy", "left_dz", "right_dy", "right_dz")

    def __post_init__(self) -> None:
        for name in ("values", "slopes"):
            arr = np.ascontiguousarray(getattr(self, name), dtype=np.float64)
            if arr.ndim != 2 or arr.shape[1] != 4:
                raise IrregularityError(f"{name} must have shape (n, 4), got {arr.shape}")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if self.values.shape != self.slopes.shape or self.values.shape[0] < 2:
            raise IrregularityError("values and slopes must have the same shape, n >= 2")

    @property
    def end_m(self) -> float:
        """Distance of the last node (m)."""
        return self.start_m + self.step_m * (self.values.shape[0] - 1)

    def evaluate(self, x: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Reference cubic Hermite interpolation: offsets (m) and slopes d/dx at ``x`` (m),
        each shaped ``x.shape + (4,)``; zero outside the grid."""
        xa = np.asarray(x, dtype=float)
        h = self.step_m
        n = self.values.shape[0]
        u = (xa - self.start_m) / h
        inside = (u >= 0.0) & (u <= n - 1)
        i = np.clip(np.floor(u).astype(np.int64), 0, n - 2)
        t = np.clip(u - i, 0.0, 1.0)[..., None]
        p0, p1 = self.values[i], self.values[i + 1]
        m0, m1 = self.slopes[i], self.slopes[i + 1]
        t2, t3 = t * t, t * t * t
        val = (
            (2 * t3 - 3 * t2 + 1) * p0
            + (t3 - 2 * t2 + t) * h * m0
            + (-2 * t3 + 3 * t2) * p1
            + (t3 - t2) * h * m1
        )
        slope = (6 * t2 - 6 * t) * (p0 - p1) / h + (3 * t2 - 4 * t + 1) * m0 + (3 * t2 - 2 * t) * m1
        mask = inside[..., None]
        return np.where(mask, val, 0.0), np.where(mask, slope, 0.0)


# ----------------------------------------------------------------------------------------------
# Measured data
# ----------------------------------------------------------------------------------------------

_CSV_BASES = ("distance", "lateral", "vertical", "cross_level", "gauge")
_CSV_EXPECTED = tuple(f"{b}_{u}" for b in _CSV_BASES for u in ("m", "mm"))
_CSV_NAME = re.compile(r"^(distance|lateral|vertical|cross_level|gauge)_(m|mm)$")


def read_measured_irregularities(
    path: str | Path, fade_length_m: float = _FADE_DEFAULT_M
) -> IrregularityProfile:
    """Read measured irregularities from a CSV file.

    The first row that is neither blank nor a ``#`` comment is the header; it must name the five
    columns ``distance_m, lateral_m, vertical_m, cross_level_m, gauge_m`` (any order; each may
    instead carry ``_mm``, in which case the values are millimetres and are converted to
    metres; other columns are ignored). The quantities and signs are those of the module
    docstring. Distances must increase strictly; an unevenly spaced record is resampled onto a
    uniform grid with its median step by a not-a-knot cubic spline (with a warning). No
    filtering is applied.

    Raises:
        IrregularityError: naming the file, the line and column, and what was expected, for a
            missing or repeated column, a wrong number of fields, a non-numeric or non-finite
            value, a non-increasing distance, or fewer than two data rows.
        OSError: the file cannot be read.
    """
    path = Path(path)
    where = str(path)
    header: list[str] | None = None
    columns: dict[str, tuple[int, float, str]] = {}
    rows: list[list[float]] = []
    row_lines: list[int] = []
    header_line = 0
    with open(path, newline="", encoding="utf-8-sig") as fh:
        reader = csv.reader(fh)
        for row in reader:
            line = reader.line_num
            if not row or all(not f.strip() for f in row) or row[0].lstrip().startswith("#"):
                continue
            if header is None:
                header = [f.strip() for f in row]
                header_line = line
                columns = _parse_header(header, where, line)
                continue
            if len(row) != len(header):
                raise IrregularityError(
                    f"{where}, line {line}: expected {len(header)} comma-separated fields "
                    f"(as in the header on line {header_line}), found {len(row)}"
                )
            values = []
            for base in _CSV_BASES:
                idx, scale, name = columns[base]
                text = row[idx].strip()
                try:
                    value = float(text)
                except ValueError:
                    raise IrregularityError(
                        f"{where}, line {line}, column {idx + 1} ({name!r}): expected a "
                        f"number, found {text!r}"
                    ) from None
                if not math.isfinite(value):
                    raise IrregularityError(
                        f"{where}, line {line}, column {idx + 1} ({name!r}): expected a finite "
                        f"number, found {text!r}"
                    )
                values.append(value * scale)
            if rows and values[0] <= rows[-1][0]:
                idx, _, name = columns["distance"]
                raise IrregularityError(
                    f"{where}, line {line}, column {idx + 1} ({name!r}): expected a distance "
                    f"greater than {rows[-1][0]:g} m (line {row_lines[-1]}), "
                    f"found {values[0]:g} m; distances must increase strictly"
                )
            rows.append(values)
            row_lines.append(line)
    if header is None:
        raise IrregularityError(
            f"{where}: no header row; expected the columns {', '.join(_default_names())}"
        )
    if len(rows) < 2:
        raise IrregularityError(
            f"{where}: expected at least 2 data rows after the header on line {header_line}, "
            f"found {len(rows)}"
        )
    data = np.asarray(rows, dtype=float)
    x = data[:, 0]
    dx = np.diff(x)
    h = (x[-1] - x[0]) / (x.size - 1)
    description = f"measured: {where}"
    if np.max(np.abs(dx - h)) > _UNIFORM_RTOL * h:
        step = float(np.median(dx))
        n = max(1, round((x[-1] - x[0]) / step)) + 1
        grid = np.linspace(x[0], x[-1], n)
        warnings.warn(
            f"{where}: distances are not evenly spaced (steps {dx.min():g}-{dx.max():g} m); "
            f"resampled onto a uniform grid of {n} points by cubic spline",
            UserWarning,
            stacklevel=2,
        )
        data = np.column_stack([grid, CubicSpline(x, data[:, 1:], axis=0)(grid)])
        description += " (resampled to a uniform grid)"
    else:
        data[:, 0] = x[0] + h * np.arange(x.size)
        data[-1, 0] = x[-1]
    try:
        return IrregularityProfile(
            distance_m=data[:, 0],
            lateral_m=data[:, 1],
            vertical_m=data[:, 2],
            cross_level_m=data[:, 3],
            gauge_m=data[:, 4],
            fade_length_m=fade_length_m,
            description=description,
        )
    except IrregularityError as exc:
        raise IrregularityError(f"{where}: {exc}") from None


def _default_names() -> list[str]:
    return [f"{b}_m" for b in _CSV_BASES]


def _parse_header(header: list[str], where: str, line: int) -> dict[str, tuple[int, float, str]]:
    columns: dict[str, tuple[int, float, str]] = {}
    unknown: list[str] = []
    for idx, raw in enumerate(header):
        m = _CSV_NAME.match(raw.lower())
        if m is None:
            unknown.append(raw)
            continue
        base, unit = m.group(1), m.group(2)
        if base in columns:
            raise IrregularityError(
                f"{where}, line {line}, column {idx + 1} ({raw!r}): {base!r} is already given "
                f"by column {columns[base][0] + 1} ({columns[base][2]!r}); expected one "
                f"column per quantity"
            )
        columns[base] = (idx, 1.0 if unit == "m" else 1e-3, raw)
    missing = [b for b in _CSV_BASES if b not in columns]
    if missing:
        hints = "".join(_did_you_mean(u.lower(), _CSV_EXPECTED) for u in unknown)
        raise IrregularityError(
            f"{where}, line {line} (header): missing column(s) "
            + ", ".join(f"{b}_m (or {b}_mm)" for b in missing)
            + f"; expected {', '.join(_default_names())}; found {', '.join(header)}."
            + hints
        )
    return columns


# ----------------------------------------------------------------------------------------------
# Statistics
# ----------------------------------------------------------------------------------------------


def rms(signal: ArrayLike) -> float:
    """Root mean square ``sqrt(mean(signal**2))`` (same unit as ``signal``; mean not removed)."""
    a = np.asarray(signal, dtype=float)
    if a.size == 0:
        raise IrregularityError("rms of an empty signal")
    return float(np.sqrt(np.mean(a * a)))


def psd_estimate(
    signal: ArrayLike, step: float, segment_length_m: float | None = None
) -> tuple[FloatArray, FloatArray]:
    """Welch estimate of the one-sided PSD of a uniformly sampled signal.

    Args:
        signal: samples (m) at spacing ``step`` (m).
        step: sample spacing (m).
        segment_length_m: Welch segment length (m); default an eighth of the record (at least
            256 samples). Hann window, 50 % overlap, mean removed per segment.

    Returns:
        ``(omega, psd)``: spatial angular frequency (rad/m) and PSD in m^2/(rad/m), the units of
        :meth:`TrackSpectrum.psd` (``scipy.signal.welch`` gives m^2/(1/m) over cycles/m; the
        PSD over rad/m is that divided by ``2 pi``).
    """
    x = np.asarray(signal, dtype=float)
    h = float(step)
    if x.ndim != 1 or x.size < 2:
        raise IrregularityError("psd_estimate needs a 1-D signal with at least 2 samples")
    if not (math.isfinite(h) and h > 0.0):
        raise IrregularityError(f"step must be positive, got {step!r}")
    if segment_length_m is None:
        nperseg = max(256, x.size // 8)
    else:
        nperseg = max(2, round(float(segment_length_m) / h))
    nperseg = min(nperseg, x.size)
    from scipy import signal as sp_signal

    f, p = sp_signal.welch(
        x, fs=1.0 / h, window="hann", nperseg=nperseg, detrend="constant", scaling="density"
    )
    return 2.0 * math.pi * f, p / (2.0 * math.pi)
