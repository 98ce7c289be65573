"""Transient and shift tangential contact on the boundary-element grid (Kalker's transient
theory; ``fortran/contact/contact_transient.f90``).

Over one time step dt the slip (a distance, m) of the particle at element I is

    S_I = W_I dt + u_I(t) - u'_I(t - dt),

the rigid slip plus the change of the displacement difference u = A t of that particle
(Kalker 1990, sect. 5.2). In a shift problem (no rolling, ``speed = 0``) u' is the previous
step's field at the same element. In rolling at the speed V particles move through the
fixed patch in -x: with ``V dt = k dx``, k a whole number of elements (no interpolation),
u'(i, j) = u_(t - dt)(i + k, j). With ``theta`` > 0 the second-order form
``S = W dt + (1 + theta) u - (1 + 2 theta) u' + theta u''`` is used; ``theta = 1/3`` with
k = 1 is the steady solver's three-point stencil (:func:`~railvti.contact.solve_rolling`),
whose steady state the transient then approaches to the solver tolerance.

Per element in contact, Coulomb's law: adhesion ``S = 0, |t| <= mu p``, or slip
``t = -mu p S / |S|``. For quasi-identical bodies the step is the convex problem
``min 1/2 (1 + theta) t.A t + t.s0`` over the Coulomb discs, solved by accelerated projected
gradients with FFT products. Conventions as in :mod:`railvti.contact.rolling`: tractions
act on the upper body; a rigid shift q along +x gives a force Fx < 0 (Fx = -K q).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError, RailvtiError
from ..material import Material
from .grid import Grid
from .normal import solve_normal
from .workspace import call_interruptibly, workspace

log = logging.getLogger(__name__)

STATUS_EXTERIOR, STATUS_ADHESION, STATUS_SLIP = 0, 1, 2
_SHIFT_GIVEN, _FORCE_GIVEN = 0, 1
#: Iteration limit of one tangential step (accelerated projected gradients).
DEFAULT_MAX_ITER = 20000
#: Relative tolerance of a whole number of elements in ``speed * dt / dx``.
_WHOLE = 1e-6


@dataclass(frozen=True)
class StepResult:
    """One tangential step (:func:`solve_step`).

    Attributes
    ----------
    tx, ty : ndarray, shape (nx, ny)
        Tractions on the upper body, Pa.
    ux, uy : ndarray, shape (nx, ny)
        Displacement difference ``u = A t`` on the whole grid, m (the next step's history).
    status : ndarray of int8, shape (nx, ny)
        0 exterior, 1 adhesion, 2 slip.
    slip_x, slip_y : ndarray, shape (nx, ny)
        Slip S over the step, m (0 in adhesion and outside contact).
    iterations : int
    residual : float
        Relative change of a Jacobi step on the exact field (0 at the solution).
    """

    tx: np.ndarray
    ty: np.ndarray
    ux: np.ndarray
    uy: np.ndarray
    status: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    iterations: int
    residual: float


def solve_step(
    grid: Grid,
    material: Material,
    bound: np.ndarray,
    s0: tuple[np.ndarray, np.ndarray],
    incontact: np.ndarray | None = None,
    weight: float = 1.0,
    t0: tuple[np.ndarray, np.ndarray] | None = None,
    tol: float = 1e-7,
    max_iter: int = DEFAULT_MAX_ITER,
) -> StepResult:
    """One tangential step: the tractions with ``S = s0 + weight A t`` obeying Coulomb's law.

    The kernel of every transient and shift problem, for callers that form their own rigid
    slip (e.g. with an extra normal-tangential coupling field) or bound (another friction law).

    Parameters
    ----------
    grid, material : Grid, Material
    bound : ndarray, shape (nx, ny)
        Traction bound g per element, Pa (>= 0; mu p for Coulomb friction).
    s0 : (ndarray, ndarray), each (nx, ny)
        Slip of zero traction over the step, m: rigid slip minus the history.
    incontact : ndarray of bool, shape (nx, ny), optional
        Elements in contact (default ``bound > 0``).
    weight : float
        Weight of ``u(t)`` in S (1 + theta), > 0.
    t0 : (tx, ty), optional
        Warm start, Pa.
    tol, max_iter
        Relative residual at which to stop; iteration limit.

    Returns
    -------
    StepResult

    Raises
    ------
    InputError
        Bad arguments (named).
    ConvergenceError
        Not converged in max_iter iterations (the last iterate attached as ``.result``).
    """
    g = _checks.finite_array("bound", bound, shape=grid.shape)
    if g.min() < 0.0:
        raise InputError("bound must be >= 0 everywhere (Pa)")
    sx = _checks.finite_array("s0[0]", s0[0], shape=grid.shape)
    sy = _checks.finite_array("s0[1]", s0[1], shape=grid.shape)
    inc = g > 0.0 if incontact is None else np.asarray(incontact, dtype=bool)
    if inc.shape != grid.shape:
        raise InputError(f"incontact must have the grid's shape {grid.shape}, got {inc.shape}")
    weight = _checks.positive("weight", weight)
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    tx, ty = _start(grid, t0)
    ux, uy, status, slx, sly, iters, resid, info = call_interruptibly(
        workspace(grid, material, tangential=True),
        core.transient_step_c,
        np.asfortranarray(inc, dtype=np.int32),
        g,
        sx,
        sy,
        weight,
        tol,
        max_iter,
        tx,
        ty,
    )
    if info not in (Status.OK, Status.NOT_CONVERGED, Status.NO_CONTACT):
        raise error(info, "transient tangential step failed")
    result = StepResult(tx, ty, ux, uy, np.asarray(status, dtype=np.int8), slx, sly, int(iters), float(resid))
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"transient tangential step did not converge: residual {resid:.3g} > tol {tol:.3g}",
            iterations=int(iters),
            residual=float(resid),
            result=result,
        )
    return result


def _start(grid: Grid, t0: tuple | None) -> tuple[np.ndarray, np.ndarray]:
    if t0 is None:
        return np.zeros(grid.shape, order="F"), np.zeros(grid.shape, order="F")
    if len(t0) != 2:
        raise InputError("t0 must be a pair (tx, ty) of (nx, ny) arrays")
    return (
        np.array(_checks.finite_array("t0[0]", t0[0], shape=grid.shape), order="F"),
        np.array(_checks.finite_array("t0[1]", t0[1], shape=grid.shape), order="F"),
    )


@dataclass(frozen=True)
class Snapshot:
    """The fields of one stored step.

    Attributes
    ----------
    step : int
        Step index (0-based).
    time : float
        End of the step, s.
    pressure, tx, ty : ndarray, shape (nx, ny)
        Pa.
    status : ndarray of int8, shape (nx, ny)
        0 exterior, 1 adhesion, 2 slip.
    slip_x, slip_y : ndarray, shape (nx, ny)
        Slip over the step, m.
    """

    step: int
    time: float
    pressure: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    status: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray

    @property
    def adhesion(self) -> np.ndarray:
        """Boolean mask of the elements in adhesion."""
        return self.status == STATUS_ADHESION

    @property
    def slip(self) -> np.ndarray:
        """Boolean mask of the elements in slip."""
        return self.status == STATUS_SLIP


@dataclass(frozen=True)
class TransientResult:
    """A transient or shift march (:func:`solve_transient`).

    Attributes
    ----------
    grid : Grid
    mu : float
    speed : float
        Rolling speed, m/s (0: shift problem).
    dt : float
        Time step, s.
    elements_per_step : int
        k = speed dt / dx (0 for a shift problem).
    theta : float
        Weight of the second-order slip (0: Kalker's first-order form).
    time, distance : ndarray, shape (nt,)
        End of each step, s; distance rolled, m.
    fn, fx, fy : ndarray, shape (nt,)
        Normal and tangential forces per step, N.
    shift : ndarray, shape (nt, 2)
        Rigid shift increment of each step (given or found under force control), m.
    n_contact, n_slip, iterations : ndarray of int, shape (nt,)
    residual : ndarray, shape (nt,)
    snapshots : tuple of Snapshot
        The stored steps (by default the last).
    converged : bool
        Every step converged.
    """

    grid: Grid
    mu: float
    speed: float
    dt: float
    elements_per_step: int
    theta: float
    time: np.ndarray
    distance: np.ndarray
    fn: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    shift: np.ndarray
    n_contact: np.ndarray
    n_slip: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    snapshots: tuple[Snapshot, ...]
    converged: bool

    @property
    def shift_total(self) -> np.ndarray:
        """Cumulative rigid shift after each step, m, shape (nt, 2)."""
        return np.cumsum(self.shift, axis=0)

    @property
    def last(self) -> Snapshot:
        """The last stored snapshot."""
        return self.snapshots[-1]

    def distance_to_fraction(self, fraction: float = 0.99, reference: float | None = None) -> float:
        """Rolled distance (m) after which |Fx| stays at or above ``fraction`` of
        ``|reference|`` (default the last step's Fx); nan if it never does."""
        ref = abs(self.fx[-1] if reference is None else reference)
        below = np.nonzero(np.abs(self.fx) < fraction * ref)[0]
        if below.size == 0:
            return float(self.distance[0])
        if below[-1] + 1 >= self.fx.size:
            return math.nan
        return float(self.distance[below[-1] + 1])


def _per_step(name: str, value, nt: int, width: int) -> np.ndarray:
    """``value`` as an (nt, width) array: one row repeated, or one row per step."""
    arr = np.asarray(_checks.finite_array(name, value), dtype=float)
    if arr.ndim == 1 and arr.shape == (width,) and width > 1:
        arr = np.broadcast_to(arr, (nt, width))
    elif arr.ndim == 0 and width == 1:
        arr = np.full((nt, 1), float(arr))
    elif arr.ndim == 1 and width == 1 and arr.shape == (nt,):
        arr = arr[:, None]
    if arr.shape != (nt, width):
        raise InputError(
            f"{name} must be {'a number' if width == 1 else f'{width} numbers'} or one per step, "
            f"shape ({nt}, {width}); got {arr.shape}"
        )
    return np.array(arr, dtype=float)


def _check_step(grid: Grid, pressure: np.ndarray, speed: float, dt: float, theta: float) -> int:
    """Elements per step k = speed dt / dx, checked against the patch and the grid (the
    largest pressure's patch): InputError naming 'dt' (or 'theta')."""
    if speed == 0.0:
        if theta != 0.0:
            raise InputError(
                f"theta = {theta} applies to rolling only: a shift problem (speed = 0) needs theta = 0"
            )
        return 0
    k_real = speed * dt / grid.dx
    k = int(round(k_real))
    if k < 1 or abs(k_real - k) > _WHOLE * max(k_real, 1.0):
        raise InputError(
            f"dt: speed * dt = {speed * dt:.6g} m must be a whole number (>= 1) of elements "
            f"dx = {grid.dx:.6g} m "
            f"(it is {k_real:.6g}); no interpolation of the history: take dt = k dx / speed"
        )
    rows = np.nonzero((pressure > 0.0).any(axis=1))[0]
    length = (rows[-1] - rows[0] + 1) * grid.dx
    if speed * dt >= length:
        raise InputError(
            f"dt: the step speed * dt = {speed * dt:.6g} m skips the contact patch "
            f"(length {length:.6g} m along x): "
            "a particle must spend at least one step in the patch"
        )
    reach = k * (2 if theta > 0.0 else 1)
    if rows[-1] + reach > grid.nx - 1:
        raise InputError(
            f"dt: the history reaches {reach} element(s) upstream of the patch (speed * dt = {k} dx"
            f"{', two steps back for theta > 0' if theta > 0 else ''}), beyond the grid's leading edge "
            "x = x_max "
            f"({grid.nx - 1 - rows[-1]} element(s) free there): shorten dt or extend the grid in +x"
        )
    return k


def solve_transient(
    grid: Grid,
    material: Material,
    mu: float,
    fn,
    steps: int,
    dt: float,
    *,
    gap: np.ndarray | None = None,
    pressure: np.ndarray | None = None,
    speed: float = 0.0,
    creepage=(0.0, 0.0, 0.0),
    shift=None,
    force=None,
    theta: float = 0.0,
    keep=None,
    tol: float = 1e-7,
    max_iter: int = DEFAULT_MAX_ITER,
    normal_tol: float = 1e-9,
    normal_max_iter: int = 2000,
) -> TransientResult:
    """A march of transient (rolling) or shift steps, the normal problem per step.

    Parameters
    ----------
    grid, material : Grid, Material
    mu : float
        Coulomb friction coefficient (> 0).
    fn : float or array of shape (steps,)
        Normal force per step, N (> 0); the normal problem is re-solved when it changes.
    steps : int
        Number of time steps nt.
    dt : float
        Time step, s (> 0). In rolling ``speed * dt`` must be a whole number of elements
        dx, shorter than the contact patch.
    gap : ndarray, shape (nx, ny), optional
        Undeformed gap, m (the normal problem solved per step). Or give ``pressure``.
    pressure : ndarray, shape (nx, ny), optional
        A pressure shape, Pa, scaled to fn at each step (no normal solve).
    speed : float
        Rolling speed V, m/s (0: a shift problem).
    creepage : (xi, eta, phi) or array of shape (steps, 3)
        Creepages (1, 1, 1/m): rigid slip ``V dt (xi - phi y, eta + phi x)`` per step.
    shift : (qx, qy) or array of shape (steps, 2), optional
        Rigid shift increment per step, m (added to the rigid slip).
    force : (fx, fy) or array of shape (steps, 2), optional
        Tangential force per step, N, instead of ``shift``: both components prescribed, the
        rigid shift found per step with the tractions (``shift`` of the result).
        ``|force| < mu fn``.
    theta : float
        Weight of the second-order slip in [0, 1] (rolling only); 1/3 matches the steady
        solver's stencil.
    keep : array of int, optional
        Steps whose fields to store (default: the last).
    tol, max_iter : float, int
        Tangential tolerance and iteration limit per solve.
    normal_tol, normal_max_iter : float, int
        Of the normal solver.

    Returns
    -------
    TransientResult

    Raises
    ------
    InputError
        Bad input, named: e.g. ``dt`` when a step skips the patch, is no whole number of
        elements, or reaches beyond the grid; ``force`` at or beyond ``mu fn``.
    GridTooSmallError
        The contact area reaches the grid's edge.
    ConvergenceError
        A step did not converge (the march result attached as ``.result``).
    """
    mu = _checks.positive("mu", mu)
    steps = _checks.positive_int("steps", steps)
    dt = _checks.positive("dt", dt)
    speed = _checks.non_negative("speed", speed)
    theta = _checks.finite("theta", theta)
    if not 0.0 <= theta <= 1.0:
        raise InputError(f"theta must lie in [0, 1], got {theta}")
    fns = _per_step("fn", fn, steps, 1)[:, 0]
    if fns.min() <= 0.0:
        raise InputError("fn must be > 0 at every step (N)")
    creep = _per_step("creepage", creepage, steps, 3)
    if shift is not None and force is not None:
        raise InputError("give shift (m) or force (N), not both")
    control = _FORCE_GIVEN if force is not None else _SHIFT_GIVEN
    load = _per_step(
        "force" if force is not None else "shift",
        force if force is not None else (shift if shift is not None else (0.0, 0.0)),
        steps,
        2,
    )
    if control == _FORCE_GIVEN and (np.hypot(load[:, 0], load[:, 1]) >= mu * fns).any():
        n = int(np.argmax(np.hypot(load[:, 0], load[:, 1]) >= mu * fns))
        raise InputError(
            f"force at step {n}: |F| = {np.hypot(*load[n]):.6g} N must stay below "
            f"mu fn = {mu * fns[n]:.6g} N "
            "(at full sliding the shift is undetermined)"
        )
    pgiven, h, p_max = _normal_input(grid, material, gap, pressure, fns, normal_tol)
    k = _check_step(grid, p_max, speed, dt, theta)
    keep_mask = np.zeros(steps, dtype=np.int32)
    if keep is None:
        keep_mask[-1] = 1
    else:
        idx = np.asarray(keep, dtype=int).ravel()
        if idx.size and (idx.min() < -steps or idx.max() >= steps):
            raise InputError(f"keep: step indices must lie in [0, {steps}), got {idx.min()}..{idx.max()}")
        keep_mask[idx] = 1
    nkeep = int(keep_mask.sum())
    out = call_interruptibly(
        workspace(grid, material, tangential=True),
        core.transient_run_c,
        max(nkeep, 1),
        h,
        int(pgiven),
        fns,
        k,
        theta,
        mu,
        grid.x0,
        grid.y0,
        speed * dt,
        np.asfortranarray(creep.T),
        control,
        np.asfortranarray(load.T),
        _checks.positive("tol", tol),
        _checks.positive_int("max_iter", max_iter),
        _checks.positive("normal_tol", normal_tol),
        _checks.positive_int("normal_max_iter", normal_max_iter),
        keep_mask,
    )
    return _result(grid, mu, speed, dt, k, theta, steps, keep_mask, out)


def _normal_input(grid, material, gap, pressure, fns, normal_tol):
    """(pgiven, h, the pressure under the largest fn) for the Fortran march."""
    if (gap is None) == (pressure is None):
        raise InputError("give gap (m) or pressure (Pa), exactly one")
    if pressure is not None:
        p = _checks.finite_array("pressure", pressure, shape=grid.shape)
        if p.min() < 0.0 or not (p > 0.0).any():
            raise InputError("pressure must be >= 0 everywhere and positive somewhere (Pa)")
        f0 = float(p.sum() * grid.element_area)
        return True, np.asfortranarray(p / f0), p * (fns.max() / f0)
    h = np.asfortranarray(_checks.finite_array("gap", gap, shape=grid.shape))
    return False, h, solve_normal(h, grid, material, fn=float(fns.max()), tol=normal_tol).pressure


def _result(grid, mu, speed, dt, k, theta, steps, keep_mask, out) -> TransientResult:
    fx, fy, fno, q, ncon, nslip, iters, resids, infos, ktx, kty, kst, ksx, ksy, kp, info = out
    if info == Status.GRID_EDGE:
        raise GridTooSmallError(
            "transient contact: the contact area reaches the grid's edge, or the history of a rolling step "
            "leaves the grid at x = x_max: enlarge the grid"
        )
    if info not in (Status.OK, Status.NOT_CONVERGED):
        raise error(
            info, "transient contact march failed", exc=RailvtiError if info != Status.NOT_FINITE else None
        )
    time = dt * np.arange(1, steps + 1)
    kept = np.nonzero(keep_mask)[0]
    snaps = tuple(
        Snapshot(
            int(n),
            float(time[n]),
            kp[:, :, m].copy(),
            ktx[:, :, m].copy(),
            kty[:, :, m].copy(),
            kst[:, :, m].astype(np.int8),
            ksx[:, :, m].copy(),
            ksy[:, :, m].copy(),
        )
        for m, n in enumerate(kept)
    )
    result = TransientResult(
        grid=grid,
        mu=mu,
        speed=speed,
        dt=dt,
        elements_per_step=k,
        theta=theta,
        time=time,
        distance=speed * time,
        fn=fno,
        fx=fx,
        fy=fy,
        shift=np.ascontiguousarray(q.T),
        n_contact=ncon,
        n_slip=nslip,
        iterations=iters,
        residual=resids,
        snapshots=snaps,
        converged=info == Status.OK,
    )
    if info == Status.NOT_CONVERGED:
        bad = np.nonzero(infos == Status.NOT_CONVERGED)[0]
        raise ConvergenceError(
            f"transient contact: {bad.size} step(s) did not converge (first: step {bad[0]}, residual "
            f"{resids[bad[0]]:.3g})",
            iterations=int(iters[bad[0]]),
            residual=float(resids[bad[0]]),
            result=result,
        )
    log.debug("solve_transient: %d steps, %d iterations", steps, int(iters.sum()))
    return result


def shift_problem(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    mu: float,
    fn: float,
    force: tuple[float, float],
    steps: int = 1,
    **kwargs,
) -> TransientResult:
    """A body pressed by ``fn`` then shifted by the tangential force ``force`` (N), reached
    in ``steps`` equal increments (Cattaneo-Mindlin for a Hertz sphere). Keyword arguments
    go to :func:`solve_transient`; the time step is 1 s (a shift has no time scale)."""
    steps = _checks.positive_int("steps", steps)
    f = np.asarray(_per_step("force", force, 1, 2)[0])
    ramp = np.outer(np.arange(1, steps + 1) / steps, f)
    return solve_transient(grid, material, mu, fn, steps, 1.0, gap=gap, force=ramp, **kwargs)


def transient_rolling(
    grid: Grid,
    material: Material,
    mu: float,
    fn,
    creepage,
    speed: float,
    distance: float,
    *,
    elements_per_step: int = 1,
    theta: float = 1.0 / 3.0,
    **kwargs,
) -> TransientResult:
    """Rolling from zero traction over ``distance`` (m) at ``speed`` (m/s) with the
    creepages ``creepage`` (constant, or one row per step), ``elements_per_step`` elements
    dx per step. Keyword arguments (gap or pressure, keep, tol, ...) go to
    :func:`solve_transient`."""
    speed = _checks.positive("speed", speed)
    distance = _checks.positive("distance", distance)
    k = _checks.positive_int("elements_per_step", elements_per_step)
    step = k * grid.dx
    steps = max(1, int(round(distance / step)))
    return solve_transient(
        grid, material, mu, fn, steps, step / speed, speed=speed, creepage=creepage, theta=theta, **kwargs
    )


__all__ = [
    "DEFAULT_MAX_ITER",
    "StepResult",
    "Snapshot",
    "TransientResult",
    "solve_step",
    "solve_transient",
    "shift_problem",
    "transient_rolling",
]
