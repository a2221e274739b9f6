"""Wear laws, their distribution over the patch and the RCF indices against closed forms and
their published values (docs/wear.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railexu.assessment.rcf import fi_surf, wlrm_damage
from railexu.contact.fastsim import fastsim3_nb
from railexu.contact.kalker import kalker_coefficients
from railexu.contact.wear.coefficients import load_coefficients
from railexu.contact.wear.laws import (
    UnknownWearLawError,
    jendel_k,
    local_wear_rate,
    usfd_rate,
    usfd_regime,
    wear_law_code,
)
from railexu.contact.wear.patch import patch_wear, wear_on_profile
from railexu.errors import InputError

COEF = load_coefficients()
G = 82.0e9
NU = 0.28
# a tread contact of 80 kN: a = 6 mm, b = 5 mm, p0 = 3 Q / (2 pi a b) = 1.27 GPa
Q, A, B = 80.0e3, 6.0e-3, 5.0e-3
P0 = 1.5 * Q / (math.pi * A * B)


def test_coefficients_are_the_published_ranges():
    """Jendel 2002: k1 300-400e-4, k2 and k4 1-10e-4, k3 30-40e-4, boundaries 0.2 and 0.7 m/s
    and 0.8 H; Lewis and Dwyer-Joyce 2004 (R8T): 5.3, 55.0, 61.9, 4778.7 at 10.4 and 77.2."""
    j, u = COEF.archard_jendel, COEF.energy_usfd
    assert 300e-4 <= j.k1 <= 400e-4 and 30e-4 <= j.k3 <= 40e-4
    assert 1e-4 <= j.k2 <= 10e-4 and 1e-4 <= j.k4 <= 10e-4
    assert (j.v1_m_per_s, j.v2_m_per_s, j.pressure_ratio) == (0.2, 0.7, 0.8)
    assert (u.slope_1, u.severe, u.slope_3, u.offset_3) == (5.3, 55.0, 61.9, 4778.7)
    assert (u.boundary_1_N_per_mm2, u.boundary_2_N_per_mm2) == (10.4, 77.2)


def test_jendel_map_regions():
    m = COEF.archard_jendel
    h = m.hardness_Pa
    k = jendel_k([0.5 * h, 0.5 * h, 0.5 * h, 0.5 * h, 0.9 * h], [0.1, 0.2, 0.7, 1.0, 0.1], m)
    assert list(k) == [m.k2, m.k3, m.k3, m.k4, m.k1]


def test_usfd_regimes_at_published_values():
    """Published USFD function (R8T/UIC60 900A): K = 5.3 Tg/A (mild, below 10.4 N/mm^2), 55.0
    (severe, to 77.2), 61.9 Tg/A - 4778.7 (catastrophic): hand values."""
    f = COEF.energy_usfd
    x = np.array([5.0, 10.0, 10.4, 50.0, 77.2, 100.0])
    assert usfd_rate(x, f) == pytest.approx([26.5, 53.0, 55.0, 55.0, 55.0, 1411.3], rel=1e-12)
    assert list(usfd_regime(x, f)) == ["mild", "mild", "severe", "severe", "severe",
                                       "catastrophic"]  # fmt: skip


def test_unknown_law_is_input_error():
    assert wear_law_code("Archard-Jendel") == 0
    with pytest.raises(UnknownWearLawError, match="Did you mean 'archard_jendel'"):
        wear_law_code("archard_jendl")
    assert issubclass(UnknownWearLawError, InputError)


def test_full_sliding_archard_closed_form():
    """Steady full sliding (xi = 0.3, far beyond saturation at about 0.007) at 1.5 m/s:
    sliding velocity 0.45 m/s and p0 = 1.27 GPa < 0.8 H put every cell in Jendel's k3.
    Archard: volume per metre rolled k3 Q s / H; depth per passage across the patch
    3 k3 s Q (1 - y^2/b^2) / (4 b H). Tolerance 1 %: the midpoint rule on the sqrt pressure at
    20 x 20 cells (0.34 % on the integrated pressure, fastsim.py) and the elastic part of the
    slip, which cancels to first order over a strip."""
    s, speed = 0.3, 1.5
    m = COEF.archard_jendel
    out = patch_wear("archard_jendel", COEF, s, 0.0, 0.0, Q, 0.3, A, B, G, NU, speed)
    expected = m.k3 * Q * s / m.hardness_Pa
    assert out["volume_per_m_m2"] == pytest.approx(expected, rel=0.01)
    y = out["y_m"]
    shape = 3.0 * m.k3 * s * Q * (1.0 - (y / B) ** 2) / (4.0 * B * m.hardness_Pa)
    inner = np.abs(y) < 0.8 * B
    np.testing.assert_allclose(out["depth_m"][inner], shape[inner], rtol=0.02)
    # the forces of full sliding: mu Q opposite the slip (on the wheel), FASTSIM's 0.34 %
    assert out["Fx_N"] == pytest.approx(-0.3 * Q, rel=0.005)


def test_full_sliding_energy_law_closed_form():
    """USFD law in full sliding: T gamma / A = mu p s everywhere; with s = 0.02 the peak is
    mu p0 s = 7.6 N/mm^2 (mild), so the volume per metre is 5.3e-9 mu s Q / rho
    (ug -> kg 1e-9, per mm^2 -> per m^2 1e6). Tolerance 2 %: near the leading edge the
    traction first sticks for a few cells at this smaller creepage."""
    s, f = 0.02, COEF.energy_usfd
    out = patch_wear("energy_usfd", COEF, s, 0.0, 0.0, Q, 0.3, A, B, G, NU, 20.0, 50, 50)
    expected = f.slope_1 * 1e-9 * 0.3 * s * Q / f.density_kg_per_m3
    assert out["volume_per_m_m2"] == pytest.approx(expected, rel=0.02)


def test_patch_forces_equal_fastsim():
    """Partial slip with spin: the traction marched here is FASTSIM's (same cells)."""
    c11, c22, c23 = kalker_coefficients(A / B, NU)
    for xi, eta, phi in ((1e-3, 0.0, 0.0), (5e-4, 1e-3, 0.5), (0.0, 3e-3, -1.0)):
        out = patch_wear("archard_jendel", COEF, xi, eta, phi, Q, 0.3, A, B, G, NU, 20.0)
        fx, fy, _ = fastsim3_nb(xi, eta, phi, Q, 0.3, A, B, G, c11, c22, c23, 20, 20)
        assert out["Fx_N"] == pytest.approx(fx, rel=1e-9, abs=1e-6)
        assert out["Fy_N"] == pytest.approx(fy, rel=1e-9, abs=1e-6)


def test_pure_rolling_does_not_wear():
    out = patch_wear("archard_jendel", COEF, 0.0, 0.0, 0.0, Q, 0.3, A, B, G, NU, 20.0)
    assert out["volume_per_m_m2"] == 0.0


def test_local_rate_matches_compiled_patch():
    """The vectorised reference law against the compiled patch (full sliding: p, mu p, s)."""
    s, speed = 0.3, 1.5
    m = COEF.archard_jendel
    w = local_wear_rate("archard_jendel", P0, 0.3 * P0, s, speed, COEF)
    assert w == pytest.approx(m.k3 * P0 * s / m.hardness_Pa)


def test_profile_deposit_conserves_area():
    """The worn area placed on the grid equals the patch volume term (linear split)."""
    rows = np.array([
        [0.3, 0.0, 0.0, Q, A, B, 0.001, -0.002, 0.05, 1.5, 2.0, 3.0, 1.0],
        [0.01, 0.002, 0.3, Q, A, B, -0.03, 0.01, 1.1, 20.0, 1.0, 1.0, -1.0],
    ])  # fmt: skip
    area, rail, total = wear_on_profile(rows, "archard_jendel", COEF, 0.3, G, NU, -0.08, 1e-4, 1601)
    assert area.sum() == pytest.approx(total, rel=1e-12)
    # the rail's weights are 1.5 and 1 times the wheel's
    vols = [patch_wear("archard_jendel", COEF, *r[:3], r[3], 0.3, r[4], r[5], G, NU, r[9])
            ["volume_per_m_m2"] for r in rows]  # fmt: skip
    assert rail.sum() == pytest.approx(3.0 * vols[0] + 1.0 * vols[1], rel=1e-12)


def test_fi_surf_on_the_shakedown_line():
    """FI_surf = f - k / p0 (p0 = 3 Fz / (2 pi a b)): zero on Johnson's surface ratchetting
    line; free rolling gives -k / p0; unloaded is NaN."""
    k = COEF.fi_surf.shear_yield_Pa
    f_line = k / P0
    fx = f_line * Q
    assert fi_surf(fx, 0.0, Q, A, B) == pytest.approx(0.0, abs=1e-12)
    assert fi_surf(0.6 * fx, 0.8 * fx, Q, A, B) == pytest.approx(0.0, abs=1e-12)
    assert fi_surf(0.0, 0.0, Q, A, B) == pytest.approx(-k / P0)
    assert np.isnan(fi_surf(0.0, 0.0, 0.0, A, B))


def test_wlrm_damage_function():
    """Burstow's WLRM: zero below 15 N, peak at 65 N, zero again from 175 N."""
    peak = COEF.wlrm.peak_damage
    d = wlrm_damage([0.0, 15.0, 40.0, 65.0, 120.0, 175.0, 300.0])
    assert d == pytest.approx([0.0, 0.0, 0.5 * peak, peak, 0.5 * peak, 0.0, 0.0])


def test_bad_coefficients_file(tmp_path):
    path = tmp_path / "c.yaml"
    from pathlib import Path

    text = Path(load_coefficients().path).read_text()
    path.write_text(text.replace("k3: 35.0e-4", "k3: .nan"))
    with pytest.raises(InputError, match="archard_jendel.k3"):
        load_coefficients(str(path))
