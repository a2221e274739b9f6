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
given by ORE/ERRI B176 (Bogies with steered or steering wheelsets, Report 1, Utrecht 1989;
see ``docs/theory.md``), with ``Oc = 0.8246``, ``Or = 0.0206``,
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
profile spectrum for track classes 1-6 (as given by Garg and Dukkipati, Dynamics of Railway
Vehicle Systems, Academic Press 1984; see ``docs/theory.md``)::

    S_v(O) = k A_v Oc^2 / (O^2 (O^2 + Oc^2)),   k = 0.25, Oc = 0.8245 rad/m

with ``A_v`` = 1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339 cm^2 rad/m for classes 1-6, converted
to SI (times 1e-4 m^2/cm^2), giving m^2/(rad/m). The formula is stated valid for wavelengths
1.524-304.8 m (5-1000 ft); synthesizing outside that band warns. Only the vertical spectrum is
implemented: the FRA alignment, cross-level and gauge formulas circulate in secondary literature
with coefficients railexu could not check against a citable source, so asking for them raises
``NotImplementedError`` (synthesize FRA track with ``components=("vertical",)``).

Synthesis (``synthesize_irregularities``)
-----------------------------------------
Sum of cosines (Shinozuka and Jan 1972, Digital simulation of random processes and its
applications, J. Sound Vib. 25; see ``docs/theory.md``): the band
``[2 pi/wavelength_max, 2 pi/wavelength_min]`` is cut into ``N`` equal intervals of width ``dO``
with midpoints ``O_k``; each signal is

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

from railexu.track.irregularities.common import COMPONENTS, RAIL_DISTANCE_M, IrregularityError
from railexu.track.irregularities.measured import read_measured_irregularities
from railexu.track.irregularities.profile import IrregularityProfile, SampledIrregularities
from railexu.track.irregularities.spectra import TrackSpectrum, available_spectra, get_spectrum
from railexu.track.irregularities.statistics import psd_estimate, rms
from railexu.track.irregularities.synthesis import component_amplitudes, synthesize_irregularities

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
