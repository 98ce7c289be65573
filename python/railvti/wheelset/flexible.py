"""The flexible wheelset as a body for a vehicle model (Kaiser eqs 1-3, 9-11).

Split between rigid and elastic motion: the six rigid-body DOFs belong to the vehicle
model; the elastic part is the set of FREE-FREE elastic modes of the wheelset (no primary
springs: the vehicle re-attaches the journal springs between the journal rows below and its
moving bogie frame). The rigid-body modes of the free-free wheelset are removed: k = 0 the
axial translation and the spin, k = 1 the two transverse translations and the two tilts.
The modes are expressed in the axle-fixed (non-spinning) frame of eq. 11: pairs Q_A, Q_B
per harmonic k > 0, constant matrices M = I, G, D, K.

Frames and signs (see docs/wheelset_flexible.md):

* vehicle frame x forward, y left, z up; the wheelset spins at Omega = v / r0 > 0 about
  +y (forward rolling). Side 0 is the RIGHT wheel (vehicle y < 0, the FE mesh's y > 0),
  side 1 the LEFT wheel, as in :meth:`Wheelset.axle_fixed` (note: the vehicle model's wheel
  outputs number 0 left, 1 right). The FE meridian coordinate y_FE = -y_vehicle.
* azimuth theta = 0 points from the axle down to the contact points; theta increases in the
  sense of the material's motion (at theta = 0 that is backwards, -x): (r, theta, +y_vehicle)
  is right-handed, the sense in which the Coriolis terms of eq. 11 take Omega > 0.
* Shape rows give the elastic displacement in the vehicle frame (x, y, z), m per unit Q,
  at the contact point on the rim edge (the FE field of the element there, not the nearest
  node), and the rim's rotation about the rolling axis x (rad per unit Q): the change of the
  slope of the running surface d u_z / d y_vehicle, taken as the least-squares slope of the
  normal (radial) displacement along the whole tread edge. Not the local d/ds at the contact
  point: under the concentrated contact load the local slope at the loaded point depends on
  the mesh (0.95..1.12 mrad for 1715..4935 nodes under 85 kN per wheel) and jumps with the
  load's position, while the tread slope is mesh-independent (1.258..1.259 mrad); the
  local indentation belongs to the contact model.
"""
from __future__ import annotations

import logging
import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .. import _checks
from .._native import core
from .._status import check
from ..errors import InputError
from .fe import HarmonicModes, check_harmonic, eq11_blocks

log = logging.getLogger(__name__)

#: Rows of a contact shape row: displacement x, y, z (vehicle frame) and the rim rotation.
CONTACT_ROWS = ("x", "y", "z", "rx")
#: Rows of a journal shape row: displacement x, y, z and the axle's rotations about x and z.
JOURNAL_ROWS = ("x", "y", "z", "rx", "rz")
#: Attachment DOFs of the residual flexibility, in order.
ATTACHMENT_DOFS = tuple(f"contact{s}.{c}" for s in (0, 1) for c in CONTACT_ROWS) + tuple(
    f"journal{s}.{c}" for s in (0, 1) for c in ("x", "y", "z"))
#: A mode with a frequency below this (Hz) is a rigid-body mode of the free-free wheelset.
_RIGID_HZ = 0.5


@dataclass(frozen=True)
class _Edge:
    """Tread/flange edge of one wheel on the meridian mesh: evaluation of nodal fields."""

    s_min: float
    s_max: float
    s_face: float          # flange face: s < s_face lies on the flange top
    y_contact: float       # FE y of the taping line (s = 0) of this side
    sign: float            # FE y = y_contact + sign * s (sign +1 right wheel, -1 left)
    r_tread: float
    r_flange: float

    def rim_samples(self, n: int = 201) -> tuple[np.ndarray, np.ndarray]:
        """Points s_j (m) on the tread edge and the weights w_j of the least-squares slope
        d/dy_FE of a field sampled there: slope = sum w_j f(s_j)."""
        s = np.linspace(self.s_face, self.s_max, n)
        d = s - s.mean()
        return s, self.sign * d / np.sum(d * d)


@dataclass(frozen=True)
class FlexibleWheelset:
    """The free-free elastic wheelset in the axle-fixed frame, for a vehicle integrator.

    Equations of the elastic coordinates q (nq,), with the rigid wheelset's roll rate
    a' and yaw rate b' (vehicle frame, rad/s) and its spin-perturbation rate s'::

        M q'' + (G + D) q' + K q - Omega * (C @ [a', b'] + c_s * s') = R^T F

    and the rigid wheelset's roll and yaw equations gain ``+ Omega * C.T @ q'`` (left-hand
    side; the spin equation ``+ Omega * c_s @ q'``) besides the rigid gyroscopic terms
    ``-I_y Omega b'`` (roll) and ``+I_y Omega a'`` (yaw). R^T F: the contact forces
    (vehicle frame, N) and rim moments about x (N m) through ``rows(side, s).T``, the journal
    forces through ``journal[side].T``.

    Attributes
    ----------
    speed : float
        Running speed, m/s.
    omega : float
        Spin Omega = speed / r0, rad/s.
    k : ndarray of int (nq,)
        Harmonic of each coordinate.
    family : ndarray of str (nq,)
        '0' (k = 0), 'A' or 'B' (k > 0).
    freq_hz : ndarray (nq,)
        Free-free non-rotating natural frequency of each coordinate's mode, Hz.
    mass, gyro, damping, stiffness : ndarray (nq, nq)
        M = I, G (skew: Coriolis and frame rotation), D (modal damping), K (with the
        centrifugal softening and prestress terms of eq. 11).
    rigid_elastic : ndarray (nq, 2)
        C: the Coriolis coupling of the elastic coordinates with the rigid wheelset's roll
        (column 0) and yaw (column 1) rates, kg^0.5 m per unit Q (see the equations above):
        -2 <phi, (0, r, 0)>_M of the k = 1 modes (set B for roll, set A for yaw), zero for
        the modes symmetric about the mid-plane; the same as the FE Coriolis matrix's block
        between the rigid tilts and the elastic modes (tested).
    spin_coupling : ndarray (nq,)
        The same for the rate of the spin perturbation (about +y, rad/s) against the k = 0
        modes (breathing: the polar moment changes): elastic equations ``- Omega * c * s'``,
        the spin equation ``+ Omega * c @ q'``. From the FE Coriolis matrix.
    polar_moment : float
        I_y, the wheelset's moment of inertia about its axle from the FE mass, kg m^2.
    journal : ndarray (2, 5, nq)
        Journal-centre rows (side 0 right, 1 left) :data:`JOURNAL_ROWS`.
    s0, ds : float
        First wheel-profile coordinate and step of the contact tables, m.
    contact_table : ndarray (2, ns, 4, nq)
        :meth:`rows` on the uniform grid s0 + i ds (linear interpolation for a kernel).
    dtheta_table : ndarray (2, ns, 4, nq)
        :meth:`dtheta_rows` on the same grid.
    residual : ndarray (14, 14)
        Residual flexibility of the truncated free-free elastic modes (those of harmonics
        0..k_max above f_max and all of harmonics k_max+1..residual_k_max) over
        :data:`ATTACHMENT_DOFS` at the contact coordinates ``residual_s``: m/N, rad/N,
        rad/(N m). Static deflection of the attachment DOFs (rigid parts removed
        mass-orthogonally) = R Lambda^-1 R^T F + residual F, R the attachment rows.
    residual_s : tuple of float
        Wheel-profile coordinate (right, left) of the contact points of ``residual``, m.
    residual_k_max : int
        Highest harmonic in the residual flexibility.
    """

    speed: float
    omega: float
    k: np.ndarray
    family: np.ndarray
    freq_hz: np.ndarray
    mass: np.ndarray
    gyro: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    rigid_elastic: np.ndarray
    spin_coupling: np.ndarray
    polar_moment: float
    journal: np.ndarray
    s0: float
    ds: float
    contact_table: np.ndarray
    dtheta_table: np.ndarray
    residual: np.ndarray
    residual_s: tuple[float, float]
    residual_k_max: int = 0
    _edges: tuple = ()
    _rim_slope: tuple = ()       # per side, per coordinate group: rim rotation of U_r (nm,)
    _shapes: tuple = ()          # per coordinate group: (k, family, shapes (n, nn, 3))
    _mesh: object = None

    @property
    def n(self) -> int:
        """Number of elastic coordinates."""
        return int(self.k.size)

    @property
    def s_range(self) -> tuple[float, float]:
        """Wheel-profile coordinates covered by the rim edge (flange back .. outer rim face), m."""
        e = self._edges[0]
        return e.s_min, e.s_max

    def rows(self, side: int, s: float) -> np.ndarray:
        """Shape rows at the contact point of wheel ``side`` at profile coordinate s.

        Parameters
        ----------
        side : int
            0 right wheel, 1 left wheel (vehicle y > 0 is left).
        s : float
            Wheel-profile coordinate of the contact point (as :class:`railvti.profiles.Profile`
            y and the vehicle table's s_wheel: from the taping line, + towards the field
            side, flange at s < 0), m.

        Returns
        -------
        ndarray (4, nq)
            Displacement x, y, z (m) per unit Q at the point, interpolated with the FE shape
            functions of the element along the rim edge, and the rim's rotation about x (rad
            per unit Q; the least-squares slope over the tread, the same for every s).

        Raises
        ------
        InputError
            An unknown side, s not finite or outside the rim edge.
        """
        return _point_rows(self, _check_side(side), _check_s(self, s), 0.0)[0]

    def dtheta_rows(self, side: int, s: float) -> np.ndarray:
        """d/dtheta of :meth:`rows` at the contact point (the Eulerian term).

        The deformation velocity of the rim material at the contact point is
        ``rows @ q' + Omega * dtheta_rows @ q`` (vehicle-frame components: the derivative
        includes the turning of the cylindrical basis).
        """
        return _point_rows(self, _check_side(side), _check_s(self, s), 0.0)[1]

    def static_deflection(self, force: np.ndarray, residual: bool = True) -> np.ndarray:
        """Static deflection of the attachment DOFs under attachment loads (Omega = 0).

        Parameters
        ----------
        force : array_like (14,)
            Loads on :data:`ATTACHMENT_DOFS` (N, N m for rx), at ``residual_s``.
        residual : bool
            Add the residual flexibility of the truncated modes.

        Returns
        -------
        ndarray (14,)
            Elastic deflection (rigid-body parts removed, mass-orthogonally), m / rad.
        """
        f = _checks.finite_array("force", force, shape=(len(ATTACHMENT_DOFS),))
        r = _attachment_rows(self, self.residual_s)
        lam = (2.0 * np.pi * self.freq_hz) ** 2
        u = r @ ((r.T @ f) / lam)
        return u + self.residual @ f if residual else u


def _check_side(side: object) -> int:
    if side not in (0, 1) or isinstance(side, bool):
        raise InputError(f"wheel side must be 0 (right) or 1 (left), got {side!r}")
    return int(side)


def _check_s(body: FlexibleWheelset, s: object) -> float:
    s = _checks.finite("s", s)
    lo, hi = body.s_range
    if not lo - 1e-12 <= s <= hi + 1e-12:
        raise InputError(f"wheel-profile coordinate s = {s * 1e3:.3f} mm lies outside the rim "
                         f"edge ({lo * 1e3:.1f}..{hi * 1e3:.1f} mm)")
    return min(max(s, lo), hi)


# ----------------------------------------------------------------- field evaluation
def _lagrange3(t: float) -> tuple[np.ndarray, np.ndarray]:
    return (np.array([0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)]),
            np.array([t - 0.5, -2.0 * t, t + 0.5]))


def _locate(mesh, r: float, y: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
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
        ns.append(np.outer(lj, li).ravel() / hit.size)           # column 3 j + i
        nrs.append(np.outer(lj, dli).ravel() * 2.0 / hr / hit.size)
        nys.append(np.outer(dlj, li).ravel() * 2.0 / hy / hit.size)
    return np.concatenate(nodes), np.concatenate(ns), np.concatenate(nrs), np.concatenate(nys)


def _edge_point(edge: _Edge, s: float) -> tuple[float, float]:
    """(r, y_FE) of the rim edge at profile coordinate s."""
    r = edge.r_tread if s >= edge.s_face else edge.r_flange
    return r, edge.y_contact + edge.sign * s


def _cyl_fields(shapes: np.ndarray, nodes, n, nr, ny) -> tuple[np.ndarray, ...]:
    """U, dU/dr, dU/dy (each (nm, 3)) of nodal shapes (nm, nn, 3) at one point."""
    s = shapes[:, nodes, :]
    return (np.einsum("mac,a->mc", s, n), np.einsum("mac,a->mc", s, nr),
            np.einsum("mac,a->mc", s, ny))


def _vehicle_rows(k: int, fam: str, u: np.ndarray, du_dy_fe: np.ndarray, theta: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Vehicle-frame rows (4, nm) (x, y, z, rx) at azimuth theta and their theta-derivative.

    u: cylindrical amplitudes (U_r, U_y, U_th) at the point; du_dy_fe: the slope d/dy_FE of
    the amplitudes (column 0 gives rx: d u_z / d y_vehicle = d u_r / d y_FE at theta = 0).
    """
    ur, uy, ut = u[:, 0], u[:, 1], u[:, 2]
    dur = du_dy_fe[:, 0]
    if k == 0:
        cr, sr, ct, st = 1.0, 0.0, 1.0, 0.0      # u_r = U_r, u_th = U_th (torsion)
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
    drows = np.array([-c * vr - s * wr + s * vt - c * wt, -wy,
                      s * vr - c * wr + c * vt + s * wt, wdr])
    return rows, drows


def _point_rows(body: FlexibleWheelset, side: int, s: float, theta: float) -> tuple[np.ndarray, np.ndarray]:
    """Rows and d/dtheta rows (4, nq) of the rim edge point (side, s) at azimuth theta."""
    edge = body._edges[side]
    r, y = _edge_point(edge, s)
    nodes, n, nr, ny = _locate(body._mesh, r, y)
    rows, drows = [], []
    for (k, fam, shapes), slope in zip(body._shapes, body._rim_slope[side]):
        u, _, _ = _cyl_fields(shapes, nodes, n, nr, ny)
        a, b = _vehicle_rows(k, fam, u, np.c_[slope, 0 * slope, 0 * slope], theta)
        rows.append(a)
        drows.append(b)
    return np.concatenate(rows, axis=1), np.concatenate(drows, axis=1)


def _journal_rows(body_shapes, mesh, node: int) -> np.ndarray:
    """Journal-centre rows (5, nq): x, y, z, rotation about x and about z (vehicle frame).

    Rotations: half the curl of the element's displacement field at the axis node (the
    cross-section's rotation of the solid, shear included).
    """
    r, y = mesh.nodes[node]
    nodes, n, nr, ny = _locate(mesh, r, y)
    out = []
    for k, fam, shapes in body_shapes:
        u, dudr, dudy = _cyl_fields(shapes, nodes, n, nr, ny)
        rows, _ = _vehicle_rows(k, fam, u, dudy, 0.0)
        rot = np.zeros((2, shapes.shape[0]))
        if k == 1 and fam == "A":      # omega_x = (dU_r/dy_FE - dU_y/dr) / 2
            rot[0] = 0.5 * (dudy[:, 0] - dudr[:, 1])
        elif k == 1:                   # omega_z = (U_y / r + dU_th/dy_FE) / 2, U_y/r -> dU_y/dr
            uy_r = dudr[:, 1] if r <= 1e-12 else u[:, 1] / r
            rot[1] = 0.5 * (uy_r + dudy[:, 2])
        out.append(np.vstack([rows[:3], rot]))
    return np.concatenate(out, axis=1)


# ------------------------------------------------------------ FE statics per harmonic
def _dof_transform(mesh, k: int) -> sp.csr_matrix:
    """T (3 nn, neq): nodal amplitudes from equations, with the axis regularity of
    wheelset_modes.f90::dof_map (k = 0: U_y only; k = 1: U_th = -U_r, U_y = 0; k >= 2: 0)."""
    x = mesh.nodes
    tol = 1e-9 * max(float(np.abs(x[:, 0]).max()), 1e-30)
    rows, cols, vals = [], [], []
    neq = 0
    for i, (r, _) in enumerate(x):
        if r <= tol:
            if k == 0:
                rows.append(3 * i + 1); cols.append(neq); vals.append(1.0); neq += 1
            elif k == 1:
                rows += [3 * i, 3 * i + 2]; cols += [neq, neq]; vals += [1.0, -1.0]; neq += 1
        else:
            for c in range(3):
                rows.append(3 * i + c); cols.append(neq); vals.append(1.0); neq += 1
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * mesh.n_nodes, neq))


def assemble_harmonic(mesh, k: int, young: float, poisson: float, density: float
                      ) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Global stiffness and mass of harmonic k over the nodal amplitudes (3 nn, node-major).

    The same element matrices as the eigen-solver (wheelset_element.f90::axisym_element),
    assembled in Python (sparse) for the static solves of the residual flexibility.
    """
    ne = mesh.n_elements
    idx = (3 * mesh.conn[:, :, None] + np.arange(3)[None, None, :]).reshape(ne, 27)
    kv = np.empty((ne, 27, 27))
    mv = np.empty((ne, 27, 27))
    for e in range(ne):
        ke, me, _, _, info = core.wheelset_element_c(k, np.asfortranarray(mesh.nodes[mesh.conn[e]].T),
                                                     young, poisson, density)
        check(info, f"harmonic k={k}: meridian element {e}")
        kv[e], mv[e] = ke, me
    ii = np.repeat(idx, 27, axis=1).ravel()
    jj = np.tile(idx, (1, 27)).ravel()
    n = 3 * mesh.n_nodes
    return (sp.csr_matrix((kv.ravel(), (ii, jj)), shape=(n, n)),
            sp.csr_matrix((mv.ravel(), (ii, jj)), shape=(n, n)))


class HarmonicStatics:
    """Static compliance of the free-free elastic wheelset for one harmonic k.

    G = sum over ALL elastic modes of phi phi^T / omega^2 = K^+ restricted to the
    mass-orthogonal complement of the rigid-body modes (the inertia-relief flexibility with
    the rigid parts removed mass-orthogonally), from the bordered system
    [[K, M Phi_r], [Phi_r^T M, 0]] [u; lam] = [f; 0] with the FE stiffness K of harmonic k.
    The rigid-body fields are built exactly (k = 0: axial translation (0, 1, 0) and spin
    (0, 0, r); k = 1: translation (1, 0, -1) and tilt (-y, r, y); amplitudes (U_r, U_y,
    U_th) of eq. 7) and made mass-orthonormal.

    Parameters
    ----------
    mesh : MeridianMesh
    k : int
    young, poisson, density : float
    """

    def __init__(self, mesh, k: int, young: float, poisson: float, density: float) -> None:
        self.k = k
        self.T = _dof_transform(mesh, k)
        kf, mf = assemble_harmonic(mesh, k, young, poisson, density)
        self.K = (self.T.T @ kf @ self.T).tocsc()
        self.M = (self.T.T @ mf @ self.T).tocsc()
        self._w = np.asarray(self.T.T.multiply(self.T.T).sum(axis=1)).ravel()
        r, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
        z, one = np.zeros_like(r), np.ones_like(r)
        fields = {0: [np.c_[z, one, z], np.c_[z, z, r]],
                  1: [np.c_[one, z, -one], np.c_[-y, r, y]]}.get(k, [])
        rig = np.zeros((self.K.shape[0], len(fields)))
        for j, f in enumerate(fields):
            x = self.reduce(f)
            for i in range(j):                              # Gram-Schmidt in the mass metric
                x -= rig[:, i] * (rig[:, i] @ (self.M @ x))
            rig[:, j] = x / np.sqrt(x @ (self.M @ x))
        self.rigid = rig
        nr = rig.shape[1]
        mr = self.M @ rig
        a = self.K if nr == 0 else sp.bmat(
            [[self.K, sp.csc_matrix(mr)], [sp.csc_matrix(mr.T), None]], format="csc")
        self._lu = splu(a)
        self._nr = nr
        self._compliance: dict[tuple, np.ndarray] = {}

    def reduce(self, field: np.ndarray) -> np.ndarray:
        """Equation vector of a nodal field (nn, 3) that obeys the axis regularity."""
        return (self.T.T @ np.asarray(field, dtype=float).ravel()) / self._w

    def solve(self, f_nodal: np.ndarray) -> np.ndarray:
        """Elastic static displacement (3 nn[, m], m) of nodal loads f (3 nn[, m], N): G f."""
        f = self.T.T @ f_nodal
        rhs = np.concatenate([f, np.zeros((self._nr,) + f.shape[1:])])
        u = self._lu.solve(rhs)[: f.shape[0]]
        return self.T @ u

    def mass_product(self, a: np.ndarray, b: np.ndarray) -> float:
        """<a, b>_M of two nodal fields (nn, 3) of this harmonic (FE consistent mass)."""
        return float(self.reduce(a) @ (self.M @ self.reduce(b)))


_STATICS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _statics(ws, k: int) -> HarmonicStatics:
    """The (cached, per Wheelset) static solver of harmonic k."""
    per = _STATICS.setdefault(ws, {})
    if k not in per:
        g = ws.geometry
        per[k] = HarmonicStatics(ws.mesh, k, g.young, g.poisson, g.density)
    return per[k]


def _harmonic(ws, k: int, f_max: float) -> HarmonicModes:
    """Free-free modes of harmonic k up to f_max, cut from a cached solve to a higher f_max
    when there is one (the eigenpairs are the same)."""
    best = None
    for key, h in ws._cache.items():
        if key[0] == k and key[2] == "free" and key[1] >= f_max and (best is None or key[1] < best[0]):
            best = (key[1], h)
    if best is None:
        return ws.harmonic(k, f_max, "free")
    h = best[1]
    m = h.freq_hz <= f_max
    ix = np.ix_(m, m)
    return HarmonicModes(k=h.k, freq_hz=h.freq_hz[m], shapes=h.shapes[m], coriolis=h.coriolis[ix],
                         inplane_mass=h.inplane_mass[ix],
                         prestress_stiffness=h.prestress_stiffness[ix],
                         n_equations=h.n_equations, bandwidth=h.bandwidth)


def _point_operator(mesh, edge: _Edge | None, s: float | None, node: int | None,
                    rim: np.ndarray | None = None) -> dict[str, list[np.ndarray]]:
    """Nodal operators of the attachment rows at theta = 0, per harmonic kind.

    Returns {'0': [...], 'A': [...], 'B': [...]}: for each row, the nodal vector (3 nn) e with
    row value = e . U of that set's amplitudes (k = 0 uses '0'; k > 0 'A' and 'B'). rim: the
    edge's :func:`_rim_operator` when already known.
    """
    if edge is not None:
        r, y = _edge_point(edge, s)
    else:
        r, y = mesh.nodes[node]
    nodes, n, nr, ny = _locate(mesh, r, y)
    nn3 = 3 * mesh.n_nodes

    def vec(comp: int, w: np.ndarray, scale: float) -> np.ndarray:
        v = np.zeros(nn3)
        np.add.at(v, 3 * nodes + comp, scale * w)
        return v

    zero = np.zeros(nn3)
    # rows x, y, z (+ rx on the rim), from _vehicle_rows at theta = 0
    ops = {"0": [vec(2, n, -1.0), vec(1, n, -1.0), vec(0, n, -1.0)],
           "A": [zero, vec(1, n, -1.0), vec(0, n, -1.0)],
           "B": [vec(2, n, 1.0), zero, zero]}
    if edge is not None:
        rim = _rim_operator(mesh, edge) if rim is None else rim
        ops["0"].append(rim)
        ops["A"].append(rim)
        ops["B"].append(zero)
    return ops


_RIM: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _rim_operators(ws, edges) -> tuple[np.ndarray, ...]:
    """:func:`_rim_operator` of both edges, cached per Wheelset."""
    per = _RIM.setdefault(ws, {})
    if edges not in per:
        per[edges] = tuple(_rim_operator(ws.mesh, e) for e in edges)
    return per[edges]


def _rim_operator(mesh, edge: _Edge) -> np.ndarray:
    """Nodal vector (3 nn) of the rim rotation: the least-squares slope d U_r / d y_FE of the
    radial amplitude over the tread edge (= d u_z / d y_vehicle at theta = 0)."""
    v = np.zeros(3 * mesh.n_nodes)
    for s, w in zip(*edge.rim_samples()):
        nodes, n, _, _ = _locate(mesh, *_edge_point(edge, float(s)))
        np.add.at(v, 3 * nodes, w * n)
    return v


def full_compliance(statics: list[HarmonicStatics], mesh, edges, s_pair, journal_nodes,
                    rims: tuple | None = None) -> np.ndarray:
    """Static compliance (14, 14) over :data:`ATTACHMENT_DOFS` of all free-free elastic modes
    of the harmonics in ``statics`` (Omega = 0), from the FE stiffness. rims: the edges'
    :func:`_rim_operator` when already known."""
    rims = rims if rims is not None else (None, None)
    pts = None
    g = np.zeros((len(ATTACHMENT_DOFS),) * 2)
    for st in statics:
        key = (tuple(s_pair), tuple(journal_nodes))
        if key not in st._compliance:
            if pts is None:
                pts = [_point_operator(mesh, edges[0], s_pair[0], None, rims[0]),
                       _point_operator(mesh, edges[1], s_pair[1], None, rims[1]),
                       _point_operator(mesh, None, None, journal_nodes[0]),
                       _point_operator(mesh, None, None, journal_nodes[1])]
            gk = np.zeros_like(g)
            for kind in (("0",) if st.k == 0 else ("A", "B")):
                e = np.array([v for p in pts for v in p[kind]])        # (14, 3 nn)
                cols = [st.solve(e[j]) if np.any(e[j]) else np.zeros(e.shape[1])
                        for j in range(e.shape[0])]
                gk += e @ np.array(cols).T
            st._compliance[key] = 0.5 * (gk + gk.T)
        g += st._compliance[key]
    return g


def _attachment_rows(body: FlexibleWheelset, s_pair) -> np.ndarray:
    """Rows (14, nq) of the attachment DOFs at contact coordinates s_pair."""
    c0 = body.rows(0, s_pair[0])
    c1 = body.rows(1, s_pair[1])
    return np.vstack([c0, c1, body.journal[0, :3], body.journal[1, :3]])


# ------------------------------------------------------------------------ the body
def _rigid_mask(h: HarmonicModes) -> np.ndarray:
    return h.freq_hz < _RIGID_HZ


def _edges(geometry) -> tuple[_Edge, _Edge]:
    g = geometry
    s_min = -g.contact_offset
    s_max = g.rim_width - g.contact_offset
    s_face = g.flange_width - g.contact_offset
    rf = g.wheel_radius + g.flange_height
    return (_Edge(s_min, s_max, s_face, g.contact_y, 1.0, g.wheel_radius, rf),
            _Edge(s_min, s_max, s_face, -g.contact_y, -1.0, g.wheel_radius, rf))


def flexible_body(ws, speed: float, k_max: int = 2, f_max: float = 800.0,
                  damping_ratio: float = 0.005, centrifugal: bool = True,
                  residual_s: tuple[float, float] = (0.0, 0.0), ds: float = 1e-3,
                  residual: bool = True, residual_k_max: int | None = None) -> FlexibleWheelset:
    """Build the free-free flexible body; see :meth:`Wheelset.flexible_body`."""
    speed = _checks.non_negative("speed", speed)
    zeta = _checks.non_negative("damping_ratio", damping_ratio)
    k_max = check_harmonic(k_max, "k_max")
    try:
        f_max = _checks.positive("f_max", f_max)
    except InputError as exc:
        raise InputError(f"f_max must be a positive frequency in Hz, got {f_max!r}") from exc
    ds = _checks.positive("ds", ds)
    k_res = max(k_max, 6) if residual_k_max is None else check_harmonic(residual_k_max,
                                                                        "residual_k_max")
    if k_res < k_max:
        raise InputError(f"residual_k_max ({k_res}) must be >= k_max ({k_max})")
    g = ws.geometry
    om = speed / g.wheel_radius
    mesh = ws.mesh
    edges = _edges(g)
    gb, kb, db, fam, kq, fq, shapes = [], [], [], [], [], [], []
    for k in range(k_max + 1):
        h = _harmonic(ws, k, f_max)
        keep = ~_rigid_mask(h)
        if k == 0:
            h0 = h
        lam = h.lam[keep]
        n = lam.size
        if n == 0:
            continue
        gam = h.coriolis[np.ix_(keep, keep)]
        mc = (h.inplane_mass - h.prestress_stiffness)[np.ix_(keep, keep)] if centrifugal \
            else np.zeros_like(gam)
        shp = h.shapes[keep]
        gk, kd, dk = eq11_blocks(lam, gam, mc, k, om, zeta)
        gb.append(gk)
        db.append(dk)
        if k == 0:
            kb.append(kd)
            fam += ["0"] * n
            kq += [0] * n
            fq += list(h.freq_hz[keep])
            shapes.append((0, "0", shp))
        else:
            kb.append(np.block([[kd, np.zeros((n, n))], [np.zeros((n, n)), kd]]))
            fam += ["A"] * n + ["B"] * n
            kq += [k] * (2 * n)
            fq += list(h.freq_hz[keep]) * 2
            shapes += [(k, "A", shp), (k, "B", shp)]
    from scipy.linalg import block_diag
    nq = len(kq)
    if nq == 0:
        log.info("flexible wheelset: no elastic mode below %.0f Hz for k <= %d", f_max, k_max)
    # polar moment and rigid-elastic coupling from the FE mass (k = 0 and k = 1)
    st0 = _statics(ws, 0)
    r = mesh.nodes[:, 0]
    spin = np.zeros((mesh.n_nodes, 3))
    spin[:, 2] = r
    polar = st0.mass_product(spin, spin)
    cpl = np.zeros((nq, 2))
    if k_max >= 1 and nq:
        st1 = _statics(ws, 1)
        tilt = np.zeros((mesh.n_nodes, 3))
        tilt[:, 1] = r                                   # the field U_y = r of harmonic 1
        col = 0
        for k, f, shp in shapes:
            n = shp.shape[0]
            if k == 1:
                # c = -2 int rho X_x u_y (roll) and -2 int rho X_z u_y (yaw), vehicle frame:
                # = -2 <phi, (0, r, 0)>_M1 for set B (roll) and set A (yaw)
                v = np.array([-2.0 * st1.mass_product(p, tilt) for p in shp])
                cpl[col:col + n, 0 if f == "B" else 1] = v
            col += n
    # spin perturbation rate against the k = 0 modes: the FE Coriolis matrix (eq. 11) between
    # the rigid spin field (0, 0, r) and the elastic modes, c = -2 (Gamma a)_elastic
    spin_c = np.zeros(nq)
    n0 = int(np.sum(np.array(kq) == 0))
    if n0:
        x = np.array([st0.reduce(p) for p in h0.shapes]).T
        a = x.T @ (st0.M @ st0.reduce(spin))
        spin_c[:n0] = -2.0 * (h0.coriolis @ a)[~_rigid_mask(h0)]
    s_grid = np.arange(edges[0].s_min, edges[0].s_max + 0.5 * ds, ds)
    s_grid = s_grid[s_grid <= edges[0].s_max + 1e-12]
    body = FlexibleWheelset(
        speed=speed, omega=om, k=np.array(kq, dtype=int), family=np.array(fam, dtype="<U1"),
        freq_hz=np.array(fq), mass=np.eye(nq), gyro=block_diag(*gb) if gb else np.zeros((0, 0)),
        damping=block_diag(*db) if db else np.zeros((0, 0)),
        stiffness=block_diag(*kb) if kb else np.zeros((0, 0)), rigid_elastic=cpl,
        spin_coupling=spin_c,
        polar_moment=polar, journal=np.zeros((2, 5, nq)), s0=float(s_grid[0]), ds=ds,
        contact_table=np.zeros((2, s_grid.size, 4, nq)),
        dtheta_table=np.zeros((2, s_grid.size, 4, nq)), residual=np.zeros((14, 14)),
        residual_s=(float(residual_s[0]), float(residual_s[1])), residual_k_max=k_res,
        _edges=edges, _rim_slope=tuple(
            tuple(shp.reshape(shp.shape[0], -1) @ op for _, _, shp in shapes)
            for op in _rim_operators(ws, edges)),
        _shapes=tuple(shapes), _mesh=mesh)
    for side in range(2):
        body.journal[side] = _journal_rows(shapes, mesh, ws._journal_nodes[side]) if nq else 0.0
        for i, s in enumerate(s_grid):
            a, b = _point_rows(body, side, float(s), 0.0)
            body.contact_table[side, i] = a
            body.dtheta_table[side, i] = b
    rs = tuple(_check_s(body, s) for s in residual_s)
    if residual:
        statics = [_statics(ws, k) for k in range(k_res + 1)]
        gfull = full_compliance(statics, mesh, edges, rs, ws._journal_nodes,
                                _rim_operators(ws, edges))
        rr = _attachment_rows(body, rs)
        lam = (2.0 * np.pi * body.freq_hz) ** 2
        body.residual[:] = gfull - (rr / lam) @ rr.T
    for a in (body.journal, body.contact_table, body.dtheta_table, body.residual):
        a.setflags(write=False)
    return body


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
    rs = tuple(_check_s(body, s) for s in s_pair)
    statics = [_statics(ws, k) for k in range(body.residual_k_max + 1)]
    gfull = full_compliance(statics, ws.mesh, body._edges, rs, ws._journal_nodes,
                            _rim_operators(ws, body._edges))
    rr = _attachment_rows(body, rs)
    return gfull - (rr / (2.0 * np.pi * body.freq_hz) ** 2) @ rr.T


def static_fe_solve(ws, force: np.ndarray, s_pair: tuple[float, float] = (0.0, 0.0),
                    k_max: int = 6, inertia_relief: bool = False) -> np.ndarray:
    """Direct static FE solve of the free wheelset under self-equilibrated attachment loads.

    Harmonic by harmonic (k = 0..k_max, both sets): the rigid-body motion is held by a few
    point constraints (k = 0: axial and torsional, k = 1: the transverse translation of both
    journal centres), K u = f is solved, and the rigid part is removed afterwards by the
    mass-orthogonal projection. An independent check of the modal + residual statics (which
    use the bordered system of :class:`HarmonicStatics`).

    Parameters
    ----------
    ws : Wheelset
    force : array_like (14,)
        Loads on :data:`ATTACHMENT_DOFS`, N (N m for rx); they must be in equilibrium.
    s_pair : (float, float)
        Wheel-profile coordinates of the right and left contact points, m.
    k_max : int
        Highest harmonic.
    inertia_relief : bool
        Loads not in equilibrium (a wheelset in the vehicle: contact and journal forces
        carry its weight too): balance them by the d'Alembert forces of the rigid-body
        acceleration they cause (per harmonic f - M Phi_r Phi_r^T f, mass-orthonormal rigid
        fields Phi_r; under the static wheel loads this is the wheelset's weight as a body
        force), as the free-free modes of the vehicle model do.

    Returns
    -------
    ndarray (14,)
        Elastic deflection of the attachment DOFs, m / rad.
    """
    from scipy.sparse.linalg import spsolve
    f14 = _checks.finite_array("force", force, shape=(len(ATTACHMENT_DOFS),))
    k_max = check_harmonic(k_max, "k_max")
    edges = _edges(ws.geometry)
    jn = ws._journal_nodes
    g = ws.geometry
    rim = ws.mesh.node_at(g.wheel_radius, g.contact_y)
    out = np.zeros(len(ATTACHMENT_DOFS))
    rims = _rim_operators(ws, edges)
    pts = [_point_operator(ws.mesh, edges[0], s_pair[0], None, rims[0]),
           _point_operator(ws.mesh, edges[1], s_pair[1], None, rims[1]),
           _point_operator(ws.mesh, None, None, jn[0]), _point_operator(ws.mesh, None, None, jn[1])]
    for k in range(k_max + 1):
        st = _statics(ws, k)
        eqs = np.asarray(abs(st.T).tocsr().argmax(axis=1)).ravel()
        fix = {0: [eqs[3 * jn[0] + 1], eqs[3 * rim + 2]], 1: [eqs[3 * jn[0]], eqs[3 * jn[1]]]}
        free = np.setdiff1d(np.arange(st.K.shape[0]), fix.get(k, []))
        kff = st.K[free][:, free].tocsc()
        for kind in (("0",) if k == 0 else ("A", "B")):
            e = np.array([v for p in pts for v in p[kind]])
            fr = st.T.T @ (e.T @ f14)
            if not np.any(fr):
                continue
            if inertia_relief and st.rigid.shape[1]:
                fr = fr - st.M @ (st.rigid @ (st.rigid.T @ fr))
            u = np.zeros(fr.size)
            u[free] = spsolve(kff, fr[free])
            u -= st.rigid @ (st.rigid.T @ (st.M @ u))
            out += e @ (st.T @ u)
    return out


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
        (i0, i1, wi), (j0, j1, wj) = (self._cell("s_pair[0] (right)", s_pair[0]),
                                      self._cell("s_pair[1] (left)", s_pair[1]))

        def lin(a, k0, k1, w):
            return (1.0 - w) * a[k0] + w * a[k1]
        cross = ((1 - wi) * ((1 - wj) * self.cross[i0, j0] + wj * self.cross[i0, j1])
                 + wi * ((1 - wj) * self.cross[i1, j0] + wj * self.cross[i1, j1]))
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
            raise InputError(f"{key} = {s!r} m outside the table's grid {self.s0:.4g}.."
                             f"{self.s0 + (ns - 1) * self.ds:.4g} m")
        i0 = min(int(np.floor(max(t, 0.0))), ns - 2)
        return i0, i0 + 1, min(max(t - i0, 0.0), 1.0)


def interpolated_rows(body: FlexibleWheelset, side: int, s: float) -> np.ndarray:
    """The contact rows (4, nq) at profile coordinate s, m, linearly interpolated in the
    body's ``contact_table`` (grid s0 + i ds): what a kernel that follows the contact point
    evaluates per step, against :meth:`FlexibleWheelset.rows` (the element's shape functions
    at s)."""
    side = _check_side(side)
    s = _check_s(body, s)
    ns = body.contact_table.shape[1]
    t = (s - body.s0) / body.ds
    i0 = min(max(int(np.floor(t)), 0), ns - 2)
    w = min(max(t - i0, 0.0), 1.0)
    return (1.0 - w) * body.contact_table[side, i0] + w * body.contact_table[side, i0 + 1]


def contact_compliance(body: FlexibleWheelset, table: ResidualTable,
                       s_pair: tuple[float, float]) -> np.ndarray:
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
    r = np.vstack([interpolated_rows(body, 0, s_pair[0]), interpolated_rows(body, 1, s_pair[1]),
                   body.journal[0, :3], body.journal[1, :3]])
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
    rims = _rim_operators(ws, body._edges)
    ops = [[_point_operator(mesh, body._edges[side], float(s), None, rims[side]) for s in grid]
           for side in (0, 1)]
    jops = [_point_operator(mesh, None, None, n) for n in ws._journal_nodes]
    n_all = 2 * 4 * ns + 6
    g = np.zeros((n_all, n_all))
    for k in range(body.residual_k_max + 1):
        st = _statics(ws, k)
        for kind in (("0",) if k == 0 else ("A", "B")):
            e = np.array([v for side in (0, 1) for p in ops[side] for v in p[kind]]
                         + [v for p in jops for v in p[kind][:3]])          # (n_all, 3 nn)
            live = np.flatnonzero(np.any(e != 0.0, axis=1))
            u = st.solve(e[live].T)                                       # (3 nn, n_live)
            g[np.ix_(live, live)] += e[live] @ u
    # kept modes' static part at the same points
    rows = np.vstack([body.rows(side, float(s)) for side in (0, 1) for s in grid]
                     + [body.journal[0, :3], body.journal[1, :3]])
    g -= (rows / (2.0 * np.pi * body.freq_hz) ** 2) @ rows.T
    g = 0.5 * (g + g.T)
    c = g[:8 * ns, :8 * ns].reshape(2, ns, 4, 2, ns, 4)
    cc = np.array([[c[side, i, :, side, i, :] for i in range(ns)] for side in (0, 1)])
    cross = c[0, :, :, 1, :, :].transpose(0, 2, 1, 3)
    cj = g[:8 * ns, 8 * ns:].reshape(2, ns, 4, 6)
    return ResidualTable(s0=float(grid[0]), ds=ds, cc=cc, cross=np.ascontiguousarray(cross),
                         cj=cj, jj=g[8 * ns:, 8 * ns:].copy())

