"""The residual flexibility of a flexible wheelset's truncated modes over its contact points.

The static compliance of all free-free elastic modes (:mod:`railvti.wheelset.statics`) less
the kept modes' part R Lambda^-1 R^T, over :data:`~railvti.wheelset.rim_rows.ATTACHMENT_DOFS`:
at given contact coordinates (:func:`residual_flexibility`), tabulated over the contact points
for a kernel that follows them (:class:`ResidualTable`, :func:`residual_table`), and with the
kept modes' interpolated rows the whole static compliance (:func:`contact_compliance`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from .flexible import FlexibleWheelset
from .rim_rows import check_side
from .statics import full_compliance, harmonic_statics, point_operator, rim_operators

__all__ = [
    "residual_flexibility",
    "ResidualTable",
    "residual_table",
    "interpolated_rows",
    "contact_compliance",
]


def residual_flexibility(ws, body: FlexibleWheelset, s_pair: tuple[float, float]) -> np.ndarray:
    """The residual flexibility of ``body`` (built from ``ws``) at other contact coordinates.

    Parameters
    ----------
    ws : Wheelset
        The wheelset the body was built from.
    body : FlexibleWheelset
    s_pair : (float, float)
        Wheel-profile coordinates of the right and left contact points, m.

    Returns
    -------
    ndarray (14, 14)
        As :attr:`FlexibleWheelset.residual`, over :data:`ATTACHMENT_DOFS` at ``s_pair``.
    """
    rs = tuple(body.check_s(s) for s in s_pair)
    statics = [harmonic_statics(ws, k) for k in range(body.residual_k_max + 1)]
    gfull = full_compliance(
        statics, ws.mesh, body.edges, rs, ws._journal_nodes, rim_operators(ws, body.edges)
    )
    rr = body.attachment_rows(rs)
    return gfull - (rr / (2.0 * np.pi * body.freq_hz) ** 2) @ rr.T


@dataclass(frozen=True)
class ResidualTable:
    """The residual flexibility of a :class:`FlexibleWheelset` as a function of the contact
    points' wheel-profile coordinates, for linear interpolation by a kernel.

    The residual at (s_right, s_left) over :data:`ATTACHMENT_DOFS` is assembled from the
    blocks at the grid points i (right) and j (left)::

        [[cc[0, i],        cross[i, j],     cj[0, i]],
         [cross[i, j].T,   cc[1, j],        cj[1, j]],
         [cj[0, i].T,      cj[1, j].T,      jj      ]]

    Attributes
    ----------
    s0, ds : float
        First wheel-profile coordinate and step of the grid, m.
    cc : ndarray (2, ns, 4, 4)
        Residual of a contact point with itself (rows and columns x, y, z, rx).
    cross : ndarray (ns, ns, 4, 4)
        Right contact at s0 + i ds (rows) against left contact at s0 + j ds (columns).
    cj : ndarray (2, ns, 4, 6)
        Contact point against the journals (journal0 x, y, z, journal1 x, y, z).
    jj : ndarray (6, 6)
        Journals against journals.
    """

    s0: float
    ds: float
    cc: np.ndarray
    cross: np.ndarray
    cj: np.ndarray
    jj: np.ndarray

    def at(self, i: int, j: int) -> np.ndarray:
        """The (14, 14) residual at grid points i (right wheel) and j (left wheel)."""
        top = np.hstack([self.cc[0, i], self.cross[i, j], self.cj[0, i]])
        mid = np.hstack([self.cross[i, j].T, self.cc[1, j], self.cj[1, j]])
        bot = np.hstack([self.cj[0, i].T, self.cj[1, j].T, self.jj])
        return np.vstack([top, mid, bot])

    def interpolate(self, s_pair: tuple[float, float]) -> np.ndarray:
        """The (14, 14) residual at contact coordinates (s_right, s_left), m, between the grid
        points: each block linear in its contact point's s (the cross block bilinear), as a
        kernel interpolates it per step (the paper's eq. 3 with the contact point moving).

        Raises
        ------
        InputError
            s_pair not two finite coordinates inside the grid.
        """
        (i0, i1, wi), (j0, j1, wj) = (
            self._cell("s_pair[0] (right)", s_pair[0]),
            self._cell("s_pair[1] (left)", s_pair[1]),
        )

        def lin(a, k0, k1, w):
            return (1.0 - w) * a[k0] + w * a[k1]

        cross = (1 - wi) * ((1 - wj) * self.cross[i0, j0] + wj * self.cross[i0, j1]) + wi * (
            (1 - wj) * self.cross[i1, j0] + wj * self.cross[i1, j1]
        )
        c0, c1 = lin(self.cc[0], i0, i1, wi), lin(self.cc[1], j0, j1, wj)
        j0c, j1c = lin(self.cj[0], i0, i1, wi), lin(self.cj[1], j0, j1, wj)
        top = np.hstack([c0, cross, j0c])
        mid = np.hstack([cross.T, c1, j1c])
        bot = np.hstack([j0c.T, j1c.T, self.jj])
        return np.vstack([top, mid, bot])

    def _cell(self, key: str, s: object) -> tuple[int, int, float]:
        ns = self.cc.shape[1]
        try:
            x = float(s)
        except (TypeError, ValueError):
            raise InputError(f"{key} must be a wheel-profile coordinate in m, got {s!r}") from None
        t = (x - self.s0) / self.ds
        if not (np.isfinite(t) and -1e-9 <= t <= ns - 1 + 1e-9):
            raise InputError(
                f"{key} = {s!r} m outside the table's grid {self.s0:.4g}.."
                f"{self.s0 + (ns - 1) * self.ds:.4g} m"
            )
        i0 = min(int(np.floor(max(t, 0.0))), ns - 2)
        return i0, i0 + 1, min(max(t - i0, 0.0), 1.0)


def interpolated_rows(body: FlexibleWheelset, side: int, s: float) -> np.ndarray:
    """The contact rows (4, nq) at profile coordinate s, m, linearly interpolated in the
    body's ``rim_rows`` (grid s0 + i ds): what a kernel that follows the contact point
    evaluates per step, against :meth:`FlexibleWheelset.rows` (the element's shape functions
    at s)."""
    side = check_side(side)
    s = body.check_s(s)
    ns = body.rim_rows.shape[1]
    t = (s - body.s0) / body.ds
    i0 = min(max(int(np.floor(t)), 0), ns - 2)
    w = min(max(t - i0, 0.0), 1.0)
    return (1.0 - w) * body.rim_rows[side, i0] + w * body.rim_rows[side, i0 + 1]


def contact_compliance(
    body: FlexibleWheelset, table: ResidualTable, s_pair: tuple[float, float]
) -> np.ndarray:
    """The static compliance (14, 14) over :data:`ATTACHMENT_DOFS` with the contact points at
    (s_right, s_left), m, from the tables alone: the kept modes through the interpolated
    rows (:func:`interpolated_rows`), R Lambda^-1 R^T, plus the interpolated residual
    (:meth:`ResidualTable.interpolate`). The tabulate-then-interpolate scheme of the moving
    contact point (eq. 3), checked against direct FE solves at tread and flange points.

    Returns
    -------
    ndarray (14, 14)
        m/N, rad/N, rad/(N m); the inertia-relief compliance of the free-free body (rigid
        parts removed mass-orthogonally), as :meth:`FlexibleWheelset.static_deflection`.
    """
    res = table.interpolate(s_pair)
    r = np.vstack(
        [
            interpolated_rows(body, 0, s_pair[0]),
            interpolated_rows(body, 1, s_pair[1]),
            body.journal[0, :3],
            body.journal[1, :3],
        ]
    )
    return (r / (2.0 * np.pi * body.freq_hz) ** 2) @ r.T + res


def residual_table(ws, body: FlexibleWheelset, ds: float = 5e-3) -> ResidualTable:
    """Tabulate the residual flexibility of ``body`` over the contact points' coordinates.

    Parameters
    ----------
    ws : Wheelset
        The wheelset the body was built from.
    body : FlexibleWheelset
    ds : float
        Grid step over the wheel-profile coordinate, m (the grid covers the rim edge).

    Returns
    -------
    ResidualTable
    """
    ds = _checks.positive("ds", ds)
    lo, hi = body.s_range
    grid = np.arange(lo, hi + 0.5 * ds, ds)
    grid = grid[grid <= hi + 1e-12]
    ns = grid.size
    mesh = ws.mesh
    rims = rim_operators(ws, body.edges)
    ops = [
        [point_operator(mesh, body.edges[side], float(s), None, rims[side]) for s in grid] for side in (0, 1)
    ]
    jops = [point_operator(mesh, None, None, n) for n in ws._journal_nodes]
    n_all = 2 * 4 * ns + 6
    g = np.zeros((n_all, n_all))
    for k in range(body.residual_k_max + 1):
        st = harmonic_statics(ws, k)
        for kind in ("0",) if k == 0 else ("A", "B"):
            e = np.array(
                [v for side in (0, 1) for p in ops[side] for v in p[kind]]
                + [v for p in jops for v in p[kind][:3]]
            )  # (n_all, 3 nn)
            live = np.flatnonzero(np.any(e != 0.0, axis=1))
            u = st.solve(e[live].T)  # (3 nn, n_live)
            g[np.ix_(live, live)] += e[live] @ u
    # kept modes' static part at the same points
    rows = np.vstack(
        [body.rows(side, float(s)) for side in (0, 1) for s in grid]
        + [body.journal[0, :3], body.journal[1, :3]]
    )
    g -= (rows / (2.0 * np.pi * body.freq_hz) ** 2) @ rows.T
    g = 0.5 * (g + g.T)
    c = g[: 8 * ns, : 8 * ns].reshape(2, ns, 4, 2, ns, 4)
    cc = np.array([[c[side, i, :, side, i, :] for i in range(ns)] for side in (0, 1)])
    cross = c[0, :, :, 1, :, :].transpose(0, 2, 1, 3)
    cj = g[: 8 * ns, 8 * ns :].reshape(2, ns, 4, 6)
    return ResidualTable(
        s0=float(grid[0]),
        ds=ds,
        cc=cc,
        cross=np.ascontiguousarray(cross),
        cj=cj,
        jj=g[8 * ns :, 8 * ns :].copy(),
    )
