"""The normal contact problem on a grid (Kaiser, sect. 4, eqs 17-23)."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._fft_size import fft_size
from .._native import core
from .._status import Status, error
from ..errors import ConvergenceError, GridTooSmallError, InputError, NoContactError, RailvtiError
from ..material import Material
from .grid import Grid
from .workspace import workspace

log = logging.getLogger(__name__)

_METHODS = {"cg": 1, "gs": 2, "pk": 3}
_DEFAULT_MAX_ITER = {"cg": 2000, "gs": 20000, "pk": 2000}
#: Wall time of one slice of the Gauss-Seidel solver, s: Ctrl-C stops a solve within it.
GS_SLICE_SECONDS = 0.1
#: Wall time of one slice of the CG solver, s (at least one iteration: ~0.1 s on 1600 x 1600).
CG_SLICE_SECONDS = 0.1
#: A CG solve of at most this many element iterations (nx ny max_iter) runs as one slice
#: (an 11 x 11 grid: the second call and its argument conversion cost as much as the solve).
_ONE_SLICE_WORK = 2_500_000
#: CG from zero pressure on grids with both sides at least this long starts from
#: the solution on the grid of twice the element size (nested iteration).
_NESTED_MIN = 128
#: Residual to which the coarse grids are solved: their solution is only a start.
_NESTED_TOL = 1e-4
#: The interpolated start keeps no pressure where the gap it predicts, h + P u_c - delta_c
#: (P the bilinear interpolation, u_c and delta_c the coarse grid's displacement and
#: approach), exceeds this share of delta_c - min(h_c): elements that the coarse solution
#: puts just outside the contact area (docs/normal_contact.md, issue 33).
_NESTED_TRIM = 5e-4


@dataclass(frozen=True)
class SubPatches:
    """Sub-patches of a patch that holds several contact areas side by side, with a reduced
    elastic interaction between neighbours (CONTACT's planform IPLAN = 4).

    The grid's columns (lateral positions y) are cut at ``split``; sub-patch a holds the
    columns with split[a-1] < y <= split[a]. The displacement that pressures in sub-patch b
    cause in sub-patch a is scaled by F[a, b]: 1 for a = b, ``factor[a]`` between the
    neighbours a and a + 1, 0 between sub-patches that are not neighbours (CONTACT's
    tridiagonal factor matrix); docs/contact_decks.md.

    Attributes
    ----------
    split : tuple of float
        Lateral positions of the cuts in the grid's frame, m, ascending.
    factor : tuple of float
        Interaction factor of each pair of neighbours, in [0, 1]; one per cut.
    """

    split: tuple[float, ...]
    factor: tuple[float, ...]

    def __post_init__(self) -> None:
        split = tuple(float(v) for v in self.split)
        factor = tuple(float(v) for v in self.factor)
        if len(split) != len(factor):
            raise InputError(f"SubPatches: {len(split)} cuts need as many factors, got {len(factor)}")
        if not all(np.isfinite(split)) or any(b <= a for a, b in zip(split, split[1:])):
            raise InputError(f"SubPatches: the cuts must be finite and ascending, got {split}")
        if not all(0.0 <= f <= 1.0 for f in factor):
            raise InputError(f"SubPatches: the factors must lie in [0, 1], got {factor}")
        object.__setattr__(self, "split", split)
        object.__setattr__(self, "factor", factor)

    def operator(self, grid: Grid) -> tuple[int, np.ndarray, np.ndarray]:
        """(nsub, lab, fac) for the kernels: the sub-patch (1-based) of each grid column and
        the factor matrix."""
        y = grid.y0 + grid.dy * np.arange(grid.ny)
        lab = 1 + np.searchsorted(np.array(self.split), y, side="left").astype(np.int32)
        n = len(self.split) + 1
        fac = np.eye(n, order="F")
        for a, f in enumerate(self.factor):
            fac[a, a + 1] = fac[a + 1, a] = f
        return n, lab, fac


def _plain(grid: Grid, sub: SubPatches | None) -> tuple[int, np.ndarray, np.ndarray]:
    if sub is None:
        return 1, np.ones(grid.ny, dtype=np.int32), np.ones((1, 1), order="F")
    return sub.operator(grid)


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
        Convolution products used (CG only) on this grid.
    coarse_fft_products : int
        Products on the coarser grids of a nested start (each a quarter or
        less of the cost of one on this grid); 0 without a nested start.
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
    coarse_fft_products: int = 0

    @property
    def pmax(self) -> float:
        """Largest pressure, Pa."""
        return float(self.pressure.max())

    @property
    def contact(self) -> np.ndarray:
        """Boolean ``(nx, ny)`` mask of the elements in contact."""
        return self.pressure > 0.0


def _check_edges(p: np.ndarray) -> None:
    if not (p[0, :].any() or p[-1, :].any() or p[:, 0].any() or p[:, -1].any()):
        return  # the common case, without the names below (small grids: per-call cost)
    edges = {
        "x = x_min (i = 0)": p[0, :],
        "x = x_max (i = nx-1)": p[-1, :],
        "y = y_min (j = 0)": p[:, 0],
        "y = y_max (j = ny-1)": p[:, -1],
    }
    touched = [name for name, row in edges.items() if (row > 0.0).any()]
    if touched:
        raise GridTooSmallError(
            "the contact area reaches the grid edge at "
            + ", ".join(touched)
            + ": enlarge the grid (more elements or a larger extent)"
        )


def _coarsen(h: np.ndarray, grid: Grid) -> tuple[np.ndarray, Grid]:
    """The gap on the grid of twice the element size: each coarse element
    averages the 2 x 2 fine elements it covers. The coarse grid has at least
    half the fine grid's elements along each side, rounded up to a size with
    prime factors 2, 3, 5 (:func:`railvti._fft_size.fft_size`); beyond the fine grid's last row and
    column the gap is held constant (the contact area does not reach there)."""
    mx, my = fft_size((grid.nx + 1) // 2), fft_size((grid.ny + 1) // 2)
    h = np.pad(h, ((0, 2 * mx - grid.nx), (0, 2 * my - grid.ny)), mode="edge")
    hc = 0.25 * (h[0::2, 0::2] + h[1::2, 0::2] + h[0::2, 1::2] + h[1::2, 1::2])
    coarse = Grid(
        mx,
        my,
        2.0 * grid.dx,
        2.0 * grid.dy,
        grid.x0 + 0.5 * grid.dx,
        grid.y0 + 0.5 * grid.dy,
    )
    return np.asfortranarray(hc), coarse


def _prolong(pc: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Bilinear interpolation of a coarse field to the fine element centres.

    Coarse element K is centred at fine index 2K + 1/2, so fine element 2K takes
    1/4 of K - 1 and 3/4 of K, and 2K + 1 takes 3/4 of K and 1/4 of K + 1; beyond the
    outer coarse centres the field is held constant."""
    out = pc
    for axis, n in enumerate(shape):
        out = np.moveaxis(_prolong_first(np.moveaxis(out, axis, 0), n), 0, axis)
    return np.asfortranarray(out)


def _prolong_first(a: np.ndarray, n: int) -> np.ndarray:
    """_prolong along the first axis of a (coarse length nc >= 2) to length n <= 2 nc (what
    _coarsen makes), by slices; each value is (1 - w) lo + w hi with w = 0, 1/4, 3/4 or 1
    (exact in floating point)."""
    nc = a.shape[0]
    lo, hi = a[:-1], a[1:]
    full = np.empty((2 * nc,) + a.shape[1:])
    full[0] = 1.0 * a[0] + 0.0 * a[1]
    full[1 : 2 * nc - 2 : 2] = 0.75 * lo + 0.25 * hi
    full[2 : 2 * nc - 1 : 2] = 0.25 * lo + 0.75 * hi
    full[2 * nc - 1] = 0.0 * a[nc - 2] + 1.0 * a[nc - 1]
    return full[:n]


def _nested_start(
    h: np.ndarray,
    grid: Grid,
    material: Material,
    control: int,
    fn_in: float,
    app_in: float,
    method: int,
    max_iter: int,
    sub: SubPatches | None = None,
) -> tuple[np.ndarray | None, int]:
    """A start pressure for a large grid from the solution on the grid of twice the
    element size, itself started the same way (nested iteration, as in full multigrid).

    Returns the interpolated pressure (None if the grid is small or the coarse
    problem has no usable solution) and the FFT products spent on coarse grids.
    The interpolated pressure is set to zero where the gap predicted from the coarse
    displacement is clearly open (:data:`_NESTED_TRIM`)."""
    if min(grid.shape) < _NESTED_MIN:
        return None, 0
    hc, coarse = _coarsen(h, grid)
    pc, nprod_c = _nested_start(hc, coarse, material, control, fn_in, app_in, method, max_iter, sub)
    if pc is None:
        pc = np.zeros(coarse.shape, order="F")
    uc = np.zeros(coarse.shape, order="F")
    _, app_c, _, nprod, _, info = _cg_in_slices(
        workspace(coarse, material),
        hc,
        control,
        method,
        _NESTED_TOL,
        max_iter,
        fn_in,
        app_in,
        pc,
        _plain(coarse, sub),
        u=uc,
    )
    nprod_c += int(nprod)
    if info not in (Status.OK, Status.NOT_CONVERGED) or not np.isfinite(pc).all() or not (pc > 0.0).any():
        return None, nprod_c
    p = _prolong(pc, grid.shape)
    gap = h + _prolong(uc, grid.shape) - app_c
    trimmed = np.where(gap > _NESTED_TRIM * (app_c - float(hc.min())), 0.0, p)
    if (trimmed > 0.0).any():
        p = np.asfortranarray(trimmed)
    return p, nprod_c


def _cg_in_slices(
    handle: int,
    h: np.ndarray,
    control: int,
    method: int,
    tol: float,
    max_iter: int,
    fn_in: float,
    app_in: float,
    p: np.ndarray,
    sub: tuple[int, np.ndarray, np.ndarray],
    u: np.ndarray | None = None,
) -> tuple[float, float, int, int, float, int]:
    """Projected CG (method 1, or 3 without preconditioner) in slices of about
    :data:`CG_SLICE_SECONDS` each (``normal_cg_slice_c``; the numbers are those of one
    ``normal_solve_c`` call): between slices Python handles Ctrl-C / SIGTERM. ``sub``: the
    sub-patch operator (nsub, lab, fac) of :meth:`SubPatches.operator`. Returns what
    ``normal_solve_c`` returns; p is updated in place, and u (optional, Fortran-ordered
    float64 of h's shape) receives the displacement A p of the last iterate."""
    if u is None:
        u = np.zeros(h.shape, order="F")
    t = np.zeros(h.shape, order="F")
    rstate = np.zeros(2)
    istate = np.zeros(5, dtype=np.int32)
    approach = np.array(app_in, dtype=np.float64)
    resid = np.array(0.0, dtype=np.float64)
    # iterations in the next slice: one, then adapted; all at once for a small problem
    budget, start = (max_iter if h.size * max_iter <= _ONE_SLICE_WORK else 1), 1
    while True:
        t0 = time.perf_counter()
        fn_out, done, info = core.normal_cg_slice_c(
            handle,
            h,
            control,
            method,
            tol,
            max_iter,
            fn_in,
            budget,
            start,
            sub[1],
            sub[2],
            approach,
            p,
            u,
            t,
            rstate,
            istate,
            resid,
        )
        start = 0
        if done:
            break
        dt = time.perf_counter() - t0
        budget = int(np.clip(budget * CG_SLICE_SECONDS / max(dt, 1e-4), 1, 4 * budget))
    return float(fn_out), float(approach), int(istate[1]), int(istate[2]), float(resid), int(info)


def _gs_in_slices(
    handle: int,
    h: np.ndarray,
    control: int,
    tol: float,
    max_iter: int,
    omega: float,
    fn_in: float,
    app_in: float,
    p: np.ndarray,
    sub: tuple[int, np.ndarray, np.ndarray],
) -> tuple[float, float, int, int, float, int]:
    """Projected Gauss-Seidel in slices of about :data:`GS_SLICE_SECONDS` of work each
    (``normal_gs_slice_c``; the numbers are those of one call): between slices Python
    handles Ctrl-C / SIGTERM and a progress bar (sweeps, residual) shows after 2 s.
    Returns what ``normal_solve_c`` returns; p is updated in place."""
    u = np.zeros(h.shape, order="F")
    approach = np.array(app_in, dtype=np.float64)
    resid = np.array(0.0, dtype=np.float64)
    iters = np.array(0, dtype=np.int32)
    pos = np.array(0, dtype=np.int32)
    budget = 2.0e6  # work units (element visits + N per column), adapted below
    bar = None
    start = 1
    t_start = time.perf_counter()
    try:
        while True:
            t0 = time.perf_counter()
            fn_out, done, info = core.normal_gs_slice_c(
                handle,
                h,
                control,
                tol,
                max_iter,
                omega,
                fn_in,
                budget,
                start,
                sub[1],
                sub[2],
                approach,
                p,
                u,
                iters,
                pos,
                resid,
            )
            start = 0
            if done:
                break
            dt = time.perf_counter() - t0
            budget = float(np.clip(budget * GS_SLICE_SECONDS / max(dt, 1e-4), 1e3, 4.0 * budget))
            if bar is None and time.perf_counter() - t_start > 2.0 and np.isfinite(resid):
                from tqdm import tqdm

                r0 = max(float(resid), 10.0 * tol)  # the bar: decades of the residual to go
                bar = tqdm(
                    total=round(np.log10(r0 / tol), 2),
                    unit="decade",
                    leave=False,
                    disable=None,
                    bar_format="{desc} {bar}| [{elapsed}<{remaining}]",
                )
            if bar is not None and np.isfinite(resid) and resid > 0:
                bar.update(max(0.0, min(bar.total, round(np.log10(r0 / float(resid)), 2))) - bar.n)
                bar.set_description_str(
                    f"normal gs: sweep {int(iters)}, residual {float(resid):.2e} > tol {tol:.0e}",
                    refresh=False,
                )
    finally:
        if bar is not None:
            bar.close()
    return float(fn_out), float(approach), int(iters), 0, float(resid), int(info)


def _check_inputs(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    fn: float | None,
    approach: float | None,
    method: str,
    tol: float,
    max_iter: int | None,
    omega: float,
    subpatches: SubPatches | None,
) -> tuple[np.ndarray, int, float, float, float, int, float]:
    """The checked arguments of :func:`solve_normal`: the gap, the control (1 force, 2
    approach) with its force and approach inputs, tol, max_iter (the method's default if
    None) and omega."""
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
                f"no contact: the approach {approach:.6g} m does not exceed the smallest gap {h.min():.6g} m"
            )
        control, fn_in, app_in = 2, 0.0, approach
    tol = _checks.positive("tol", tol)
    if max_iter is None:
        max_iter = _DEFAULT_MAX_ITER[method]
    max_iter = _checks.positive_int("max_iter", max_iter)
    omega = _checks.positive("omega", omega)
    if subpatches is not None and not isinstance(subpatches, SubPatches):
        raise InputError("subpatches must be a railvti.contact.SubPatches or None")
    if omega >= 2.0:
        raise InputError(f"omega must lie in (0, 2), got {omega}")
    return h, control, fn_in, app_in, tol, max_iter, omega


def _start_pressure(
    p0: np.ndarray | None,
    h: np.ndarray,
    grid: Grid,
    material: Material,
    control: int,
    fn_in: float,
    app_in: float,
    method: str,
    max_iter: int,
    nested: bool,
    subpatches: SubPatches | None,
) -> tuple[np.ndarray, int]:
    """The start pressure of :func:`solve_normal` (the checked p0; else the nested start of
    'cg' and 'pk' on a large grid, or zero) and the FFT products spent on coarse grids."""
    nprod_coarse = 0
    if p0 is None:
        p = None
        if nested and method in ("cg", "pk"):
            p, nprod_coarse = _nested_start(
                h, grid, material, control, fn_in, app_in, _METHODS[method], max_iter, subpatches
            )
        if p is None:
            p = np.zeros(grid.shape, order="F")
    else:
        p = _checks.finite_array("p0", p0, shape=grid.shape)
        if (p < 0.0).any():
            raise InputError("p0 must be >= 0 everywhere")
    return p, nprod_coarse


def solve_normal(
    gap: np.ndarray,
    grid: Grid,
    material: Material,
    fn: float | None = None,
    approach: float | None = None,
    method: str = "cg",
    tol: float = 1e-8,
    max_iter: int | None = None,
    p0: np.ndarray | None = None,
    omega: float = 1.0,
    nested: bool = True,
    subpatches: SubPatches | None = None,
) -> NormalResult:
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
    nested : bool
        For 'cg' and 'pk' without p0 on grids of at least 128 x 128 elements:
        start from the solution on the grid of twice the element size, found
        the same way (nested iteration). It saves about half the FFT products
        on this grid; the answer is the same to the tolerance.
    subpatches : SubPatches, optional
        A patch of several contact areas whose elastic interaction is reduced
        (CONTACT's IPLAN = 4): A becomes sum_ab F[a, b] A_ab over the sub-patches'
        blocks. Each product then costs one FFT product per loaded sub-patch.

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
    h, control, fn_in, app_in, tol, max_iter, omega = _check_inputs(
        gap, grid, material, fn, approach, method, tol, max_iter, omega, subpatches
    )
    p, nprod_coarse = _start_pressure(
        p0, h, grid, material, control, fn_in, app_in, method, max_iter, nested, subpatches
    )
    sub = _plain(grid, subpatches)
    if method == "gs":
        fn_out, app_out, iters, nprod, resid, info = _gs_in_slices(
            workspace(grid, material), h, control, tol, max_iter, omega, fn_in, app_in, p, sub
        )
    else:
        fn_out, app_out, iters, nprod, resid, info = _cg_in_slices(
            workspace(grid, material), h, control, _METHODS[method], tol, max_iter, fn_in, app_in, p, sub
        )
    if info == Status.NO_CONTACT:
        raise NoContactError("no contact: the approach does not exceed the smallest gap")
    if info not in (Status.OK, Status.NOT_CONVERGED, Status.NOT_FINITE):
        raise error(info, "normal contact solver failed internally", exc=RailvtiError)
    if info == Status.NOT_FINITE or not (
        np.isfinite(p).all() and np.isfinite(fn_out) and np.isfinite(app_out)
    ):
        raise ConvergenceError(
            f"normal contact solver ({method}) diverged to non-finite values",
            iterations=int(iters),
            residual=float(resid),
        )
    n_contact = int((p > 0.0).sum())
    result = NormalResult(
        grid=grid,
        pressure=p,
        fn=float(fn_out),
        approach=float(app_out),
        area=n_contact * grid.element_area,
        n_contact=n_contact,
        iterations=int(iters),
        residual=float(resid),
        converged=info == Status.OK,
        method=method,
        fft_products=int(nprod),
        coarse_fft_products=nprod_coarse,
    )
    if info == Status.NOT_CONVERGED:
        raise ConvergenceError(
            f"normal contact solver ({method}) did not converge: residual {resid:.3g} > tol {tol:.3g} "
            f"after {iters} iterations",
            iterations=int(iters),
            residual=float(resid),
            result=result,
        )
    _check_edges(p)
    log.debug("solve_normal %s: %d iterations, residual %.3g, %d in contact", method, iters, resid, n_contact)
    return result


__all__ = ["GS_SLICE_SECONDS", "CG_SLICE_SECONDS", "SubPatches", "NormalResult", "solve_normal"]
