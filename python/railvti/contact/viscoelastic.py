"""Steady rolling of viscoelastic bodies (standard linear solid): the normal problem of a line
(plane-strain) contact, its pressure asymmetry and rolling resistance (docs/contact_viscoelastic.md).

Each body is rigid (``None``), elastic (:class:`railvti.Material`) or a standard linear solid
(:class:`ViscoelasticMaterial`). The kernel (``contact_viscoelastic``) filters the elastic
influence of each strip along the rolling direction with the body's creep function, in
closed form, and solves the non-symmetric normal problem by an active-set iteration.
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

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ViscoelasticMaterial:
    """A standard linear solid (three-parameter model) in shear, Poisson's ratio constant.

    The shear relaxation modulus is ``G(t) = Ginf + (G0 - Ginf) exp(-t / relaxation_time)``;
    the creep compliance ``J(t) = 1/G0 + (1/Ginf - 1/G0)(1 - exp(-t / tc))`` has the creep
    (retardation) time ``tc = relaxation_time G0 / Ginf``. ``Ginf = G0`` is an elastic body.
    A Maxwell body (Ginf = 0) creeps without bound and has no steady rolling state on a
    half-space: it is refused.

    Parameters
    ----------
    shear_modulus : float
        Instantaneous (glassy) shear modulus G0, Pa (> 0).
    shear_modulus_relaxed : float
        Long-term (rubbery) shear modulus Ginf, Pa, 0 < Ginf <= G0.
    relaxation_time : float
        Relaxation time of G(t), s (> 0).
    poisson : float
        Poisson's ratio nu, in (-1, 0.5).
    """

    shear_modulus: float
    shear_modulus_relaxed: float
    relaxation_time: float
    poisson: float

    def __post_init__(self) -> None:
        g0 = _checks.positive("shear_modulus", self.shear_modulus)
        ginf = _checks.positive("shear_modulus_relaxed", self.shear_modulus_relaxed)
        tau = _checks.positive("relaxation_time", self.relaxation_time)
        nu = _checks.finite("poisson", self.poisson)
        if not -1.0 < nu < 0.5:
            raise InputError(f"poisson must lie in (-1, 0.5), got {nu}")
        if ginf > g0:
            raise InputError(
                f"shear_modulus_relaxed ({ginf:g} Pa) must not exceed shear_modulus ({g0:g} Pa): "
                "a standard linear solid relaxes"
            )
        for name, value in (
            ("shear_modulus", g0),
            ("shear_modulus_relaxed", ginf),
            ("relaxation_time", tau),
            ("poisson", nu),
        ):
            object.__setattr__(self, name, value)

    @property
    def creep_time(self) -> float:
        """Creep (retardation) time tc = relaxation_time G0 / Ginf, s."""
        return self.relaxation_time * self.shear_modulus / self.shear_modulus_relaxed

    @property
    def compliance_instant(self) -> float:
        """Plane-strain contact compliance (1 - nu^2)/E = (1 - nu)/(2 G0) at t = 0, 1/Pa."""
        return (1.0 - self.poisson) / (2.0 * self.shear_modulus)

    @property
    def compliance_relaxed(self) -> float:
        """The same with the relaxed modulus Ginf, 1/Pa."""
        return (1.0 - self.poisson) / (2.0 * self.shear_modulus_relaxed)


def body_compliances(body: ViscoelasticMaterial | Material | None, name: str) -> tuple[float, float, float]:
    """(J0, Jinf, tc) of one body: rigid (None) 0, 0, 0; elastic J, J, 0 with
    J = (1 - nu)/(2 G); a standard linear solid its instantaneous and relaxed compliances and
    creep time (1/Pa, 1/Pa, s)."""
    if body is None:
        return 0.0, 0.0, 0.0
    if isinstance(body, ViscoelasticMaterial):
        return body.compliance_instant, body.compliance_relaxed, body.creep_time
    if isinstance(body, Material):
        j = (1.0 - body.poisson) / (2.0 * body.shear_modulus)
        return j, j, 0.0
    raise InputError(f"{name} must be a ViscoelasticMaterial, a Material or None (rigid), got {type(body)}")


def _bodies(body1, body2, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel's per-body arrays j0, jinf (1/Pa) and vlen = V tc (m)."""
    rows = [body_compliances(body1, "body1"), body_compliances(body2, "body2")]
    j0 = np.array([r[0] for r in rows])
    jinf = np.array([r[1] for r in rows])
    vlen = np.array([speed * r[2] for r in rows])
    if not (jinf > 0.0).any():
        raise InputError("body1 and body2 are both rigid: at least one must deform")
    return j0, jinf, vlen


@dataclass(frozen=True)
class ViscoelasticLineResult:
    """Steady rolling of a viscoelastic line contact (per unit length along the axle).

    Attributes
    ----------
    x : ndarray, shape (n,)
        Strip centres, m (x in the rolling direction, origin below the axle; the leading
        edge is at the larger x).
    pressure : ndarray, shape (n,)
        Pressure, Pa.
    displacement : ndarray, shape (n,)
        Sum of the bodies' surface displacements A p, m.
    fn : float
        Load per unit length, N/m.
    approach : float
        Approach, m, relative to surface points at ``reference_length`` from the load.
    x_trailing, x_leading : float
        Contact edges (outer edges of the end strips in contact), m.
    centroid : float
        Pressure centroid e = sum p x / sum p, m (> 0: ahead of the axle).
    moment : float
        fn e, the pressure's moment about the axle's line, N m/m.
    resistance_coefficient : float
        mu_R = e / R, the rolling-resistance force over the load (rigid roller).
    hertz_half_width_instant, hertz_half_width_relaxed : float
        Hertz half-widths with the instantaneous and with the relaxed compliances, m.
    iterations : int
        Active-set iterations.
    residual : float
        Relative complementarity residual reached.
    """

    x: np.ndarray
    pressure: np.ndarray
    displacement: np.ndarray
    fn: float
    approach: float
    x_trailing: float
    x_leading: float
    centroid: float
    moment: float
    resistance_coefficient: float
    hertz_half_width_instant: float
    hertz_half_width_relaxed: float
    iterations: int
    residual: float

    @property
    def pmax(self) -> float:
        """Largest pressure, Pa."""
        return float(self.pressure.max())


def line_hertz_half_width(radius: float, fn: float, compliance: float) -> float:
    """Half-width a = sqrt(4 fn R J / pi) of a plane-strain Hertz contact, m (J = 1/E*)."""
    return math.sqrt(4.0 * fn * radius * compliance / math.pi)


def solve_viscoelastic_line(
    radius: float,
    fn: float,
    speed: float,
    body1: ViscoelasticMaterial | Material | None,
    body2: ViscoelasticMaterial | Material | None = None,
    n: int = 400,
    half_length: float | None = None,
    reference_length: float | None = None,
    tol: float = 1e-10,
    max_iter: int = 200,
) -> ViscoelasticLineResult:
    """Steady rolling of a cylinder on a half-space (or two cylinders), plane strain, with
    viscoelastic bodies: pressure, contact shift and rolling resistance.

    The gap is ``x^2 / (2 R)``; the bodies' surface particles pass through the contact in -x
    at the speed V, each body's displacement being the hereditary integral of its creep
    function over the elastic field (docs/equations.md, eqs VE1-VE4).

    Parameters
    ----------
    radius : float
        Combined radius R, 1/R = 1/R1 + 1/R2, m.
    fn : float
        Load per unit length, N/m.
    speed : float
        Rolling speed V, m/s (>= 0; 0 gives the relaxed, elastic response).
    body1, body2 : ViscoelasticMaterial, Material or None
        The bodies; None is rigid. Default: body2 rigid.
    n : int
        Strips of the grid (>= 8).
    half_length : float, optional
        The grid covers [-half_length, half_length], m. Default: 1.5 times the relaxed
        Hertz half-width.
    reference_length : float, optional
        Distance from a line load at which the surface is taken as fixed (fixes the 2-D
        approach; no other result depends on it), m. Default: R.
    tol : float
        Interpenetration allowed outside the contact, relative to the deformation.
    max_iter : int
        Active-set iteration limit.

    Returns
    -------
    ViscoelasticLineResult

    Raises
    ------
    InputError
        A bad argument (named), or both bodies rigid.
    GridTooSmallError
        The contact reaches the end of the grid.
    ConvergenceError
        The active-set iteration did not settle in max_iter iterations.
    """
    radius = _checks.positive("radius", radius)
    fn = _checks.positive("fn", fn)
    speed = _checks.non_negative("speed", speed)
    n = _checks.positive_int("n", n, minimum=8)
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    j0, jinf, vlen = _bodies(body1, body2, speed)
    a0 = line_hertz_half_width(radius, fn, float(j0.sum())) if j0.sum() > 0 else 0.0
    a_inf = line_hertz_half_width(radius, fn, float(jinf.sum()))
    half = 1.5 * a_inf if half_length is None else _checks.positive("half_length", half_length)
    ell = radius if reference_length is None else _checks.positive("reference_length", reference_length)
    d = 2.0 * half / n
    x = -half + d * (np.arange(n) + 0.5)
    h = x * x / (2.0 * radius)
    p = np.zeros(n)
    u, approach, iters, resid, info = core.visco_line_solve_c(d, h, j0, jinf, vlen, ell, fn, tol, max_iter, p)
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"viscoelastic line contact: the active set did not settle in {max_iter} iterations",
            iterations=int(iters),
            residual=float(resid),
        )
    if info != Status.OK:
        raise error(info, "viscoelastic line contact solver failed")
    if p[0] > 0.0 or p[-1] > 0.0:
        raise GridTooSmallError(
            f"the contact reaches the end of the grid (half_length = {half:.4g} m): enlarge half_length"
        )
    inside = np.flatnonzero(p > 0.0)
    e = float(np.dot(p, x) / p.sum())
    log.debug("viscoelastic line: %d active-set iterations, residual %.3g", iters, resid)
    return ViscoelasticLineResult(
        x=x,
        pressure=p,
        displacement=u,
        fn=float(p.sum() * d),
        approach=float(approach),
        x_trailing=float(x[inside[0]] - 0.5 * d),
        x_leading=float(x[inside[-1]] + 0.5 * d),
        centroid=e,
        moment=float(fn * e),
        resistance_coefficient=e / radius,
        hertz_half_width_instant=a0,
        hertz_half_width_relaxed=a_inf,
        iterations=int(iters),
        residual=float(resid),
    )


@dataclass(frozen=True)
class ViscoelasticResult:
    """Steady rolling of a viscoelastic point contact on the 3-D grid (normal problem).

    Attributes
    ----------
    grid : Grid
    pressure : ndarray, shape (nx, ny)
        Pressure, Pa.
    displacement : ndarray, shape (nx, ny)
        Sum of the bodies' surface displacements C * p, m.
    fn : float
        Normal force, N.
    approach : float
        Approach of distant points, m.
    area : float
        Contact area, m^2.
    n_contact : int
        Elements in contact.
    centroid : float
        Pressure centroid along x, sum p x / sum p, m (> 0: ahead of the origin).
    resistance_force : float
        Rolling-resistance force sum p dh/dx dA, N: the horizontal component of the pressure
        on the inclined undeformed surface of the gap (2 A fn e for the gap A x^2 + B y^2).
    resistance_coefficient : float
        resistance_force / fn.
    iterations : int
        Active-set iterations.
    fft_products : int
        FFT products (GMRES steps and checks).
    residual : float
        Relative complementarity residual reached.
    """

    grid: Grid
    pressure: np.ndarray
    displacement: np.ndarray
    fn: float
    approach: float
    area: float
    n_contact: int
    centroid: float
    resistance_force: float
    resistance_coefficient: float
    iterations: int
    fft_products: int
    residual: float

    @property
    def pmax(self) -> float:
        """Largest pressure, Pa."""
        return float(self.pressure.max())


def _relaxed_start(h: np.ndarray, grid: Grid, fn: float, jinf: float) -> np.ndarray:
    """The start set of the active-set iteration: the contact of the relaxed elastic pair
    (compliance jinf, solved coarsely by solve_normal's CG; it holds the viscoelastic contact
    but for a few elements), or all elements if that solve fails. Saves ~30 % of the time."""
    try:
        r = solve_normal(h, grid, Material(shear_modulus=1.0 / jinf, poisson=0.0), fn=fn, tol=1e-6)
    except RailvtiError:
        return np.zeros(grid.shape, order="F")
    return np.asfortranarray(r.pressure)


def solve_viscoelastic(
    gap: np.ndarray,
    grid: Grid,
    fn: float,
    speed: float,
    body1: ViscoelasticMaterial | Material | None,
    body2: ViscoelasticMaterial | Material | None = None,
    tol: float = 1e-10,
    max_iter: int = 100,
    strip: bool = False,
) -> ViscoelasticResult:
    """Steady rolling of a point contact with viscoelastic bodies on the BEM grid: pressure,
    contact shifted forward, rolling resistance.

    Each body's Boussinesq influence coefficients are filtered along x with its creep
    function (the surface particles pass through the contact in -x at the speed V), exactly
    to quadrature (docs/equations.md, eqs VE9-VE10); the non-symmetric normal problem is
    solved by an active-set iteration with GMRES steps and FFT products.

    Parameters
    ----------
    gap : ndarray, shape (nx, ny)
        Undeformed gap at the element centres, m.
    grid : Grid
        The potential contact area.
    fn : float
        Normal force, N.
    speed : float
        Rolling speed V, m/s (>= 0; 0 gives the relaxed, elastic response).
    body1, body2 : ViscoelasticMaterial, Material or None
        The bodies; None is rigid. Two elastic bodies of one Material give
        :func:`railvti.contact.solve_normal`'s problem.
    tol : float
        Interpenetration allowed outside the contact, relative to the deformation.
    max_iter : int
        Active-set iteration limit.
    strip : bool
        The grid is a band of long rows emulating plane strain (the gap uniform in y): the
        contact may then reach the lateral edges; only the edges in x are checked.

    Returns
    -------
    ViscoelasticResult

    Raises
    ------
    InputError
        A bad argument (named), or both bodies rigid.
    GridTooSmallError
        The contact reaches the edge of the grid.
    ConvergenceError
        The active-set iteration or a GMRES solve did not converge.
    """
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    h = _checks.finite_array("gap", gap, shape=grid.shape)
    fn = _checks.positive("fn", fn)
    speed = _checks.non_negative("speed", speed)
    tol = _checks.positive("tol", tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    j0, jinf, vlen = _bodies(body1, body2, speed)
    p = _relaxed_start(h, grid, fn, float(jinf.sum()))
    u, approach, iters, nprod, resid, info = core.visco_grid_solve_c(
        grid.dx, grid.dy, h, j0, jinf, vlen, fn, tol, max_iter, p
    )
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"viscoelastic contact: not converged after {iters} active-set iterations",
            iterations=int(iters),
            residual=float(resid),
        )
    if info != Status.OK:
        raise error(info, "viscoelastic contact solver failed")
    if p[0, :].any() or p[-1, :].any() or (not strip and (p[:, 0].any() or p[:, -1].any())):
        raise GridTooSmallError("the contact area reaches the grid edge: enlarge the grid")
    x = grid.x
    e = float(np.dot(p.sum(axis=1), x) / p.sum())
    dhdx = np.gradient(h, grid.dx, axis=0)
    force = float(np.sum(p * dhdx) * grid.element_area)
    n_contact = int((p > 0.0).sum())
    return ViscoelasticResult(
        grid=grid,
        pressure=p,
        displacement=u,
        fn=float(p.sum() * grid.element_area),
        approach=float(approach),
        area=n_contact * grid.element_area,
        n_contact=n_contact,
        centroid=e,
        resistance_force=force,
        resistance_coefficient=force / fn,
        iterations=int(iters),
        fft_products=int(nprod),
        residual=float(resid),
    )


def line_kernel(
    n: int,
    d: float,
    speed: float,
    body1: ViscoelasticMaterial | Material | None,
    body2: ViscoelasticMaterial | Material | None = None,
    reference_length: float = 1.0,
) -> np.ndarray:
    """The line contact's influence coefficients k(m), m = -(n-1)..n-1 (index m + n - 1):
    the displacement at offset m d from a strip of width d under unit pressure, m/Pa."""
    n = _checks.positive_int("n", n)
    d = _checks.positive("d", d)
    speed = _checks.non_negative("speed", speed)
    ell = _checks.positive("reference_length", reference_length)
    j0, jinf, vlen = _bodies(body1, body2, speed)
    k, info = core.visco_line_kernel_c(n, d, j0, jinf, vlen, ell)
    if info != Status.OK:
        raise error(info, "viscoelastic line kernel failed")
    return k


def grid_coefficients(
    grid: Grid,
    speed: float,
    body1: ViscoelasticMaterial | Material | None,
    body2: ViscoelasticMaterial | Material | None = None,
) -> np.ndarray:
    """The 3-D grid's influence coefficients of the pair in steady rolling, m/Pa, in the
    circular layout of :func:`railvti.contact.influence_field` (shape (2 nx, 2 ny); offset
    (k, l) at index (k mod 2nx, l mod 2ny)): sum_b J0_b ce + (Jinf_b - J0_b) cf_b (eq. VE9)."""
    if not isinstance(grid, Grid):
        raise InputError("grid must be a railvti.contact.Grid")
    speed = _checks.non_negative("speed", speed)
    j0, jinf, vlen = _bodies(body1, body2, speed)
    c, info = core.visco_grid_coefficients_c(grid.nx, grid.ny, grid.dx, grid.dy, j0, jinf, vlen)
    if info != Status.OK:
        raise error(info, "viscoelastic grid coefficients failed")
    return c


__all__ = [
    "ViscoelasticMaterial",
    "ViscoelasticLineResult",
    "ViscoelasticResult",
    "body_compliances",
    "grid_coefficients",
    "line_hertz_half_width",
    "line_kernel",
    "solve_viscoelastic",
    "solve_viscoelastic_line",
]
