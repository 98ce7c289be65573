"""Structured meridian meshes of nine-node quadrilaterals.

The meridian section (r, y) of an axisymmetric body is given as a union of
axis-parallel rectangles ("blocks"). Their edges define a tensor-product grid;
each grid interval is split into equal cells no longer than the finest target
size of the blocks that cover it, and a cell is kept if its centre lies in a
block. The mesh is conforming by construction (every cell shares whole edges
with its neighbours), needs no external mesher, and numbering the nodes row by
row along the axle keeps the bandwidth of the assembled matrices small.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError


@dataclass(frozen=True)
class Block:
    """An axis-parallel rectangle of the meridian section, m.

    Attributes
    ----------
    r0, r1 : float
        Radial extent, 0 <= r0 < r1.
    y0, y1 : float
        Axial extent, y0 < y1.
    size : float
        Target element edge length inside the block, m.
    """

    r0: float
    r1: float
    y0: float
    y1: float
    size: float


@dataclass(frozen=True)
class MeridianMesh:
    """Nine-node quadrilateral mesh of a meridian section.

    Attributes
    ----------
    nodes : ndarray (nn, 2)
        Node coordinates (r, y), m.
    conn : ndarray (ne, 9)
        Zero-based node indices per element, tensor order: local node
        (i, j) (i along r, j along y, each 0..2) at column 3 * j + i.
    """

    nodes: np.ndarray
    conn: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.conn.shape[0])

    def node_at(self, r: float, y: float) -> int:
        """Index of the node nearest to (r, y)."""
        d = (self.nodes[:, 0] - r) ** 2 + (self.nodes[:, 1] - y) ** 2
        return int(np.argmin(d))


def _intervals(edges: list[float], blocks: list[Block], axis: int) -> np.ndarray:
    """Cell boundaries along one axis (0: r, 1: y)."""
    pts = [edges[0]]
    for a, b in zip(edges[:-1], edges[1:]):
        mid = 0.5 * (a + b)
        sizes = [
            blk.size for blk in blocks if (blk.r0 <= mid <= blk.r1 if axis == 0 else blk.y0 <= mid <= blk.y1)
        ]
        h = min(sizes) if sizes else (b - a)
        n = max(1, math.ceil((b - a) / h - 1e-9))
        pts.extend(np.linspace(a, b, n + 1)[1:].tolist())
    return np.asarray(pts)


def mesh_blocks(
    blocks: list[Block], extra_r: tuple[float, ...] = (), extra_y: tuple[float, ...] = ()
) -> MeridianMesh:
    """Mesh a union of blocks with nine-node quadrilaterals.

    Parameters
    ----------
    blocks : list of Block
        The meridian section; blocks may touch or overlap.
    extra_r, extra_y : tuple of float
        Extra grid lines, m (e.g. to put a node on a contact point).

    Returns
    -------
    MeridianMesh
    """
    if not blocks:
        raise InputError("the meridian section has no blocks")
    for b in blocks:
        if not (b.r0 >= 0.0 and b.r1 > b.r0 and b.y1 > b.y0 and b.size > 0.0):
            raise InputError(f"bad meridian block {b}")
    tol = 1e-9
    redges = sorted({round(v, 12) for b in blocks for v in (b.r0, b.r1)} | {round(v, 12) for v in extra_r})
    yedges = sorted({round(v, 12) for b in blocks for v in (b.y0, b.y1)} | {round(v, 12) for v in extra_y})
    rc = _intervals(redges, blocks, 0)
    yc = _intervals(yedges, blocks, 1)
    nr, ny = len(rc) - 1, len(yc) - 1
    rm = 0.5 * (rc[:-1] + rc[1:])
    ym = 0.5 * (yc[:-1] + yc[1:])
    active = np.zeros((nr, ny), dtype=bool)
    for b in blocks:
        active |= (
            (rm[:, None] > b.r0 - tol)
            & (rm[:, None] < b.r1 + tol)
            & (ym[None, :] > b.y0 - tol)
            & (ym[None, :] < b.y1 + tol)
        )
    # Refined grid with mid-side points: index 2 i (+1 for a mid-point).
    rf = np.empty(2 * nr + 1)
    rf[0::2] = rc
    rf[1::2] = rm
    yf = np.empty(2 * ny + 1)
    yf[0::2] = yc
    yf[1::2] = ym
    used = np.zeros((2 * nr + 1, 2 * ny + 1), dtype=bool)
    ir, iy = np.nonzero(active)
    for di in range(3):
        for dj in range(3):
            used[2 * ir + di, 2 * iy + dj] = True
    # Number the nodes row by row along y (r fastest): small bandwidth.
    num = -np.ones(used.shape, dtype=np.int64)
    jj, ii = np.nonzero(used.T)
    num[ii, jj] = np.arange(ii.size)
    nodes = np.column_stack([rf[ii], yf[jj]])
    conn = np.empty((ir.size, 9), dtype=np.int64)
    for dj in range(3):
        for di in range(3):
            conn[:, 3 * dj + di] = num[2 * ir + di, 2 * iy + dj]
    order = np.lexsort((ir, iy))
    return MeridianMesh(nodes=nodes, conn=conn[order])


def rectangle_mesh(r0: float, r1: float, y0: float, y1: float, nr: int, ny: int) -> MeridianMesh:
    """Mesh one rectangle with nr x ny nine-node elements (validation meshes)."""
    hr, hy = (r1 - r0) / nr, (y1 - y0) / ny
    blk = [Block(r0, r1, y0, y1, size=2.0 * max(r1 - r0, y1 - y0))]
    return mesh_blocks(
        blk, extra_r=tuple(r0 + hr * np.arange(1, nr)), extra_y=tuple(y0 + hy * np.arange(1, ny))
    )


def segments_intersect(p1, p2, p3, p4) -> bool:
    """True if closed segments p1-p2 and p3-p4 share a point (collinear overlap included)."""

    def orient(a, b, c):
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return 0 if abs(v) < 1e-14 else (1 if v > 0 else -1)

    def on_seg(a, b, c):
        return (
            min(a[0], b[0]) - 1e-14 <= c[0] <= max(a[0], b[0]) + 1e-14
            and min(a[1], b[1]) - 1e-14 <= c[1] <= max(a[1], b[1]) + 1e-14
        )

    o1, o2, o3, o4 = orient(p1, p2, p3), orient(p1, p2, p4), orient(p3, p4, p1), orient(p3, p4, p2)
    if o1 != o2 and o3 != o4:
        return True
    return (
        (o1 == 0 and on_seg(p1, p2, p3))
        or (o2 == 0 and on_seg(p1, p2, p4))
        or (o3 == 0 and on_seg(p3, p4, p1))
        or (o4 == 0 and on_seg(p3, p4, p2))
    )


def _pt(p: tuple[float, float]) -> str:
    return f"(r={p[0]:.4f}, y={p[1]:.4f})"


def check_simple_polygon(points: np.ndarray, name: str) -> None:
    """Raise InputError if the closed polygon ``points`` (n, 2) intersects itself.

    Zero-length edges are dropped first; non-adjacent edges must not touch.
    """
    pts = [(float(p[0]), float(p[1])) for p in np.asarray(points, dtype=float)]
    clean = [pts[0]]
    for p in pts[1:]:
        if np.hypot(p[0] - clean[-1][0], p[1] - clean[-1][1]) > 1e-12:
            clean.append(p)
    if np.hypot(clean[0][0] - clean[-1][0], clean[0][1] - clean[-1][1]) <= 1e-12:
        clean.pop()
    n = len(clean)
    if n < 3:
        raise InputError(f"the {name} outline is degenerate")
    for i in range(n):
        a, b = clean[i], clean[(i + 1) % n]
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            c, d = clean[j], clean[(j + 1) % n]
            if segments_intersect(a, b, c, d):
                raise InputError(
                    f"the {name} meridian outline intersects itself "
                    f"(edge {_pt(a)}-{_pt(b)} meets edge {_pt(c)}-{_pt(d)}); check its dimensions"
                )


__all__ = [
    "Block",
    "MeridianMesh",
    "mesh_blocks",
    "rectangle_mesh",
    "segments_intersect",
    "check_simple_polygon",
]
