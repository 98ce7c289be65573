"""The UIC60 (60E1) rail cross-section: outline, 6-node triangle mesh, section properties.

The outline follows EN 13674-1 profile 60E1 where the drawing gives a value (height 172 mm,
foot width 150 mm, head width 72 mm, web 16.5 mm, crown radii R300/R80/R13, head sides 1:20,
fishing surfaces 1:2.75). Fillet radii and the two depths that a sketch cannot fix (the depth of
the head side and the thickness of the foot tip) are set so that the area and the height of the
centroid equal the published 76.70 cm^2 and 80.9 mm (EN 13674-1: W_head = 333.6 cm^3,
W_foot = 375.5 cm^3, so e = 3038.3/375.5 = 80.9 mm). I_y, I_z and the torsion constant are then
independent checks (see docs/track.md).

Coordinates: eta lateral (m), zeta vertical up from the foot's underside (m), eta = 0 on the
rail's axis of symmetry.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import InputError

log = logging.getLogger(__name__)

#: Published 60E1 values (EN 13674-1, Annex A): area m^2, I_y m^4 (about the horizontal
#: axis), I_z m^4 (vertical axis), mass per length kg/m.
PUBLISHED_60E1 = {"area": 76.70e-4, "iy": 3038.3e-8, "iz": 512.3e-8, "mass": 60.21}

# Dunavant's 6-point rule, exact to degree 4: area coordinates (l1, l2, l3) and weights (sum 1).
_A1, _B1, _W1 = 0.445948490915965, 0.108103018168070, 0.223381589678011
_A2, _B2, _W2 = 0.091576213509771, 0.816847572980459, 0.109951743655322
GAUSS_L = np.array(
    [[_A1, _A1, _B1], [_A1, _B1, _A1], [_B1, _A1, _A1], [_A2, _A2, _B2], [_A2, _B2, _A2], [_B2, _A2, _A2]]
)
GAUSS_W = np.array([_W1] * 3 + [_W2] * 3)

#: Largest ``arc_step`` taken, m: a larger value is refused as a probable mm value
#: (``arc_step`` was in mm before issue 16; the deck key's bound is the same).
ARC_STEP_MAX = 0.05


def arc_step_si(arc_step: float | None, arc_step_mm: float | None, default: float) -> float:
    """The outline's arc spacing in m from ``arc_step`` (m) or its deprecated mm alias.

    Parameters
    ----------
    arc_step : float or None
        Spacing, m.
    arc_step_mm : float or None
        The same in mm (deprecated: a DeprecationWarning; converted x 1e-3).
    default : float
        The spacing when neither is given, m.

    Raises
    ------
    InputError
        Both given; a value <= 0, non-finite, or above :data:`ARC_STEP_MAX` (a mm value
        given as m: the message says how to write it).
    """
    if arc_step_mm is not None:
        if arc_step is not None:
            raise InputError("give arc_step (m) or arc_step_mm (mm, deprecated), not both")
        warnings.warn(
            "arc_step_mm is deprecated: give arc_step in m (arc_step_mm = 8 is arc_step = 0.008)",
            DeprecationWarning,
            stacklevel=3,
        )
        arc_step = _checks.positive("arc_step_mm", arc_step_mm) * 1e-3
    elif arc_step is None:
        arc_step = default
    arc_step = _checks.positive("arc_step", arc_step)
    if arc_step > ARC_STEP_MAX:
        raise InputError(
            f"arc_step = {arc_step:g} m is above {ARC_STEP_MAX:g} m: arc_step is "
            f"in m (it was in mm before issue 16): 8 mm is arc_step = 0.008"
        )
    return arc_step


def _arc(center, radius, a0, a1, step):
    """Points on a circle from angle a0 to a1 (radians, measured from +zeta towards +eta)."""
    n = max(2, int(np.ceil(abs(a1 - a0) * radius / step)) + 1)
    a = np.linspace(a0, a1, n)
    return np.column_stack([center[0] + radius * np.sin(a), center[1] + radius * np.cos(a)])


def _fillet(p_prev, p, p_next, r, step):
    """Replace corner p of a polyline by a tangent arc of radius r (kept sharp if r < step/2)."""
    if r < 0.5 * step:
        return p[None, :]
    d1 = (p - p_prev) / np.linalg.norm(p - p_prev)
    d2 = (p_next - p) / np.linalg.norm(p_next - p)
    cos_t = np.clip(np.dot(-d1, d2), -1.0, 1.0)
    half = 0.5 * np.arccos(cos_t)  # half of the interior angle
    t = r / np.tan(half)
    q1, q2 = p - d1 * t, p + d2 * t
    bis = (-d1 + d2) / np.linalg.norm(-d1 + d2)
    c = p + bis * r / np.sin(half)
    a0 = np.arctan2(q1[0] - c[0], q1[1] - c[1])
    a1 = np.arctan2(q2[0] - c[0], q2[1] - c[1])
    da = (a1 - a0 + np.pi) % (2 * np.pi) - np.pi
    return _arc(c, r, a0, a0 + da, step)


def uic60_outline(
    step: float = 1.0, head_side_depth: float = 40.39, foot_tip: float = 11.0, foot_slope: float = 0.1613
) -> np.ndarray:
    """Closed 60E1 outline, counter-clockwise, in metres (the last point repeats the first).

    Parameters
    ----------
    step : float
        Largest spacing of points on arcs, mm.
    head_side_depth : float
        Depth of the head's side faces below the crown, mm (calibrated, see module doc).
    foot_tip : float
        Thickness of the foot at its tip, mm.
    foot_slope : float
        Mean slope of the foot's upper face between the tip and the web fillet (calibrated).
    """
    h, bh, bf, tw = 172.0, 72.0, 150.0, 16.5
    # Crown: R300 to eta = 10 mm, then R80, then R13 into the 1:20 head side.
    c300 = np.array([0.0, h - 300.0])
    a1 = np.arcsin(10.0 / 300.0)
    c80 = c300 + (300.0 - 80.0) * np.array([np.sin(a1), np.cos(a1)])
    zsb = h - head_side_depth  # bottom of the head side
    sb = np.array([bh / 2, zsb])
    n_out = np.array([20.0, 1.0]) / np.hypot(20.0, 1.0)  # outward normal of the side
    # c13: distance 67 from c80 and 13 inside the side line.
    dline = np.array([-1.0, 20.0]) / np.hypot(1.0, 20.0)
    base = sb - 13.0 * n_out
    # |base + s dline - c80| = 67
    w = base - c80
    bq = 2 * np.dot(w, dline)
    cq = np.dot(w, w) - 67.0**2
    s = (-bq + np.sqrt(bq * bq - 4 * cq)) / 2
    c13 = base + s * dline
    u = (c13 - c80) / 67.0
    a2 = np.arctan2(u[0], u[1])
    ts = c13 + 13.0 * n_out
    a3 = np.arctan2(n_out[0], n_out[1])
    crown = np.vstack(
        [
            _arc(c300, 300.0, 0.0, a1, step)[:-1],
            _arc(c80, 80.0, a1, a2, step)[:-1],
            _arc(c13, 13.0, a2, a3, step),
        ]
    )
    # Straight parts with fillets: side bottom, fishing 1:2.75, web, foot top 1:2.75, tip.
    p_head_corner = sb
    p_web_top = np.array([tw / 2, zsb - (bh / 2 - tw / 2) / 2.75])
    z_foot_web = foot_tip + (bf / 2 - tw / 2) * foot_slope  # foot top meets the web
    p_web_bot = np.array([tw / 2, z_foot_web])
    p_tip_top = np.array([bf / 2, foot_tip])
    p_tip_bot = np.array([bf / 2, 0.0])
    p_axis_bot = np.array([0.0, 0.0])
    poly = [ts, p_head_corner, p_web_top, p_web_bot, p_tip_top, p_tip_bot, p_axis_bot]
    radii = [0.0, 3.0, 20.0, 30.0, 4.0, 2.0, 0.0]
    pts = [crown]
    for i in range(1, len(poly) - 1):
        if radii[i] > 0:
            pts.append(_fillet(poly[i - 1], poly[i], poly[i + 1], radii[i], step))
        else:
            pts.append(poly[i][None, :])
    pts.append(p_axis_bot[None, :])
    right = np.vstack(pts)  # from the crown (0, h) to (0, 0), clockwise
    # Drop near-duplicates.
    keep = np.r_[True, np.linalg.norm(np.diff(right, axis=0), axis=1) > 1e-6]
    right = right[keep]
    left = right[-2:0:-1] * np.array([-1.0, 1.0])
    outline = np.vstack([right[::-1], left[::-1]])[::-1]
    # counter-clockwise orientation
    x, y = outline[:, 0], outline[:, 1]
    if 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) < 0:
        outline = outline[::-1]
    return np.vstack([outline, outline[:1]]) * 1e-3


def check_outline(outline: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Validate a closed polygon and return it counter-clockwise without the repeated point.

    The outline is an (n, 2) array whose last point repeats the first (that is what
    "closed" means here); it must enclose an area and must not cross itself.
    """
    pts = _checks.finite_array("outline", outline, ndim=2)
    if pts.shape[1] != 2 or pts.shape[0] < 4:
        raise InputError(f"outline must be an (n >= 4, 2) array of points, got shape {pts.shape}")
    gap = float(np.linalg.norm(pts[0] - pts[-1]))
    if gap > tol:
        raise InputError(
            f"outline is not closed: its last point is {gap:.3g} m from the first "
            "(repeat the first point at the end)"
        )
    pts = pts[:-1]
    seg = np.linalg.norm(np.diff(np.vstack([pts, pts[:1]]), axis=0), axis=1)
    if np.any(seg <= tol):
        raise InputError("outline has repeated consecutive points")
    x, y = pts[:, 0], pts[:, 1]
    area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    if abs(area) <= tol * tol:
        raise InputError("outline encloses no area")
    if area < 0:
        pts = pts[::-1].copy()
    # Self-intersection: any two non-adjacent edges that cross.
    p, q = pts, np.roll(pts, -1, axis=0)
    n = len(p)
    d = q - p
    for i in range(n):
        j = np.arange(i + 2, n if i > 0 else n - 1)
        if j.size == 0:
            continue
        r = d[i]
        s = d[j]
        den = r[0] * s[:, 1] - r[1] * s[:, 0]
        qp = p[j] - p[i]
        ok = np.abs(den) > 1e-30
        t = np.where(ok, (qp[:, 0] * s[:, 1] - qp[:, 1] * s[:, 0]) / np.where(ok, den, 1), -1)
        u = np.where(ok, (qp[:, 0] * r[1] - qp[:, 1] * r[0]) / np.where(ok, den, 1), -1)
        if np.any((t > 1e-12) & (t < 1 - 1e-12) & (u > 1e-12) & (u < 1 - 1e-12)):
            raise InputError("outline crosses itself")
    return np.ascontiguousarray(pts)


def t6_shape(l: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """6-node triangle shape functions and their derivatives w.r.t. (l1, l2) at area coords l.

    Node order: corners 1, 2, 3, then mid-sides 1-2, 2-3, 3-1.
    Returns N (npt, 6) and dN (npt, 6, 2).
    """
    l1, l2, l3 = l[:, 0], l[:, 1], l[:, 2]
    n = np.column_stack(
        [l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3, 4 * l3 * l1]
    )
    # d/dl1 and d/dl2 with l3 = 1 - l1 - l2
    d1 = np.column_stack([4 * l1 - 1, 0 * l1, -(4 * l3 - 1), 4 * l2, -4 * l2, 4 * (l3 - l1)])
    d2 = np.column_stack([0 * l1, 4 * l2 - 1, -(4 * l3 - 1), 4 * l1, 4 * (l3 - l2), -4 * l1])
    return n, np.stack([d1, d2], axis=2)


@dataclass(frozen=True)
class RailSection:
    """A meshed rail cross-section with its properties.

    Attributes
    ----------
    nodes : ndarray (nn, 2)
        Node coordinates (eta, zeta), m.
    elements : ndarray (ne, 6)
        6-node triangles, 0-based node numbers (corners, then mid-sides 12, 23, 31).
    outline : ndarray (nb, 2)
        The polygon that was meshed, m.
    area, iy, iz, torsion : float
        Area m^2; second moments about the horizontal and vertical centroidal axes, m^4;
        Saint-Venant torsion constant, m^4.
    centroid : tuple
        (eta, zeta) of the centroid, m.
    crown_node : int
        Node at the top of the head on the axis (rail-head load and output point).
    foot_edges : ndarray (nf, 3)
        Quadratic edges on the foot's underside (zeta = 0): end, end, middle node.
    """

    nodes: np.ndarray
    elements: np.ndarray
    outline: np.ndarray
    area: float
    iy: float
    iz: float
    torsion: float
    centroid: tuple[float, float]
    crown_node: int
    foot_edges: np.ndarray
    published: dict = field(default_factory=lambda: dict(PUBLISHED_60E1))

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        """Number of 6-node triangles."""
        return int(self.elements.shape[0])

    def mass_per_length(self, density: float = 7850.0) -> float:
        """Mass per unit length, kg/m, for steel density ``density`` kg/m^3."""
        return self.area * density

    def errors(self) -> dict[str, float]:
        """Relative differences from the published 60E1 values (area, iy, iz)."""
        return {k: getattr(self, k) / self.published[k] - 1.0 for k in ("area", "iy", "iz")}


def _mesh_linear(outline: np.ndarray, max_area: float) -> tuple[np.ndarray, np.ndarray]:
    import triangle  # Shewchuk's Triangle (PyPI 'triangle'): quality constrained Delaunay

    n = len(outline)
    segs = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
    out = triangle.triangulate({"vertices": outline, "segments": segs}, f"pq30a{max_area:.12f}Q")
    return np.asarray(out["vertices"], float), np.asarray(out["triangles"], int)


def _mirror_halves(outline: np.ndarray, tol: float = 1e-9) -> np.ndarray | None:
    """The half of a mirror-symmetric outline on eta >= 0, closed along the axis, or None.

    ``outline`` is counter-clockwise without the repeated point. It is mirror-symmetric when
    its vertex set maps onto itself under eta -> -eta and exactly two vertices lie on eta = 0
    (the top and the bottom of the axis). The half runs counter-clockwise from the bottom axis
    vertex over eta > 0 to the top one; its last edge is the axis itself.
    """
    scale = max(float(np.abs(outline).max()), 1.0)
    on_axis = np.where(np.abs(outline[:, 0]) <= tol * scale)[0]
    if on_axis.size != 2:
        return None
    mirrored = outline * np.array([-1.0, 1.0])
    d = np.linalg.norm(outline[:, None, :] - mirrored[None, :, :], axis=2).min(axis=1)
    if d.max() > tol * scale:
        return None
    bot, top = on_axis[np.argsort(outline[on_axis, 1])]
    n = len(outline)
    chain = outline[[(bot + i) % n for i in range((top - bot) % n + 1)]]
    if chain.shape[0] < 3 or np.any(chain[1:-1, 0] <= 0.0):
        return None
    return chain


def _mesh_mirrored(half: np.ndarray, max_area: float) -> tuple[np.ndarray, np.ndarray]:
    """Mesh one half (eta >= 0, axis as a boundary edge) and mirror it, merging the axis nodes.

    Every node off the axis has its mirror image, every triangle its mirror triangle, so the
    section FE and everything computed from it are exactly symmetric about eta = 0.
    """
    nodes, tri = _mesh_linear(half, max_area)
    scale = max(float(np.abs(half).max()), 1.0)
    axis = np.abs(nodes[:, 0]) <= 1e-9 * scale
    nodes[axis, 0] = 0.0  # Steiner points on the axis edge: exactly on it
    if np.any(nodes[:, 0] < 0.0):
        raise InputError("half-section mesh crosses the axis of symmetry")
    off = np.where(~axis)[0]
    image = np.arange(len(nodes))
    image[off] = len(nodes) + np.arange(off.size)
    all_nodes = np.vstack([nodes, nodes[off] * np.array([-1.0, 1.0])])
    all_tri = np.vstack([tri, image[tri][:, ::-1]])  # reversed: mirror flips orientation
    return all_nodes, all_tri


def _to_t6(nodes: np.ndarray, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    edges: dict[tuple[int, int], int] = {}
    new = [p for p in nodes]
    el = np.zeros((len(tri), 6), dtype=int)
    for e, (a, b, c) in enumerate(tri):
        # counter-clockwise corners
        pa, pb, pc = nodes[a], nodes[b], nodes[c]
        if (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]) < 0:
            b, c = c, b
        el[e, :3] = (a, b, c)
        for k, (i, j) in enumerate(((a, b), (b, c), (c, a))):
            key = (min(i, j), max(i, j))
            if key not in edges:
                edges[key] = len(new)
                new.append(0.5 * (nodes[i] + nodes[j]))
            el[e, 3 + k] = edges[key]
    return np.array(new), el


def boundary_edges(elements: np.ndarray) -> np.ndarray:
    """Quadratic edges that belong to one element only: (a, b, m), a -> b counter-clockwise.

    For a counter-clockwise element the outside of such an edge lies to the right of a -> b,
    so its outward normal is (d_zeta, -d_eta) / |d| with d = node b - node a.
    """
    count: dict[tuple[int, int], list] = {}
    for e in elements:
        for a, b, m in ((e[0], e[1], e[3]), (e[1], e[2], e[4]), (e[2], e[0], e[5])):
            count.setdefault((min(a, b), max(a, b)), []).append((a, b, m))
    return np.array([v[0] for v in count.values() if len(v) == 1], dtype=int).reshape(-1, 3)


@dataclass(frozen=True)
class HeadSurface:
    """The rail head's running surface as the section mesh has it: a chain of quadratic edges.

    Attributes
    ----------
    edges : ndarray (ne, 3)
        Boundary edges (a, b, m) ordered by eta, eta_a < eta_b, where the surface faces upwards
        (outward normal's zeta component > ``min_normal_zeta``) above the centroid: the crown
        and the gauge-corner radii, not the 1:20 head sides.
    eta : ndarray (ne + 1,)
        Lateral positions of the edges' ends, m, ascending: the surface spans eta[0]..eta[-1].
    zeta : ndarray (ne + 1,)
        Heights of the edges' ends above the foot, m.
    """

    edges: np.ndarray
    eta: np.ndarray
    zeta: np.ndarray

    def locate(self, s: float) -> tuple[int, float]:
        """The edge holding lateral position s (m) and the local coordinate t in [-1, 1] on it.

        Raises
        ------
        InputError
            s outside the head surface.
        """
        s = _checks.finite("s", s)
        if not self.eta[0] <= s <= self.eta[-1]:
            raise InputError(
                f"s = {s:.6g} m is off the rail head's surface [{self.eta[0]:.6g}, {self.eta[-1]:.6g}] m"
            )
        i = int(np.clip(np.searchsorted(self.eta, s, side="right") - 1, 0, len(self.edges) - 1))
        ea, eb = self.eta[i], self.eta[i + 1]
        return i, float((2.0 * s - ea - eb) / (eb - ea))

    def point(self, s: float) -> tuple[float, float]:
        """Height zeta (m, above the foot) and slope d zeta / d eta of the surface at eta = s.

        The mesh's boundary is the outline's polygon (straight-sided elements), so the
        surface is piecewise linear between outline points; at an edge end the slope of the
        edge to its right is returned.
        """
        i, t = self.locate(s)
        slope = (self.zeta[i + 1] - self.zeta[i]) / (self.eta[i + 1] - self.eta[i])
        return float(self.zeta[i] + slope * (s - self.eta[i])), float(slope)

    def weights(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Section nodes (3,) and quadratic edge shape functions (3,) at eta = s."""
        i, t = self.locate(s)
        return self.edges[i], np.array([0.5 * t * (t - 1.0), 0.5 * t * (t + 1.0), 1.0 - t * t])


def head_surface(sec: RailSection, min_normal_zeta: float = 0.1) -> HeadSurface:
    """The running surface of a section's head (see :class:`HeadSurface`).

    Raises
    ------
    InputError
        No upward-facing boundary above the centroid, or one that is not a single chain.
    """
    nodes = sec.nodes
    picked = []
    for a, b, m in boundary_edges(sec.elements):
        d = nodes[b] - nodes[a]
        n_zeta = -d[0] / np.hypot(*d)
        if n_zeta > min_normal_zeta and min(nodes[a, 1], nodes[b, 1]) > sec.centroid[1]:
            picked.append((a, b, m) if nodes[a, 0] < nodes[b, 0] else (b, a, m))
    if not picked:
        raise InputError("the section has no upward-facing head surface above its centroid")
    edges = np.array(sorted(picked, key=lambda e: nodes[e[0], 0]), dtype=int)
    if np.any(edges[1:, 0] != edges[:-1, 1]):
        raise InputError("the section's head surface is not one chain of edges")
    ends = np.r_[edges[:, 0], edges[-1, 1]]
    return HeadSurface(edges=edges, eta=nodes[ends, 0].copy(), zeta=nodes[ends, 1].copy())


def section_properties(nodes: np.ndarray, elements: np.ndarray) -> dict[str, float]:
    """Area, centroid, I_y, I_z (centroidal) and the Saint-Venant torsion constant of a T6 mesh.

    The torsion constant comes from the warping function omega (Prandtl's/Saint-Venant's
    problem): Laplace(omega) = 0 with d omega/dn = z n_y - y n_z on the boundary, solved
    on the same quadratic mesh; J = int(y^2 + z^2 + y d omega/dz - z d omega/dy) dA.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    xy = nodes[elements]  # (ne, 6, 2)
    n, dn = t6_shape(GAUSS_L)  # (ng, 6), (ng, 6, 2)
    # Jacobian of the (straight-sided) map from (l1, l2) to (y, z)
    jac = np.einsum("gab,eac->egbc", dn, xy)  # (ne, ng, 2[l], 2[yz])
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0):
        raise InputError("mesh has inverted or degenerate elements")
    w = det * GAUSS_W[None, :] * 0.5  # (ne, ng) quadrature weights (area factor 1/2)
    pts = np.einsum("ga,eac->egc", n, xy)  # (ne, ng, 2)
    area = w.sum()
    cy = (w * pts[..., 0]).sum() / area
    cz = (w * pts[..., 1]).sum() / area
    y = pts[..., 0] - cy
    z = pts[..., 1] - cz
    iy = (w * z * z).sum()
    iz = (w * y * y).sum()
    # Warping function about the centroid.
    inv = np.linalg.inv(jac)  # (ne, ng, 2, 2): d(l)/d(yz)
    dxy = np.einsum("gal,egyl->egay", dn, inv)  # (ne, ng, 6, 2)  dN/dy, dN/dz
    ke = np.einsum("eg,egay,egby->eab", w, dxy, dxy)
    fe = np.einsum("eg,egay,egy->ea", w, dxy, np.stack([z, -y], axis=-1))
    nn = len(nodes)
    rows = np.repeat(elements, 6, axis=1).ravel()
    cols = np.tile(elements, (1, 6)).ravel()
    kg = sp.csr_matrix((ke.ravel(), (rows, cols)), shape=(nn, nn)).tolil()
    f = np.zeros(nn)
    np.add.at(f, elements.ravel(), fe.ravel())
    kg[0, :] = 0.0
    kg[0, 0] = 1.0
    f[0] = 0.0
    om = spla.spsolve(kg.tocsc(), f)
    g = np.einsum("egay,ea->egy", dxy, om[elements])
    torsion = (w * (y * y + z * z + y * g[..., 1] - z * g[..., 0])).sum()
    return {"area": area, "iy": iy, "iz": iz, "torsion": torsion, "cy": cy, "cz": cz}


def rail_section(
    max_element_area: float = 25e-6,
    outline: np.ndarray | None = None,
    arc_step: float | None = None,
    *,
    arc_step_mm: float | None = None,
) -> RailSection:
    """Mesh the UIC60 (60E1) rail cross-section and compute its properties.

    Parameters
    ----------
    max_element_area : float
        Largest triangle area, m^2 (25e-6 gives about 150 six-node triangles).
    outline : ndarray (n, 2), optional
        A closed polygon (m, last point = first) to mesh instead of 60E1. The crown
        node is the highest point on eta = 0 (or the highest point); the foot edges are
        those on the lowest zeta.
    arc_step : float, optional
        Spacing of outline points on the 60E1 arcs, m (default 0.003; at most
        :data:`ARC_STEP_MAX`).
    arc_step_mm : float, optional
        Deprecated: the same in mm (a DeprecationWarning). Not with ``arc_step``.

    Returns
    -------
    RailSection

    Raises
    ------
    InputError
        An outline that is not closed, crosses itself or encloses no area; a bad size;
        ``arc_step`` above :data:`ARC_STEP_MAX` (a mm value: the message says so).
    """
    max_element_area = _checks.positive("max_element_area", max_element_area)
    arc_step = arc_step_si(arc_step, arc_step_mm, 3e-3)
    # the outline is drawn in mm (the drawing's unit): 3e-3 * 1e3 is 3.0 to the bit
    poly = uic60_outline(step=arc_step * 1e3) if outline is None else np.asarray(outline, float)
    poly = check_outline(poly)
    half = _mirror_halves(poly)
    if half is None:
        lin_nodes, tri = _mesh_linear(poly, max_element_area)
    else:
        lin_nodes, tri = _mesh_mirrored(half, max_element_area)
    nodes, el = _to_t6(lin_nodes, tri)
    props = section_properties(nodes, el)
    top = nodes[:, 1].max()
    on_axis = np.where(np.abs(nodes[:, 0]) < 1e-9)[0]
    cand = on_axis if on_axis.size else np.arange(len(nodes))
    crown = int(cand[np.argmax(nodes[cand, 1])])
    zmin = nodes[:, 1].min()
    # Boundary edges (in one element only) on the lowest line.
    feet = [
        tuple(v)
        for v in boundary_edges(el)
        if abs(nodes[v[0], 1] - zmin) < 1e-9 and abs(nodes[v[1], 1] - zmin) < 1e-9
    ]
    if not feet:
        raise InputError("the outline has no flat underside to carry the pads")
    log.debug("rail section: %d nodes, %d T6 elements, top %.4f m", len(nodes), len(el), top)
    return RailSection(
        nodes=nodes,
        elements=el,
        outline=poly,
        area=props["area"],
        iy=props["iy"],
        iz=props["iz"],
        torsion=props["torsion"],
        centroid=(props["cy"], props["cz"]),
        crown_node=crown,
        foot_edges=np.array(feet, dtype=int),
    )


__all__ = [
    "PUBLISHED_60E1",
    "GAUSS_L",
    "GAUSS_W",
    "ARC_STEP_MAX",
    "arc_step_si",
    "uic60_outline",
    "check_outline",
    "t6_shape",
    "RailSection",
    "boundary_edges",
    "HeadSurface",
    "head_surface",
    "section_properties",
    "rail_section",
]
