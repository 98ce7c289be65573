"""Static compliance of the free-free elastic wheelset, harmonic by harmonic (Omega = 0).

The FE stiffness and mass of each harmonic assembled in Python (sparse), the bordered static
solve that removes the rigid-body modes mass-orthogonally (:class:`HarmonicStatics`), the
nodal operators of the attachment rows (rim points and journals) and the compliance over
:data:`~railvti.wheelset.rim_rows.ATTACHMENT_DOFS` of all elastic modes: what the residual
flexibility of the truncated modes is made of (:mod:`railvti.wheelset.residual`), and a
direct FE solve to check it (:func:`static_fe_solve`).
"""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from .._native import core
from .._status import check
from .fe import check_harmonic
from .rim_rows import ATTACHMENT_DOFS, RimEdge, edge_point, locate, rim_edges

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = [
    "assemble_harmonic",
    "HarmonicStatics",
    "harmonic_statics",
    "point_operator",
    "rim_operators",
    "rim_operator",
    "full_compliance",
    "static_fe_solve",
]


def _dof_transform(mesh, k: int) -> sp.csr_matrix:
    """T (3 nn, neq): nodal amplitudes from equations, with the axis regularity of
    wheelset_modes.f90::dof_map (k = 0: U_y only; k = 1: U_th = -U_r, U_y = 0; k >= 2: 0)."""
    import scipy.sparse as sp  # on first use: ~0.2 s at start-up (issue 33)

    x = mesh.nodes
    tol = 1e-9 * max(float(np.abs(x[:, 0]).max()), 1e-30)
    rows, cols, vals = [], [], []
    neq = 0
    for i, (r, _) in enumerate(x):
        if r <= tol:
            if k == 0:
                rows.append(3 * i + 1)
                cols.append(neq)
                vals.append(1.0)
                neq += 1
            elif k == 1:
                rows += [3 * i, 3 * i + 2]
                cols += [neq, neq]
                vals += [1.0, -1.0]
                neq += 1
        else:
            for c in range(3):
                rows.append(3 * i + c)
                cols.append(neq)
                vals.append(1.0)
                neq += 1
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * mesh.n_nodes, neq))


def assemble_harmonic(
    mesh, k: int, young: float, poisson: float, density: float
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Global stiffness and mass of harmonic k over the nodal amplitudes (3 nn, node-major).

    The same element matrices as the eigen-solver (wheelset_element.f90::axisym_element),
    assembled in Python (sparse) for the static solves of the residual flexibility.
    """
    import scipy.sparse as sp  # on first use: ~0.2 s at start-up (issue 33)

    ne = mesh.n_elements
    idx = (3 * mesh.conn[:, :, None] + np.arange(3)[None, None, :]).reshape(ne, 27)
    kv = np.empty((ne, 27, 27))
    mv = np.empty((ne, 27, 27))
    for e in range(ne):
        ke, me, _, _, info = core.wheelset_element_c(
            k, np.asfortranarray(mesh.nodes[mesh.conn[e]].T), young, poisson, density
        )
        check(info, f"harmonic k={k}: meridian element {e}")
        kv[e], mv[e] = ke, me
    ii = np.repeat(idx, 27, axis=1).ravel()
    jj = np.tile(idx, (1, 27)).ravel()
    n = 3 * mesh.n_nodes
    return (
        sp.csr_matrix((kv.ravel(), (ii, jj)), shape=(n, n)),
        sp.csr_matrix((mv.ravel(), (ii, jj)), shape=(n, n)),
    )


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
        import scipy.sparse as sp  # on first use: ~0.2 s at start-up (issue 33)
        from scipy.sparse.linalg import splu

        self.k = k
        self.T = _dof_transform(mesh, k)
        kf, mf = assemble_harmonic(mesh, k, young, poisson, density)
        self.K = (self.T.T @ kf @ self.T).tocsc()
        self.M = (self.T.T @ mf @ self.T).tocsc()
        self._w = np.asarray(self.T.T.multiply(self.T.T).sum(axis=1)).ravel()
        r, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
        z, one = np.zeros_like(r), np.ones_like(r)
        fields = {0: [np.c_[z, one, z], np.c_[z, z, r]], 1: [np.c_[one, z, -one], np.c_[-y, r, y]]}.get(k, [])
        rig = np.zeros((self.K.shape[0], len(fields)))
        for j, f in enumerate(fields):
            x = self.reduce(f)
            for i in range(j):  # Gram-Schmidt in the mass metric
                x -= rig[:, i] * (rig[:, i] @ (self.M @ x))
            rig[:, j] = x / np.sqrt(x @ (self.M @ x))
        self.rigid = rig
        nr = rig.shape[1]
        mr = self.M @ rig
        a = (
            self.K
            if nr == 0
            else sp.bmat([[self.K, sp.csc_matrix(mr)], [sp.csc_matrix(mr.T), None]], format="csc")
        )
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


def harmonic_statics(ws, k: int) -> HarmonicStatics:
    """The (cached, per Wheelset) static solver of harmonic k."""
    per = _STATICS.setdefault(ws, {})
    if k not in per:
        g = ws.geometry
        per[k] = HarmonicStatics(ws.mesh, k, g.young, g.poisson, g.density)
    return per[k]


def point_operator(
    mesh, edge: RimEdge | None, s: float | None, node: int | None, rim: np.ndarray | None = None
) -> dict[str, list[np.ndarray]]:
    """Nodal operators of the attachment rows at theta = 0, per harmonic kind.

    Returns {'0': [...], 'A': [...], 'B': [...]}: for each row, the nodal vector (3 nn) e with
    row value = e . U of that set's amplitudes (k = 0 uses '0'; k > 0 'A' and 'B'). rim: the
    edge's :func:`rim_operator` when already known.
    """
    if edge is not None:
        r, y = edge_point(edge, s)
    else:
        r, y = mesh.nodes[node]
    nodes, n, nr, ny = locate(mesh, r, y)
    nn3 = 3 * mesh.n_nodes

    def vec(comp: int, w: np.ndarray, scale: float) -> np.ndarray:
        v = np.zeros(nn3)
        np.add.at(v, 3 * nodes + comp, scale * w)
        return v

    zero = np.zeros(nn3)
    # rows x, y, z (+ rx on the rim), from vehicle_rows at theta = 0
    ops = {
        "0": [vec(2, n, -1.0), vec(1, n, -1.0), vec(0, n, -1.0)],
        "A": [zero, vec(1, n, -1.0), vec(0, n, -1.0)],
        "B": [vec(2, n, 1.0), zero, zero],
    }
    if edge is not None:
        rim = rim_operator(mesh, edge) if rim is None else rim
        ops["0"].append(rim)
        ops["A"].append(rim)
        ops["B"].append(zero)
    return ops


_RIM: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def rim_operators(ws, edges) -> tuple[np.ndarray, ...]:
    """:func:`rim_operator` of both edges, cached per Wheelset."""
    per = _RIM.setdefault(ws, {})
    if edges not in per:
        per[edges] = tuple(rim_operator(ws.mesh, e) for e in edges)
    return per[edges]


def rim_operator(mesh, edge: RimEdge) -> np.ndarray:
    """Nodal vector (3 nn) of the rim rotation: the least-squares slope d U_r / d y_FE of the
    radial amplitude over the tread edge (= d u_z / d y_vehicle at theta = 0)."""
    v = np.zeros(3 * mesh.n_nodes)
    for s, w in zip(*edge.rim_samples()):
        nodes, n, _, _ = locate(mesh, *edge_point(edge, float(s)))
        np.add.at(v, 3 * nodes, w * n)
    return v


def full_compliance(
    statics: list[HarmonicStatics], mesh, edges, s_pair, journal_nodes, rims: tuple | None = None
) -> np.ndarray:
    """Static compliance (14, 14) over :data:`ATTACHMENT_DOFS` of all free-free elastic modes
    of the harmonics in ``statics`` (Omega = 0), from the FE stiffness. rims: the edges'
    :func:`rim_operator` when already known."""
    rims = rims if rims is not None else (None, None)
    pts = None
    g = np.zeros((len(ATTACHMENT_DOFS),) * 2)
    for st in statics:
        key = (tuple(s_pair), tuple(journal_nodes))
        if key not in st._compliance:
            if pts is None:
                pts = [
                    point_operator(mesh, edges[0], s_pair[0], None, rims[0]),
                    point_operator(mesh, edges[1], s_pair[1], None, rims[1]),
                    point_operator(mesh, None, None, journal_nodes[0]),
                    point_operator(mesh, None, None, journal_nodes[1]),
                ]
            gk = np.zeros_like(g)
            for kind in ("0",) if st.k == 0 else ("A", "B"):
                e = np.array([v for p in pts for v in p[kind]])  # (14, 3 nn)
                cols = [st.solve(e[j]) if np.any(e[j]) else np.zeros(e.shape[1]) for j in range(e.shape[0])]
                gk += e @ np.array(cols).T
            st._compliance[key] = 0.5 * (gk + gk.T)
        g += st._compliance[key]
    return g


def static_fe_solve(
    ws,
    force: np.ndarray,
    s_pair: tuple[float, float] = (0.0, 0.0),
    k_max: int = 6,
    inertia_relief: bool = False,
) -> np.ndarray:
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
    edges = rim_edges(ws.geometry)
    jn = ws._journal_nodes
    g = ws.geometry
    rim = ws.mesh.node_at(g.wheel_radius, g.contact_y)
    out = np.zeros(len(ATTACHMENT_DOFS))
    rims = rim_operators(ws, edges)
    pts = [
        point_operator(ws.mesh, edges[0], s_pair[0], None, rims[0]),
        point_operator(ws.mesh, edges[1], s_pair[1], None, rims[1]),
        point_operator(ws.mesh, None, None, jn[0]),
        point_operator(ws.mesh, None, None, jn[1]),
    ]
    for k in range(k_max + 1):
        st = harmonic_statics(ws, k)
        eqs = np.asarray(abs(st.T).tocsr().argmax(axis=1)).ravel()
        fix = {0: [eqs[3 * jn[0] + 1], eqs[3 * rim + 2]], 1: [eqs[3 * jn[0]], eqs[3 * jn[1]]]}
        free = np.setdiff1d(np.arange(st.K.shape[0]), fix.get(k, []))
        kff = st.K[free][:, free].tocsc()
        for kind in ("0",) if k == 0 else ("A", "B"):
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
