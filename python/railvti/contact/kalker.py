"""Kalker's linear theory of rolling contact: the creep coefficients C11, C22, C23.

The coefficients are interpolated in Kalker's Table E.3 (J.J. Kalker, *Three-
dimensional elastic bodies in rolling contact*, Kluwer 1990), shipped as
``railvti/data/kalker_table_e3.csv`` with its source lines. The table gives
C11, C22 and C23 at 19 values of a/b from 0.1 to 10 and Poisson's ratios
nu = 0, 0.25 and 0.5.

Interpolation
-------------
* in a/b: a monotone piecewise-cubic Hermite interpolant (PCHIP, scipy's
  ``PchipInterpolator``) in ``log(a/b)`` through the 19 tabulated points, so
  the table nodes are reproduced exactly and no overshoot appears between
  them (the table is locally monotone; PCHIP keeps it so);
* in nu: linear between the columns nu = 0, 0.25 and 0.5;
* outside 0.1 <= a/b <= 10 no value is returned: :class:`KalkerRangeError`
  (an :class:`~railvti.errors.InputError`) is raised. Kalker's slender-ellipse
  asymptotics are not used: FASTSIM and the linear theory are rarely needed
  beyond a/b = 10, and an extrapolation would hide the question.

Sign convention (rolling in +x, creepages xi, eta, spin phi in 1/m)::

    Fx = -G a b C11 xi
    Fy = -G a b C22 eta - G (a b)^1.5 C23 phi
"""

from __future__ import annotations

import csv
from functools import lru_cache
from importlib import resources
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from ..material import Material

if TYPE_CHECKING:
    from scipy.interpolate import PchipInterpolator

__all__ = ["KalkerRangeError", "kalker_coefficients", "kalker_table", "linear_creep_forces", "A_OVER_B_RANGE"]

#: The range of a/b covered by Table E.3.
A_OVER_B_RANGE = (0.1, 10.0)
_NU = np.array([0.0, 0.25, 0.5])


class KalkerRangeError(InputError):
    """a/b outside Kalker's Table E.3 (0.1 to 10) or nu outside [0, 0.5]."""


@lru_cache(maxsize=1)
def kalker_table() -> tuple[np.ndarray, np.ndarray]:
    """Kalker's Table E.3 as read from the packaged CSV.

    Returns
    -------
    a_over_b : ndarray, shape (19,)
        Tabulated a/b (a along the rolling direction).
    c : ndarray, shape (3, 19, 3)
        ``c[k, i, m]``: coefficient k (0 C11, 1 C22, 2 C23) at ``a_over_b[i]``
        and nu = (0, 0.25, 0.5)[m].
    """
    text = resources.files("railvti").joinpath("data", "kalker_table_e3.csv").read_text()
    rows = [
        r for r in csv.reader(line for line in text.splitlines() if line.strip() and not line.startswith("#"))
    ]
    header, body = rows[0], np.array(rows[1:], dtype=float)
    expected = ["a_over_b"] + [f"c{k}_nu{n}" for k in ("11", "22", "23") for n in ("0", "025", "05")]
    if header != expected:  # pragma: no cover - a corrupted install
        raise RuntimeError(f"unexpected header in kalker_table_e3.csv: {header}")
    ab = body[:, 0]
    c = body[:, 1:].reshape(len(ab), 3, 3).transpose(1, 0, 2)
    return ab, c


@lru_cache(maxsize=1)
def _interpolants() -> PchipInterpolator:
    # imported on first use: scipy.interpolate costs ~0.2 s at start-up, paid by every
    # CONTACT deck run that never asks for Kalker's coefficients (issue 33)
    from scipy.interpolate import PchipInterpolator

    ab, c = kalker_table()
    # one PCHIP over log(a/b) for all 9 columns: values shape (19, 3, 3)
    return PchipInterpolator(np.log(ab), np.moveaxis(c, 1, 0), axis=0, extrapolate=False)


def kalker_coefficients(a_over_b, poisson: float):
    """Kalker's creep coefficients C11, C22, C23 for an elliptic contact.

    Parameters
    ----------
    a_over_b : float or array_like
        Ratio of the semi-axes, a along the rolling direction x, b lateral;
        0.1 <= a/b <= 10.
    poisson : float
        Poisson's ratio nu in [0, 0.5].

    Returns
    -------
    c11, c22, c23 : float or ndarray
        The coefficients (dimensionless), same shape as ``a_over_b``.

    Raises
    ------
    KalkerRangeError
        a/b outside [0.1, 10] or nu outside [0, 0.5].
    InputError
        NaN or non-numeric input.

    Notes
    -----
    PCHIP in log(a/b) through the table nodes, linear in nu between the
    columns 0, 0.25, 0.5 (see the module docstring). Exact at the nodes.

    Examples
    --------
    >>> kalker_coefficients(1.0, 0.25)
    (4.12, 3.67, 1.47)
    """
    nu = _checks.finite("poisson", poisson)
    if not 0.0 <= nu <= 0.5:
        raise KalkerRangeError(f"poisson must lie in [0, 0.5] for Kalker's table, got {nu}")
    try:
        r = np.asarray(a_over_b, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"a_over_b must be a number or an array of numbers, got {a_over_b!r}") from None
    if not np.isfinite(r).all():
        raise InputError("a_over_b must be finite")
    lo, hi = A_OVER_B_RANGE
    # a tolerance of a few ulps so that 1/(1/10) etc. is accepted
    bad = (r < lo * (1 - 1e-12)) | (r > hi * (1 + 1e-12))
    if bad.any():
        raise KalkerRangeError(
            f"a_over_b must lie in [{lo}, {hi}] (Kalker's Table E.3), got {r[bad].ravel()[0]}"
        )
    logr = np.clip(np.log(r), np.log(lo), np.log(hi))
    v = _interpolants()(logr)  # shape r.shape + (3, 3): coefficient, nu column
    m = min(int(nu // 0.25), 1)
    w = (nu - _NU[m]) / 0.25
    out = (1.0 - w) * v[..., m] + w * v[..., m + 1]
    c11, c22, c23 = out[..., 0], out[..., 1], out[..., 2]
    if np.ndim(r) == 0:
        return float(c11), float(c22), float(c23)
    return c11, c22, c23


def linear_creep_forces(a: float, b: float, material: Material, creepage) -> tuple[float, float]:
    """Kalker's linear-theory creep forces on an ellipse.

    Parameters
    ----------
    a, b : float
        Semi-axes, m (a along x).
    material : Material
        Shear modulus and Poisson's ratio.
    creepage : (xi, eta, phi)
        Longitudinal and lateral creepage (-), spin (1/m).

    Returns
    -------
    fx, fy : float
        ``-G a b C11 xi`` and ``-G a b C22 eta - G (ab)^1.5 C23 phi``, N.
    """
    a = _checks.positive("a", a)
    b = _checks.positive("b", b)
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    xi, eta, phi = (_checks.finite(n, v) for n, v in zip(("xi", "eta", "phi"), creepage))
    c11, c22, c23 = kalker_coefficients(a / b, material.poisson)
    g = material.shear_modulus
    return -g * a * b * c11 * xi, -g * a * b * c22 * eta - g * (a * b) ** 1.5 * c23 * phi
