"""Modal shape rows at points of the wheelset's meridian mesh: the rim edge and the journals.

A free-free mode's nodal amplitudes (U_r, U_y, U_th) of harmonic k, evaluated with the FE
shape functions of the element at a point, give the point's elastic displacement in the
vehicle frame (x, y, z) at azimuth theta and its theta-derivative; at the rim edge also the
rim's rotation about x. Frames, signs and the wheel sides as in :mod:`railvti.wheelset.flexible`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = [
    "CONTACT_ROWS",
    "JOURNAL_ROWS",
    "ATTACHMENT_DOFS",
    "RimEdge",
    "rim_edges",
    "check_side",
    "locate",
    "edge_point",
    "cylinder_fields",
    "vehicle_rows",
    "journal_rows",
]

#: Rows of a contact shape row: displacement x, y, z (vehicle frame) and the rim rotation.
CONTACT_ROWS = ("x", "y", "z", "rx")
#: Rows of a journal shape row: displacement x, y, z and the axle's rotations about x and z.
JOURNAL_ROWS = ("x", "y", "z", "rx", "rz")
#: Attachment DOFs of the residual flexibility, in order.
ATTACHMENT_DOFS = tuple(f"contact{s}.{c}" for s in (0, 1) for c in CONTACT_ROWS) + tuple(
    f"journal{s}.{c}" for s in (0, 1) for c in ("x", "y", "z")
)


@dataclass(frozen=True)
class RimEdge:
    """Tread/flange edge of one wheel on the meridian mesh: evaluation of nodal fields."""

    s_min: float
    s_max: float
    s_face: float  # flange face: s < s_face lies on the flange top
    y_contact: float  # FE y of the taping line (s = 0) of this side
    sign: float  # FE y = y_contact + sign * s (sign +1 right wheel, -1 left)
    r_tread: float
    r_flange: float

    def rim_samples(self, n: int = 201) -> tuple[np.ndarray, np.ndarray]:
        """Points s_j (m) on the tread edge and the weights w_j of the least-squares slope
        d/dy_FE of a field sampled there: slope = sum w_j f(s_j)."""
        s = np.linspace(self.s_face, self.s_max, n)
        d = s - s.mean()
        return s, self.sign * d / np.sum(d * d)


def rim_edges(geometry) -> tuple[RimEdge, RimEdge]:
    """The rim edges (right wheel, left wheel) of a :class:`~railvti.wheelset.WheelsetGeometry`."""
    g = geometry
    s_min = -g.contact_offset
    s_max = g.rim_width - g.contact_offset
    s_face = g.flange_width - g.contact_offset
    rf = g.wheel_radius + g.flange_height
    return (
        RimEdge(s_min, s_max, s_face, g.contact_y, 1.0, g.wheel_radius, rf),
        RimEdge(s_min, s_max, s_face, -g.contact_y, -1.0, g.wheel_radius, rf),
    )


def check_side(side: object) -> int:
    """A wheel side checked: 0 (right) or 1 (left); InputError otherwise."""
    if side not in (0, 1) or isinstance(side, bool):
        raise InputError(f"wheel side must be 0 (right) or 1 (left), got {side!r}")
    return int(side)


# ----------------------------------------------------------------- field evaluation
def _lagrange3(t: float) -> tuple[np.ndarray, np.ndarray]:
    return (
        np.array([0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)]),
        np.array([t - 0.5, -2.0 * t, t + 0.5]),
    )


def locate(mesh, r: float, y: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Element nodes and shape functions (N, dN/dr, dN/dy) at (r, y), m.

    The structured mesh has axis-parallel rectangles with mid-side nodes at the midpoints, so
    the natural coordinates are linear in (r, y). A point on the rim edge lies on the top of
    the elements below it. On a boundary between two elements along y (a node line) the
    derivatives jump; the two elements' values are averaged (the displacement is continuous,
    so N is unchanged; the slope is the mean of the one-sided slopes). Returns possibly
    repeated node indices: sum over them.
    """
    x = mesh.nodes
    c = mesh.conn
    r0, r1 = x[c[:, 0], 0], x[c[:, 2], 0]
    y0, y1 = x[c[:, 0], 1], x[c[:, 6], 1]
    tol = 1e-9
    hit = np.flatnonzero((r >= r0 - tol) & (r <= r1 + tol) & (y >= y0 - tol) & (y <= y1 + tol))
    if hit.size == 0:
        raise InputError(f"point (r={r:.4f}, y={y:.4f}) m lies outside the meridian mesh")
    hit = hit[np.isclose(r0[hit], r0[hit].min(), rtol=0.0, atol=tol)]
    nodes, ns, nrs, nys = [], [], [], []
    for e in hit:
        hr, hy = r1[e] - r0[e], y1[e] - y0[e]
        xi = 2.0 * (r - 0.5 * (r0[e] + r1[e])) / hr
        eta = 2.0 * (y - 0.5 * (y0[e] + y1[e])) / hy
        li, dli = _lagrange3(xi)
        lj, dlj = _lagrange3(eta)
        nodes.append(c[e])
        ns.append(np.outer(lj, li).ravel() / hit.size)  # column 3 j + i
        nrs.append(np.outer(lj, dli).ravel() * 2.0 / hr / hit.size)
        nys.append(np.outer(dlj, li).ravel() * 2.0 / hy / hit.size)
    return np.concatenate(nodes), np.concatenate(ns), np.concatenate(nrs), np.concatenate(nys)


def edge_point(edge: RimEdge, s: float) -> tuple[float, float]:
    """(r, y_FE) of the rim edge at profile coordinate s."""
    r = edge.r_tread if s >= edge.s_face else edge.r_flange
    return r, edge.y_contact + edge.sign * s


def cylinder_fields(shapes: np.ndarray, nodes, n, nr, ny) -> tuple[np.ndarray, ...]:
    """U, dU/dr, dU/dy (each (nm, 3)) of nodal shapes (nm, nn, 3) at one point."""
    s = shapes[:, nodes, :]
    return (np.einsum("mac,a->mc", s, n), np.einsum("mac,a->mc", s, nr), np.einsum("mac,a->mc", s, ny))


def vehicle_rows(
    k: int, fam: str, u: np.ndarray, du_dy_fe: np.ndarray, theta: float
) -> tuple[np.ndarray, np.ndarray]:
    """Vehicle-frame rows (4, nm) (x, y, z, rx) at azimuth theta and their theta-derivative.

    u: cylindrical amplitudes (U_r, U_y, U_th) at the point; du_dy_fe: the slope d/dy_FE of
    the amplitudes (column 0 gives rx: d u_z / d y_vehicle = d u_r / d y_FE at theta = 0).
    """
    ur, uy, ut = u[:, 0], u[:, 1], u[:, 2]
    dur = du_dy_fe[:, 0]
    if k == 0:
        cr, ct = 1.0, 1.0  # u_r = U_r, u_th = U_th (torsion)
        dcr, dct = 0.0, 0.0
    elif fam == "A":
        cr, ct = np.cos(k * theta), np.sin(k * theta)
        dcr, dct = -k * np.sin(k * theta), k * np.cos(k * theta)
    else:
        cr, ct = np.sin(k * theta), -np.cos(k * theta)
        dcr, dct = k * np.cos(k * theta), k * np.sin(k * theta)
    c, s = np.cos(theta), np.sin(theta)
    # cylindrical components at theta and their theta-derivatives
    vr, vy, vt, vdr = ur * cr, uy * cr, ut * ct, dur * cr
    wr, wy, wt, wdr = ur * dcr, uy * dcr, ut * dct, dur * dcr
    # e_r = -cos e_z - sin e_x, e_th = sin e_z - cos e_x, e_yFE = -e_y
    rows = np.array([-s * vr - c * vt, -vy, -c * vr + s * vt, vdr])
    drows = np.array([-c * vr - s * wr + s * vt - c * wt, -wy, s * vr - c * wr + c * vt + s * wt, wdr])
    return rows, drows


def journal_rows(body_shapes, mesh, node: int) -> np.ndarray:
    """Journal-centre rows (5, nq): x, y, z, rotation about x and about z (vehicle frame).

    Rotations: half the curl of the element's displacement field at the axis node (the
    cross-section's rotation of the solid, shear included).
    """
    r, y = mesh.nodes[node]
    nodes, n, nr, ny = locate(mesh, r, y)
    out = []
    for k, fam, shapes in body_shapes:
        u, dudr, dudy = cylinder_fields(shapes, nodes, n, nr, ny)
        rows, _ = vehicle_rows(k, fam, u, dudy, 0.0)
        rot = np.zeros((2, shapes.shape[0]))
        if k == 1 and fam == "A":  # omega_x = (dU_r/dy_FE - dU_y/dr) / 2
            rot[0] = 0.5 * (dudy[:, 0] - dudr[:, 1])
        elif k == 1:  # omega_z = (U_y / r + dU_th/dy_FE) / 2, U_y/r -> dU_y/dr
            uy_r = dudr[:, 1] if r <= 1e-12 else u[:, 1] / r
            rot[1] = 0.5 * (uy_r + dudy[:, 2])
        out.append(np.vstack([rows[:3], rot]))
    return np.concatenate(out, axis=1)
