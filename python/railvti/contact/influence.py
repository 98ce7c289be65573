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


__all__ = ["KERNELS", "influence_field", "convolve"]
