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

The rows at points of the meridian mesh are built in :mod:`railvti.wheelset.rim_rows`, the
static compliance of every free-free mode per harmonic in :mod:`railvti.wheelset.statics`,
the residual flexibility over the contact points in :mod:`railvti.wheelset.residual`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _cache, _checks
from ..errors import InputError
from .fe import HarmonicModes, check_harmonic, eq11_blocks
from .rim_rows import (
    ATTACHMENT_DOFS,
    check_side,
    cylinder_fields,
    edge_point,
    journal_rows,
    locate,
    rim_edges,
    vehicle_rows,
)
from .statics import full_compliance, harmonic_statics, rim_operators

__all__ = ["RIGID_HZ", "FlexibleWheelset", "flexible_body", "free_modes", "rigid_mask"]

log = logging.getLogger(__name__)

#: A mode with a frequency below this (Hz) is a rigid-body mode of the free-free wheelset.
RIGID_HZ = 0.5


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
        First wheel-profile coordinate and step of the tabulated rim rows, m.
    rim_rows : ndarray (2, ns, 4, nq)
        The modal rows at the rim points: :meth:`rows` on the uniform grid s0 + i ds of the
        wheel-profile coordinate (linear interpolation for a kernel).
    rim_dtheta_rows : ndarray (2, ns, 4, nq)
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
    edges : tuple of RimEdge
        The rim edge of the right (0) and left (1) wheel on the meridian mesh
        (:func:`railvti.wheelset.rim_rows.rim_edges`).
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
    rim_rows: np.ndarray
    rim_dtheta_rows: np.ndarray
    residual: np.ndarray
    residual_s: tuple[float, float]
    residual_k_max: int = 0
    edges: tuple = ()
    _rim_slope: tuple = ()  # per side, per coordinate group: rim rotation of U_r (nm,)
    _shapes: tuple = ()  # per coordinate group: (k, family, shapes (n, nn, 3))
    _mesh: object = None

    @property
    def n(self) -> int:
        """Number of elastic coordinates."""
        return int(self.k.size)

    @property
    def s_range(self) -> tuple[float, float]:
        """Wheel-profile coordinates covered by the rim edge (flange back .. outer rim face), m."""
        e = self.edges[0]
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
        return self._point_rows(check_side(side), self.check_s(s), 0.0)[0]

    def dtheta_rows(self, side: int, s: float) -> np.ndarray:
        """d/dtheta of :meth:`rows` at the contact point (the Eulerian term).

        The deformation velocity of the rim material at the contact point is
        ``rows @ q' + Omega * dtheta_rows @ q`` (vehicle-frame components: the derivative
        includes the turning of the cylindrical basis).
        """
        return self._point_rows(check_side(side), self.check_s(s), 0.0)[1]

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
        r = self.attachment_rows(self.residual_s)
        lam = (2.0 * np.pi * self.freq_hz) ** 2
        u = r @ ((r.T @ f) / lam)
        return u + self.residual @ f if residual else u

    def check_s(self, s: object) -> float:
        """A wheel-profile coordinate s, m, checked to lie on the rim edge (:attr:`s_range`,
        to 1e-12 m) and clipped onto it.

        Raises
        ------
        InputError
            s not finite or outside the rim edge.
        """
        s = _checks.finite("s", s)
        lo, hi = self.s_range
        if not lo - 1e-12 <= s <= hi + 1e-12:
            raise InputError(
                f"wheel-profile coordinate s = {s * 1e3:.3f} mm lies outside the rim "
                f"edge ({lo * 1e3:.1f}..{hi * 1e3:.1f} mm)"
            )
        return min(max(s, lo), hi)

    def attachment_rows(self, s_pair) -> np.ndarray:
        """Rows (14, nq) of :data:`~railvti.wheelset.rim_rows.ATTACHMENT_DOFS` with the
        contact points at the wheel-profile coordinates s_pair (right, left), m."""
        c0 = self.rows(0, s_pair[0])
        c1 = self.rows(1, s_pair[1])
        return np.vstack([c0, c1, self.journal[0, :3], self.journal[1, :3]])

    def _point_rows(self, side: int, s: float, theta: float) -> tuple[np.ndarray, np.ndarray]:
        """Rows and d/dtheta rows (4, nq) of the rim edge point (side, s) at azimuth theta."""
        edge = self.edges[side]
        r, y = edge_point(edge, s)
        nodes, n, nr, ny = locate(self._mesh, r, y)
        rows, drows = [], []
        for (k, fam, shapes), slope in zip(self._shapes, self._rim_slope[side]):
            u, _, _ = cylinder_fields(shapes, nodes, n, nr, ny)
            a, b = vehicle_rows(k, fam, u, np.c_[slope, 0 * slope, 0 * slope], theta)
            rows.append(a)
            drows.append(b)
        return np.concatenate(rows, axis=1), np.concatenate(drows, axis=1)


def free_modes(ws, k: int, f_max: float) -> HarmonicModes:
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
    return HarmonicModes(
        k=h.k,
        freq_hz=h.freq_hz[m],
        shapes=h.shapes[m],
        coriolis=h.coriolis[ix],
        inplane_mass=h.inplane_mass[ix],
        prestress_stiffness=h.prestress_stiffness[ix],
        n_equations=h.n_equations,
        bandwidth=h.bandwidth,
    )


def rigid_mask(h: HarmonicModes) -> np.ndarray:
    """Which of the free-free modes ``h`` are rigid-body modes (frequency below :data:`RIGID_HZ`)."""
    return h.freq_hz < RIGID_HZ


def flexible_body(
    ws,
    speed: float,
    k_max: int = 2,
    f_max: float = 800.0,
    damping_ratio: float = 0.005,
    centrifugal: bool = True,
    residual_s: tuple[float, float] = (0.0, 0.0),
    ds: float = 1e-3,
    residual: bool = True,
    residual_k_max: int | None = None,
) -> FlexibleWheelset:
    """Build the free-free flexible body; see :meth:`Wheelset.flexible_body`."""
    speed = _checks.non_negative("speed", speed)
    zeta = _checks.non_negative("damping_ratio", damping_ratio)
    k_max = check_harmonic(k_max, "k_max")
    try:
        f_max = _checks.positive("f_max", f_max)
    except InputError as exc:
        raise InputError(f"f_max must be a positive frequency in Hz, got {f_max!r}") from exc
    ds = _checks.positive("ds", ds)
    k_res = max(k_max, 6) if residual_k_max is None else check_harmonic(residual_k_max, "residual_k_max")
    if k_res < k_max:
        raise InputError(f"residual_k_max ({k_res}) must be >= k_max ({k_max})")
    g = ws.geometry
    om = speed / g.wheel_radius
    mesh = ws.mesh
    edges = rim_edges(g)
    gb, kb, db, fam, kq, fq, shapes = [], [], [], [], [], [], []
    for k in range(k_max + 1):
        h = free_modes(ws, k, f_max)
        keep = ~rigid_mask(h)
        if k == 0:
            h0 = h
        lam = h.lam[keep]
        n = lam.size
        if n == 0:
            continue
        gam = h.coriolis[np.ix_(keep, keep)]
        mc = (
            (h.inplane_mass - h.prestress_stiffness)[np.ix_(keep, keep)]
            if centrifugal
            else np.zeros_like(gam)
        )
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
    # the FE statics' terms on disk (railvti._cache): a later process replays them
    rec = _cache.Recorder(
        "wheelset-statics",
        mesh.nodes,
        mesh.conn,
        g.young,
        g.poisson,
        g.density,
        k_max,
        f_max,
        k_res,
        residual_s,
    )
    polar, cpl, spin_c = rec.call(
        "mass_terms", _mass_terms, ws, k_max, h0, shapes, kq, key=(k_max, h0, shapes, kq)
    )
    s_grid = np.arange(edges[0].s_min, edges[0].s_max + 0.5 * ds, ds)
    s_grid = s_grid[s_grid <= edges[0].s_max + 1e-12]
    body = FlexibleWheelset(
        speed=speed,
        omega=om,
        k=np.array(kq, dtype=int),
        family=np.array(fam, dtype="<U1"),
        freq_hz=np.array(fq),
        mass=np.eye(nq),
        gyro=block_diag(*gb) if gb else np.zeros((0, 0)),
        damping=block_diag(*db) if db else np.zeros((0, 0)),
        stiffness=block_diag(*kb) if kb else np.zeros((0, 0)),
        rigid_elastic=cpl,
        spin_coupling=spin_c,
        polar_moment=polar,
        journal=np.zeros((2, 5, nq)),
        s0=float(s_grid[0]),
        ds=ds,
        rim_rows=np.zeros((2, s_grid.size, 4, nq)),
        rim_dtheta_rows=np.zeros((2, s_grid.size, 4, nq)),
        residual=np.zeros((14, 14)),
        residual_s=(float(residual_s[0]), float(residual_s[1])),
        residual_k_max=k_res,
        edges=edges,
        _rim_slope=tuple(
            tuple(shp.reshape(shp.shape[0], -1) @ op for _, _, shp in shapes)
            for op in rim_operators(ws, edges)
        ),
        _shapes=tuple(shapes),
        _mesh=mesh,
    )
    for side in range(2):
        body.journal[side] = journal_rows(shapes, mesh, ws._journal_nodes[side]) if nq else 0.0
        for i, s in enumerate(s_grid):
            a, b = body._point_rows(side, float(s), 0.0)
            body.rim_rows[side, i] = a
            body.rim_dtheta_rows[side, i] = b
    rs = tuple(body.check_s(s) for s in residual_s)
    if residual:
        gfull = rec.call(
            "full_compliance",
            _full_compliance,
            ws,
            k_res,
            edges,
            rs,
            key=(k_res, edges, rs, ws._journal_nodes),
        )
        rr = body.attachment_rows(rs)
        lam = (2.0 * np.pi * body.freq_hz) ** 2
        body.residual[:] = gfull - (rr / lam) @ rr.T
    rec.finish()
    for a in (body.journal, body.rim_rows, body.rim_dtheta_rows, body.residual):
        a.setflags(write=False)
    return body


def _full_compliance(ws, k_res: int, edges, rs) -> np.ndarray:
    """The static compliance of harmonics 0..k_res at the attachment points
    (:func:`railvti.wheelset.statics.full_compliance`)."""
    statics = [harmonic_statics(ws, k) for k in range(k_res + 1)]
    return full_compliance(statics, ws.mesh, edges, rs, ws._journal_nodes, rim_operators(ws, edges))


def _mass_terms(
    ws, k_max: int, h0: HarmonicModes, shapes: list, kq: list
) -> tuple[float, np.ndarray, np.ndarray]:
    """The terms of the FE mass (harmonics 0 and 1) between the rigid and the kept elastic
    modes: the polar moment (kg m^2), the rigid-elastic coupling (nq, 2) (roll, yaw) and the
    spin coupling (nq,)."""
    mesh = ws.mesh
    nq = len(kq)
    # polar moment and rigid-elastic coupling from the FE mass (k = 0 and k = 1)
    st0 = harmonic_statics(ws, 0)
    r = mesh.nodes[:, 0]
    spin = np.zeros((mesh.n_nodes, 3))
    spin[:, 2] = r
    polar = st0.mass_product(spin, spin)
    cpl = np.zeros((nq, 2))
    if k_max >= 1 and nq:
        st1 = harmonic_statics(ws, 1)
        tilt = np.zeros((mesh.n_nodes, 3))
        tilt[:, 1] = r  # the field U_y = r of harmonic 1
        col = 0
        for k, f, shp in shapes:
            n = shp.shape[0]
            if k == 1:
                # c = -2 int rho X_x u_y (roll) and -2 int rho X_z u_y (yaw), vehicle frame:
                # = -2 <phi, (0, r, 0)>_M1 for set B (roll) and set A (yaw)
                v = np.array([-2.0 * st1.mass_product(p, tilt) for p in shp])
                cpl[col : col + n, 0 if f == "B" else 1] = v
            col += n
    # spin perturbation rate against the k = 0 modes: the FE Coriolis matrix (eq. 11) between
    # the rigid spin field (0, 0, r) and the elastic modes, c = -2 (Gamma a)_elastic
    spin_c = np.zeros(nq)
    n0 = int(np.sum(np.array(kq) == 0))
    if n0:
        x = np.array([st0.reduce(p) for p in h0.shapes]).T
        a = x.T @ (st0.M @ st0.reduce(spin))
        spin_c[:n0] = -2.0 * (h0.coriolis @ a)[~rigid_mask(h0)]
    return polar, cpl, spin_c
