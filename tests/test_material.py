import math

import pytest

import railvti
from railvti import InputError, Material


def test_material_derived_moduli():
    m = Material(shear_modulus=80e9, poisson=0.25)
    assert m.young_modulus == pytest.approx(200e9)
    assert m.contact_modulus == pytest.approx(80e9 / 0.75)


@pytest.mark.parametrize(
    "g, nu, word",
    [
        (0.0, 0.3, "shear_modulus"),
        (-1e9, 0.3, "shear_modulus"),
        (80e9, 0.5, "poisson"),
        (80e9, -1.0, "poisson"),
        (80e9, -1.5, "poisson"),
        (math.nan, 0.3, "shear_modulus"),
        (80e9, math.inf, "poisson"),
    ],
)
def test_material_rejects_bad_values(g, nu, word):
    with pytest.raises(InputError, match=word):
        Material(shear_modulus=g, poisson=nu)


def test_package_imports_core():
    from railvti import _native

    assert hasattr(_native.core, "normal_solve_c")
    assert railvti.__version__


@pytest.mark.parametrize("nu", [-0.99, -0.1, 0.0, 0.499])
def test_material_accepts_the_open_range(nu):
    """Issue 35: nu in (-1, 0.5), auxetic materials included; steel unchanged."""
    assert Material(shear_modulus=1e9, poisson=nu).poisson == nu
    assert railvti.STEEL.poisson == 0.28
