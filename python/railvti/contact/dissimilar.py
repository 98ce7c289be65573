"""Contact of two bodies of dissimilar materials: the normal-tangential coupling.

Each body has its own shear modulus and Poisson's ratio (:class:`BodyPair`). The
elastic operator of the pair is that of the quasi-identical bodies with the combined
(G, nu) of Kalker (1990, eq. 1.44) plus the cross terms of the difference parameter
K (``fortran/contact/contact_coupling.f90``): the pressure moves the surfaces
tangentially (``u_t += A_tz p``) and the tangential tractions move them normally
(``u_n += A_zt t``). The two problems are solved alternately, the normal one with the
tractions fixed and the tangential one with the pressure fixed, until neither changes
by more than a tolerance (Panagiotopoulos' process, Kalker 1990 sect. 5.1):

* :func:`solve_dissimilar_rolling`: steady rolling; the pressure's coupling enters the
  steady solver as an extra rigid slip, its upwind difference (eq. 29 of
  ``contact_rolling.f90``). ``free_rolling=True`` finds the creepage xi with Fx = 0
  (Bentall and Johnson 1967).
* :func:`solve_progressive_compression`: a quasi-static loading history without
  rolling; each step's slip is the increment of the tangential displacement difference
  (Spence 1975).

With K = 0 (identical materials) both reduce to today's decoupled solvers: the rolling
result equals :func:`~railvti.contact.solve_rolling`'s to rounding (tested).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from .._roots import brent_root
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError, RailvtiError
from ..material import Material
from .grid import Grid
from .normal import NormalResult, solve_normal
from .rolling import RollingResult, _check_creepage
from .workspace import call_directly, workspace

log = logging.getLogger(__name__)

_METHODS = {"gs": 1, "fftgs": 2}


@dataclass(frozen=True)
class BodyPair:
    """The materials of the two bodies: the wheel (body 1, upper, carries the tractions)
    and the rail (body 2).

    Parameters
    ----------
    wheel, rail : Material
        Each body's shear modulus (Pa, > 0) and Poisson's ratio (in (-1, 0.5)).
    """

    wheel: Material
    rail: Material

    def __post_init__(self) -> None:
        for name in ("wheel", "rail"):
            if not isinstance(getattr(self, name), Material):
                raise InputError(f"{name} must be a railvti.Material")

    @classmethod
    def from_constants(
        cls, wheel_shear_modulus: float, wheel_poisson: float, rail_shear_modulus: float, rail_poisson: float
    ) -> "BodyPair":
        """The pair from four constants (Pa, 1); an error names the bad one."""
        for name, value in (
            ("wheel_shear_modulus", wheel_shear_modulus),
            ("rail_shear_modulus", rail_shear_modulus),
        ):
            v = _checks.finite(name, value)
            if v <= 0.0:
                raise InputError(f"{name} must be > 0, got {v}")
        for name, value in (("wheel_poisson", wheel_poisson), ("rail_poisson", rail_poisson)):
            v = _checks.finite(name, value)
            if not -1.0 < v < 0.5:
                raise InputError(f"{name} must lie in (-1, 0.5), got {v}")
        return cls(Material(wheel_shear_modulus, wheel_poisson), Material(rail_shear_modulus, rail_poisson))

    @property
    def shear_modulus(self) -> float:
        """Combined G: 1/G = (1/G1 + 1/G2)/2, Pa (Kalker 1990, eq. 1.44)."""
        return 2.0 / (1.0 / self.wheel.shear_modulus + 1.0 / self.rail.shear_modulus)

    @property
    def poisson(self) -> float:
        """Combined nu: nu/G = (nu1/G1 + nu2/G2)/2 (Kalker 1990, eq. 1.44)."""
        w, r = self.wheel, self.rail
        return 0.5 * self.shear_modulus * (w.poisson / w.shear_modulus + r.poisson / r.shear_modulus)

    @property
    def difference_parameter(self) -> float:
        """Kalker's K = G/4 ((1 - 2 nu1)/G1 - (1 - 2 nu2)/G2) (1; eq. 1.44); 0 for equal bodies."""
        w, r = self.wheel, self.rail
        return (
            0.25
            * self.shear_modulus
            * ((1.0 - 2.0 * w.poisson) / w.shear_modulus - (1.0 - 2.0 * r.poisson) / r.shear_modulus)
        )

    @property
    def beta(self) -> float:
        """Dundurs' second constant beta = K / (1 - nu) (Johnson 1985, eq. 5.4), in (-0.5, 0.5)."""
        return self.difference_parameter / (1.0 - self.poisson)

    @property
    def combined(self) -> Material:
        """The quasi-identical material with the combined G and nu: the pair's normal
        compliance and its tangential one (the cross terms aside)."""
        return Material(self.shear_modulus, self.poisson)

    @property
    def contact_modulus(self) -> float:
        """Hertz's E*: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 = (1 - nu)/G, Pa."""
        return self.shear_modulus / (1.0 - self.poisson)


@dataclass(frozen=True)
class DissimilarRollingResult:
    """Steady rolling of a dissimilar pair.

    Attributes
    ----------
    rolling : RollingResult
        The last tangential solution (its pressure and normal solution included; its
        slip includes the pressure's coupling).
    pair : BodyPair
    outer_iterations : int
        Panagiotopoulos iterations (normal + tangential solves).
    outer_change : float
        The last iteration's largest change of p and t, over max(p) and mu max(p).
    creepage : tuple of float
        (xi, eta, phi) used; xi is the solved one with ``free_rolling``.
    """

    rolling: RollingResult
    pair: BodyPair
    outer_iterations: int
    outer_change: float
    creepage: tuple[float, float, float]


@dataclass(frozen=True)
class CompressionResult:
    """A progressive compression (quasi-static loading history) of a dissimilar pair.

    Attributes
    ----------
    grid : Grid
    pair : BodyPair
    mu : float
    fn : ndarray, shape (nsteps,)
        Normal force per step, N.
    pressure, tx, ty : ndarray, shape (nx, ny)
        Final step's pressure and tractions on the wheel (body 1), Pa.
    status : ndarray of int8, shape (nx, ny)
        Final step: 0 exterior, 1 adhesion, 2 slip.
    n_contact, n_adhesion : ndarray of int, shape (nsteps,)
        Elements in contact and in adhesion per step.
    outer_iterations : ndarray of int, shape (nsteps,)
        Panagiotopoulos iterations per step.
    sweeps : int
        Gauss-Seidel sweeps of all tangential solves.
    """

    grid: Grid
    pair: BodyPair
    mu: float
    fn: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    status: np.ndarray
    n_contact: np.ndarray
    n_adhesion: np.ndarray
    outer_iterations: np.ndarray
    sweeps: int

    @property
    def stick_ratio(self) -> np.ndarray:
        """c/a per step from the areas, sqrt(adhesion area / contact area) (circular patch)."""
        return np.sqrt(self.n_adhesion / np.maximum(self.n_contact, 1))


def coupling_displacements(
    grid: Grid, pair: BodyPair, pressure: np.ndarray, tx: np.ndarray, ty: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cross terms' displacements: ``(A_zx tx + A_zy ty, A_xz p, A_yz p)``, m, each
    (nx, ny): the gap's increase from the tractions on the wheel and the tangential
    displacement difference (wheel minus rail) from the pressure (Pa)."""
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(pair, BodyPair):
        raise InputError("pair must be a railvti.contact.BodyPair")
    p = _checks.finite_array("pressure", pressure, shape=grid.shape)
    qx = _checks.finite_array("tx", tx, shape=grid.shape)
    qy = _checks.finite_array("ty", ty, shape=grid.shape)
    kg = pair.difference_parameter / pair.shear_modulus
    return core.coupling_apply_c(grid.dx, grid.dy, kg, p, qx, qy)


def cross_coefficients(grid: Grid, kernel: str = "x") -> np.ndarray:
    """(1/pi) I[X/r^2] ('x') or (1/pi) I[Y/r^2] ('y') over an element, m, for every offset
    (k, l) = observation minus source: array (2nx - 1, 2ny - 1), index [k + nx - 1, l + ny - 1].
    ``A_xz = -K/G`` times the 'x' field (contact_coupling.f90)."""
    if kernel not in ("x", "y"):
        raise InputError(f"kernel must be 'x' or 'y', got {kernel!r}")
    c, info = core.cross_field_c(1 if kernel == "x" else 2, grid.nx, grid.ny, grid.dx, grid.dy)
    if info != Status.OK:
        raise error(info, "cross coefficients", exc=RailvtiError)
    return c


def _normal(h, grid, material, fn, tol, p0) -> NormalResult:
    """solve_normal warm-started from p0 (the previous outer iteration's pressure); from
    zero when that start does not converge (solve_normal's CG stops after one iteration
    when p0's contact set is smaller than the solution's, seen with the load steps)."""
    if p0 is not None:
        try:
            return solve_normal(h, grid, material, fn=fn, tol=tol, p0=p0)
        except ConvergenceError:
            log.debug("dissimilar: warm-started normal solve failed, solved from zero")
    return solve_normal(h, grid, material, fn=fn, tol=tol)


def _tangential(p, grid, pair, mu, creepage, speed, method, tol, max_iter, t0, normal):
    """One steady tangential solve of the pair for the pressure p (the shim's checks done)."""
    g = grid
    tx = np.array(t0[0], dtype=np.float64, order="F")
    ty = np.array(t0[1], dtype=np.float64, order="F")
    if p[-2:, :].max() > 0.0:
        raise GridTooSmallError(
            "the contact area reaches the last two element rows at x = x_max: enlarge the grid"
        )
    kg = pair.difference_parameter / pair.shear_modulus
    xi, eta, phi = creepage
    status, sx, sy, iters, resid, info = call_directly(
        workspace(g, pair.combined, tangential=True),
        core.dissimilar_rolling_c,
        p, g.x0, g.y0, xi, eta, phi, mu, speed, _METHODS[method], 16, 1, tol, max_iter, 0, kg, tx, ty,
    )  # fmt: skip
    if info == Status.GRID_EDGE:
        raise GridTooSmallError("the contact area reaches the leading grid edge: enlarge the grid")
    if info not in (Status.OK, Status.NOT_CONVERGED, Status.NO_CONTACT):
        raise error(info, "dissimilar rolling contact", iterations=int(iters), residual=float(resid))
    da = g.element_area
    x, y = g.mesh()
    n_contact = int(np.count_nonzero(p))
    result = RollingResult(
        grid=g, pressure=p, fn=normal.fn, approach=normal.approach, area=n_contact * da, n_contact=n_contact,
        mu=mu, creepage=(xi, eta, phi), speed=speed, tx=tx, ty=ty, status=np.asarray(status, dtype=np.int8),
        slip_velocity_x=sx, slip_velocity_y=sy, fx=float(tx.sum()) * da, fy=float(ty.sum()) * da,
        mz=float((x * ty - y * tx).sum() * da), power=float((np.hypot(tx, ty) * np.hypot(sx, sy)).sum() * da),
        iterations=int(iters), residual=float(resid), converged=info != Status.NOT_CONVERGED, method=method,
        normal=normal,
    )  # fmt: skip
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"dissimilar rolling ({method}): residual {resid:.3g} > tol {tol:.3g} after {iters} sweeps",
            iterations=int(iters),
            residual=float(resid),
            result=result,
        )
    return result


def _free_rolling_xi(p, grid, pair, mu, creepage, speed, method, tol, max_iter, t0, normal, guess):
    """The tangential solve with xi such that Fx = 0 (Fx falls with xi): Brent's method on a
    bracket grown around ``guess`` (the last outer iteration's xi, or Bentall and Johnson's
    estimate -2 K/G 0.9 p_max at first)."""
    _, eta, phi = creepage
    # the slip the pressure causes is of the order 2 K/G p_max (Bentall and Johnson's creepage)
    scale = max(2.0 * abs(pair.difference_parameter / pair.shear_modulus) * float(p.max()), 1e-7)
    cache: dict[float, RollingResult] = {}

    def fx(xi: float) -> float:
        if xi not in cache:
            cache[xi] = _tangential(
                p, grid, pair, mu, (xi, eta, phi), speed, method, tol, max_iter, t0, normal
            )
        return cache[xi].fx / max(mu * normal.fn, 1e-300)

    step = 0.02 * max(abs(guess), 0.05 * scale)
    lo, hi = guess - step, guess + step
    for _ in range(60):
        f_lo, f_hi = fx(lo), fx(hi)
        if f_lo >= 0.0 >= f_hi:
            break
        # Fx falls with xi: move the side that misses the root outwards, doubling the step
        step *= 2.0
        if f_lo < 0.0:
            lo, hi = lo - step, lo
        else:
            lo, hi = hi, hi + step
    else:
        raise ConvergenceError(
            "free rolling: no creepage bracket with Fx = 0", iterations=60, residual=math.inf
        )
    xi = brent_root(fx, lo, hi, xtol=1e-9 * scale, rtol=1e-9)
    fx(xi)
    return cache[xi]


def solve_dissimilar_rolling(
    gap: np.ndarray,
    grid: Grid,
    pair: BodyPair,
    mu: float,
    fn: float,
    creepage: tuple[float, float, float],
    speed: float,
    free_rolling: bool = False,
    method: str = "fftgs",
    tol: float = 1e-7,
    max_iter: int = 2000,
    outer_tol: float = 1e-6,
    max_outer: int = 30,
    normal_tol: float = 1e-8,
    normal_coupling: bool = True,
) -> DissimilarRollingResult:
    """Steady rolling of two bodies of dissimilar materials (Panagiotopoulos' process).

    Parameters
    ----------
    gap, grid, mu, fn, creepage, speed, method, tol, max_iter, normal_tol
        As in :func:`~railvti.contact.solve_rolling` (gap m, fn N, creepage (1, 1, 1/m),
        speed m/s).
    pair : BodyPair
        The wheel's and the rail's materials.
    free_rolling : bool
        Solve xi for Fx = 0 (creepage[0] ignored): free rolling of dissimilar cylinders.
    outer_tol : float
        Stop when neither p nor t changed by more than ``outer_tol`` times max(p)
        (resp. mu max(p)) in an outer iteration.
    max_outer : int
        Outer iteration limit (ConvergenceError beyond it).
    normal_coupling : bool
        False: leave out the tractions' effect on the pressure (A_zx t), Johnson's process
        (Kalker 1990; CONTACT's MAXOUT = 1): one normal solve, then the tangential problem
        with the pressure's coupling. Exact at mu -> 0 and cheap; True is the full coupling.

    Returns
    -------
    DissimilarRollingResult
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(pair, BodyPair):
        raise InputError("pair must be a railvti.contact.BodyPair")
    h = _checks.finite_array("gap", gap, shape=grid.shape)
    mu = _checks.non_negative("mu", mu)
    fn = _checks.positive("fn", fn)
    creepage = _check_creepage(creepage)
    speed = _checks.positive("speed", speed)
    if method not in _METHODS:
        raise InputError(f"method must be one of {sorted(_METHODS)}, got {method!r}")
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    outer_tol = _checks.positive("outer_tol", outer_tol)
    max_outer = _checks.positive_int("max_outer", max_outer)
    material = pair.combined
    kg = pair.difference_parameter / pair.shear_modulus
    tx = np.zeros(grid.shape, order="F")
    ty = np.zeros(grid.shape, order="F")
    p_old = None
    change = math.inf
    roll = None
    for it in range(1, max_outer + 1):
        kn = kg if normal_coupling else 0.0  # the tractions' normal displacement, or none
        un, _, _ = core.coupling_apply_c(grid.dx, grid.dy, kn, np.zeros(grid.shape, order="F"), tx, ty)
        normal = _normal(h + un, grid, material, fn, normal_tol, p_old)
        p = normal.pressure
        args = (p, grid, pair, mu, creepage, speed, method, tol, max_iter, (tx, ty), normal)
        if free_rolling:
            guess = -1.8 * kg * float(p.max()) if roll is None else roll.creepage[0]
            roll = _free_rolling_xi(*args, guess)
        else:
            roll = _tangential(*args)
        pmax = float(p.max())
        dp = 0.0 if p_old is None else float(np.abs(p - p_old).max()) / pmax
        dt = float(max(np.abs(roll.tx - tx).max(), np.abs(roll.ty - ty).max())) / max(mu * pmax, 1e-300)
        change = max(dp, dt) if p_old is not None else (0.0 if kg == 0.0 else math.inf)
        tx, ty, p_old = roll.tx, roll.ty, p
        log.debug("dissimilar rolling: outer %d, change %.3g", it, change)
        if change <= outer_tol or kg == 0.0 or not normal_coupling:
            return DissimilarRollingResult(roll, pair, it, change, roll.creepage)
    raise ConvergenceError(
        f"dissimilar rolling: the outer (Panagiotopoulos) iteration changed p or t by {change:.3g} "
        f"> outer_tol {outer_tol:.3g} after {max_outer} iterations",
        iterations=max_outer,
        residual=change,
        result=DissimilarRollingResult(roll, pair, max_outer, change, roll.creepage),
    )


def _check_history(fn_steps) -> np.ndarray:
    f = _checks.finite_array("fn_steps", fn_steps, ndim=1)
    if f.size < 1:
        raise InputError("fn_steps must hold at least one normal force")
    if (f <= 0.0).any() or (np.diff(f) < 0.0).any():
        raise InputError("fn_steps must be positive and non-decreasing (a progressive loading)")
    return f


def solve_progressive_compression(
    gap: np.ndarray,
    grid: Grid,
    pair: BodyPair,
    mu: float,
    fn_steps,
    tol: float = 1e-9,
    max_iter: int = 5000,
    outer_tol: float = 1e-7,
    max_outer: int = 30,
    normal_tol: float = 1e-9,
    normal_coupling: bool = True,
) -> CompressionResult:
    """Progressive normal loading of a dissimilar pair with friction (Spence 1975).

    Each step k solves, by the outer iteration, the normal problem for ``fn_steps[k]``
    with the tractions' normal displacements and the shift problem whose slip is the
    increment of the tangential displacement difference since step k - 1 (no rigid shift).

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Undeformed gap, m.
    grid : Grid
    pair : BodyPair
    mu : float
        Coefficient of friction (> 0).
    fn_steps : sequence of float
        Normal force per step, N, positive and non-decreasing.
    tol : float
        Shift solve: largest traction change of a sweep over mu max(p).
    max_iter : int
        Sweeps per shift solve.
    outer_tol, max_outer
        As in :func:`solve_dissimilar_rolling`.
    normal_tol : float
        Tolerance of the normal solves.
    normal_coupling : bool
        False: Johnson's process (the pressure without the tractions' effect, A_zx t left
        out), as :func:`solve_dissimilar_rolling`.

    Returns
    -------
    CompressionResult
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(pair, BodyPair):
        raise InputError("pair must be a railvti.contact.BodyPair")
    h = _checks.finite_array("gap", gap, shape=grid.shape)
    mu = _checks.positive("mu", mu)
    steps = _check_history(fn_steps)
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    outer_tol = _checks.positive("outer_tol", outer_tol)
    max_outer = _checks.positive_int("max_outer", max_outer)
    material = pair.combined
    g, nu, kg = pair.shear_modulus, pair.poisson, pair.difference_parameter / pair.shear_modulus
    zero = np.zeros(grid.shape, order="F")
    tx, ty = zero.copy(), zero.copy()
    uoldx, uoldy = zero.copy(), zero.copy()
    n_contact, n_adh, outer, sweeps = [], [], [], 0
    for k, fn in enumerate(steps):
        p_it, d = None, math.inf
        for it in range(1, max_outer + 1):
            un, _, _ = core.coupling_apply_c(grid.dx, grid.dy, kg if normal_coupling else 0.0, zero, tx, ty)
            p = _normal(h + un, grid, material, float(fn), normal_tol, p_it).pressure
            qx, qy = np.array(tx, order="F"), np.array(ty, order="F")
            # the shift solve to a tolerance the outer iteration can use: 1 % of its last change
            inner = max(tol, min(1e-4, 1e-2 * d)) if normal_coupling else tol
            status, ux, uy, iters, change, info = core.coupling_shift_c(
                grid.dx, grid.dy, g, nu, kg, mu, p, uoldx, uoldy, 0.0, 0.0, inner, max_iter, qx, qy
            )
            sweeps += int(iters)
            n_outer = it
            if info not in (Status.OK, Status.NO_CONTACT):
                raise error(
                    info, f"progressive compression, step {k}", iterations=int(iters), residual=float(change)
                )
            pmax = float(p.max())
            d = 0.0 if p_it is None else float(np.abs(p - p_it).max()) / pmax
            d = max(d, float(max(np.abs(qx - tx).max(), np.abs(qy - ty).max())) / (mu * pmax))
            tx, ty, p_it = qx, qy, p
            if (d <= outer_tol and inner == tol) or kg == 0.0 or (not normal_coupling and inner == tol):
                break
        else:
            raise ConvergenceError(
                f"progressive compression, step {k}: outer iteration change {d:.3g} > {outer_tol:.3g}",
                iterations=max_outer,
                residual=d,
            )
        uoldx, uoldy = ux, uy
        n_contact.append(int(np.count_nonzero(p)))
        n_adh.append(int(np.count_nonzero(status == 1)))
        outer.append(n_outer)
    return CompressionResult(
        grid=grid, pair=pair, mu=mu, fn=steps, pressure=p, tx=tx, ty=ty,
        status=np.asarray(status, dtype=np.int8), n_contact=np.array(n_contact), n_adhesion=np.array(n_adh),
        outer_iterations=np.array(outer), sweeps=sweeps,
    )  # fmt: skip


__all__ = [
    "BodyPair",
    "DissimilarRollingResult",
    "CompressionResult",
    "coupling_displacements",
    "cross_coefficients",
    "solve_dissimilar_rolling",
    "solve_progressive_compression",
]
