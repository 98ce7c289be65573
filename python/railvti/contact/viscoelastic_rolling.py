"""Tangential steady rolling with viscoelastic bodies on the 3-D grid: creep forces.

The normal problem is :func:`railvti.contact.viscoelastic.solve_viscoelastic`; the tangential
one is the steady-rolling solver of contact_rolling (Kalker's upwind slip, row-implicit
Gauss-Seidel) run on a workspace whose Cerruti coefficients are filtered with each body's
creep function like the normal ones (eq. VE9 on kernels xx, yy, xy;
contact_viscoelastic_grid::visco_grid_kernels). The slip relation s = w - du/dx of steady
rolling holds for any material; only the coefficients change. Normal-tangential coupling is
neglected (exact for two bodies of one material, Kalker's quasi-identity otherwise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError
from ..material import Material
from .grid import Grid
from .rolling import DEFAULT_BLOCK, DEFAULT_INNER
from .viscoelastic import ViscoelasticMaterial, ViscoelasticResult, solve_viscoelastic


@dataclass(frozen=True)
class ViscoelasticRollingResult:
    """Steady rolling with viscoelastic bodies: the normal solution and the tangential one.

    Attributes
    ----------
    normal : ViscoelasticResult
        Pressure, contact, rolling resistance.
    tx, ty : ndarray, shape (nx, ny)
        Tangential tractions, Pa.
    status : ndarray of int, shape (nx, ny)
        0 exterior, 1 adhesion, 2 slip.
    fx, fy : float
        Creep forces, N.
    mz : float
        Spin moment about the grid's origin, N m.
    iterations : int
        Gauss-Seidel sweeps.
    residual : float
        Relative residual of the tangential solver.
    """

    normal: ViscoelasticResult
    tx: np.ndarray
    ty: np.ndarray
    status: np.ndarray
    fx: float
    fy: float
    mz: float
    iterations: int
    residual: float


def _body_moduli(body, name: str) -> tuple[float, float, float, float]:
    """(G0, Ginf, nu, tc) of a body: rigid (None) G0 = 0; elastic G, G, nu, 0."""
    if body is None:
        return 0.0, 0.0, 0.0, 0.0
    if isinstance(body, ViscoelasticMaterial):
        return body.shear_modulus, body.shear_modulus_relaxed, body.poisson, body.creep_time
    if isinstance(body, Material):
        return body.shear_modulus, body.shear_modulus, body.poisson, 0.0
    raise InputError(f"{name} must be a ViscoelasticMaterial, a Material or None (rigid), got {type(body)}")


def solve_viscoelastic_rolling(
    gap: np.ndarray,
    grid: Grid,
    fn: float,
    speed: float,
    creepage: tuple[float, float, float],
    mu: float,
    body1: ViscoelasticMaterial | Material | None,
    body2: ViscoelasticMaterial | Material | None = None,
    tol: float = 1e-7,
    max_iter: int = 2000,
    strip: bool = False,
) -> ViscoelasticRollingResult:
    """Steady rolling with viscoelastic bodies: pressure, tractions and creep forces.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Undeformed gap, m.
    grid : Grid
        The potential contact area.
    fn : float
        Normal force, N.
    speed : float
        Rolling speed V, m/s (> 0).
    creepage : tuple of float
        (xi, eta, phi): longitudinal, lateral creepage (1) and spin (1/m).
    mu : float
        Coulomb friction coefficient (> 0).
    body1, body2 : ViscoelasticMaterial, Material or None
        The bodies; None is rigid.
    tol, max_iter : float, int
        Tolerance and sweep limit of the tangential solver ('fftgs').
    strip : bool
        A band of long rows emulating plane strain (see :func:`solve_viscoelastic`).

    Returns
    -------
    ViscoelasticRollingResult

    Raises
    ------
    InputError
        A bad argument (named).
    GridTooSmallError
        The contact reaches the grid's edge.
    ConvergenceError
        A solver did not converge.
    """
    speed = _checks.positive("speed", speed)
    mu = _checks.positive("mu", mu)
    if len(tuple(creepage)) != 3:
        raise InputError("creepage must be (xi, eta, phi)")
    xi, eta, phi = (_checks.finite(n, v) for n, v in zip(("xi", "eta", "phi"), creepage))
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    normal = solve_viscoelastic(gap, grid, fn, speed, body1, body2, strip=strip)
    p = np.asfortranarray(normal.pressure)
    if p[-2:, :].max() > 0.0:
        raise GridTooSmallError("the contact reaches the last two rows at the leading edge: enlarge the grid")
    rows = [_body_moduli(body1, "body1"), _body_moduli(body2, "body2")]
    g0, ginf, nu = (np.array([r[k] for r in rows]) for k in range(3))
    vlen = np.array([speed * r[3] for r in rows])
    handle, info = core.visco_ws_create_c(grid.nx, grid.ny, grid.dx, grid.dy, g0, ginf, nu, vlen)
    if info != Status.OK:
        raise error(info, "viscoelastic workspace failed")
    tx = np.zeros(grid.shape, order="F")
    ty = np.zeros(grid.shape, order="F")
    try:
        status, _, _, iters, resid, info = core.rolling_solve_c(
            handle, p, grid.x0, grid.y0, xi, eta, phi, mu, speed, 2, DEFAULT_BLOCK, DEFAULT_INNER,
            tol, max_iter, 0, tx, ty,
        )  # fmt: skip
    finally:
        core.contact_ws_free_c(handle)
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"viscoelastic rolling: tangential solver not converged in {iters} sweeps",
            iterations=int(iters),
            residual=float(resid),
        )
    if info != Status.OK:
        raise error(info, "viscoelastic rolling: tangential solver failed")
    da = grid.element_area
    x, y = grid.mesh()
    fx, fy = float(tx.sum() * da), float(ty.sum() * da)
    if not math.isfinite(fx + fy):
        raise ConvergenceError("viscoelastic rolling: non-finite tractions", iterations=int(iters))
    return ViscoelasticRollingResult(
        normal=normal,
        tx=tx,
        ty=ty,
        status=np.asarray(status),
        fx=fx,
        fy=fy,
        mz=float(np.sum(x * ty - y * tx) * da),
        iterations=int(iters),
        residual=float(resid),
    )


__all__ = ["ViscoelasticRollingResult", "solve_viscoelastic_rolling"]
