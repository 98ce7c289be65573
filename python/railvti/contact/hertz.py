"""Hertz's solution for two quasi-identical elastic bodies with a quadratic gap."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._elliptic import ellipke
from .._roots import brent_root
from ..material import Material
from .grid import Grid


@dataclass(frozen=True)
class HertzResult:
    """Hertz contact of the gap ``h = A x^2 + B y^2`` under the normal force ``fn``.

    Attributes
    ----------
    a, b : float
        Semi-axes of the contact ellipse in x and y, m.
    p0 : float
        Maximum pressure, Pa.
    approach : float
        Approach of distant points, m.
    fn : float
        Normal force, N.
    """

    a: float
    b: float
    p0: float
    approach: float
    fn: float

    def pressure(self, grid: Grid) -> np.ndarray:
        """The Hertz pressure ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` at the grid's element centres, Pa."""
        x, y = grid.mesh()
        return self.p0 * np.sqrt(np.maximum(1.0 - (x / self.a) ** 2 - (y / self.b) ** 2, 0.0))


def _ratio_residual(k: float, target: float) -> float:
    """(B/A)(k) - target for b/a = k <= 1, with m = 1 - k^2 (Johnson 1985, eq. 4.39)."""
    kk, ee = ellipke(1.0 - k * k)
    return (ee / (k * k) - kk) / (kk - ee) - target


def hertz(A: float, B: float, fn: float, material: Material) -> HertzResult:
    """Hertz's solution for the gap ``h = A x^2 + B y^2``.

    With the eccentricity e^2 = 1 - (b/a)^2 of the ellipse (a >= b) and the
    complete elliptic integrals K(e), E(e), the pressure
    ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` displaces the surfaces by
    ``delta - A x^2 - B y^2`` with (Johnson 1985, sect. 4.2)::

        A = p0 b (K - E) / (E* a^2 e^2)
        B = p0 b ((a/b)^2 E - K) / (E* a^2 e^2)
        delta = p0 b K / E*,          p0 = 3 fn / (2 pi a b)

    where 1/E* = (1 - nu)/G for two bodies of the same material.
    The ratio B/A fixes b/a (solved to machine precision), A then fixes a.

    Parameters
    ----------
    A, B : float
        Gap coefficients, 1/m (half the relative curvatures in x and y).
    fn : float
        Normal force, N.
    material : Material
        The bodies' material.

    Returns
    -------
    HertzResult
    """
    A = _checks.positive("A", A)
    B = _checks.positive("B", B)
    fn = _checks.positive("fn", fn)
    es = material.contact_modulus
    swap = A > B  # solve with the longer semi-axis along x, then swap back
    a_lo, a_hi = (B, A) if swap else (A, B)
    ratio = a_hi / a_lo
    # Near the circle (K - E)/e^2 loses digits: below b/a = 1 - 1e-6 solve for
    # b/a, above it interpolate linearly to the circle (error O(1e-12)).
    k_ub = 1.0 - 1e-6
    r_ub = _ratio_residual(k_ub, 0.0)
    if ratio <= r_ub:
        k = 1.0 - (1.0 - k_ub) * (ratio - 1.0) / (r_ub - 1.0)
    else:
        k = brent_root(_ratio_residual, 1e-7, k_ub, args=(ratio,), xtol=1e-17, rtol=1e-15, maxiter=500)
    e2 = 1.0 - k * k
    kk, ee = ellipke(e2)
    km = (kk - ee) / e2 if e2 > 1e-12 else math.pi / 4.0
    # A = p0 b km / (E* a^2) and p0 = 3 fn / (2 pi a b)  ->  a^3 = 3 fn km / (2 pi A E*)
    a = (3.0 * fn * km / (2.0 * math.pi * a_lo * es)) ** (1.0 / 3.0)
    b = k * a
    p0 = 3.0 * fn / (2.0 * math.pi * a * b)
    approach = p0 * b * kk / es
    if swap:
        a, b = b, a
    return HertzResult(a=float(a), b=float(b), p0=float(p0), approach=float(approach), fn=fn)


def hertz_gap(grid: Grid, A: float, B: float) -> np.ndarray:
    """The quadratic gap ``A x^2 + B y^2`` at the grid's element centres, m, shape (nx, ny)."""
    A = _checks.finite("A", A)
    B = _checks.finite("B", B)
    x, y = grid.mesh()
    return np.asfortranarray(A * x * x + B * y * y)


__all__ = ["HertzResult", "hertz", "hertz_gap"]
