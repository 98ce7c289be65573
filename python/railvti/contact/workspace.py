"""Cache of Fortran contact workspaces (coefficients, FFT spectra, FFTW plans).

A workspace is made once per grid and material and reused by every solve on
that grid, so repeated solves (sweeps, time steps) pay the set-up once.
"""
from __future__ import annotations

import atexit
from collections import OrderedDict

from .._native import core
from .._status import Status, error
from ..errors import RailvtiError
from ..material import Material
from .grid import Grid

_CACHE_SIZE = 16
_cache: "OrderedDict[tuple, int]" = OrderedDict()


def _free(handle: int) -> None:
    core.contact_ws_free_c(handle)


def workspace(grid: Grid, material: Material, tangential: bool = False) -> int:
    """Handle of the workspace of ``grid`` and ``material`` (made if needed).

    Parameters
    ----------
    grid : Grid
    material : Material
    tangential : bool
        Also hold the Cerruti kernels (rolling contact).
    """
    key = (grid.nx, grid.ny, grid.dx, grid.dy, material.shear_modulus, material.poisson, tangential)
    handle = _cache.get(key)
    if handle is None and not tangential:
        # a tangential workspace serves normal solves too
        handle = _cache.get(key[:-1] + (True,))
    if handle is not None:
        _cache.move_to_end(key if key in _cache else key[:-1] + (True,))
        return handle
    while len(_cache) >= _CACHE_SIZE:
        _free(_cache.popitem(last=False)[1])
    handle, info = core.contact_ws_create_c(grid.nx, grid.ny, grid.dx, grid.dy, material.shear_modulus,
                                            material.poisson, int(tangential))
    if info != Status.OK:
        raise error(info, "could not make a contact workspace", exc=RailvtiError)
    _cache[key] = handle
    return handle


def clear() -> None:
    """Free every cached workspace."""
    while _cache:
        _free(_cache.popitem()[1])


atexit.register(clear)
