"""The normal contact problem on a grid (Kaiser, sect. 4, eqs 17-23)."""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from ..errors import ConvergenceError, GridTooSmallError, InputError, NoContactError, RailvtiError
from ..material import Material
from .grid import Grid
from .workspace import workspace

log = logging.getLogger(__name__)

_METHODS = {"cg": 1, "gs": 2, "pk": 3}
_DEFAULT_MAX_ITER = {"cg": 2000, "gs": 20000, "pk": 2000}


@dataclass(frozen=True)
class NormalResult:
    """Solution of a normal contact problem.

    Attributes
    ----------
    grid : Grid
    pressure : ndarray, shape (nx, ny)
        Normal pressure, Pa (>= 0).
    fn : float
        Normal force, N.
    approach : float
        Approach of the two bodies, m.
    area : float
        Contact area, m^2.
    n_contact : int
        Elements in contact.
    iterations : int
        CG iterations or Gauss-Seidel sweeps.
    residual : float
        Relative complementarity residual reached.
    converged : bool
    method : str
        'cg', 'pk' or 'gs'.
    fft_products : int
        Convolution products used (CG only).
    """

    grid: Grid
    pressure: np.ndarray
    fn: float
    approach: float
    area: float
    n_contact: int
    iterations: int
    residual: float
    converged: bool
    method: str
    fft_products: int = 0

    @property
    def pmax(self) -> float:
        """Largest pressure, Pa."""
        return float(self.pressure.max())

    @property
    def contact(self) -> np.ndarray:
        """Boolean ``(nx, ny)`` mask of the elements in contact."""
        return self.pressure > 0.0


def _check_edges(p: np.ndarray) -> None:
    edges = {"x = x_min (i = 0)": p[0, :], "x = x_max (i = nx-1)": p[-1, :],
             "y = y_min (j = 0)": p[:, 0], "y = y_max (j = ny-1)": p[:, -1]}
    touched = [name for name, row in edges.items() if (row > 0.0).any()]
    if touched:
        raise GridTooSmallError(
            "the contact area reaches the grid edge at " + ", ".join(touched)
            + ": enlarge the grid (more elements or a larger extent)")


def solve_normal(gap: np.ndarray, grid: Grid, material: Material, fn: float | None = None,
                 approach: float | None = None, method: str = "cg", tol: float = 1e-8,
                 max_iter: int | None = None, p0: np.ndarray | None = None,
                 omega: float = 1.0) -> NormalResult:
    """Solve the normal contact problem for a given undeformed gap.

    Finds the pressure p >= 0 with deformed gap ``e = gap + A p - approach``
    zero where p > 0 and non-negative elsewhere (Kaiser eqs 21-23), A being
    the Boussinesq influence matrix applied by FFT.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Undeformed distance between the surfaces at the element centres, m.
    grid : Grid
        The potential contact area.
    material : Material
        The bodies' (common) material.
    fn : float, optional
        Prescribed normal force, N (> 0). Give exactly one of fn and approach.
    approach : float, optional
        Prescribed approach, m.
    method : {'cg', 'gs', 'pk'}
        'cg': projected conjugate gradients (Polonsky & Keer 1999) with FFT
        products and an FFT preconditioner M(k) = G |k| / (2 (1 - nu)), the
        inverse of the half-space's symbol; 'pk': the same without the
        preconditioner; 'gs': projected Gauss-Seidel (Kaiser eq. 23).
    tol : float
        Relative complementarity residual at which to stop.
    max_iter : int, optional
        Iteration (CG) or sweep (GS) limit; 2000 and 20000 by default.
    p0 : ndarray, shape (nx, ny), optional
        Warm start pressure, Pa.
    omega : float
        Gauss-Seidel relaxation factor in (0, 2).

    Returns
    -------
    NormalResult

    Raises
    ------
    InputError
        Bad arguments (named in the message).
    NoContactError
        The prescribed approach does not close the smallest gap.
    GridTooSmallError
        The contact area reaches the edge of the grid.
    ConvergenceError
        The tolerance was not reached in max_iter iterations.
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    h = _checks.finite_array("gap", gap, shape=grid.shape)
    if method not in _METHODS:
        raise InputError(f"method must be one of {sorted(_METHODS)}, got {method!r}")
    if (fn is None) == (approach is None):
        raise InputError("give exactly one of fn (force control) and approach (approach control)")
    if fn is not None:
        fn = _checks.positive("fn", fn)
        control, fn_in, app_in = 1, fn, 0.0
    else:
        approach = _checks.finite("approach", approach)
        if approach <= float(h.min()):
            raise NoContactError(
                f"no contact: the approach {approach:.6g} m does not exceed the smallest gap {h.min():.6g} m")
        control, fn_in, app_in = 2, 0.0, approach
    tol = _checks.positive("tol", tol)
    if max_iter is None:
        max_iter = _DEFAULT_MAX_ITER[method]
    max_iter = _checks.positive_int("max_iter", max_iter)
    omega = _checks.positive("omega", omega)
    if omega >= 2.0:
        raise InputError(f"omega must lie in (0, 2), got {omega}")
    if p0 is None:
        p = np.zeros(grid.shape, order="F")
    else:
        p = _checks.finite_array("p0", p0, shape=grid.shape)
        if (p < 0.0).any():
            raise InputError("p0 must be >= 0 everywhere")

    fn_out, app_out, iters, nprod, resid, info = core.normal_solve_c(
        workspace(grid, material), h, control, _METHODS[method], tol, max_iter, omega, fn_in, app_in, p)
    if info == 2:
        raise NoContactError("no contact: the approach does not exceed the smallest gap")
    if info < 0:
        raise RailvtiError(f"normal contact solver failed internally (info={info})")
    if not (np.isfinite(p).all() and np.isfinite(fn_out) and np.isfinite(app_out)):
        raise ConvergenceError(f"normal contact solver ({method}) diverged to non-finite values",
                               iterations=int(iters), residual=float(resid))
    n_contact = int((p > 0.0).sum())
    result = NormalResult(grid=grid, pressure=p, fn=float(fn_out), approach=float(app_out),
                          area=n_contact * grid.element_area, n_contact=n_contact,
                          iterations=int(iters), residual=float(resid), converged=info == 0,
                          method=method, fft_products=int(nprod))
    if info == 1:
        raise ConvergenceError(
            f"normal contact solver ({method}) did not converge: residual {resid:.3g} > tol {tol:.3g} "
            f"after {iters} iterations", iterations=int(iters), residual=float(resid), result=result)
    _check_edges(p)
    log.debug("solve_normal %s: %d iterations, residual %.3g, %d in contact", method, iters, resid, n_contact)
    return result
