"""Complete elliptic integrals K(m) and E(m) by the arithmetic-geometric mean (Abramowitz &
Stegun 17.6), the few lines Hertz's ellipse needs instead of importing scipy.special (about
0.25 s at start-up, a tenth of a CONTACT deck's run; issue 33).

The parameter is m = k^2, as in ``scipy.special.ellipk(m)``:
K(m) = int_0^{pi/2} (1 - m sin^2 t)^{-1/2} dt and E(m) = int_0^{pi/2} (1 - m sin^2 t)^{1/2} dt.
With a_0 = 1, b_0 = sqrt(1 - m), c_0 = sqrt(m) and a_{n+1} = (a_n + b_n)/2,
b_{n+1} = sqrt(a_n b_n), c_{n+1} = (a_n - b_n)/2 (quadratic convergence),
K = pi / (2 a_N) and E = K (1 - sum_n 2^(n-1) c_n^2) (A&S 17.6.3-4).
"""

from __future__ import annotations

import math

from .errors import InputError


def _agm(m: float) -> tuple[float, float]:
    if not 0.0 <= m < 1.0:
        raise InputError(f"elliptic parameter m must lie in [0, 1), got {m!r}")
    a, b, c = 1.0, math.sqrt(1.0 - m), math.sqrt(m)
    s = 0.5 * m  # 2^(n-1) c_n^2 for n = 0
    w = 0.5
    for _ in range(40):
        # a - b stalls at an ulp of a, so 1e-17 would run all 40 passes; at 1e-15 the next
        # c^2 terms (< 1e-30 relative) and a's next change are below the double's precision
        if abs(c) <= 1e-15 * a:
            break
        a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
        w *= 2.0
        s += w * c * c
    kk = math.pi / (2.0 * a)
    return kk, kk * (1.0 - s)


def ellipke(m: float) -> tuple[float, float]:
    """Both complete elliptic integrals (K(m), E(m)) from one AGM, m = k^2 in [0, 1)."""
    return _agm(float(m))


def ellipk(m: float) -> float:
    """Complete elliptic integral of the first kind K(m), m = k^2 in [0, 1)."""
    return _agm(float(m))[0]


def ellipe(m: float) -> float:
    """Complete elliptic integral of the second kind E(m), m = k^2 in [0, 1)."""
    return _agm(float(m))[1]


__all__ = ["ellipk", "ellipe", "ellipke"]
