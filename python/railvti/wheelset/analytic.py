"""Closed-form references for validating the axisymmetric finite elements.

* Free-free Timoshenko beam of circular cross-section: exact solution of the
  Timoshenko equations, split into modes symmetric and antisymmetric about
  mid-length (2 x 2 frequency determinants); shear coefficient of a solid
  circle kappa = 6 (1 + nu) / (7 + 6 nu) (Cowper 1966).
* Kirchhoff annular plate clamped at the inner radius b and free at the outer
  radius a, nodal diameters k: W = A J_k + B Y_k + C I_k + D K_k of lambda r,
  lambda^4 = rho h omega^2 / D (Leissa, Vibration of Plates, NASA SP-160, 1969,
  sec. 2.3): 4 x 4 determinant, roots by bracketing.
"""
from __future__ import annotations

import numpy as np
from scipy import optimize, special


def _roots(fun, x_lo: float, x_hi: float, n: int, steps: int = 4000) -> list[float]:
    xs = np.linspace(x_lo, x_hi, steps)
    vals = np.array([fun(x) for x in xs])
    out: list[float] = []
    for i in range(steps - 1):
        if np.sign(vals[i]) != np.sign(vals[i + 1]) and np.isfinite(vals[i]) and np.isfinite(vals[i + 1]):
            r = optimize.brentq(fun, xs[i], xs[i + 1], xtol=1e-13)
            # keep roots only, not sign flips through poles
            if abs(fun(r)) < 1e-6 * (abs(vals[i]) + abs(vals[i + 1]) + 1e-300) + 1e-12:
                out.append(r)
        if len(out) >= n:
            break
    return out


def timoshenko_free_free(length: float, diameter: float, young: float, poisson: float,
                         density: float, n_modes: int = 4) -> np.ndarray:
    """Bending natural frequencies (Hz) of a free-free solid circular Timoshenko beam."""
    g = young / (2.0 * (1.0 + poisson))
    kap = 6.0 * (1.0 + poisson) / (7.0 + 6.0 * poisson)
    area = np.pi * diameter ** 2 / 4.0
    inertia = np.pi * diameter ** 4 / 64.0
    ei, kga, ra, ri = young * inertia, kap * g * area, density * area, density * inertia
    half = 0.5 * length

    def det(w: float, sym: bool) -> float:
        # k s^4 + ... : roots s^2 = a^2 (real) and -b^2 (oscillatory)
        c4, c2, c0 = kga * ei, w * w * (kga * ri + ra * ei), ra * w * w * (ri * w * w - kga)
        disc = np.sqrt(c2 * c2 - 4.0 * c4 * c0)
        a = np.sqrt((-c2 + disc) / (2.0 * c4))
        b = np.sqrt((c2 + disc) / (2.0 * c4))
        # w = cosh(a x) (sym) / sinh(a x); psi = ((kga s^2 + ra w^2)/(kga s)) w-amplitude
        pa = (kga * a * a + ra * w * w) / (kga * a)
        pb = (-kga * b * b + ra * w * w) / (kga * b)
        x = half
        if sym:
            # w = C1 cosh(ax) + C2 cos(bx); psi = C1 pa sinh(ax) + C2 pb sin(bx)
            wp = [a * np.sinh(a * x), -b * np.sin(b * x)]
            ps = [pa * np.sinh(a * x), pb * np.sin(b * x)]
            psp = [pa * a * np.cosh(a * x), pb * b * np.cos(b * x)]
        else:
            # w = C1 sinh(ax) + C2 sin(bx); psi = C1 pa cosh(ax) - C2 pb cos(bx)
            wp = [a * np.cosh(a * x), b * np.cos(b * x)]
            ps = [pa * np.cosh(a * x), -pb * np.cos(b * x)]
            psp = [pa * a * np.sinh(a * x), pb * b * np.sin(b * x)]
        m = np.array([psp, [wp[0] - ps[0], wp[1] - ps[1]]])
        m /= np.abs(m).max(axis=0)
        return float(np.linalg.det(m))

    w_hi = 2.0 * np.pi * 20.0 * np.sqrt(ei / ra) / length ** 2 * (n_modes + 2) ** 2
    w_hi = min(w_hi, 0.95 * np.sqrt(kga / ri))
    roots = _roots(lambda w: det(w, True), 1e-3, w_hi, n_modes) + \
        _roots(lambda w: det(w, False), 1e-3, w_hi, n_modes)
    return np.sort(np.array(roots))[:n_modes] / (2.0 * np.pi)


def annular_plate_clamped_free(inner: float, outer: float, thickness: float, young: float,
                               poisson: float, density: float, k: int, n_modes: int = 2) -> np.ndarray:
    """Natural frequencies (Hz) of a Kirchhoff annular plate, clamped inside, free outside."""
    dp = young * thickness ** 3 / (12.0 * (1.0 - poisson ** 2))
    nu = poisson

    def rows(lam: float) -> np.ndarray:
        b, a = inner, outer
        cols = []
        for fun, dfun in ((special.jv, special.jvp), (special.yv, special.yvp),
                          (special.iv, special.ivp), (special.kv, special.kvp)):
            wb = fun(k, lam * b)
            wpb = lam * dfun(k, lam * b, 1)
            w, w1 = fun(k, lam * a), lam * dfun(k, lam * a, 1)
            w2, w3 = lam ** 2 * dfun(k, lam * a, 2), lam ** 3 * dfun(k, lam * a, 3)
            r = a
            mr = w2 + nu * (w1 / r - k * k * w / r ** 2)
            lap_d = w3 + w2 / r - w1 / r ** 2 - k * k * w1 / r ** 2 + 2.0 * k * k * w / r ** 3
            vr = lap_d - (1.0 - nu) * k * k / r ** 2 * (w1 - w / r)
            cols.append([wb, wpb, mr, vr])
        m = np.array(cols).T
        m /= np.abs(m).max(axis=0)
        return m

    def det(lam: float) -> float:
        return float(np.linalg.det(rows(lam)))

    lam_hi = (n_modes + 3) * 3.5 / (outer - inner) + 1.0
    lams = _roots(det, 0.2 / outer, lam_hi, n_modes, steps=6000)
    rho_h = density * thickness
    return np.array([lam ** 2 * np.sqrt(dp / rho_h) / (2.0 * np.pi) for lam in lams])
