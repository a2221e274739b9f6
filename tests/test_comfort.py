"""Ride comfort: the weighting filters against the standards' tabulated gains, Sperling's index
and EN 12299's mean comfort against hand computations on sines."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import signal

from railexu.assessment.comfort import (
    block_rms,
    comfort_class,
    mean_comfort,
    sperling_index,
    sperling_weighting,
)
from railexu.assessment.filters import weight, weighting_gain, weighting_sos

DATA = Path(__file__).parent / "data" / "weighting_reference.csv"


def reference_rows() -> list[dict]:
    with DATA.open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    return [
        {
            "weighting": r["weighting"],
            "f": float(r["frequency_Hz"]),
            "gain": float(r["gain"]),
            "text": r["gain"],
        }  # fmt: skip
        for r in rows
    ]


def half_last_digit(text: str) -> float:
    """Half a unit of the last printed digit: the rounding of the standard's table."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0**-decimals


@pytest.mark.parametrize("row", reference_rows(), ids=lambda r: f"{r['weighting']}@{r['f']}Hz")
def test_analogue_weighting_matches_the_standards_table(row):
    """The analogue weighting (EN 12299 / ISO 2631-1 annex A formulas) reproduces the tabulated
    gain to the table's rounding (half a unit of its last digit, plus 1e-9)."""
    gain = weighting_gain(row["weighting"], [row["f"]])[0]
    assert abs(gain - row["gain"]) <= half_last_digit(row["text"]) + 1e-9


@pytest.mark.parametrize(
    ("fs_Hz", "f_max_Hz", "tol"),
    [
        # 2 kHz: the bilinear transform shifts 20 Hz by 0.03 %: the table's rounding dominates
        (2000.0, 20.0, 0.006),
        # a run's 200 Hz output: 10 Hz is warped by 0.8 % on a slope of at most one decade per
        # decade, so the gain may be off by that much on top of the rounding
        (200.0, 10.0, 0.015),
    ],
)
def test_digital_weightings_at_run_sample_rates(fs_Hz, f_max_Hz, tol):
    rows = [r for r in reference_rows() if r["weighting"] == "Wd" and 0.2 <= r["f"] <= f_max_Hz]
    f = np.array([r["f"] for r in rows])
    _, h = signal.sosfreqz(weighting_sos("Wd", fs_Hz), worN=f, fs=fs_Hz)
    assert np.abs(h) == pytest.approx([r["gain"] for r in rows], rel=tol)


def test_weighted_sine_keeps_the_tabulated_gain_in_the_time_domain():
    """A 4 Hz lateral sine of 1 m/s^2 weighted by Wd keeps the rms 0.512 / sqrt(2) (ISO 2631-1
    Table 3), once the filter's start-up (the 0.4 Hz high pass: a few seconds) is over; 0.3 %
    covers the table's rounding (0.1 %) and the warping at 200 Hz (0.05 % of gain at 4 Hz)."""
    fs = 200.0
    t = np.arange(0.0, 60.0, 1.0 / fs)
    a = weight(np.sin(2 * np.pi * 4.0 * t), fs, "Wd")
    steady = a[t >= 20.0]
    assert math.sqrt(np.mean(steady**2)) == pytest.approx(0.512 / math.sqrt(2), rel=3e-3)


def test_sperling_index_of_sines_by_hand():
    """Wz = 0.896 (b^3 F(f) / f)^(1/10) with b in cm/s^2 (Sperling; Garg and Dukkipati 1984).

    - vertical, b = 1 m/s^2 = 100 cm/s^2 at 2 Hz: F = 0.325 * 2^2 = 1.3,
      b^3 F / f = 1e6 * 1.3 / 2 = 650 000, Wz = 0.896 * 650000^0.1 = 3.41664;
    - lateral, b = 0.5 m/s^2 = 50 cm/s^2 at 1 Hz: F = 0.8, b^3 F / f = 125 000 * 0.8 = 1e5,
      Wz = 0.896 * 10^0.5 = 2.83340;
    - vertical at 10 Hz, b = 100 cm/s^2: F = 400 / 100 = 4, Wz = 0.896 (1e6 * 4 / 10)^0.1 = 3.25472.
    The records hold whole periods, so the Fourier amplitude is exact; 1e-5 covers the hand
    rounding.
    """
    fs = 200.0
    t = np.arange(0.0, 10.0, 1.0 / fs)
    assert sperling_index(np.sin(2 * np.pi * 2.0 * t), fs, "vertical") == pytest.approx(
        3.41664, rel=1e-5
    )
    assert sperling_index(0.5 * np.sin(2 * np.pi * 1.0 * t), fs, "lateral") == pytest.approx(
        2.83340, rel=1e-5
    )
    assert sperling_index(np.cos(2 * np.pi * 10.0 * t), fs, "vertical") == pytest.approx(
        3.25472, rel=1e-5
    )
    # two components add as the 10th root of the sum of 10th powers
    two = np.sin(2 * np.pi * 2.0 * t) + np.cos(2 * np.pi * 10.0 * t)
    expected = (3.41664**10 + 3.25472**10) ** 0.1
    assert sperling_index(two, fs, "vertical") == pytest.approx(expected, rel=1e-5)
    assert sperling_index(np.zeros(2000), fs, "lateral") == 0.0
    assert sperling_index(np.ones(100), fs, "lateral") is None  # 0.5 s: too short


def test_sperling_weighting_pieces():
    f = np.array([1.0, 5.0, 10.0, 30.0])
    assert sperling_weighting(f, "vertical") == pytest.approx([0.325, 8.125, 4.0, 1.0])
    assert sperling_weighting(f, "lateral") == pytest.approx([0.8, 20.0, 6.5, 1.0])
    with pytest.raises(ValueError, match="direction"):
        sperling_weighting(f, "up")


def test_mean_comfort_of_a_lateral_sine_by_hand():
    """N_MV = 6 a_YP95 with a_YP95 the 95 % percentile of the 5 s rms of the Wd-weighted lateral
    acceleration: a 1 Hz sine of 1 m/s^2 gives 6 * 1.011 / sqrt(2) = 4.289 (ISO 2631-1 Table 3:
    Wd(1 Hz) = 1.011). The first block holds the filter's start-up, which the 95 % percentile of
    24 blocks leaves out; 0.5 % covers the table's rounding (0.05 %) and the block edges."""
    fs = 200.0
    t = np.arange(0.0, 120.0, 1.0 / fs)
    out = mean_comfort(np.sin(2 * np.pi * t), None, fs)
    assert out["blocks"] == 24
    assert out["a_y_P95_m_per_s2"] == pytest.approx(1.011 / math.sqrt(2), rel=5e-3)
    assert out["N_MV"] == pytest.approx(6 * 1.011 / math.sqrt(2), rel=5e-3)
    assert out["class"] == "uncomfortable"  # 3.5 <= N < 4.5 (EN 12299 scale)


def test_mean_comfort_vertical_at_the_reference_frequency():
    """Vertical: Wb(15.915 Hz) = 0.8126 (ISO 8041): 1 m/s^2 gives N_MV = 6 * 0.8126 / sqrt(2)
    = 3.448; at 1 kHz sampling the warping at 16 Hz is 0.08 %; 0.5 % as above."""
    fs = 1000.0
    t = np.arange(0.0, 60.0, 1.0 / fs)
    out = mean_comfort(None, np.sin(2 * np.pi * 15.915 * t), fs)
    assert out["N_MV"] == pytest.approx(6 * 0.8126 / math.sqrt(2), rel=5e-3)
    assert out["a_y_P95_m_per_s2"] is None


def test_block_rms_and_comfort_scale():
    assert block_rms(np.full(1000, 2.0), 100.0) == pytest.approx([2.0, 2.0])
    assert block_rms(np.full(100, 3.0), 100.0) == pytest.approx([3.0])  # shorter than 5 s
    assert [comfort_class(v) for v in (1.0, 2.0, 3.0, 4.0, 5.0)] == [
        "very comfortable", "comfortable", "medium", "uncomfortable", "very uncomfortable"
    ]  # fmt: skip
    assert comfort_class(None) is None
