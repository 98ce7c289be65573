"""Hertz's solution against the closed-form circle and an independent integral form."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from railvti import InputError, Material
from railvti.contact import hertz

MAT = Material(shear_modulus=82e9, poisson=0.28)


def test_circle_closed_form():
    R, F = 0.46, 1.0e4
    h = hertz(1 / (2 * R), 1 / (2 * R), F, MAT)
    es = MAT.contact_modulus
    a = (3 * F * R / (4 * es)) ** (1 / 3)
    assert h.a == pytest.approx(a, rel=1e-12)
    assert h.b == pytest.approx(a, rel=1e-12)
    assert h.p0 == pytest.approx(3 * F / (2 * math.pi * a * a), rel=1e-12)
    assert h.approach == pytest.approx(a * a / R, rel=1e-12)


@pytest.mark.parametrize("A, B", [(1.0, 2.0), (0.3, 3.0), (5.0, 0.5), (1.0, 1.0001), (0.05, 5.0)])
def test_ellipse_against_love_integrals(A, B):
    """For p = p0 sqrt(1 - x^2/a^2 - y^2/b^2) the surface displacement is
    (p0 a b / 2E*) int_0^inf [1 - x^2/(a^2+w) - y^2/(b^2+w)] dw / sqrt((a^2+w)(b^2+w)w)
    (Johnson 1985, eq. 3.60 with 3.64); its quadratic coefficients must be A and B."""
    h = hertz(A, B, 1.0e4, MAT)
    a, b, es = h.a, h.b, MAT.contact_modulus
    s = h.p0 * a * b / (2 * es)

    def integral(fn):
        # w = t^2 removes the 1/sqrt(w) end singularity
        return quad(lambda t: 2 * fn(t * t), 0, np.inf, epsabs=0, epsrel=1e-12, limit=500)[0]

    root = lambda w: math.sqrt((a * a + w) * (b * b + w))  # noqa: E731
    assert s * integral(lambda w: 1 / ((a * a + w) * root(w))) == pytest.approx(A, rel=1e-8)
    assert s * integral(lambda w: 1 / ((b * b + w) * root(w))) == pytest.approx(B, rel=1e-8)
    assert s * integral(lambda w: 1 / root(w)) == pytest.approx(h.approach, rel=1e-8)


def test_swapping_axes_swaps_semi_axes():
    h1 = hertz(0.2, 1.0, 5e3, MAT)
    h2 = hertz(1.0, 0.2, 5e3, MAT)
    assert (h1.a, h1.b) == pytest.approx((h2.b, h2.a), rel=1e-13)
    assert h1.p0 == pytest.approx(h2.p0, rel=1e-13)


@pytest.mark.parametrize(
    "args, word",
    [((0.0, 1.0, 1e4), "A"), ((1.0, -1.0, 1e4), "B"), ((1.0, 1.0, 0.0), "fn"), ((1.0, 1.0, math.nan), "fn")],
)
def test_bad_input(args, word):
    with pytest.raises(InputError, match=word):
        hertz(*args, MAT)
