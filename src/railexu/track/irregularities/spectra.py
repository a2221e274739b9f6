"""Track spectra: the German (ERRI B176) and US FRA PSDs, by name."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from railexu.track.irregularities.common import (
    COMPONENTS,
    FRA_A_V_CM2,
    FRA_K,
    FRA_OMEGA_C,
    FRA_VALID_WAVELENGTH_M,
    GERMAN_HALF_RAIL_DISTANCE_M,
    GERMAN_OMEGA_C,
    GERMAN_OMEGA_R,
    GERMAN_OMEGA_S,
    RAIL_DISTANCE_M,
    FloatArray,
    IrregularityError,
    _check_component,
    _did_you_mean,
)

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
            "ERRI (ORE) B176 German spectra as given in railexu docs/theory.md; "
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
            "US FRA vertical-profile spectrum as given in railexu docs/theory.md; "
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
