"""Cache of Fortran contact workspaces (coefficients, FFT spectra, FFTW plans).

A workspace is made once per grid and material and reused by every solve on
that grid, so repeated solves (sweeps, time steps) pay the set-up once.
"""

from __future__ import annotations

import atexit
import threading
import time
from collections import OrderedDict

import numpy as np

from .._native import core
from .._status import Status, error
from ..errors import InputError, RailvtiError
from ..material import Material
from .grid import Grid

_CACHE_SIZE = 16
_cache: "OrderedDict[tuple, int]" = OrderedDict()


#: Workspaces a Fortran call still uses in a worker thread (:func:`call_interruptibly`).
_busy: set[int] = set()

#: Seconds between the main thread's checks for signals while a worker thread computes.
POLL_SECONDS = 0.05


#: Workspaces made here and not yet freed: only these may be freed.
_live: set[int] = set()


def _free(handle: int) -> None:
    """Free a workspace this module made (InputError for any other handle: the core would
    ignore it, and a wrong handle is a bug to name, not to pass over)."""
    if isinstance(handle, bool) or not isinstance(handle, (int, np.integer)) or int(handle) not in _live:
        raise InputError(
            f"contact workspace handle {handle!r} is not a live workspace (never made, "
            "or already freed); live: " + (", ".join(map(str, sorted(_live))) or "none")
        )
    if handle in _busy:  # an interrupted call still runs on it: leave it (freed at exit)
        return
    _live.discard(int(handle))
    core.contact_ws_free_c(handle)


def call_interruptibly(handle: int, fn, *args):
    """``fn(handle, *args)``, an f2py routine that releases the GIL (``!f2py threadsafe``)
    and works on the workspace ``handle``, run in a worker thread while the main thread
    waits in steps of :data:`POLL_SECONDS`: Ctrl-C / SIGTERM then raise in the main thread
    within that, however long the call. The interrupted call runs on to its end in the
    background (its workspace kept busy: a later call on it waits, and it is not freed);
    a Fortran call cannot be stopped from outside. Used for the calls that cannot run in
    resumable slices (the steady rolling solver: its Anderson history and patch set-up)."""
    while handle in _busy:  # a call interrupted earlier still runs on this workspace
        time.sleep(POLL_SECONDS)
    box: dict = {}
    done = threading.Event()

    def work() -> None:
        try:
            box["out"] = fn(handle, *args)
        except BaseException as exc:  # noqa: BLE001 - re-raised in the caller's thread
            box["exc"] = exc
        finally:
            _busy.discard(handle)
            done.set()

    _busy.add(handle)
    threading.Thread(target=work, name="railvti-fortran", daemon=True).start()
    while not done.wait(POLL_SECONDS):
        pass
    if "exc" in box:
        raise box["exc"]
    return box["out"]


def call_directly(handle: int, fn, *args):
    """``fn(handle, *args)`` in the calling thread, once no interrupted call still runs on
    the workspace ``handle`` (the signature of :func:`call_interruptibly`): for calls short
    enough that Ctrl-C may wait for their end."""
    while handle in _busy:
        time.sleep(POLL_SECONDS)
    return fn(handle, *args)


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
    handle, info = core.contact_ws_create_c(
        grid.nx, grid.ny, grid.dx, grid.dy, material.shear_modulus, material.poisson, int(tangential)
    )
    if info != Status.OK:
        raise error(info, "could not make a contact workspace", exc=RailvtiError)
    _cache[key] = handle
    _live.add(int(handle))
    return handle


def clear() -> None:
    """Free every cached workspace."""
    while _cache:
        _free(_cache.popitem()[1])


atexit.register(clear)

__all__ = ["POLL_SECONDS", "call_interruptibly", "call_directly", "workspace", "clear"]
