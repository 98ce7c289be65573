"""Equivalent conicity (EN 15302) and Klingel wavelength from a geometry table."""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError
from .table import GeometryTable

__all__ = ["conicity_of_delta_r", "equivalent_conicity", "klingel_wavelength"]


def equivalent_conicity(
    table: GeometryTable, amplitude: float | np.ndarray = 0.003, n_quad: int = 4000
) -> float | np.ndarray:
    """Equivalent conicity tan(gamma_e) for a lateral oscillation of the given amplitude.

    EN 15302 linear-regression method: the Delta-r(y) function is linearised as
    Delta-r ~ 2 tan(gamma_e) y by a least-squares fit weighted with the displacement
    density of a sinusoidal motion y = A sin(t) (the regression is done over t, so the
    two-point jumps of Delta-r are integrated, not interpolated across):

        tan(gamma_e)(A) = <Delta-r(A sin t) sin t> / A    (mean over one period)

    This is also the harmonic linearisation (describing function) of Delta-r: the first
    Fourier coefficient b1 = 2 <Delta-r(A sin t) sin t> of Delta-r along y = A sin t, set equal to
    2 tan(gamma_e) A. The two methods are the same formula.

    Parameters
    ----------
    table : GeometryTable
        Computed at zero yaw, covering [-A, A] (status ok there).
    amplitude : float or ndarray
        Amplitude(s) A of the wheelset's lateral motion, m (EN 15302 quotes A = 3 mm).
    n_quad : int
        Quadrature points over one period.

    Returns
    -------
    float or ndarray
        tan(gamma_e), dimensionless.
    """
    amp = np.atleast_1d(np.asarray(amplitude, dtype=float))
    _checks.finite_array("amplitude", amp)
    if np.any(amp <= 0):
        raise InputError("amplitude must be > 0")
    if np.any(np.abs(table.yaw) > 0):
        raise InputError("equivalent conicity needs a geometry table at zero yaw")
    ok = table.ok & np.isfinite(table.delta_r)
    out = conicity_of_delta_r(table.y[ok], table.delta_r[ok], amp, n_quad)
    return float(out[0]) if np.ndim(amplitude) == 0 else out


def conicity_of_delta_r(
    y: np.ndarray, delta_r: np.ndarray, amplitude: float | np.ndarray = 0.003, n_quad: int = 4000
) -> float | np.ndarray:
    """Equivalent conicity from a tabulated rolling-radius difference (the formula of
    :func:`equivalent_conicity`), e.g. a measured Delta-r function or EN 15302's reference
    ones.

    Parameters
    ----------
    y, delta_r : ndarray
        Lateral displacements and the rolling-radius difference there, in one unit (m, or
        mm as the standard tabulates them), any order.
    amplitude : float or ndarray
        Amplitude(s), in the unit of y (> 0, inside the table).
    n_quad : int
        Quadrature points over one period.
    """
    amp = np.atleast_1d(np.asarray(amplitude, dtype=float))
    _checks.finite_array("amplitude", amp)
    if np.any(amp <= 0):
        raise InputError("amplitude must be > 0")
    y = np.asarray(_checks.finite_array("y", y), dtype=float)
    dr = np.asarray(_checks.finite_array("delta_r", delta_r), dtype=float)
    if y.shape != dr.shape or y.ndim != 1:
        raise InputError(f"y {y.shape} and delta_r {dr.shape} must be 1-D arrays of one length")
    order = np.argsort(y)
    y, dr = y[order], dr[order]
    if y.size < 3 or amp.max() > min(-y[0], y[-1]) + 1e-12:
        lo, hi = (y[0], y[-1]) if y.size else (np.nan, np.nan)
        raise InputError(f"the table (y in [{lo:.3g}, {hi:.3g}]) does not cover +-{amp.max():.3g}")
    t = (np.arange(_checks.positive_int("n_quad", n_quad, 16)) + 0.5) * (2 * np.pi / n_quad)
    st = np.sin(t)
    out = np.array([np.mean(np.interp(A * st, y, dr) * st) / A for A in amp])
    return float(out[0]) if np.ndim(amplitude) == 0 else out


def klingel_wavelength(
    conicity: float | np.ndarray, radius: float = 0.46, half_distance: float = 0.75
) -> float | np.ndarray:
    """Klingel's kinematic wavelength 2 pi sqrt(r0 e0 / tan(gamma_e)), m.

    Parameters
    ----------
    conicity : float or ndarray
        tan(gamma_e) (> 0).
    radius : float
        Nominal rolling radius r0, m.
    half_distance : float
        Half the lateral distance between the contact points e0, m.
    """
    c = np.asarray(conicity, dtype=float)
    if np.any(~np.isfinite(c)) or np.any(c <= 0):
        raise InputError("conicity must be finite and > 0")
    r0 = _checks.positive("radius", radius)
    e0 = _checks.positive("half_distance", half_distance)
    lam = 2 * np.pi * np.sqrt(r0 * e0 / c)
    return float(lam) if lam.ndim == 0 else lam
