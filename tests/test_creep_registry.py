"""Creep-law registry: names, codes, did-you-mean errors, Python and compiled dispatchers."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from railexu.contact.creep import (
    CREEP_MODELS,
    FASTSIM_KERNEL_POINTS,
    FASTSIM_KERNEL_STRIPS,
    UnknownCreepModelError,
    creep_forces,
    creep_forces_nb,
    creep_model_code,
    creep_model_name,
)
from railexu.contact.fastsim import fastsim_forces
from railexu.contact.kalker import kalker_coefficients, kalker_linear_forces
from railexu.contact.polach import (
    POLACH_2005_PRESETS,
    Polach2005Parameters,
    polach_2005_forces,
    polach_forces,
)

G, Q, MU, V = 8.1e10, 1.0e5, 0.3, 30.0
A_M, B_M = 8.3e-3, 5.1e-3
C11, C22, C23 = kalker_coefficients(A_M / B_M, 0.28)
GEOM = (A_M, B_M, G, C11, C22, C23)
CASES = [(0.0, 0.0, 0.0), (1e-4, 0.0, 0.0), (2e-3, -1e-3, 0.3), (0.0, 0.0, 1.5), (0.2, 0.05, -0.4)]


def test_codes_in_order():
    assert CREEP_MODELS == ("kalker_linear", "polach", "polach_2005", "fastsim", "polach_fastsim")
    for k, name in enumerate(CREEP_MODELS):
        assert creep_model_code(name) == k
        assert creep_model_name(k) == name
    assert creep_model_code(" Polach-2005 ") == 2
    assert creep_model_code("KALKER LINEAR") == 0


@pytest.mark.parametrize(
    ("wrong", "suggestion"),
    [
        ("polach2005", "polach_2005"),
        ("fastsm", "fastsim"),
        ("kalker", "kalker_linear"),
        ("polack", "polach"),
    ],
)
def test_unknown_name_suggests(wrong, suggestion):
    with pytest.raises(UnknownCreepModelError) as info:
        creep_model_code(wrong)
    msg = str(info.value)
    assert f"Did you mean {suggestion!r}?" in msg
    for name in CREEP_MODELS:
        assert name in msg
    assert isinstance(info.value, ValueError)


def test_unknown_name_without_close_match_lists_valid_names():
    with pytest.raises(UnknownCreepModelError, match="Valid creep models: kalker_linear, polach"):
        creep_model_code("hertz")
    with pytest.raises(UnknownCreepModelError):
        creep_model_name(5)
    with pytest.raises(UnknownCreepModelError):
        creep_model_code(1)  # type: ignore[arg-type]


@pytest.mark.parametrize("case", CASES)
def test_python_dispatcher_matches_the_laws(case):
    xi, eta, phi = case
    assert creep_forces("kalker_linear", xi, eta, phi, Q, *GEOM, MU, V) == pytest.approx(
        kalker_linear_forces(xi, eta, phi, *GEOM), rel=1e-14, abs=1e-12
    )
    assert creep_forces("polach", xi, eta, phi, Q, *GEOM, MU, V) == pytest.approx(
        polach_forces(xi, eta, phi, Q, MU, *GEOM), rel=1e-13, abs=1e-9
    )
    for preset in ("dry", "wet"):
        p = POLACH_2005_PRESETS[preset]
        ref = polach_2005_forces(
            xi, eta, phi, Q, MU, *GEOM, V, p.k_a, p.k_s, p.friction_ratio_A,
            p.friction_decay_B_s_per_m,
        )  # fmt: skip
        assert creep_forces("polach_2005", xi, eta, phi, Q, *GEOM, MU, V, preset) == pytest.approx(
            ref, rel=1e-13, abs=1e-9
        )
        assert creep_forces(2, xi, eta, phi, Q, *GEOM, MU, V, p) == pytest.approx(
            ref, rel=1e-13, abs=1e-9
        )
    # default 2005 parameters: dry
    assert creep_forces("polach_2005", xi, eta, phi, Q, *GEOM, MU, V) == creep_forces(
        "polach_2005", xi, eta, phi, Q, *GEOM, MU, V, "dry"
    )
    assert creep_forces("fastsim", xi, eta, phi, Q, *GEOM, MU, V) == fastsim_forces(
        xi, eta, phi, Q, MU, *GEOM, FASTSIM_KERNEL_STRIPS, FASTSIM_KERNEL_POINTS
    )


def test_python_dispatcher_rejects_bad_input():
    with pytest.raises(UnknownCreepModelError, match="Did you mean 'fastsim'"):
        creep_forces("fast_sim", 1e-3, 0.0, 0.0, Q, *GEOM, MU, V)
    with pytest.raises(ValueError):
        creep_forces("polach_2005", 1e-3, 0.0, 0.0, Q, *GEOM, MU, V, "icy")
    with pytest.raises(TypeError):
        creep_forces("polach_2005", 1e-3, 0.0, 0.0, Q, *GEOM, MU, V, (1.0, 0.4, 0.4, 0.6))


@numba.njit(cache=False)
def _call_from_njit(code, xi, eta, phi, Q, a, b, G, c11, c22, c23, mu0, k_a, k_s, fa, fb, V):
    fx, fy = creep_forces_nb(
        code, xi, eta, phi, Q, a, b, G, c11, c22, c23, mu0, k_a, k_s, fa, fb, V
    )
    return fx, fy


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("model", CREEP_MODELS)
def test_compiled_dispatcher_equals_python(model, case):
    code = creep_model_code(model)
    p = Polach2005Parameters(0.8, 0.3, 0.5, 0.4, 0.5)
    ref = creep_forces(model, *case, Q, *GEOM, MU, V, p)
    args = (*case, Q, *GEOM, MU, p.k_a, p.k_s, p.friction_ratio_A, p.friction_decay_B_s_per_m, V)
    assert creep_forces_nb(code, *args) == ref
    assert _call_from_njit(code, *args) == ref


def test_compiled_dispatcher_unknown_code_raises():
    with pytest.raises(ValueError, match="unknown creep model code"):
        creep_forces_nb(7, 1e-3, 0.0, 0.0, Q, *GEOM, MU, 1.0, 1.0, 1.0, 0.0, V)


def test_all_laws_tend_to_kalker():
    """Small creepage: every law gives Kalker's force (Polach 2005: times (k_A + k_S)/2)."""
    xi, eta, phi = 1e-9, 0.0, 0.0
    ref = np.array(kalker_linear_forces(xi, eta, phi, *GEOM))
    for model in ("kalker_linear", "polach", "fastsim"):
        np.testing.assert_allclose(
            creep_forces(model, xi, eta, phi, Q, *GEOM, MU, V), ref, rtol=1e-6
        )
    p = POLACH_2005_PRESETS["wet"]
    np.testing.assert_allclose(
        creep_forces("polach_2005", xi, eta, phi, Q, *GEOM, MU, V, p),
        0.5 * (p.k_a + p.k_s) * ref,
        rtol=1e-6,
    )


def test_input_errors_are_railexu_input_errors():
    """Bad names are input errors (the command line turns them into a short message)."""
    from railexu.contact.parameters import ContactParameterError, ContactParameters
    from railexu.errors import InputError

    with pytest.raises(InputError):
        creep_model_code("polak")
    with pytest.raises(ContactParameterError):
        ContactParameters(friction=-1.0)


def test_parameters_module_does_not_import_numba():
    """Vehicle files import ContactParameters: it must not pull in the compiled layer."""
    import subprocess
    import sys

    code = (
        "import sys; import railexu.contact.parameters as p; p.ContactParameters(); "
        "print('numba' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
