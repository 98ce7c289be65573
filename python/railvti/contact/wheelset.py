"""The loaded wheelset: normal (and rolling) contact in every patch of both wheels,
with the vertical load of each wheel prescribed.

Method. :func:`railvti.geometry.contact_points` gives the rigid pose (roll and height
from the constraint that both wheels touch) and the candidate contact points of each
wheel: the carrying point and any point within ``max_separation`` (e.g. the flange
before it touches). Around each point :func:`railvti.geometry.gap_field` gives the
undeformed gap h_k on a grid in its tangent plane. From the rigid pose the wheelset
moves down by w and rolls by theta (about the track x axis through its centre c); a
wheel point p then moves by u = (0, 0, -w) + theta e_x x (p - c), and the approach of
patch k (motion of the wheel towards the rail along the rail normal n_k) is linear:

    delta_k = -u . n_k = a_k w + b_k theta,
    a_k = n_k,z,   b_k = r_z n_k,y - r_y n_k,z,   r = p_k - c.

Two patches on one wheel thus share the wheel's motion. (w, theta) are found by
Newton's method such that each wheel's vertical load sum_k Fn_k n_k,z equals the
prescribed load; the Jacobian uses each patch's stiffness dFn/ddelta ~ 1.5 Fn /
(delta - min h), exact for Hertz. The gap fields stay those of the rigid pose (the
extra roll is a few mrad). Patches are independent half-spaces (no cross influence).
With ``mu`` and ``speed`` each loaded patch is then solved for steady rolling with its
rigid creepages (:func:`railvti.geometry.creepages`).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, GridTooSmallError, InputError, NoContactError
from ..geometry import ContactPoint, Creepages, WheelsetContact, contact_points, creepages, gap_field
from ..material import Material
from ..profiles import Profile
from .grid import Grid
from .hertz import hertz
from .normal import solve_normal
from .rolling import solve_tangential

log = logging.getLogger(__name__)

_LINE_HALF = 0.025   # m: half-length of the lateral line that sizes a patch's grid
_LINE_STEP = 1e-4    # m: its sampling
_GROW = 1.6          # the grid covers h < sep + _GROW * (expected approach)
_ROUND = 8          # grid sizes are multiples of this
_RIDGE = 5e-5        # m: the geometry merges minima joined by lower ridges into one point


@dataclass(frozen=True)
class WheelsetPatch:
    """One contact patch of a loaded wheelset.

    Forces act on the wheel. ``fn`` along the rail normal (into the wheel), ``fx``, ``fy``
    along the contact frame's ``t_x`` (rolling) and ``t_y`` (lateral, to the track's left).

    Attributes
    ----------
    side : str
        'left' or 'right'.
    contact : ContactPoint
        The candidate point (rigid pose) the patch grows from.
    contact_angle : float
        rad.
    creepage : Creepages or None
        Rigid creepages xi, eta (-) and spin phi (1/m); None without rolling.
    approach : float
        Approach of the patch along its normal, m.
    fn, fx, fy : float
        Forces on the wheel in the contact frame, N (fx = fy = 0 without rolling).
    force_track : ndarray (3,)
        The same force in track coordinates (x forward, y left, z up), N.
    pmax : float
        Largest pressure, Pa.
    n_contact : int
        Elements in contact.
    grid : Grid
        The patch's grid (x along t_x, y along t_y, origin at the contact point).
    gap, pressure : ndarray (nx, ny)
        Undeformed gap (m) and pressure (Pa).
    tx, ty : ndarray (nx, ny) or None
        Tangential tractions on the wheel, Pa; None without rolling.
    rolling : RollingResult or None
        The full steady-rolling result (slip, slip velocity, power density, power, ...).
    """

    side: str
    contact: ContactPoint
    contact_angle: float
    creepage: Creepages | None
    approach: float
    fn: float
    fx: float
    fy: float
    force_track: np.ndarray
    pmax: float
    n_contact: int
    grid: Grid
    gap: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray | None = None
    ty: np.ndarray | None = None
    rolling: object | None = None


@dataclass(frozen=True)
class WheelsetSolution:
    """Contact of a loaded wheelset at one position.

    Attributes
    ----------
    geometry : WheelsetContact
        The rigid-pose contact search (pose, candidate points, status per wheel).
    left, right : list of WheelsetPatch
        Loaded patches of each wheel (unloaded candidates are dropped).
    fz : tuple of float
        Vertical load carried by the left and right wheel, N (normal forces only).
    sink, roll : float
        Vertical motion w (m, down) and extra roll theta (rad) from the rigid pose.
    iterations : int
        Load-control Newton iterations.
    """

    geometry: WheelsetContact
    left: list[WheelsetPatch]
    right: list[WheelsetPatch]
    fz: tuple[float, float]
    sink: float
    roll: float
    iterations: int

    @property
    def patches(self) -> list[WheelsetPatch]:
        """All patches, left wheel first."""
        return self.left + self.right

    def wheel(self, side: str) -> list[WheelsetPatch]:
        """Patches of 'left' or 'right'."""
        if side not in ("left", "right"):
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.left if side == "left" else self.right


class _Patch:
    """Working state of one candidate patch during load control."""

    def __init__(self, cp: ContactPoint, centre: np.ndarray) -> None:
        self.cp = cp
        r = cp.position - centre
        n = cp.normal
        self.a = float(n[2])
        self.b = float(r[2] * n[1] - r[1] * n[2])
        self.grid: Grid | None = None
        self.gap: np.ndarray | None = None
        self.p: np.ndarray | None = None
        self.fn = 0.0
        self.approach = 0.0
        self.stiffness = 0.0
        self.pmax = 0.0
        self.n_contact = 0
        self.A = 1e-3          # gap coefficient along x (1/m), from the curvature fit
        self.reach = 0.0       # the grid covers h < separation + reach, m

    def delta(self, w: float, theta: float) -> float:
        return self.a * w + self.b * theta


def _curvature_fit(wheel: Profile, rail: Profile, cp: ContactPoint, s: float) -> tuple[float, float]:
    """Gap coefficients A, B of h ~ sep + A x^2 + B y^2 from a 3 x 3 stencil of spacing s."""
    g = gap_field(wheel, rail, cp, s, s, 3, 3).gap
    A = (g[0, 1] + g[2, 1] - 2.0 * g[1, 1]) / (2.0 * s * s)
    B = (g[1, 0] + g[1, 2] - 2.0 * g[1, 1]) / (2.0 * s * s)
    return A, B


def _round_up(n: int) -> int:
    return _ROUND * -(-n // _ROUND)


def _size_grid(wheel: Profile, rail: Profile, cp: ContactPoint, A: float, reach: float,
               dx: float, dy: float) -> tuple[Grid, np.ndarray]:
    """The grid over {h < sep + reach} around a candidate point, bounded laterally by the
    ridges to neighbouring points, with its gap field."""
    n_line = int(2 * _LINE_HALF / _LINE_STEP) + 1
    line = gap_field(wheel, rail, cp, dx, _LINE_STEP, 1, n_line, x0=0.0, y0=-_LINE_HALF).gap[0]
    yl = -_LINE_HALF + _LINE_STEP * np.arange(n_line)
    j0 = int(np.argmin(np.abs(yl)))
    limit = cp.separation + reach
    ends = []
    for step in (-1, 1):
        j = j0
        while 0 < j + step < n_line - 1 and line[j + step] < limit:
            if line[j + step] < line[j] - 1e-9 and line[j] > _RIDGE:
                break   # past a ridge to another candidate point: its own patch
            j += step
        ends.append(yl[j])
    y_lo, y_hi = ends[0] - 3 * dy, ends[1] + 3 * dy
    x_half = math.sqrt(max(reach, 1e-7) / max(A, 1e-3)) + 3 * dx
    # sizes rounded up to multiples of _ROUND so that sweeps reuse workspaces (FFT plans)
    nx = _round_up(2 * int(math.ceil(x_half / dx)) + 1)
    ny_raw = int(math.ceil((y_hi - y_lo) / dy)) + 1
    ny = _round_up(ny_raw)
    y_lo -= 0.5 * (ny - ny_raw) * dy
    x0 = -(nx - 1) / 2 * dx
    field = gap_field(wheel, rail, cp, dx, dy, nx, ny, x0=x0, y0=y_lo)
    return Grid(nx, ny, dx, dy, x0, y_lo), field.gap


def _solve_patch(wheel: Profile, rail: Profile, pt: _Patch, approach: float, material: Material,
                 dx: float, dy: float, method: str) -> None:
    """Normal solve of one patch at a prescribed approach; regrow its grid when the
    contact area reaches the edge."""
    pt.approach = approach
    for _ in range(6):
        if pt.gap is None or approach - pt.cp.separation > pt.reach:
            pt.reach = max(pt.reach, _GROW * (approach - pt.cp.separation))
            pt.grid, pt.gap = _size_grid(wheel, rail, pt.cp, pt.A, pt.reach, dx, dy)
            pt.p = None
        hmin = float(pt.gap.min())
        if approach <= hmin:
            pt.fn, pt.stiffness, pt.p = 0.0, 0.0, None
            return
        try:
            r = solve_normal(pt.gap, pt.grid, material, approach=approach, method=method, p0=pt.p)
        except NoContactError:
            pt.fn, pt.stiffness, pt.p = 0.0, 0.0, None
            return
        except GridTooSmallError:
            pt.reach *= 2.0
            pt.gap = None
            continue
        pt.p = r.pressure
        pt.fn = r.fn
        pt.pmax = r.pmax
        pt.n_contact = r.n_contact
        pt.stiffness = 1.5 * r.fn / max(approach - hmin, 1e-12)
        return
    raise GridTooSmallError(f"the {pt.cp.side} patch at y_rail = {pt.cp.y_rail * 1e3:.2f} mm outgrows "
                            "its grid: the load is too large for the contact geometry")


def solve_wheelset(wheel: Profile, rail: Profile, y: float, yaw: float, fz: float | tuple[float, float],
                   mu: float | None, speed: float | None, material: Material, dx: float, *,
                   dy: float | None = None, method: str = "cg", rolling_method: str | None = None,
                   track=None, wheelset=None, max_separation: float = 5e-3, load_tol: float = 1e-5,
                   max_iter: int = 30) -> WheelsetSolution:
    """Normal and steady-rolling contact of a loaded rigid wheelset on rigid rails.

    Parameters
    ----------
    wheel, rail : Profile
        Wheel and (canted) rail profiles, as for :func:`railvti.geometry.contact_points`.
    y : float
        Lateral shift of the wheelset, m (to the left).
    yaw : float
        Yaw angle, rad.
    fz : float or (float, float)
        Vertical load per wheel (left, right), N (> 0).
    mu : float or None
        Coulomb friction coefficient; None: normal contact only.
    speed : float or None
        Rolling speed, m/s (> 0); None: normal contact only.
    material : Material
        Wheel and rail material.
    dx : float
        Element size along the rolling direction, m.
    dy : float, optional
        Lateral element size, m (default dx).
    method : str
        Normal solver ('cg', 'pk', 'gs').
    rolling_method : str, optional
        Tangential solver of :func:`railvti.contact.solve_tangential` (its default if None).
    track, wheelset : optional
        Layout (see :func:`railvti.geometry.contact_points`).
    max_separation : float
        Candidate points up to this rigid separation are patches that may close, m.
    load_tol : float
        Relative tolerance on each wheel's vertical load.
    max_iter : int
        Newton iterations of the load control.

    Returns
    -------
    WheelsetSolution

    Raises
    ------
    InputError
        Bad arguments, or a wheel without any contact candidate.
    ConvergenceError
        The load control did not converge.
    GridTooSmallError
        A patch keeps outgrowing its grid.
    """
    y = _checks.finite("y", y)
    yaw = _checks.finite("yaw", yaw)
    fzs = (fz, fz) if np.ndim(fz) == 0 else tuple(fz)
    if len(fzs) != 2:
        raise InputError("fz must be one load or a (left, right) pair")
    fzs = tuple(_checks.positive("fz", f) for f in fzs)
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    dx = _checks.positive("dx", dx)
    dy = dx if dy is None else _checks.positive("dy", dy)
    rolling = mu is not None or speed is not None
    if rolling:
        if mu is None or speed is None:
            raise InputError("give both mu and speed for rolling contact, or neither")
        mu = _checks.non_negative("mu", mu)
        speed = _checks.positive("speed", speed)
    load_tol = _checks.positive("load_tol", load_tol)

    geo = contact_points(wheel, rail, y, yaw, track=track, wheelset=wheelset,
                         max_separation=max_separation)
    centre = geo.pose.centre
    sides = ("left", "right")
    patches = {s: [_Patch(cp, centre) for cp in geo.wheel(s)] for s in sides}
    for s in sides:
        if not patches[s]:
            raise InputError(f"the {s} wheel has no contact candidate at y = {y * 1e3:.2f} mm "
                             f"({geo.status[sides.index(s)]})")

    # Hertz estimate of each carrying patch's approach, for the start and the grid size
    s_fit = 5.0 * max(dx, dy)
    start = []
    for k, s in enumerate(sides):
        for pt in patches[s]:
            A, B = _curvature_fit(wheel, rail, pt.cp, s_fit)
            pt.A = max(A, 1e-3)
            ref = hertz(pt.A, max(B, 0.05 * pt.A, 1e-3), fzs[k] / max(pt.a, 0.2), material)
            pt.reach = _GROW * ref.approach
        carry = patches[s][0]
        start.append((carry, carry.reach / _GROW + carry.cp.separation))
    # (w, theta) that give the carrying points their Hertz approaches
    M = np.array([[pt.a, pt.b] for pt, _ in start])
    w, theta = np.linalg.solve(M, np.array([d for _, d in start]))

    it = 0
    fz_now = np.zeros(2)
    for it in range(1, max_iter + 1):
        J = np.zeros((2, 2))
        for k, s in enumerate(sides):
            fz_now[k] = 0.0
            for pt in patches[s]:
                _solve_patch(wheel, rail, pt, pt.delta(w, theta), material, dx, dy, method)
                fz_now[k] += pt.fn * pt.a
                J[k] += pt.stiffness * pt.a * np.array([pt.a, pt.b])
        err = fz_now - np.array(fzs)
        if np.all(np.abs(err) <= load_tol * np.array(fzs)):
            break
        if np.any(np.diag(J) <= 0.0) or abs(np.linalg.det(J)) < 1e-30:
            # a wheel lost contact: push both wheels down by the Hertz scale
            w += 0.5 * max(pt.reach for s in sides for pt in patches[s]) / _GROW
            continue
        step = np.linalg.solve(J, -err)
        w, theta = w + step[0], theta + step[1]
    else:
        raise ConvergenceError(f"wheelset load control did not converge: vertical loads {fz_now} N "
                               f"against {fzs} N after {max_iter} iterations",
                               iterations=max_iter, residual=float(np.max(np.abs(err) / np.array(fzs))))

    out = {}
    for s in sides:
        res = []
        for pt in patches[s]:
            if pt.fn <= 0.0:
                continue
            cp = pt.cp
            fx = fy = 0.0
            tx = ty = roll_res = cr = None
            if rolling:
                cr = creepages(cp, speed)
                kw = {} if rolling_method is None else {"method": rolling_method}
                # quasi-identical bodies: the tangential problem on the load-controlled pressure
                roll_res = solve_tangential(pt.p, pt.grid, material, mu, (cr.xi, cr.eta, cr.phi), speed,
                                            approach=pt.approach, **kw)
                fx, fy, tx, ty = roll_res.fx, roll_res.fy, roll_res.tx, roll_res.ty
            f_track = pt.fn * cp.normal + fx * cp.t_x + fy * cp.t_y
            res.append(WheelsetPatch(side=s, contact=cp, contact_angle=cp.contact_angle, creepage=cr,
                                     approach=pt.approach, fn=pt.fn, fx=fx, fy=fy, force_track=f_track,
                                     pmax=pt.pmax, n_contact=pt.n_contact, grid=pt.grid, gap=pt.gap,
                                     pressure=pt.p, tx=tx, ty=ty, rolling=roll_res))
        out[s] = res
    log.debug("solve_wheelset y=%.4g: %d iterations, loads %s", y, it, fz_now)
    return WheelsetSolution(geometry=geo, left=out["left"], right=out["right"],
                            fz=(float(fz_now[0]), float(fz_now[1])), sink=float(w), roll=float(theta),
                            iterations=it)
