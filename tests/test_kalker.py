"""Kalker's creepage coefficients (Table E.3) and linear theory."""

from __future__ import annotations

import numpy as np
import pytest

from railexu.contact.kalker import (
    KALKER_POISSON_NODES,
    KALKER_TABLE_E3,
    kalker_coefficients,
    kalker_coefficients_nb,
    kalker_linear_forces,
    kalker_linear_nb,
    kalker_table_for_poisson,
)

# a/b as printed in docs/theory.md 4.2 (the a > b rows are rounded there: 1.111 = 1/0.9, ...)
PRINTED_RATIOS = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
PRINTED_RATIOS += [1.111, 1.25, 1.429, 1.667, 2.0, 2.5, 3.333, 5.0, 10.0]


def test_kalker_example_nu_028():
    """nu = 0.28, a/b = 1: c11 = 4.226, c22 = 3.705, c23 = 1.488 (quoted to 3 decimals)."""
    c11, c22, c23 = kalker_coefficients(1.0, 0.28)
    assert c11 == pytest.approx(4.226, abs=5e-4)
    assert c22 == pytest.approx(3.705, abs=5e-4)
    assert c23 == pytest.approx(1.488, abs=5e-4)


@pytest.mark.parametrize("k", range(3))
def test_table_nodes_are_reproduced(k):
    """At every a/b node and every tabulated nu the printed value comes back (to rounding)."""
    nu = KALKER_POISSON_NODES[k]
    for row in KALKER_TABLE_E3:
        c = kalker_coefficients(row[0], nu)
        assert c[0] == pytest.approx(row[1 + k], rel=1e-13)
        assert c[1] == pytest.approx(row[4 + k], rel=1e-13)
        assert c[2] == pytest.approx(row[7 + k], rel=1e-13)


def test_printed_ratios_map_onto_the_nodes():
    """The printed, rounded a/b (1.111, 1.429, ...) sit within rounding of the g = 0.1 k nodes."""
    assert KALKER_TABLE_E3[:, 0] == pytest.approx(PRINTED_RATIOS, abs=5e-4)
    # so looking up the printed value gives the node value up to a 5e-4 relative change
    for r, row in zip(PRINTED_RATIOS, KALKER_TABLE_E3, strict=True):
        assert kalker_coefficients(r, 0.25)[0] == pytest.approx(row[2], rel=5e-4)


def test_reduced_table_for_poisson():
    t = kalker_table_for_poisson(0.28)
    assert t.shape == (19, 4)
    assert np.all(np.diff(t[:, 0]) > 0.0)
    assert t[9, 0] == 1.0
    # 1/c is quadratic in nu: at the nodes the columns come back
    for k, nu in enumerate(KALKER_POISSON_NODES):
        tk = kalker_table_for_poisson(nu)
        np.testing.assert_allclose(tk[:, 1], KALKER_TABLE_E3[:, 1 + k], rtol=1e-13)
        np.testing.assert_allclose(tk[:, 3], KALKER_TABLE_E3[:, 7 + k], rtol=1e-13)


def test_linear_in_g_between_nodes():
    """Halfway between two g nodes the coefficient is the mean (linear in g = min(a/b, b/a))."""
    t = kalker_table_for_poisson(0.3)
    assert kalker_coefficients(0.55, 0.3)[0] == pytest.approx(0.5 * (t[4, 1] + t[5, 1]))
    # a > b half: g = b/a = 0.55 lies between the rows a/b = 1/0.5 and 1/0.6
    c = kalker_coefficients(1.0 / 0.55, 0.3)
    assert c[2] == pytest.approx(0.5 * (t[13, 3] + t[14, 3]), rel=1e-12)


def test_continuous_at_circle():
    below = np.array(kalker_coefficients(1.0 - 1e-9, 0.3))
    above = np.array(kalker_coefficients(1.0 + 1e-9, 0.3))
    np.testing.assert_allclose(below, above, rtol=1e-7)


def test_clamping_outside_the_table():
    """a/b < 0.1 and > 10 use the end rows; nu is clamped to [0, 0.5]."""
    assert kalker_coefficients(0.01, 0.25) == kalker_coefficients(0.1, 0.25)
    assert kalker_coefficients(100.0, 0.25) == kalker_coefficients(10.0, 0.25)
    assert kalker_coefficients(2.0, 0.7) == kalker_coefficients(2.0, 0.5)
    assert kalker_coefficients(2.0, -0.2) == kalker_coefficients(2.0, 0.0)
    with pytest.raises(ValueError):
        kalker_coefficients(0.0, 0.3)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.28, 0.3, 0.5])
def test_numba_agrees_with_python(nu):
    """Same algorithm on the same reduced table: agreement to rounding (1e-12)."""
    t = kalker_table_for_poisson(nu)
    ratios = np.concatenate(
        [np.geomspace(0.01, 100.0, 301), KALKER_TABLE_E3[:, 0], PRINTED_RATIOS, [1.0 - 1e-12]]
    )
    for r in ratios:
        np.testing.assert_allclose(
            kalker_coefficients_nb(t, r), kalker_coefficients(r, nu), rtol=1e-12
        )
    # degenerate input: first row, no NaN
    for bad in (0.0, -1.0, float("nan")):
        assert kalker_coefficients_nb(t, bad) == tuple(t[0, 1:])


def test_linear_forces():
    """Fx = -G a b c11 xi, Fy = -G a b c22 eta - G (ab)^1.5 c23 phi (docs/conventions.md)."""
    G, a, b = 8.0e10, 6e-3, 4e-3
    c11, c22, c23 = kalker_coefficients(a / b, 0.28)
    fx, fy = kalker_linear_forces(1e-3, 0.0, 0.0, a, b, G, c11, c22, c23)
    assert fx == pytest.approx(-G * a * b * c11 * 1e-3)
    assert fy == 0.0
    fx, fy = kalker_linear_forces(0.0, -2e-3, 0.0, a, b, G, c11, c22, c23)
    assert fx == 0.0
    assert fy == pytest.approx(G * a * b * c22 * 2e-3)
    fx, fy = kalker_linear_forces(0.0, 0.0, 0.5, a, b, G, c11, c22, c23)
    assert fy == pytest.approx(-G * (a * b) ** 1.5 * c23 * 0.5)
    # numpy arrays and the compiled version
    xi = np.linspace(-1e-3, 1e-3, 5)
    fx, fy = kalker_linear_forces(xi, 2 * xi, 0.1, a, b, G, c11, c22, c23)
    for k in range(5):
        assert kalker_linear_nb(xi[k], 2 * xi[k], 0.1, a, b, G, c11, c22, c23) == pytest.approx(
            (fx[k], fy[k]), rel=1e-14
        )
