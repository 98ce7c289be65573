"""Influence coefficients of the half-space and their discrete convolution."""

from __future__ import annotations

import numpy as np

from .. import _checks
from .._native import core
from .._status import Status, error
from ..errors import InputError, RailvtiError
from ..material import Material
from .grid import Grid

#: Kernel names -> codes of the Fortran module contact_influence.
KERNELS = {"zz": 1, "xx": 2, "yy": 3, "xy": 4}


def _kernel_code(kernel: str) -> int:
    try:
        return KERNELS[kernel]
    except KeyError:
        raise InputError(f"kernel must be one of {sorted(KERNELS)}, got {kernel!r}") from None


def influence_field(grid: Grid, material: Material, kernel: str = "zz") -> np.ndarray:
    """Influence coefficients for every offset of the grid, m/Pa.

    Entry ``[k, l]`` is the displacement difference at offset
    ``(k dx, l dy)`` (k, l taken modulo ``2 nx``, ``2 ny``: negative offsets
    wrap around) due to a unit traction on one element, i.e. the circular
    layout of the zero-padded FFT convolution.

    Parameters
    ----------
    grid : Grid
    material : Material
    kernel : {'zz', 'xx', 'yy', 'xy'}
        'zz' Boussinesq (normal), 'xx', 'yy', 'xy' Cerruti (tangential).

    Returns
    -------
    ndarray, shape (2 nx, 2 ny)
    """
    code = _kernel_code(kernel)
    c, info = core.influence_field_c(
        code, grid.nx, grid.ny, grid.dx, grid.dy, material.shear_modulus, material.poisson
    )
    if info != Status.OK:
        raise error(info, "influence_field_c failed", exc=RailvtiError)
    return c


def convolve(
    traction: np.ndarray, grid: Grid, material: Material, kernel: str = "zz", method: str = "fft"
) -> np.ndarray:
    """Surface displacement difference due to a traction field, m.

    Parameters
    ----------
    traction : ndarray, shape (nx, ny)
        Traction on each element, Pa.
    grid, material : Grid, Material
    kernel : {'zz', 'xx', 'yy', 'xy'}
    method : {'fft', 'direct'}
        Zero-padded FFT, O(N log N), or direct summation, O(N^2).

    Returns
    -------
    ndarray, shape (nx, ny)
    """
    q = _checks.finite_array("traction", traction, shape=grid.shape)
    if method not in ("fft", "direct"):
        raise InputError(f"method must be 'fft' or 'direct', got {method!r}")
    u, info = core.convolve_c(
        _kernel_code(kernel),
        1 if method == "fft" else 2,
        grid.dx,
        grid.dy,
        material.shear_modulus,
        material.poisson,
        q,
    )
    if info != Status.OK:
        raise error(info, "convolve_c failed", exc=RailvtiError)
    return u


_FIELD_METHODS = {"fft": 1, "direct": 2, "fft_plain": 3}


def convolve_field(
    coefficients: np.ndarray, values: np.ndarray, method: str = "fft"
) -> tuple[np.ndarray, bool]:
    """Discrete linear convolution of a grid field with a coefficient field.

    ``u[i, j] = sum_kl coefficients[(i - k) mod 2 nx, (j - l) mod 2 ny] values[k, l]``,
    the product that the contact solvers make with influence coefficients
    (:func:`influence_field`'s circular layout, or any other field).

    Parameters
    ----------
    coefficients : ndarray, shape (2 nx, 2 ny)
        Coefficients in circular layout (units of u per unit of values).
    values : ndarray, shape (nx, ny)
        The field convolved, e.g. a traction, Pa.
    method : {'fft', 'fft_plain', 'direct'}
        'fft' the solvers' zero-padded FFT product, its transforms pruned to the
        padding; 'fft_plain' the unpruned zero-padded FFT product (one 2-D r2c
        transform, the spectral product, one c2r); 'direct' summation, O(N^2).

    Returns
    -------
    u : ndarray, shape (nx, ny)
    real_spectrum : bool
        Whether the pruned product multiplied by a real spectrum (coefficients even, or
        odd, in both directions); False for the other methods.
    """
    q = _checks.finite_array("values", values, ndim=2)
    c = _checks.finite_array("coefficients", coefficients, shape=(2 * q.shape[0], 2 * q.shape[1]))
    if method not in _FIELD_METHODS:
        raise InputError(f"method must be one of {sorted(_FIELD_METHODS)}, got {method!r}")
    u, real_spec, info = core.convolve_field_c(_FIELD_METHODS[method], 1, c, q)
    if info != Status.OK:
        raise error(info, "convolve_field_c failed", exc=RailvtiError)
    return u, bool(real_spec)


__all__ = ["KERNELS", "influence_field", "convolve", "convolve_field"]
