"""Synthesis of random irregularities by the sum of cosines (chirp-z evaluated)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable

import numpy as np

from railexu.track.irregularities.common import (
    _CZT_BLOCK,
    _FADE_DEFAULT_M,
    COMPONENTS,
    FloatArray,
    IrregularityError,
)
from railexu.track.irregularities.profile import IrregularityProfile
from railexu.track.irregularities.spectra import TrackSpectrum, _band, _resolve_spectrum

# ----------------------------------------------------------------------------------------------
# Synthesis
# ----------------------------------------------------------------------------------------------


#: Most samples (and cosines) per synthesised signal: 160 MB per signal; a longer record is a
#: unit mistake, refused before anything is allocated.
MAX_SAMPLES = 20_000_000


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
        z = chirp_z(coeff, m, w)
        out[start : start + m] = np.real(np.exp(1j * omega[0] * step * np.arange(m)) * z)
    return out


def chirp_z(x: np.ndarray, m: int, w: complex) -> np.ndarray:
    """The chirp z-transform ``X_k = sum_j x_j w^(j k)``, ``k < m``, by Bluestein's algorithm
    (Rabiner, Schafer and Rader, IEEE Trans. Audio Electroacoustics 17(2), 1969).

    The same operations as ``scipy.signal.czt(x, m, w, a=1)`` (SciPy 1.17), so the same values
    to the last bit (``tests/test_irregularities.py`` checks it), on ``scipy.fft`` alone:
    importing ``scipy.signal`` costs some 0.8 s, a tenth of the seed run as a command, and a run
    needs it only for its assessment, which ``railexu run`` does in a process started early
    (:mod:`railexu.runtime.warm_process`)."""
    from scipy.fft import fft, ifft, next_fast_len

    n = x.shape[-1]
    k = np.arange(max(m, n), dtype=np.min_scalar_type(-(max(m, n) ** 2)))
    wk2 = w ** (k**2 / 2.0)
    a = 1.0  # SciPy's factor a^-k (ones here) is kept: the same operations, the same bits
    nfft = next_fast_len(n + m - 1)
    awk2 = a ** -k[:n] * wk2[:n]
    fwk2 = fft(1 / np.hstack((wk2[n - 1 : 0 : -1], wk2[:m])), nfft)
    y = ifft(fwk2 * fft(x * awk2, nfft))
    return y[..., n - 1 : n + m - 1] * wk2[:m]


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
    if not length / step_target <= MAX_SAMPLES or not n_components <= MAX_SAMPLES:
        raise IrregularityError(
            f"{length:g} m in steps of {step_target:g} m with {n_components:g} cosines is more "
            f"than {MAX_SAMPLES:.3g} samples or cosines per signal: is a length or a unit wrong?"
        )
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
