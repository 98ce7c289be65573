"""Closed-form references: Wickens' single suspended wheelset and Nadal's flange-climb limit.

Klingel's kinematic wavelength is :func:`railvti.geometry.klingel_wavelength`.

Single wheelset of mass m and yaw inertia I on lateral springs (total k_y) and a yaw spring
k_psi, conicity lambda, contact points at +-l, radius r0, linear creep coefficients f11, f22
per wheel, no spin creep and no gravitational stiffness (Wickens 1965; e.g. Iwnicki (ed.),
Handbook of Railway Vehicle Dynamics, ch. 7)::

    m y'' + 2 f22 (y'/V - psi) + k_y y = 0
    I psi'' + 2 f11 l^2 psi'/V + 2 f11 lambda l y / r0 + k_psi psi = 0

Characteristic quartic a4 s^4 + ... + a0: with c1 = 2 f22/V, c2 = 2 f11 l^2/V,
a4 = m I, a3 = m c2 + I c1, a2 = m k_psi + c1 c2 + I k_y, a1 = c1 k_psi + c2 k_y,
a0 = k_y k_psi + 4 f11 f22 lambda l / r0. Stable iff all a_i > 0 and the Hurwitz
determinant H = a3 a2 a1 - a4 a1^2 - a0 a3^2 > 0; the critical speed is the root of H(V).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from .._roots import brent_root
from ..errors import InputError

__all__ = ["wickens_coefficients", "wickens_critical_speed", "nadal_limit"]


def wickens_coefficients(
    v: float,
    m: float,
    inertia: float,
    ky: float,
    kpsi: float,
    f11: float,
    f22: float,
    conicity: float,
    l: float,
    r0: float,
) -> np.ndarray:
    """Coefficients (a4, a3, a2, a1, a0) of the characteristic quartic at speed v (m/s)."""
    c1 = 2 * f22 / v
    c2 = 2 * f11 * l * l / v
    return np.array(
        [
            m * inertia,
            m * c2 + inertia * c1,
            m * kpsi + c1 * c2 + inertia * ky,
            c1 * kpsi + c2 * ky,
            ky * kpsi + 4 * f11 * f22 * conicity * l / r0,
        ]
    )


def wickens_critical_speed(
    m: float,
    inertia: float,
    ky: float,
    kpsi: float,
    f11: float,
    f22: float,
    conicity: float,
    l: float,
    r0: float,
    v_max: float = 1000.0,
) -> float:
    """Critical speed (m/s) of the suspended wheelset from the Routh-Hurwitz condition."""
    for name, val in (
        ("m", m),
        ("inertia", inertia),
        ("ky", ky),
        ("kpsi", kpsi),
        ("f11", f11),
        ("f22", f22),
        ("conicity", conicity),
        ("l", l),
        ("r0", r0),
    ):
        _checks.positive(name, val)

    def hurwitz(v: float) -> float:
        a4, a3, a2, a1, a0 = wickens_coefficients(v, m, inertia, ky, kpsi, f11, f22, conicity, l, r0)
        return a3 * a2 * a1 - a4 * a1 * a1 - a0 * a3 * a3

    lo = 0.1
    if hurwitz(lo) <= 0:
        raise InputError("the wheelset is unstable already at 0.1 m/s")
    if hurwitz(v_max) > 0:
        return math.inf
    return brent_root(hurwitz, lo, v_max, xtol=1e-10, rtol=1e-12)


def nadal_limit(flange_angle: float, friction: float) -> float:
    """Nadal's limit of the flange-climb ratio Y/Q (Nadal 1908; e.g. Iwnicki (ed.), Handbook
    of Railway Vehicle Dynamics, ch. 8): Y/Q = (tan(gamma) - mu) / (1 + mu tan(gamma)).

    Parameters
    ----------
    flange_angle : float
        Flange contact angle gamma, rad (in (0, pi/2)).
    friction : float
        Friction coefficient mu (>= 0).
    """
    g = float(flange_angle)
    mu = float(friction)
    if not (0.0 < g < 0.5 * math.pi) or not (mu >= 0.0):
        raise InputError(
            f"flange_angle must lie in (0, pi/2) rad and friction be >= 0, got {flange_angle}, {friction}"
        )
    t = math.tan(g)
    return (t - mu) / (1.0 + mu * t)
