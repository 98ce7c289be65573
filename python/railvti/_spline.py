"""The not-a-knot cubic interpolating spline of a profile, the few lines railvti needs instead
of importing scipy.interpolate (about 0.45 s at start-up with the scipy.special it pulls in: a
quarter of a CONTACT deck's run of 21 positions; issue 33). It gives scipy's
``CubicSpline(x, y, bc_type="not-a-knot", extrapolate=False)`` to rounding.

The slopes s_i at the knots solve the tridiagonal system of C2 continuity (de Boor, A
Practical Guide to Splines, ch. IV) closed by the not-a-knot conditions (the third
derivative continuous at the second and the last-but-one knot), solved by Gaussian
elimination with partial pivoting (LAPACK's dgtsv). Each interval [x_i, x_i+1] then holds
the cubic ((c0 t + c1) t + s_i) t + y_i, t = x - x_i.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError


def _tridiagonal_solve(dl: np.ndarray, d: np.ndarray, du: np.ndarray, b: np.ndarray) -> np.ndarray:
    """x with A x = b, A tridiagonal (sub-diagonal dl, diagonal d, super-diagonal du):
    elimination with row interchanges, as LAPACK's dgtsv (a second super-diagonal appears)."""
    n = len(d)
    d, du, b = d.astype(float), du.astype(float), b.astype(float)
    dl = dl.astype(float)
    du2 = np.zeros(max(n - 2, 0))
    for i in range(n - 1):
        if abs(d[i]) >= abs(dl[i]):  # no interchange
            f = dl[i] / d[i]
            d[i + 1] -= f * du[i]
            b[i + 1] -= f * b[i]
        else:  # interchange rows i and i+1
            f = d[i] / dl[i]
            d[i], dl[i] = dl[i], d[i + 1]
            d[i + 1] = du[i] - f * dl[i]
            if i < n - 2:
                du2[i] = du[i + 1]
                du[i + 1] = -f * du2[i]
            du[i] = dl[i]
            b[i], b[i + 1] = b[i + 1], b[i] - f * b[i + 1]
    x = np.empty(n)
    x[n - 1] = b[n - 1] / d[n - 1]
    if n > 1:
        x[n - 2] = (b[n - 2] - du[n - 2] * x[n - 1]) / d[n - 2]
    for i in range(n - 3, -1, -1):
        x[i] = (b[i] - du[i] * x[i + 1] - du2[i] * x[i + 2]) / d[i]
    return x


class NotAKnotSpline:
    """Cubic spline through (x_i, y_i), x strictly increasing, at least 4 points, with
    not-a-knot end conditions; ``spline(x, nu)`` is its nu-th derivative (nu = 0, 1, 2), NaN
    outside [x_0, x_n-1].
    """

    def __init__(self, x: np.ndarray, y: np.ndarray) -> None:
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        if x.ndim != 1 or x.shape != y.shape or x.size < 4 or not (np.diff(x) > 0.0).all():
            raise InputError("a spline needs at least 4 points with strictly increasing x")
        n = x.size
        dx = np.diff(x)
        slope = np.diff(y) / dx
        d = np.empty(n)
        dl = np.empty(n - 1)
        du = np.empty(n - 1)
        b = np.empty(n)
        # C2 continuity at the interior knots
        d[1:-1] = 2.0 * (dx[:-1] + dx[1:])
        dl[:-1] = dx[1:]
        du[1:] = dx[:-1]
        b[1:-1] = 3.0 * (dx[1:] * slope[:-1] + dx[:-1] * slope[1:])
        # not-a-knot at both ends
        w = x[2] - x[0]
        d[0], du[0] = dx[1], w
        b[0] = ((dx[0] + 2.0 * w) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / w
        w = x[-1] - x[-3]
        d[-1], dl[-1] = dx[-2], w
        b[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * w + dx[-1]) * dx[-2] * slope[-1]) / w
        s = _tridiagonal_solve(dl, d, du, b)
        t = (s[:-1] + s[1:] - 2.0 * slope) / dx
        self.x = x
        self.c = np.stack([t / dx, (slope - s[:-1]) / dx - t, s[:-1], y[:-1]])

    def __call__(self, xv: np.ndarray | float, nu: int = 0) -> np.ndarray:
        a = np.asarray(xv, dtype=np.float64)
        i = np.clip(np.searchsorted(self.x, a, side="right") - 1, 0, self.x.size - 2)
        t = a - self.x[i]
        c0, c1, c2, c3 = self.c[:, i]
        if nu == 0:
            out = ((c0 * t + c1) * t + c2) * t + c3
        elif nu == 1:
            out = (3.0 * c0 * t + 2.0 * c1) * t + c2
        elif nu == 2:
            out = 6.0 * c0 * t + 2.0 * c1
        else:
            raise InputError(f"spline derivative order must be 0, 1 or 2, got {nu!r}")
        return np.where((a >= self.x[0]) & (a <= self.x[-1]), out, np.nan)


__all__ = ["NotAKnotSpline"]
