"""Steady-state rolling contact on the boundary-element grid (Kaiser, eqs 24-29).

For quasi-identical bodies the normal and tangential problems decouple: the
pressure comes from :func:`~railvti.contact.solve_normal`, then the tangential
tractions from a Gauss-Seidel creep iteration in Fortran
(``fortran/contact/contact_rolling.f90``).

Conventions (Kalker's): x is the rolling direction; particles move through the
patch in -x at the speed V, so the leading edge is at the largest x. The rigid
slip (creepage units) is ``w_x = xi - phi y``, ``w_y = eta + phi x`` with x, y
measured from the grid's origin (x = y = 0). The tractions ``tx, ty`` act on
the upper body (the wheel) and are such that in the linear limit
``Fx = -G a b C11 xi`` and ``Fy = -G a b C22 eta - G (a b)^1.5 C23 phi``.
``Mz = sum (x ty - y tx) dA`` about the grid's z axis (x = y = 0).

The slip uses a three-point upwind difference over the element and its two
upstream neighbours (see the Fortran module): the contact area must stay
two elements clear of the leading grid edge.
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
from .normal import NormalResult, solve_normal
from .workspace import call_directly, call_interruptibly, workspace

log = logging.getLogger(__name__)

_METHODS = {"gs": 1, "fftgs": 2}
_PRODUCTS = {"auto": 0, "fft": 1, "direct": 2}
_DEFAULT_MAX_ITER = {"gs": 500, "fftgs": 2000}
_EDGE_MESSAGE = (
    "the contact area reaches the last two element rows at the leading grid edge "
    "x = x_max (the slip needs two elements upstream): enlarge the grid"
)
#: Rows per FFT refresh of method 'fftgs'.
DEFAULT_BLOCK = 16
#: Passes over each row before the next row (both methods).
DEFAULT_INNER = 1
#: Solves of at most this many element sweeps (nx ny max_iter; about 0.3 s at the worst)
#: call the Fortran directly; larger ones run in a worker thread that Ctrl-C can leave
#: (call_interruptibly). Starting that thread and handing the result back costs
#: 0.1-1 ms, more than a whole 11 x 11 solve.
DIRECT_CALL_WORK = 2_500_000

STATUS_EXTERIOR, STATUS_ADHESION, STATUS_SLIP = 0, 1, 2


@dataclass(frozen=True)
class RollingResult:
    """Solution of a steady rolling contact problem.

    Attributes
    ----------
    grid : Grid
    pressure : ndarray, shape (nx, ny)
        Normal pressure, Pa.
    fn : float
        Normal force, N.
    approach : float
        Approach of the bodies, m (nan when the pressure was given).
    area : float
        Contact area, m^2.
    n_contact : int
        Elements in contact.
    mu : float
        Coefficient of friction.
    creepage : tuple of float
        (xi, eta, phi): longitudinal, lateral (1) and spin (1/m) creepage.
    speed : float
        Rolling speed V, m/s.
    tx, ty : ndarray, shape (nx, ny)
        Tangential tractions on the wheel, Pa.
    status : ndarray of int, shape (nx, ny)
        0 exterior, 1 adhesion, 2 slip.
    slip_velocity_x, slip_velocity_y : ndarray, shape (nx, ny)
        Slip velocity components, m/s (zero in adhesion and outside contact).
    fx, fy : float
        Creep forces, N (sums of the tractions times the element area).
    mz : float
        Spin moment about the grid's z axis through x = y = 0, N m.
    power : float
        Frictional power, W (sum of the power density times the element area).
    iterations : int
        Gauss-Seidel sweeps, plus the Newton steps that finish a small contact set's solve
        (at most 100 elements in contact, Coulomb friction: docs/rolling.md).
    residual : float
        Relative residual ||F(t) - t|| / ||F(t)|| of a Jacobi step on the exact field.
    converged : bool
    method : str
        'gs' or 'fftgs'.
    normal : NormalResult or None
        The normal solution (None when the pressure was given).
    """

    grid: Grid
    pressure: np.ndarray
    fn: float
    approach: float
    area: float
    n_contact: int
    mu: float
    creepage: tuple[float, float, float]
    speed: float
    tx: np.ndarray
    ty: np.ndarray
    status: np.ndarray
    slip_velocity_x: np.ndarray
    slip_velocity_y: np.ndarray
    fx: float
    fy: float
    mz: float
    power: float
    iterations: int
    residual: float
    converged: bool
    method: str
    normal: NormalResult | None = None

    @property
    def contact(self) -> np.ndarray:
        """Boolean ``(nx, ny)`` mask of the elements in contact."""
        return self.pressure > 0.0

    @property
    def pmax(self) -> float:
        """Largest pressure, Pa."""
        return float(self.pressure.max())

    @property
    def slip(self) -> np.ndarray:
        """Boolean ``(nx, ny)`` mask of the elements in slip."""
        return self.status == STATUS_SLIP

    @property
    def adhesion(self) -> np.ndarray:
        """Boolean ``(nx, ny)`` mask of the elements in adhesion."""
        return self.status == STATUS_ADHESION

    @property
    def slip_velocity(self) -> np.ndarray:
        """Magnitude of the slip velocity, m/s, shape (nx, ny)."""
        return np.hypot(self.slip_velocity_x, self.slip_velocity_y)

    @property
    def power_density(self) -> np.ndarray:
        """Frictional power density ``|tau| |s|``, W/m^2, shape (nx, ny)."""
        return np.hypot(self.tx, self.ty) * self.slip_velocity

    @property
    def traction_bound(self) -> np.ndarray:
        """``mu p``, Pa."""
        return self.mu * self.pressure


def _check_creepage(creepage: object) -> tuple[float, float, float]:
    try:
        values = tuple(creepage)  # type: ignore[arg-type]
    except TypeError:
        raise InputError("creepage must be a sequence (xi, eta, phi)") from None
    if len(values) != 3:
        raise InputError(f"creepage must have 3 entries (xi, eta, phi), got {len(values)}")
    return (
        _checks.finite("creepage xi", values[0]),
        _checks.finite("creepage eta", values[1]),
        _checks.finite("creepage phi (1/m)", values[2]),
    )


def start_tractions(grid: Grid, t0: tuple | None) -> tuple[np.ndarray, np.ndarray]:
    """The start tractions of a tangential solve: zero, or checked copies of ``t0 = (tx, ty)``
    (the solver overwrites them), Pa."""
    if t0 is None:
        return np.zeros(grid.shape, order="F"), np.zeros(grid.shape, order="F")
    if len(t0) != 2:
        raise InputError("t0 must be a pair (tx, ty) of (nx, ny) arrays")
    return (
        _checks.finite_array("t0[0]", t0[0], shape=grid.shape),
        _checks.finite_array("t0[1]", t0[1], shape=grid.shape),
    )


def rolling_result(
    grid: Grid,
    p: np.ndarray,
    t: tuple[np.ndarray, np.ndarray],
    s: tuple[np.ndarray, np.ndarray],
    status: np.ndarray,
    mu: float,
    creepage: tuple[float, float, float],
    speed: float,
    method: str,
    iterations: int,
    residual: float,
    converged: bool,
    normal: NormalResult | None = None,
    approach: float = math.nan,
) -> RollingResult:
    """A RollingResult from a solve's fields: tractions ``t = (tx, ty)`` (Pa), slip velocities
    ``s = (sx, sy)`` (m/s) and the element status; forces, spin moment and power summed over
    the grid."""
    tx, ty = t
    sx, sy = s
    da = grid.element_area
    # x_i ty_ij - y_j tx_ij by broadcasting, laid out (C order) and so summed as the products
    # of grid.mesh()'s arrays were (the same Mz to the bit), without making the mesh
    arm = np.subtract(
        np.multiply(grid.x[:, None], ty, order="C"), np.multiply(grid.y[None, :], tx, order="C"), order="C"
    )
    n_contact = int(np.count_nonzero(p))  # p >= 0
    return RollingResult(
        grid=grid,
        pressure=p,
        fn=float(p.sum() * da) if normal is None else normal.fn,
        approach=float(approach),
        area=n_contact * da,
        n_contact=n_contact,
        mu=mu,
        creepage=creepage,
        speed=speed,
        tx=tx,
        ty=ty,
        status=np.asarray(status, dtype=np.int8),
        slip_velocity_x=sx,
        slip_velocity_y=sy,
        fx=float(tx.sum()) * da,
        fy=float(ty.sum()) * da,
        mz=float(arm.sum() * da),  # this order: Mz of a saturated patch cancels
        power=float((np.hypot(tx, ty) * np.hypot(sx, sy)).sum() * da),
        iterations=iterations,
        residual=residual,
        converged=converged,
        method=method,
        normal=normal,
    )


def solve_tangential(
    pressure: np.ndarray,
    grid: Grid,
    material: Material,
    mu: float,
    creepage: tuple[float, float, float],
    speed: float,
    method: str = "fftgs",
    tol: float = 1e-7,
    max_iter: int | None = None,
    t0: tuple | None = None,
    block: int = DEFAULT_BLOCK,
    inner: int = DEFAULT_INNER,
    normal: NormalResult | None = None,
    approach: float = math.nan,
    product: str = "auto",
) -> RollingResult:
    """Steady rolling tangential problem for a given pressure.

    Parameters
    ----------
    pressure : ndarray, shape (nx, ny)
        Normal pressure, Pa (>= 0); the elements with p > 0 are in contact.
    grid, material, mu, creepage, speed, method, tol, max_iter, t0, block, inner, product
        As in :func:`solve_rolling`.
    normal : NormalResult, optional
        Attached to the result.
    approach : float
        Attached to the result, m.

    Returns
    -------
    RollingResult
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    p = _checks.finite_array("pressure", pressure, shape=grid.shape)
    if p.min() < 0.0:
        raise InputError("pressure must be >= 0 everywhere")
    mu = _checks.non_negative("mu", mu)
    xi, eta, phi = _check_creepage(creepage)
    speed = _checks.positive("speed", speed)
    if method not in _METHODS:
        raise InputError(f"method must be one of {sorted(_METHODS)}, got {method!r}")
    tol = _checks.positive("tol", tol)
    if max_iter is None:
        max_iter = _DEFAULT_MAX_ITER[method]
    max_iter = _checks.positive_int("max_iter", max_iter)
    block = _checks.positive_int("block", block)
    inner = _checks.positive_int("inner", inner)
    if product not in _PRODUCTS:
        raise InputError(f"product must be one of {sorted(_PRODUCTS)}, got {product!r}")
    tx, ty = start_tractions(grid, t0)
    if p[-2:, :].max() > 0.0:
        raise GridTooSmallError(_EDGE_MESSAGE)

    # one Fortran call (not resumable), in a worker thread so that Ctrl-C stops a long one;
    # a small one directly (it ends within DIRECT_CALL_WORK element sweeps)
    call = call_interruptibly if grid.nx * grid.ny * max_iter > DIRECT_CALL_WORK else call_directly
    status, sx, sy, iters, resid, info = call(
        workspace(grid, material, tangential=True),
        core.rolling_solve_c,
        p,
        grid.x0,
        grid.y0,
        xi,
        eta,
        phi,
        mu,
        speed,
        _METHODS[method],
        block,
        inner,
        tol,
        max_iter,
        _PRODUCTS[product],
        tx,
        ty,
    )
    if info == Status.GRID_EDGE:
        raise GridTooSmallError(_EDGE_MESSAGE)
    if info not in (Status.OK, Status.NOT_CONVERGED, Status.NO_CONTACT, Status.NOT_FINITE):
        raise error(info, "rolling contact solver failed internally", exc=RailvtiError)
    # one sum per field (needed anyway): a NaN or inf anywhere makes it non-finite, and
    # tractions (<= mu p) and slip velocities are far from overflowing a sum
    sums = float(tx.sum()) + float(ty.sum()) + float(sx.sum()) + float(sy.sum())
    if info == Status.NOT_FINITE or not math.isfinite(sums):
        raise ConvergenceError(
            f"rolling contact solver ({method}) produced non-finite values",
            iterations=int(iters),
            residual=float("inf"),
        )
    result = rolling_result(
        grid, p, (tx, ty), (sx, sy), status, mu, (xi, eta, phi), speed, method, int(iters), float(resid),
        info in (Status.OK, Status.NO_CONTACT), normal=normal, approach=approach,
    )  # fmt: skip
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"rolling contact solver ({method}) did not converge: residual {resid:.3g} > tol {tol:.3g} "
            f"after {iters} sweeps",
            iterations=int(iters),
            residual=float(resid),
            result=result,
        )
    log.debug(
        "solve_tangential %s: %d sweeps, residual %.3g, %d in contact", method, iters, resid, result.n_contact
    )
    return result


def solve_rolling(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    mu: float,
    fn: float,
    creepage: tuple[float, float, float],
    speed: float,
    method: str = "fftgs",
    tol: float = 1e-7,
    max_iter: int | None = None,
    t0: tuple | None = None,
    block: int = DEFAULT_BLOCK,
    inner: int = DEFAULT_INNER,
    normal_method: str = "cg",
    normal_tol: float = 1e-8,
    product: str = "auto",
) -> RollingResult:
    """Steady-state rolling contact: normal problem, then the tangential one.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Undeformed gap at the element centres, m.
    grid : Grid
        Potential contact area; x is the rolling direction.
    material : Material
        The bodies' common material (quasi-identical bodies).
    mu : float
        Coefficient of friction (>= 0; static = kinetic).
    fn : float
        Normal force, N (> 0).
    creepage : (xi, eta, phi)
        Longitudinal and lateral creepage (1) and spin (1/m). Rigid slip
        ``w = V (xi - phi y, eta + phi x)``.
    speed : float
        Rolling speed V, m/s (> 0). Scales the slip velocity and the power
        only; the tractions do not depend on it.
    method : {'fftgs', 'gs'}
        Both sweep the rows (lines along x) with exact in-row updates
        (row-implicit Gauss-Seidel, see ``fortran/contact/contact_rolling.f90``; a
        point Gauss-Seidel diverges on this system), accelerated by Anderson
        mixing of the sweeps (safeguarded). 'gs': one FFT refresh per sweep,
        direct updates of all later rows (O(N^2) per sweep, the reference);
        'fftgs': an FFT refresh every ``block`` rows, direct updates only
        inside the block: the fast method.
    tol : float
        Relative residual ``||F(t) - t|| / ||F(t)||`` at which to stop, F being
        the element solutions on the exact field.
    max_iter : int, optional
        Sweep limit (500 for 'gs', 2000 for 'fftgs').
    t0 : (tx, ty), optional
        Warm-start tractions, Pa, (nx, ny) each (put on the Coulomb disc first).
    block : int
        Rows per FFT refresh of 'fftgs'.
    inner : int
        Passes over each run of a row before the next row.
    product : {'auto', 'fft', 'direct'}
        How the displacement field u = A t is formed in each sweep: 'fft' by
        zero-padded FFT over the grid (the reference), 'direct' by direct sums
        over the contact set onto its bounding box, 'auto' the one with fewer
        operations (direct on small patches, e.g. 11 x 11 grids). The answers
        agree to rounding.
    normal_method, normal_tol
        Passed to :func:`~railvti.contact.solve_normal`.

    Returns
    -------
    RollingResult

    Raises
    ------
    InputError
        Bad arguments (named in the message): mu < 0, speed <= 0, NaN creepage, fn <= 0, ...
    GridTooSmallError
        The contact area reaches the grid edge.
    ConvergenceError
        The tolerance was not reached in max_iter sweeps; the unconverged
        result is attached as ``.result`` and the residual as ``.residual``.
    """
    mu = _checks.non_negative("mu", mu)
    fn = _checks.positive("fn", fn)
    creepage = _check_creepage(creepage)
    speed = _checks.positive("speed", speed)
    normal = solve_normal(gap, grid, material, fn=fn, method=normal_method, tol=normal_tol)
    return solve_tangential(
        normal.pressure,
        grid,
        material,
        mu,
        creepage,
        speed,
        method=method,
        tol=tol,
        max_iter=max_iter,
        t0=t0,
        block=block,
        inner=inner,
        normal=normal,
        approach=normal.approach,
        product=product,
    )


__all__ = [
    "DEFAULT_BLOCK",
    "DEFAULT_INNER",
    "DIRECT_CALL_WORK",
    "RollingResult",
    "rolling_result",
    "start_tractions",
    "solve_tangential",
    "solve_rolling",
]
