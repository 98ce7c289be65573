"""Creep-force tables: many steady rolling cases on one grid in one Fortran call.

A vehicle code's contact table (or a study over creepages) solves the same small
problem many times: the normal problem, then steady rolling, for a list of creepages
and geometries. :func:`solve_rolling` per case spends more time in Python than in the
solvers on an 11 x 11 grid; :func:`creep_force_table` hands the whole table to the
Fortran (``fortran/contact/contact_creep_table.f90``), which runs each case as
:func:`solve_rolling` does (the normal problem, then the steady rolling solver from zero
traction, method 'fftgs') and returns the forces. On small grids (the 11 x 11 case) the
normal problem is solved exactly by an active set on the dense influence matrix
(``contact_normal_dense.f90``), elsewhere by projected CG from zero pressure as
:func:`solve_rolling` does.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError, RailvtiError
from ..material import Material
from .grid import Grid
from .workspace import call_directly, call_interruptibly, workspace

log = logging.getLogger(__name__)

#: Slices of a table of at most this many element sweeps (cases x nx ny x max_iter, the worst
#: case) call the Fortran in the calling thread, one after the other, Ctrl-C acting between
#: them; a case of more work runs in a worker thread that Ctrl-C can leave (as
#: :data:`railvti.contact.rolling.DIRECT_CALL_WORK`; the thread costs 0.1 ms of CPU per call).
DIRECT_CALL_WORK = 2_500_000


@dataclass(frozen=True)
class CreepForceTable:
    """Creep forces of a table of steady rolling cases on one grid.

    Attributes (arrays over the cases, in the order given)
    ------------------------------------------------------
    grid : Grid
    creepage : ndarray, shape (ncase, 3)
        (xi, eta, phi): longitudinal, lateral (1) and spin (1/m) creepage.
    fn : ndarray, shape (ncase,)
        Normal force, N.
    mu : float
        Coefficient of friction.
    speed : float
        Rolling speed, m/s.
    fx, fy : ndarray, shape (ncase,)
        Creep forces on the wheel, N (as :attr:`RollingResult.fx`, ``fy``).
    mz : ndarray, shape (ncase,)
        Spin moment about the grid's z axis through x = y = 0, N m.
    power : ndarray, shape (ncase,)
        Frictional power, W.
    n_contact : ndarray of int, shape (ncase,)
        Elements in contact.
    approach : ndarray, shape (ncase,)
        Approach of the bodies, m.
    normal_iterations : ndarray of int, shape (ncase,)
        Iterations of the case's normal solve (shared by the cases that reuse it): trial
        contact sets of the active set on small grids, else CG iterations.
    iterations : ndarray of int, shape (ncase,)
        Sweeps of the rolling solver, plus its Newton steps (as ``RollingResult.iterations``).
    normal_solves : int
        Normal problems solved (one per run of consecutive cases with the same gap and
        normal force).
    """

    grid: Grid
    creepage: np.ndarray
    fn: np.ndarray
    mu: float
    speed: float
    fx: np.ndarray
    fy: np.ndarray
    mz: np.ndarray
    power: np.ndarray
    n_contact: np.ndarray
    approach: np.ndarray
    normal_iterations: np.ndarray
    iterations: np.ndarray
    normal_solves: int

    def __len__(self) -> int:
        return len(self.fx)


def _gap_stack(gap: object, grid: Grid, ncase: int) -> tuple[np.ndarray, np.ndarray]:
    """The gaps as a Fortran (nx, ny, ngap) stack and each case's index into it (1-based)."""
    g = np.asarray(gap, dtype=np.float64)
    if g.shape == grid.shape:
        stack = _checks.finite_array("gap", g, shape=grid.shape)[:, :, None]
        kgap = np.ones(ncase, dtype=np.int32)
    elif g.shape == (ncase,) + grid.shape:
        if not np.isfinite(g).all():
            raise InputError("gap must be finite everywhere")
        stack = np.moveaxis(g, 0, -1)
        kgap = np.arange(1, ncase + 1, dtype=np.int32)
    else:
        raise InputError(
            f"gap must have shape {grid.shape} (one for all cases) or "
            f"{(ncase,) + grid.shape} (one per case), got {g.shape}"
        )
    return np.asfortranarray(stack), kgap


def _raise_for_case(k: int, nfo_n: int, nfo_t: int, iters_n: int, iters_t: int) -> None:
    """The error of the failed case k from its statuses and iterations (its normal solve's,
    else its rolling solve's)."""
    if nfo_n == Status.GRID_EDGE:
        raise GridTooSmallError(
            f"case {k}: the contact area reaches the grid edge (or the last two "
            "element rows at x = x_max, which the slip needs): enlarge the grid"
        )
    if nfo_n != Status.OK:
        raise ConvergenceError(
            f"case {k}: the normal contact solver failed "
            f"({Status(int(nfo_n)).name}) after {iters_n} iterations",
            iterations=int(iters_n),
        )
    if nfo_t == Status.GRID_EDGE:
        raise GridTooSmallError(
            f"case {k}: the contact area reaches the last two element rows at the "
            "leading grid edge x = x_max (the slip needs two elements upstream)"
        )
    raise ConvergenceError(
        f"case {k}: the rolling contact solver failed ({Status(int(nfo_t)).name}) after {iters_t} sweeps",
        iterations=int(iters_t),
    )


def _solve_in_slices(
    grid: Grid,
    material: Material,
    stack: np.ndarray,
    kgap: np.ndarray,
    fns: np.ndarray,
    creep: np.ndarray,
    starts: np.ndarray,
    params: tuple,
) -> tuple[np.ndarray, ...]:
    """The table's Fortran calls: slices of at most DIRECT_CALL_WORK element sweeps (cases x nx ny
    x max_iter, the worst case) in the calling thread, Ctrl-C acting between them (a worker
    thread costs 0.1 ms of CPU per call, more than an 11 x 11 case), each slice continuing
    the previous one's normal solution (the same normal solves as one call); a case of more
    work alone in a worker thread that Ctrl-C can leave. The outputs per case, in order; the
    first failed case raises (its slice's successors are not solved)."""
    mu, speed, normal_tol, tol, normal_max_iter, max_iter = params
    ncase = len(kgap)
    per_case = grid.nx * grid.ny * max_iter
    call = call_interruptibly if per_case > DIRECT_CALL_WORK else call_directly
    step = ncase if per_case > DIRECT_CALL_WORK else max(1, DIRECT_CALL_WORK // per_case)
    handle = workspace(grid, material, tangential=True)
    pstate = np.zeros(grid.shape, order="F")
    rstate = np.zeros(1)
    istate = np.zeros(1, dtype=np.int32)
    creep_t = np.asfortranarray(creep.T)
    parts = []
    for a in range(0, ncase, step):
        b = min(a + step, ncase)
        *out, nfo_n, nfo_t, info = call(
            handle,
            core.creep_force_table_c,
            stack,
            kgap[a:b],
            np.ascontiguousarray(fns[a:b]),
            np.asfortranarray(creep_t[:, a:b]),
            mu,
            speed,
            grid.x0,
            grid.y0,
            normal_tol,
            tol,
            normal_max_iter,
            max_iter,
            int(a > 0 and not starts[a]),
            pstate,
            rstate,
            istate,
        )
        if info != Status.OK:
            raise error(info, "creep-force table failed internally", exc=RailvtiError)
        # the slice's statuses checked at once (a loop over IntEnum members costs more than
        # an 11 x 11 case); the first failed case is named as a loop over the cases would
        failed = np.flatnonzero((nfo_n != Status.OK) | (nfo_t != Status.OK))
        if failed.size:
            k = int(failed[0])
            _raise_for_case(a + k, nfo_n[k], nfo_t[k], out[6][k], out[7][k])
        parts.append(out)
    return tuple(col[0] if len(col) == 1 else np.concatenate(col) for col in zip(*parts))


def creep_force_table(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    mu: float,
    fn: float | np.ndarray,
    creepages: np.ndarray,
    speed: float,
    tol: float = 1e-7,
    normal_tol: float = 1e-8,
    max_iter: int = 2000,
    normal_max_iter: int = 2000,
) -> CreepForceTable:
    """Steady rolling creep forces of a table of cases on one grid, in one Fortran call.

    Each case is the one :func:`~railvti.contact.solve_rolling` solves with its default
    methods (the pressure, then the steady rolling solver 'fftgs' from zero traction), and
    gives the same forces to the normal solver's tolerance: on small grids (where its
    operation count wins, e.g. 11 x 11) the pressure is the exact solution of an active set
    on the dense influence matrix, where solve_rolling's projected CG stops at its tolerance
    (forces within 2e-8 of the largest on the 11 x 11 benchmark); elsewhere both run CG from
    zero (the same forces to rounding on grids below 128 x 128). The normal problem is solved
    once for each run of consecutive cases with the same gap and normal force: the pressure
    of quasi-identical bodies does not depend on the creepages. The table runs in slices
    (Ctrl-C acts between them) with the same results as one call.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny) or (ncase, nx, ny)
        Undeformed gap, m: one for all cases, or one per case.
    grid : Grid
        The potential contact area; x is the rolling direction.
    material : Material
        The bodies' common material.
    mu : float
        Coefficient of friction (>= 0).
    fn : float or ndarray, shape (ncase,)
        Normal force, N (> 0), one for all cases or one per case.
    creepages : ndarray, shape (ncase, 3)
        (xi, eta, phi) per case: longitudinal, lateral creepage (1) and spin (1/m).
    speed : float
        Rolling speed, m/s (> 0).
    tol, max_iter
        Residual and sweep limit of the rolling solver (as :func:`solve_rolling`).
    normal_tol, normal_max_iter
        Residual and iteration limit of the normal solver.

    Returns
    -------
    CreepForceTable

    Raises
    ------
    InputError
        Bad arguments (named in the message).
    GridTooSmallError
        A case's contact area reaches the grid's edge (the case is named).
    ConvergenceError
        A case's normal or rolling solver did not converge (the case is named).
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    creep = np.asarray(creepages, dtype=np.float64)
    if creep.ndim != 2 or creep.shape[1] != 3 or creep.shape[0] < 1:
        raise InputError(f"creepages must have shape (ncase, 3), got {creep.shape}")
    if not np.isfinite(creep).all():
        raise InputError("creepages must be finite")
    ncase = creep.shape[0]
    fns = (
        np.broadcast_to(np.asarray(fn, dtype=np.float64), (ncase,))
        if np.ndim(fn) == 0
        else np.asarray(fn, dtype=np.float64)
    )
    if fns.shape != (ncase,):
        raise InputError(f"fn must be a number or have shape ({ncase},), got {fns.shape}")
    if not (np.isfinite(fns).all() and (fns > 0.0).all()):
        raise InputError("fn must be finite and > 0")
    mu = _checks.non_negative("mu", mu)
    speed = _checks.positive("speed", speed)
    tol = _checks.positive("tol", tol)
    normal_tol = _checks.positive("normal_tol", normal_tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    normal_max_iter = _checks.positive_int("normal_max_iter", normal_max_iter)
    stack, kgap = _gap_stack(gap, grid, ncase)

    starts = np.ones(ncase, dtype=bool)
    starts[1:] = (kgap[1:] != kgap[:-1]) | (fns[1:] != fns[:-1])
    params = (mu, speed, normal_tol, tol, normal_max_iter, max_iter)
    fx, fy, mz, power, ncontact, approach, iters_n, iters_t = _solve_in_slices(
        grid, material, stack, kgap, fns, creep, starts, params
    )
    if log.isEnabledFor(logging.DEBUG):
        log.debug(
            "creep_force_table: %d cases, %d normal solves, %.1f sweeps on average",
            ncase,
            int(starts.sum()),
            float(iters_t.mean()),
        )
    return CreepForceTable(
        grid=grid,
        creepage=creep.copy(),
        fn=np.array(fns),
        mu=mu,
        speed=speed,
        fx=fx,
        fy=fy,
        mz=mz,
        power=power,
        n_contact=ncontact.astype(int),
        approach=approach,
        normal_iterations=iters_n.astype(int),
        iterations=iters_t.astype(int),
        normal_solves=int(starts.sum()),
    )


__all__ = ["DIRECT_CALL_WORK", "CreepForceTable", "creep_force_table"]
