"""One contact patch of a loaded wheelset while its wheelset is being balanced: the grid
around a candidate point, the normal solve at a prescribed approach (regrowing the grid when
the contact area reaches its edge) and the steady-rolling solve with the patch's rigid slip.

Used by :mod:`railvti.contact.wheelset`. Implements no equation of the paper itself (the
normal and tangential kernels do: eqs 17-29).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import GridTooSmallError, NoContactError
from ..geometry import ContactPoint, WheelsetPose, gap_field
from ..material import Material
from ..profiles import Profile
from .grid import Grid
from .normal import SubPatches, solve_normal
from .rolling import RollingResult, solve_tangential
from .workspace import workspace
from .wheelset_kinematics import RigidSlip, WheelsetMotion, rigid_slip

_LINE_HALF = 0.025  # m: half-length of the lateral line that sizes a patch's grid
_LINE_STEP = 1e-4  # m: its sampling
#: The grid covers h < sep + GROW * (expected approach).
GROW = 1.15
_ROUND = 8  # grid sizes are multiples of this
_MARGIN = 3  # elements between {h < sep + reach} and the grid's edge
_RIDGE = 5e-5  # m: the geometry merges minima joined by lower ridges into one point


class PatchState:
    """Working state of one candidate patch during the balance of its wheelset.

    The approach of the patch is ``grad @ u`` for the wheelset's unknown motion ``u``
    (sink and roll, or one sink per half wheelset); its vertical force is ``fn * vertical``.
    ``cp`` is the patch's reference point (grid origin and contact frame, where the creepages
    are taken); ``seed`` the candidate point of smallest gap it grew from (the same point,
    or the patch's point before it moved to CONTACT's reference). ``loaded``: the loaded pose
    the creepages are evaluated at (CONTACT's reference), or None (the rigid pose).
    """

    def __init__(
        self,
        cp: ContactPoint,
        side_index: int,
        grad: np.ndarray,
        seed: ContactPoint | None = None,
        loaded: WheelsetPose | None = None,
    ) -> None:
        self.cp = cp
        self.seed = cp if seed is None else seed
        self.loaded = loaded
        self.side_index = side_index
        self.grad = np.asarray(grad, dtype=float)
        self.vertical = float(cp.normal[2])  # vertical force per unit Fn (normal force alone at first)
        self.grid: Grid | None = None
        self.gap: np.ndarray | None = None
        self.p: np.ndarray | None = None
        self.fn = 0.0
        self.approach = 0.0
        self.stiffness = 0.0
        self.pmax = 0.0
        self.n_contact = 0
        self.A = 1e-3  # gap coefficient along x (1/m), from the curvature fit
        self.reach = 0.0  # the grid covers h < separation + reach, m
        self.last: tuple[float, float] | None = None  # (approach, fn) of the last loaded solve
        self.slip: RigidSlip | None = None
        self.rolling: RollingResult | None = None
        #: CONTACT's sub-patches (reduced interaction of its areas in the normal problem), or None
        self.subpatches: SubPatches | None = None

    @property
    def carrying(self) -> bool:
        """The patch carries load."""
        return self.fn > 0.0

    def force(self) -> np.ndarray:
        """Resultant force on the wheel, track coordinates, N."""
        cp = self.cp
        fx, fy = (
            (self.rolling.fx, self.rolling.fy) if self.rolling is not None and self.carrying else (0.0, 0.0)
        )
        return self.fn * cp.normal + fx * cp.t_x + fy * cp.t_y

    def centre_of_pressure(self) -> tuple[float, float]:
        """(x, y) of the pressure's centre in the contact frame, m (0, 0 without load)."""
        if not self.carrying or self.p is None:
            return 0.0, 0.0
        x, y = self.grid.mesh()
        total = float(self.p.sum())
        return float((x * self.p).sum() / total), float((y * self.p).sum() / total)


def curvature_fit(wheel: Profile, rail: Profile, cp: ContactPoint, s: float) -> tuple[float, float]:
    """Gap coefficients A, B of h ~ sep + A x^2 + B y^2 from a 3 x 3 stencil of spacing s."""
    g = gap_field(wheel, rail, cp, s, s, 3, 3).gap
    A = (g[0, 1] + g[2, 1] - 2.0 * g[1, 1]) / (2.0 * s * s)
    B = (g[1, 0] + g[1, 2] - 2.0 * g[1, 1]) / (2.0 * s * s)
    return A, B


def _round_up(n: int) -> int:
    return _ROUND * -(-n // _ROUND)


def _lateral_extent(line: np.ndarray, j0: int, limit: float) -> tuple[int, int]:
    """Indices of the outermost line points with gap < ``limit`` that are reached from j0
    without crossing a ridge higher than _RIDGE (the geometry's rule for one patch): a second
    valley behind a low ridge that dips below the limit belongs to this patch."""
    ends = []
    for step in (-1, 1):
        j = last = j0
        ceiling = max(limit, _RIDGE)
        while 0 < j + step < line.size - 1 and line[j + step] < ceiling:
            if line[j + step] < line[j] - 1e-9 and line[j] > _RIDGE:
                break  # past a ridge to another candidate point: its own patch
            j += step
            if line[j] < limit:
                last = j
        ends.append(last)
    return ends[0], ends[1]


def _centred_range(lo: float, hi: float, h: float) -> tuple[int, float]:
    """Elements (a multiple of _ROUND) covering [lo, hi] with centres at (m + 1/2) h, the
    padding shared by both ends: their number and the first centre."""
    m_lo, m_hi = math.floor(lo / h - 0.5), math.ceil(hi / h - 0.5)
    n = _round_up(m_hi - m_lo + 1)
    m_lo -= (n - (m_hi - m_lo + 1)) // 2
    return n, (m_lo + 0.5) * h


def _size_grid(
    wheel: Profile,
    rail: Profile,
    cp: ContactPoint,
    A: float,
    reach: float,
    dx: float,
    dy: float,
    seed: ContactPoint | None = None,
) -> tuple[Grid, np.ndarray]:
    """The grid over {h < sep + reach} around a candidate point, bounded laterally by the
    ridges to neighbouring points, with its gap field. Element centres lie at odd multiples
    of dx/2, dy/2 from the reference point whatever the grid's size (results do not move
    when a grid is regrown). With a ``seed`` other than ``cp`` (CONTACT's reference point
    ``cp`` of the patch grown from the point of smallest gap ``seed``), the grid lies in
    cp's plane and is sized around the seed's place in it."""
    ex = ey = 0.0
    if seed is not None and seed is not cp:
        d = seed.position - cp.position
        ex, ey = float(d @ cp.t_x), float(d @ cp.t_y)
    n_line = int(2 * _LINE_HALF / _LINE_STEP) + 1
    line = gap_field(wheel, rail, cp, dx, _LINE_STEP, 1, n_line, x0=ex, y0=ey - _LINE_HALF).gap[0]
    yl = ey - _LINE_HALF + _LINE_STEP * np.arange(n_line)
    j_lo, j_hi = _lateral_extent(line, int(np.argmin(np.abs(yl - ey))), cp.separation + reach)
    y_lo, y_hi = yl[j_lo] - _MARGIN * dy, yl[j_hi] + _MARGIN * dy
    x_half = math.sqrt(max(reach, 1e-7) / max(A, 1e-3)) + _MARGIN * dx
    # sizes rounded up to multiples of _ROUND so that sweeps reuse workspaces (FFT plans)
    if ex == 0.0:
        nx = _round_up(2 * int(math.ceil(x_half / dx)))
        x0 = -(nx - 1) / 2 * dx
    else:
        nx, x0 = _centred_range(min(ex, 0.0) - x_half, max(ex, 0.0) + x_half, dx)
    ny, y0 = _centred_range(y_lo, y_hi, dy)
    field = gap_field(wheel, rail, cp, dx, dy, nx, ny, x0=x0, y0=y0)
    return Grid(nx, ny, dx, dy, x0, y0), field.gap


def solve_patch_normal(
    wheel: Profile,
    rail: Profile,
    pt: PatchState,
    approach: float,
    material: Material,
    dx: float,
    dy: float,
    method: str,
    rolling: bool = False,
) -> None:
    """Normal solve of one patch at a prescribed approach (warm-started from its last
    pressure); regrow its grid when the contact area reaches the edge. A patch already
    solved at this approach is left as it is. ``rolling``: the patch will be rolled too, so
    its grid gets the workspace that serves both solves at once."""
    if pt.last is not None and pt.p is not None and approach == pt.approach:
        return
    pt.approach = approach
    for _ in range(6):
        if pt.gap is None or approach - pt.cp.separation > pt.reach:
            pt.reach = max(pt.reach, GROW * (approach - pt.cp.separation))
            pt.grid, pt.gap = _size_grid(wheel, rail, pt.cp, pt.A, pt.reach, dx, dy, pt.seed)
            if rolling:
                workspace(pt.grid, material, tangential=True)
            pt.p = None
            pt.rolling = None
            pt.last = None
        hmin = float(pt.gap.min())
        if approach <= hmin:
            pt.fn, pt.stiffness, pt.p, pt.last = 0.0, 0.0, None, None
            return
        try:
            r = solve_normal(
                pt.gap, pt.grid, material, approach=approach, method=method, p0=pt.p, subpatches=pt.subpatches
            )
        except NoContactError:
            pt.fn, pt.stiffness, pt.p, pt.last = 0.0, 0.0, None, None
            return
        except GridTooSmallError:
            pt.reach *= 2.0
            pt.gap = None
            continue
        pt.p = r.pressure
        pt.stiffness = 1.5 * r.fn / max(approach - hmin, 1e-12)  # Hertz: Fn ~ (delta - hmin)^1.5
        if pt.last is not None and abs(approach - pt.last[0]) > 1e-4 * (approach - hmin):
            secant = (r.fn - pt.last[1]) / (approach - pt.last[0])
            if secant > 0.0:
                pt.stiffness = secant
        pt.last = (approach, r.fn)
        pt.fn = r.fn
        pt.pmax = r.pmax
        pt.n_contact = r.n_contact
        return
    raise GridTooSmallError(
        f"the {pt.cp.side} patch at y_rail = {pt.cp.y_rail * 1e3:.2f} mm outgrows "
        "its grid: the load is too large for the contact geometry"
    )


def solve_patch_rolling(
    pt: PatchState,
    material: Material,
    mu: float,
    motion: WheelsetMotion,
    omega: float,
    method: str | None,
    tol: float = 1e-7,
) -> None:
    """Steady rolling of a loaded patch on its pressure (quasi-identical bodies), with the
    rigid slip of the wheelset's motion at its reference point; started from the patch's last
    tractions on the same grid, or from full slip."""
    pt.slip = rigid_slip(pt.cp, motion, omega, loaded=pt.loaded, approach=pt.approach)
    if not pt.carrying:
        pt.rolling = None
        return
    c = pt.slip.creepage
    kw = {} if method is None else {"method": method}
    if pt.rolling is not None and pt.rolling.grid == pt.grid:
        # the last tractions, scaled by the change of pressure (exact for the slip area)
        old = pt.rolling.pressure
        scale = np.divide(pt.p, old, out=np.zeros_like(old), where=old > 0.0)
        t0 = (pt.rolling.tx * scale, pt.rolling.ty * scale)
    else:
        # full slip against the rigid slip w = (xi - phi y, eta + phi x): half the sweeps of a
        # start from zero in the patches (most of them slide entirely)
        x, y = pt.grid.mesh()
        wx, wy = c.xi - c.phi * y, c.eta + c.phi * x
        bound = mu * pt.p / np.maximum(np.hypot(wx, wy), 1e-300)
        t0 = (-bound * wx, -bound * wy)
    pt.rolling = solve_tangential(
        pt.p,
        pt.grid,
        material,
        mu,
        (c.xi, c.eta, c.phi),
        pt.slip.reference_speed,
        tol=tol,
        t0=t0,
        approach=pt.approach,
        **kw,
    )


__all__ = ["GROW", "PatchState", "curvature_fit", "solve_patch_normal", "solve_patch_rolling"]
