"""Hunting (self-excited lateral oscillation) told apart from track-forced response.

The leading wheelset's lateral displacement over the second half of the evaluation window is
examined (:func:`detect_hunting`). The verdict is one of:

- ``"below threshold"``: the amplitude over the last 10 % (:func:`~railexu.results.signals.
  amplitude`, half peak to peak) does not exceed the threshold (1 mm by default);
- ``"decaying"``: the amplitude of the last quarter is below 0.9 times that of the third quarter
  (a disturbance dying out: stable);
- ``"no sustained oscillation"``: fewer than one full period in the second half, or the last zero
  crossing is more than a wavelength before the end (a drift or an offset);
- ``"track-forced response"``: the motion is not narrow-band: less than
  :data:`NARROW_BAND_SHARE` of its power lies within +-10 % of its dominant frequency (a
  self-excited oscillation is nearly harmonic; the response to random irregularities spreads
  over the band the track excites);
- on irregular track (``track_irregular=True``), EN 14363's band-passed running-stability
  criterion decides among the rest: ``"hunting (running-stability limit exceeded)"`` or
  ``"oscillation within the running-stability limit"`` (EN 14363 calls a vehicle unstable when
  that criterion is exceeded, whatever the displacement);
- otherwise ``"hunting (growing)"`` (last quarter more than 10 % above the third) or
  ``"hunting (limit cycle)"``.

``detected`` is True exactly for the two or three verdicts starting with ``"hunting"``: the
verdict always agrees with the amplitude, growth and band share it reports.
The thresholds (0.9, 10 %, 0.5) are railexu's choices.

Every sustained oscillation (issue 28): :func:`wheelset_oscillations` fits each wheelset's
lateral displacement and angle of attack (:func:`railexu.assessment.oscillation.
fit_oscillation`: dominant frequency, quasi-static position removed, fitted envelope, growth
rate) and reports each one that neither decays nor stays below its floor
(:data:`OSCILLATION_FLOORS`), on straight track and in curves (about the quasi-static
position), with ``flange_contact`` telling an oscillation with flange contact from one on the
treads. When such an oscillation exists and the verdict would be ``"below threshold"``, the
verdict says ``"sustained oscillation below the hunting threshold"`` instead: an oscillation
that does not decay is never reported as "no hunting" without being named.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from railexu.assessment.criterion import Criterion, finite_or_none
from railexu.assessment.filters import scipy_signal
from railexu.assessment.oscillation import GROWTH_PER_PERIOD, fit_oscillation
from railexu.assessment.signals import amplitude, zero_crossing_wavelength, zero_crossings

FloatArray = NDArray[np.float64]

#: The amplitude over the last 10 % of the window is reported as the hunting amplitude.
FINAL_FRACTION = 0.10
#: Decaying when the last quarter's amplitude is below this fraction of the third quarter's.
HUNTING_DECAY_RATIO = 0.9
#: Growing when the last quarter's amplitude is above this multiple of the third quarter's.
HUNTING_GROWTH_RATIO = 1.1
#: Share of the power within +-10 % of the dominant frequency above which the motion is narrow
#: band (self-excited); below it, track-forced.
NARROW_BAND_SHARE = 0.5
NARROW_BAND_HALF_WIDTH = 0.10
#: Amplitudes below which a wheelset's oscillation is not reported (railexu's assumption: a
#: tenth of the 1 mm hunting threshold, and 0.1 mrad of angle of attack, the order of the
#: angle of attack of a wheelset with 0.1 mm lateral motion at a hunting wavelength of 10-20 m).
OSCILLATION_FLOORS = {"lateral_m": 1.0e-4, "yaw_rad": 1.0e-4}
#: The floors and tolerances of the oscillation report, written with every verdict (railexu's
#: assumptions, not a standard's values).
ASSUMPTIONS = {
    "source": "railexu's assumptions (docs/assessment.md), not a standard's values",
    "hunting_threshold": "threshold_m (1 mm by default): a sustained oscillation of the leading "
    "wheelset at least this large is hunting",
    "oscillation_floor_lateral_m": OSCILLATION_FLOORS["lateral_m"],
    "oscillation_floor_angle_of_attack_rad": OSCILLATION_FLOORS["yaw_rad"],
    "sustained_within_per_period": GROWTH_PER_PERIOD,
}
#: The statuses of :func:`~railexu.assessment.oscillation.classify` that are reported.
REPORTED_OSCILLATIONS = ("sustained", "growing")


@dataclass
class HuntingResult:
    """Hunting verdict with the numbers it rests on (SI units)."""

    detected: bool = False
    verdict: str = "not evaluated"
    wavelength_m: float | None = None
    frequency_Hz: float | None = None
    amplitude_m: float | None = None
    growth_ratio: float | None = None
    narrow_band_share: float | None = None
    threshold_m: float | None = None
    oscillations: list | None = None

    def to_dict(self) -> dict:
        return {
            "detected": bool(self.detected),
            "verdict": self.verdict,
            "wavelength_m": finite_or_none(self.wavelength_m),
            "frequency_Hz": finite_or_none(self.frequency_Hz),
            "amplitude_m": finite_or_none(self.amplitude_m),
            "growth_ratio": finite_or_none(self.growth_ratio),
            "narrow_band_share": finite_or_none(self.narrow_band_share),
            "threshold_m": finite_or_none(self.threshold_m),
            "oscillations": list(self.oscillations or []),
            "assumptions": ASSUMPTIONS,
        }


def narrow_band_share(x: FloatArray, y: FloatArray, wavelength_m: float) -> float | None:
    """Share of the power of ``y`` (mean removed, Hann window, resampled to a uniform distance
    grid) within +-10 % (at least +-2.5 frequency bins) of the spatial frequency
    ``1 / wavelength_m``."""
    if x.size < 16 or not x[-1] > x[0]:
        return None
    grid = np.linspace(x[0], x[-1], x.size)
    v = np.interp(grid, x, y)
    dx = grid[1] - grid[0]
    f, p = scipy_signal().periodogram(v, fs=1.0 / dx, window="hann", detrend="constant")
    total = float(np.sum(p[1:]))
    if not total > 0.0:
        return None
    f0 = 1.0 / wavelength_m
    half = max(NARROW_BAND_HALF_WIDTH * f0, 2.5 * (f[1] - f[0]))
    return float(np.sum(p[1:][np.abs(f[1:] - f0) <= half]) / total)


def detect_hunting(
    x: FloatArray,
    y: FloatArray | None,
    speed_m_per_s: float,
    threshold_m: float,
    track_irregular: bool | None = None,
    running_stability: Criterion | None = None,
    oscillations: list[dict] | None = None,
) -> HuntingResult:
    """Hunting verdict for the lateral displacement ``y`` (m) of the leading wheelset against
    the distance ``x`` (m) of the evaluation window; see the module docstring for the rules.
    ``oscillations``: the reported oscillations of :func:`wheelset_oscillations` (kept in the
    result; a verdict ``"below threshold"`` becomes ``"sustained oscillation below the
    hunting threshold"`` when there is one)."""
    out = HuntingResult(threshold_m=threshold_m, oscillations=list(oscillations or []))
    if y is None or x.size < 4 or not x[-1] > x[0]:
        return out
    x0, span = float(x[0]), float(x[-1] - x[0])
    last_half = x >= x0 + 0.5 * span
    xs, ys = x[last_half], y[last_half]
    amp_q3 = amplitude(y[last_half & (x < x0 + 0.75 * span)])
    amp_q4 = amplitude(y[x >= x0 + 0.75 * span])
    out.amplitude_m = amplitude(y[x >= x0 + (1.0 - FINAL_FRACTION) * span])
    out.growth_ratio = amp_q4 / amp_q3 if amp_q3 > 0.0 else None
    wl = zero_crossing_wavelength(xs, ys, min_periods=1.0)
    crossings = zero_crossings(xs, ys)
    sustained = wl is not None and crossings.size > 0 and float(x[-1] - crossings[-1]) <= wl
    if wl is not None:
        out.narrow_band_share = narrow_band_share(xs, ys, wl)
    if out.amplitude_m <= threshold_m:
        out.verdict = "below threshold"
    elif amp_q4 < HUNTING_DECAY_RATIO * amp_q3:
        out.verdict = "decaying"
    elif not sustained:
        out.verdict = "no sustained oscillation"
    elif out.narrow_band_share is None or out.narrow_band_share < NARROW_BAND_SHARE:
        out.verdict = "track-forced response"
    elif track_irregular and running_stability is not None and running_stability.value is not None:
        if running_stability.exceeded:
            out.verdict = "hunting (running-stability limit exceeded)"
        else:
            out.verdict = "oscillation within the running-stability limit"
    elif amp_q4 > HUNTING_GROWTH_RATIO * amp_q3:
        out.verdict = "hunting (growing)"
    else:
        out.verdict = "hunting (limit cycle)"
    out.detected = out.verdict.startswith("hunting")
    if out.verdict == "below threshold" and out.oscillations:
        out.verdict = "sustained oscillation below the hunting threshold"
    if not out.detected:
        wl = zero_crossing_wavelength(xs, ys, min_periods=2.0)
    out.wavelength_m = wl
    if wl is not None and speed_m_per_s > 0 and math.isfinite(wl):
        out.frequency_Hz = speed_m_per_s / wl
    return out


def wheelset_oscillations(
    t_s: FloatArray,
    signals: dict[str, FloatArray],
    flange_contact: dict[str, bool] | None = None,
    floors: dict[str, float] | None = None,
) -> list[dict]:
    """The reported oscillations of the wheelsets' signals over a window.

    Args:
        t_s: time (s) of the window's samples.
        signals: ``"ws1_lateral_m"``, ``"ws1_yaw_rad"`` (angle of attack), ... -> samples.
        flange_contact: ``"ws1"`` -> whether a wheel of that wheelset had flange contact in
            the window.
        floors: per signal suffix (``lateral_m``, ``yaw_rad``) the amplitude floor; default
            :data:`OSCILLATION_FLOORS`.

    Returns one dict per signal whose oscillation is sustained or growing: ``signal``,
    ``wheelset``, ``quantity`` (``lateral displacement`` or ``angle of attack``), ``unit``,
    ``status``, ``frequency_Hz``, ``amplitude`` (fitted envelope at the window's end),
    ``growth_rate_per_s``, ``growth_per_period``, ``offset`` (quasi-static position),
    ``narrow_band_share``, ``window_s``, ``floor``, ``flange_contact`` and ``label``
    (``"oscillation with flange contact"`` or ``"oscillation in tread contact"``)."""
    floors = {**OSCILLATION_FLOORS, **(floors or {})}
    flange_contact = flange_contact or {}
    out = []
    for name, values in signals.items():
        wheelset, _, suffix = name.partition("_")
        if suffix not in floors:
            continue
        fit = fit_oscillation(t_s, values, floors[suffix])
        if fit.status not in REPORTED_OSCILLATIONS:
            continue
        flange = bool(flange_contact.get(wheelset, False))
        lateral = suffix == "lateral_m"
        contact = "with flange contact" if flange else "in tread contact"
        out.append({
            "signal": name,
            "wheelset": wheelset,
            "quantity": "lateral displacement" if lateral else "angle of attack",
            "unit": "m" if lateral else "rad",
            **fit.to_dict(),
            "floor": floors[suffix],
            "flange_contact": flange,
            "label": f"oscillation {contact}",
        })  # fmt: skip
    return out


def describe_oscillation(o: dict) -> str:
    """One line: ``ws2 angle of attack: sustained 7.70 Hz, +-1.00 mrad, growth -0.01 1/s
    (tread contact)``."""
    scale, unit = (1e3, "mm") if o["unit"] == "m" else (1e3, "mrad")
    return (
        f"{o['wheelset']} {o['quantity']}: {o['status']} {o['frequency_Hz']:.2f} Hz, "
        f"+-{o['amplitude'] * scale:.2f} {unit}, growth {o['growth_rate_per_s']:+.3f} 1/s "
        f"({'flange' if o['flange_contact'] else 'tread'} contact)"
    )
