"""Hunter's rigid cylinder rolling on a standard-linear-solid half-space (plane strain): the
exact solution by Hunter's reduction, computed by quadrature, independent of the BEM grid.

Hunter (1961, J. Appl. Mech. 28, 611-617) reduced the steady-rolling problem of a rigid
cylinder on a standard linear solid to a singular integral equation that the classical
airfoil inversion solves. With the creep compliance ``J(t) = J0 + (Jinf - J0)(1 - exp(-t/tc))``,
the memory length ``L = V tc`` and the contact ``c1 < x < c2`` (particles move in -x, the
leading edge is c2), applying ``(1 - L d/dx)`` to the hereditary surface displacement and
differentiating once gives, on the contact (docs/contact_viscoelastic.md, eqs VE5-VE8)::

    H[q](x) = (x - L) / (2 R),        q = Jinf p - J0 L p',                      (VE5)

with H the finite Hilbert transform (1/pi) PV Int q(xi)/(x - xi) dxi. With
``x = m + c cos(theta)`` its general solution is
``q = (C0 - A cos(theta) - B cos^2(theta)) / sin(theta)``, A = (m - L)/(2R), B = c/(2R), and
the first-order equation for p, integrated from the leading edge p(c2) = 0, is::

    p(theta) = c/(J0 L) Int_0^theta exp(-c (cos t - cos theta) / lambda)
               (C0 - A cos t - B cos^2 t) dt,       lambda = J0 L / Jinf.          (VE6)

Three conditions fix (C0, c, m): p(c1) = 0 (VE7, linear in C0), the load Int p dx = fn, and
the displacement at the leading edge, which the two differentiations lost::

    -(Jinf - J0) Int_0^inf exp(-s/L) w'(c2 + s) ds - J0 L w'(c2) = L c2 / R,     (VE8)

w' = -(2/pi) Int p(xi)/(x - xi) dxi the slope of the unit-compliance field. The integrals
are done on a uniform grid in theta (the integrands are smooth there) and (c, m) found by
Newton's method (scipy's ``fsolve``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import fsolve
from scipy.special import exp1

from .. import _checks
from ..errors import ConvergenceError, InputError

#: Gauss-Legendre nodes per theta panel.
_GAUSS = np.polynomial.legendre.leggauss(8)


@dataclass(frozen=True)
class HunterResult:
    """Hunter's solution for a rigid cylinder on a standard-linear-solid half-space.

    Attributes
    ----------
    x_trailing, x_leading : float
        Contact edges c1 < c2, m (x in the rolling direction, origin below the axle).
    x, pressure : ndarray
        Points in the contact (m) and the pressure there (Pa), from the leading edge back.
    centroid : float
        Pressure centroid e = Int p x dx / fn, m (> 0: ahead of the axle).
    resistance_coefficient : float
        mu_R = e / R: the rolling-resistance force over the load.
    """

    x_trailing: float
    x_leading: float
    x: np.ndarray
    pressure: np.ndarray
    centroid: float
    resistance_coefficient: float


def _exp_e1(z: np.ndarray) -> np.ndarray:
    """exp(z) E1(z) for z >= 0 (0 at z = 0 is replaced by a large finite value, the
    integrable log singularity being weighted by p = 0 there)."""
    z = np.maximum(z, 1e-300)
    big = z > 40.0
    out = np.empty_like(z)
    zb = z[big]
    out[big] = (1.0 - 1.0 / zb + 2.0 / zb**2 - 6.0 / zb**3 + 24.0 / zb**4) / zb
    out[~big] = np.exp(z[~big]) * exp1(z[~big])
    return out


def _profile(c: float, m: float, radius: float, j0: float, jinf: float, ell: float, n: int):
    """theta grid, p(theta) (VE6 with C0 from VE7), on n panels."""
    lam = j0 * ell / jinf
    a_coef = (m - ell) / (2.0 * radius)
    b_coef = c / (2.0 * radius)
    th = np.linspace(0.0, np.pi, n + 1)
    xg, wg = _GAUSS
    ta = th[:-1, None] + 0.5 * (th[1:, None] - th[:-1, None]) * (xg[None, :] + 1.0)
    wa = 0.5 * (th[1:, None] - th[:-1, None]) * wg[None, :]
    # VE7: Int_0^pi exp(-c (cos t + 1)/lambda) g(t) dt = 0 (weights at most 1)
    wt = np.exp(-c * (np.cos(ta) + 1.0) / lam) * wa
    c0 = float(np.sum(wt * (a_coef * np.cos(ta) + b_coef * np.cos(ta) ** 2)) / np.sum(wt))
    g = c0 - a_coef * np.cos(ta) - b_coef * np.cos(ta) ** 2
    # panel integrals relative to the panel's end, then the recursion over panels
    loc = np.sum(np.exp(-c * (np.cos(ta) - np.cos(th[1:, None])) / lam) * g * wa, axis=1)
    dec = np.exp(-c * (np.cos(th[:-1]) - np.cos(th[1:])) / lam)
    p = np.zeros(n + 1)
    for i in range(n):
        p[i + 1] = p[i] * dec[i] + loc[i]
    return th, p * c / (j0 * ell)


def _trap(f: np.ndarray, th: np.ndarray) -> float:
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(th)))


def _conditions(c, m, radius, fn, j0, jinf, ell, n):
    th, p = _profile(c, m, radius, j0, jinf, ell, n)
    force = _trap(p * c * np.sin(th), th)
    c2 = m + c
    # w'(c2) = -(2/pi) Int p cot(theta/2) dtheta; the limit at theta = 0 is 2 p'(0)
    cot = np.zeros_like(th)
    cot[1:] = 1.0 / np.tan(0.5 * th[1:])
    f0 = p * cot
    f0[0] = 2.0 * p[1] / th[1]
    w1 = -(2.0 / np.pi) * _trap(f0, th)
    dist = c * (1.0 - np.cos(th))
    tail = -(2.0 / np.pi) * _trap(p * _exp_e1(dist / ell) * c * np.sin(th), th)
    edge = -(jinf - j0) * tail - j0 * ell * w1 - ell * c2 / radius
    return th, p, force, edge


def hunter_cylinder(
    radius: float,
    fn: float,
    j0: float,
    jinf: float,
    memory_length: float,
    panels: int = 4000,
) -> HunterResult:
    """Hunter's rolling rigid cylinder on a standard-linear-solid half-space.

    Parameters
    ----------
    radius : float
        Cylinder radius R, m.
    fn : float
        Load per unit length, N/m.
    j0, jinf : float
        Instantaneous and relaxed plane-strain contact compliance (1 - nu^2)/E, 1/Pa,
        0 < j0 < jinf.
    memory_length : float
        L = V tc, rolling speed times the creep (retardation) time, m (> 0).
    panels : int
        Panels of the theta quadrature.

    Returns
    -------
    HunterResult

    Raises
    ------
    InputError
        A parameter outside its range (named).
    ConvergenceError
        Newton's method did not solve eqs VE7-VE8.
    """
    radius = _checks.positive("radius", radius)
    fn = _checks.positive("fn", fn)
    j0 = _checks.positive("j0", j0)
    jinf = _checks.positive("jinf", jinf)
    ell = _checks.positive("memory_length", memory_length)
    if not jinf > j0:
        raise InputError(f"jinf must exceed j0 (a standard linear solid creeps), got {jinf} <= {j0}")
    a_inf = np.sqrt(4.0 * fn * radius * jinf / np.pi)

    def residual(v):
        c, m = v[0] * a_inf, v[1] * a_inf
        if c <= 0:
            return [1e3, 1e3]
        _, _, force, edge = _conditions(c, m, radius, fn, j0, jinf, ell, panels)
        return [force / fn - 1.0, edge * radius / (ell * a_inf)]

    best = None
    for guess in ([np.sqrt(j0 / jinf) ** 0.5, 0.1], [0.8, 0.3], [0.9, 0.05], [0.6, 0.2]):
        sol, info, ier, _ = fsolve(residual, guess, full_output=True, xtol=1e-13)
        r = np.abs(residual(sol)).max()
        if best is None or r < best[1]:
            best = (sol, r)
        if ier == 1 and r < 1e-9:
            break
    sol, r = best
    if r > 1e-7:
        raise ConvergenceError(f"hunter_cylinder: Newton's method stopped at residual {r:.3g}")
    c, m = sol[0] * a_inf, sol[1] * a_inf
    th, p, force, _ = _conditions(c, m, radius, fn, j0, jinf, ell, panels)
    x = m + c * np.cos(th)
    moment = _trap(p * x * c * np.sin(th), th)
    e = moment / force
    return HunterResult(
        x_trailing=float(m - c),
        x_leading=float(m + c),
        x=x,
        pressure=p,
        centroid=float(e),
        resistance_coefficient=float(e / radius),
    )


__all__ = ["HunterResult", "hunter_cylinder"]
