"""Flexible bodies as the Fortran core takes them: modal coordinates in blocks, their
attachment points and the forces on those points.

:class:`ModalBlocks` holds modal coordinates with block-diagonal damping (+ gyroscopic) and
stiffness matrices, coupled to the rigid DOFs only through attachment points u = Phi Q and
:class:`PointElement` forces, and :class:`ModalCouplings` (linear couplings with rigid DOF
combinations, flexible rims, :class:`RimFollow`'s rows that follow the contact point).
:func:`compliance_block` and :func:`with_mass` make the residual flexibility of truncated modes a
block (docs/vehicle_integrator.md). :class:`railvti.vehicle.model.VehicleModel` attaches them to
a System's handle once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = [
    "POINT_ELEMENT_KINDS",
    "PointElement",
    "RimFollow",
    "COUPLING_KINDS",
    "ModalCouplings",
    "ModalBlocks",
    "compliance_block",
    "RESIDUAL_ZETA",
    "with_mass",
]

#: Point element kinds: name -> Fortran id (vehicle_modal PEL_*).
POINT_ELEMENT_KINDS = {"linear": 1, "hertz": 2}


@dataclass(frozen=True)
class PointElement:
    """A force between a rigid DOF (or the ground) and an attachment point of ModalBlocks.

    With d = u_point - q_dof (q_dof = 0 for the ground) and dd its rate, the element's force f
    acts as +f on the rigid DOF and -f on the point (-Phi[point]^T f on the modal coordinates):

    - 'linear': f = p[0] d + p[1] dd + p[2] (spring N/m, damper N s/m, preload N);
    - 'hertz': f = p[0] max(d - p[1], 0)^1.5 + p[2] dd while d > p[1] (a one-sided
      Hertz-like contact: p[0] in N/m^1.5, clearance p[1] in m, damper p[2] in N s/m).

    Attributes
    ----------
    kind : str
        'linear' or 'hertz' (:data:`POINT_ELEMENT_KINDS`).
    point : int
        Attachment point, 0-based row of ``ModalBlocks.phi``.
    dof : int or None
        Rigid DOF, 0-based index into the System's DOFs; None for the ground.
    params : tuple of float
        Up to 4 parameters (see above), the rest zero.
    """

    kind: str
    point: int
    dof: int | None
    params: tuple = (0.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if self.kind not in POINT_ELEMENT_KINDS:
            raise InputError(
                f"unknown point element kind {self.kind!r}; one of {sorted(POINT_ELEMENT_KINDS)}"
            )
        p = np.asarray(_checks.finite_array("params", self.params), dtype=float).ravel()
        if p.size > 4:
            raise InputError(f"a point element has at most 4 parameters, got {p.size}")
        object.__setattr__(self, "params", tuple(float(x) for x in np.pad(p, (0, 4 - p.size))))
        if self.kind == "hertz" and self.params[0] < 0.0:
            raise InputError("a Hertz point element needs a stiffness >= 0")

    @classmethod
    def linear(
        cls, point: int, dof: int | None, stiffness: float, damping: float = 0.0, preload: float = 0.0
    ) -> "PointElement":
        """A spring (N/m), damper (N s/m) and preload (N) between ``dof`` and ``point``."""
        return cls("linear", point, dof, (stiffness, damping, preload))

    @classmethod
    def hertz(
        cls, point: int, dof: int | None, stiffness: float, clearance: float = 0.0, damping: float = 0.0
    ) -> "PointElement":
        """A one-sided d^1.5 contact spring (N/m^1.5) with clearance (m) and damper (N s/m)."""
        return cls("hertz", point, dof, (stiffness, clearance, damping))


@dataclass(frozen=True)
class RimFollow:
    """Rows of flexible rims that follow the contact point (variant FR, Kaiser eq. 3): the time
    loop sets each rim's rows (y, z, rx), their d/dtheta, its residual coordinates' rows and
    its reference arm at the wheel's contact point of the last accepted step
    (vehicle_modal%modal_follow); everything else (statics, forces, linear analysis) sees
    the taping line (s = 0).

    Attributes
    ----------
    s0, ds : float
        Grid of the rim rows, m along the wheel profile from the taping line (+ field side).
    rows, drows : ndarray (3, nq, ns, 2)
        Rim rows (y, z, rx) and their d/dtheta per grid point, wheel 0 left, 1 right.
    rs0, rds : float
        Grid of the residual's blocks, m.
    rcc : ndarray (3, 3, nrs, 2)
        Rim self blocks (y, z, rx) of the residual, m/N and rad/(N m).
    rcx : ndarray (3, 3, nrs, nrs)
        Left rim (rows, at its grid point) against right rim (columns, at its grid point).
    rcj : ndarray (3, 6, nrs, 2)
        Rim against the journals (left x, y, z, right x, y, z).
    rjj : ndarray (6, 6)
        Journals against journals.
    modes, residual : ndarray (nfr,) int
        0-based first modal column of each wheelset's modes and of its 12 residual
        coordinates (-1: none).
    points : ndarray (12, nfr) int
        0-based points of the residual (rims y, z, rx left, right; journals x, y, z left,
        right).
    post : float
        The residual rows' factor: rows L post with L L^T = R, stiffness post^2 I.
    """

    s0: float
    ds: float
    rows: np.ndarray
    drows: np.ndarray
    rs0: float
    rds: float
    rcc: np.ndarray
    rcx: np.ndarray
    rcj: np.ndarray
    rjj: np.ndarray
    modes: np.ndarray
    residual: np.ndarray
    points: np.ndarray
    post: float

    def args(self) -> tuple:
        """The arguments of vehicle_modal_follow_c after the handle (1-based points)."""
        f = np.asfortranarray
        return (
            float(self.s0),
            float(self.ds),
            f(self.rows),
            f(self.drows),
            float(self.rs0),
            float(self.rds),
            f(self.rcc),
            f(self.rcx),
            f(self.rcj),
            f(self.rjj),
            np.asarray(self.modes, np.int32),
            np.asarray(self.residual, np.int32),
            f(np.asarray(self.points) + 1, dtype=np.int32),
            float(self.post),
        )


#: Linear coupling kinds: name -> Fortran id (vehicle_modal LC_*).
COUPLING_KINDS = {"split": 1, "gyro": 2}


@dataclass(frozen=True)
class ModalCouplings:
    """Couplings of ModalBlocks' points with combinations of rigid DOFs, and flexible rims.

    Linear couplings e (point p, rigid direction g over the System's DOFs, parameters
    (k, c, f0)):

    - 'split': a spring/damper between g.q and u_p whose rigid-rigid part is already in the
      System's K, C and f0 (a journal spring of a flexible wheelset): the point gets
      k (g.q - u_p) + c (g.v - u_p') + f0, the rigid DOFs g (k u_p + c u_p');
    - 'gyro': a skew velocity coupling (Coriolis terms): the point gets k g.v, the rigid
      DOFs -g k u_p'.

    Flexible rims (variant FR): for wheelset ``rim_wheelsets[i]`` (0-based) the points of the
    elastic displacement (track y, z) of each wheel's rim reference point and the rim's
    rotation about x, ``rim_points[:, w, i]`` for w = 0 left, 1 right; ``rim_arms[:, i]``
    the reference point's lateral distance from the wheelset centre and depth below it, m.
    The wheel-rail contact of that wheelset is evaluated on the moved wheels and its
    generalised forces act on these points (docs/vehicle_integrator.md, "Flexible wheelsets").

    Attributes
    ----------
    kinds : tuple of str
    points : ndarray (nlc,) int
    directions : ndarray (n_dofs, nlc)
    params : ndarray (3, nlc)
    rim_wheelsets : ndarray (nfr,) int
    rim_points : ndarray (3, 2, nfr) int
    rim_arms : ndarray (2, nfr)
    rim_euler : ndarray (3, 2, nfr) int, optional
        The Eulerian term Omega dW/dtheta of the rims: the points whose displacement is
        dPhi/dtheta Q of each rim point (-1: none); the rim material's velocity at the contact
        point is then u'_p + Omega u_e.
    rim_omega : ndarray (nfr,), optional
        The spin Omega of each flexible wheelset, rad/s (with ``rim_euler``).
    rim_follow : RimFollow, optional
        Tables that make the rims' rows follow the contact point along the wheel profile
        (Kaiser eq. 3); None: the rows stay where the model put them.
    """

    kinds: tuple
    points: np.ndarray
    directions: np.ndarray
    params: np.ndarray
    rim_wheelsets: np.ndarray
    rim_points: np.ndarray
    rim_arms: np.ndarray
    rim_euler: np.ndarray | None = None
    rim_omega: np.ndarray | None = None
    rim_follow: "RimFollow | None" = None

    def __post_init__(self) -> None:
        for k in self.kinds:
            if k not in COUPLING_KINDS:
                raise InputError(f"unknown coupling kind {k!r}; one of {sorted(COUPLING_KINDS)}")
        nlc = len(self.kinds)
        pts = np.asarray(self.points, dtype=np.int32).reshape(nlc)
        g = np.asarray(_checks.finite_array("directions", self.directions), dtype=float)
        par = np.asarray(_checks.finite_array("params", self.params), dtype=float)
        if g.ndim != 2 or g.shape[1] != nlc or par.shape != (3, nlc):
            raise InputError(
                f"directions (n_dofs, {nlc}) and params (3, {nlc}) expected, got {g.shape} and {par.shape}"
            )
        rw = np.asarray(self.rim_wheelsets, dtype=np.int32).ravel()
        rp = np.asarray(self.rim_points, dtype=np.int32).reshape(3, 2, rw.size)
        ra = np.asarray(_checks.finite_array("rim_arms", self.rim_arms), dtype=float).reshape(2, rw.size)
        if np.any(ra <= 0):
            raise InputError("rim arms must be > 0")
        for name, val in (
            ("points", pts),
            ("directions", g),
            ("params", par),
            ("rim_wheelsets", rw),
            ("rim_points", rp),
            ("rim_arms", ra),
        ):
            val.setflags(write=False)
            object.__setattr__(self, name, val)
        object.__setattr__(self, "kinds", tuple(self.kinds))
        if self.rim_euler is not None:
            re = np.asarray(self.rim_euler, dtype=np.int32).reshape(3, 2, rw.size)
            om = np.asarray(_checks.finite_array("rim_omega", self.rim_omega), dtype=float).reshape(rw.size)
            re.setflags(write=False)
            om.setflags(write=False)
            object.__setattr__(self, "rim_euler", re)
            object.__setattr__(self, "rim_omega", om)

    def without_damping(self) -> "ModalCouplings":
        """The same couplings without the split couplings' dampers."""
        par = np.array(self.params, copy=True)
        par[1] = 0.0
        return replace(self, params=par)

    def arrays(self, n_dofs: int, n_points: int) -> tuple[np.ndarray, ...]:
        """The core's arrays (1-based indices; a dummy zero 'split' coupling and no rim when
        empty would leave a zero-size array: a zero-stiffness coupling on point 1 is used)."""
        if self.directions.shape[0] != n_dofs:
            raise InputError(
                f"coupling directions over {self.directions.shape[0]} DOFs: the system has {n_dofs}"
            )
        if (
            np.any(self.points < 0)
            or np.any(self.points >= n_points)
            or np.any(self.rim_points < 0)
            or np.any(self.rim_points >= n_points)
        ):
            raise InputError(f"a coupling or rim on a point outside 0..{n_points - 1}")
        kinds = np.array([COUPLING_KINDS[k] for k in self.kinds], dtype=np.int32)
        pts, g, par = self.points + 1, self.directions, self.params
        if kinds.size == 0:
            kinds, pts = np.ones(1, np.int32), np.ones(1, np.int32)
            g, par = np.zeros((n_dofs, 1)), np.zeros((3, 1))
        rw, rp, ra = self.rim_wheelsets + 1, self.rim_points + 1, self.rim_arms
        return (
            kinds,
            np.asarray(pts, np.int32),
            np.asfortranarray(g),
            np.asfortranarray(par),
            np.asarray(rw, np.int32),
            np.asfortranarray(rp, dtype=np.int32),
            np.asfortranarray(ra),
        )


@dataclass(frozen=True)
class ModalBlocks:
    """Modal coordinates Q of flexible bodies, coupled to the rigid DOFs through points.

    Q'' + B Q' + K Q = Phi^T g_p, u = Phi Q, with B and K block-diagonal (mass-normalised
    modes: M = I). Only the small blocks and Phi (n_points x n_modes) are stored: nothing of
    size n_modes x n_modes.

    Attributes
    ----------
    damping : tuple of ndarray (s_b, s_b)
        Blocks of B (modal damping plus gyroscopic terms), 1/s.
    stiffness : tuple of ndarray (s_b, s_b)
        Blocks of K (same sizes), 1/s^2.
    phi : ndarray (n_points, n_modes)
        Attachment rows (the mode shapes at the points, m per unit modal coordinate).
    elements : tuple of PointElement
    names : tuple of str
        Names of the modal coordinates (default 'mode1', 'mode2', ...).
    couplings : ModalCouplings, optional
    massless : tuple of bool, optional
        Per block: a block of massless coordinates (M = 0 there): the equations
        ``B Q' + K Q = Phi^T g_p`` are algebraic. With B = 0, K = diag(1 / lambda) and rows
        Phi_r = V of a compliance R = V diag(lambda) V^T the block is the point
        compliance u = R g_p (the residual flexibility of truncated modes; see
        :func:`compliance_block`). Default: no massless block.

    Raises
    ------
    InputError
        Blocks not square or of unequal sizes between B and K, phi of another width than the
        modes, non-finite entries, an element on a point outside phi's rows.
    """

    damping: tuple
    stiffness: tuple
    phi: np.ndarray
    elements: tuple = ()
    names: tuple | None = None
    couplings: ModalCouplings | None = None
    massless: tuple | None = None

    def __post_init__(self) -> None:
        if len(self.damping) != len(self.stiffness) or not self.damping:
            raise InputError(
                f"damping and stiffness need the same, non-zero number of blocks "
                f"({len(self.damping)} and {len(self.stiffness)})"
            )
        bb, kb = [], []
        for i, (b, k) in enumerate(zip(self.damping, self.stiffness)):
            b = _checks.finite_array(f"damping block {i}", b)
            k = _checks.finite_array(f"stiffness block {i}", k)
            b, k = np.atleast_2d(b).astype(float), np.atleast_2d(k).astype(float)
            if b.ndim != 2 or b.shape[0] != b.shape[1] or k.shape != b.shape:
                raise InputError(
                    f"block {i}: damping {b.shape} and stiffness {k.shape} must be "
                    "square and of the same size"
                )
            b.setflags(write=False)
            k.setflags(write=False)
            bb.append(b)
            kb.append(k)
        object.__setattr__(self, "damping", tuple(bb))
        object.__setattr__(self, "stiffness", tuple(kb))
        nm = sum(b.shape[0] for b in bb)
        phi = np.array(_checks.finite_array("phi", self.phi), dtype=float, order="F")
        if phi.ndim != 2 or phi.shape[1] != nm or phi.shape[0] < 1:
            raise InputError(f"phi must have shape (n_points >= 1, {nm}) for {nm} modes, got {phi.shape}")
        phi.setflags(write=False)
        object.__setattr__(self, "phi", phi)
        els = tuple(self.elements)
        for e in els:
            if not isinstance(e, PointElement):
                raise InputError(f"elements must be PointElement, got {type(e).__name__}")
            if not 0 <= e.point < phi.shape[0]:
                raise InputError(f"point element on point {e.point}: phi has {phi.shape[0]} points")
        object.__setattr__(self, "elements", els)
        names = (
            tuple(f"mode{i + 1}" for i in range(nm))
            if self.names is None
            else tuple(str(n) for n in self.names)
        )
        if len(names) != nm:
            raise InputError(f"{len(names)} names for {nm} modes")
        object.__setattr__(self, "names", names)
        if self.massless is not None:
            ml = tuple(bool(m) for m in self.massless)
            if len(ml) != len(bb):
                raise InputError(f"massless: {len(ml)} flags for {len(bb)} blocks")
            object.__setattr__(self, "massless", ml if any(ml) else None)

    @classmethod
    def diagonal(
        cls,
        omega: np.ndarray,
        zeta: np.ndarray | float,
        phi: np.ndarray,
        elements: tuple = (),
        names: tuple | None = None,
    ) -> "ModalBlocks":
        """Modes without coupling: one 1 x 1 block per mode, K = omega^2, B = 2 zeta omega
        (omega in rad/s, zeta the damping ratios)."""
        om = _checks.finite_array("omega", omega).astype(float).ravel()
        ze = np.broadcast_to(np.asarray(zeta, dtype=float), om.shape)
        return cls(
            tuple((2.0 * z * w).reshape(1, 1) for z, w in zip(ze, om)),
            tuple((w * w).reshape(1, 1) for w in om),
            phi,
            elements,
            names,
        )

    def place_blocks(self, c: np.ndarray, k: np.ndarray, start: int) -> None:
        """Write the blocks' damping (B = G + D) and stiffness into dense c and k (in place),
        block-diagonally from row/column ``start``: for small linear analyses only."""
        j = start
        for b, kb in zip(self.damping, self.stiffness):
            s = b.shape[0]
            c[j : j + s, j : j + s] = b
            k[j : j + s, j : j + s] = kb
            j += s

    def without_damping(self) -> "ModalBlocks":
        """The same blocks with B reduced to its skew (gyroscopic) part and the point elements'
        dampers removed: a conservative system (modal damping is symmetric)."""
        els = []
        for e in self.elements:
            p = list(e.params)
            p[1 if e.kind == "linear" else 2] = 0.0
            els.append(PointElement(e.kind, e.point, e.dof, tuple(p)))
        cpl = self.couplings.without_damping() if self.couplings is not None else None
        return ModalBlocks(
            tuple(0.5 * (b - b.T) for b in self.damping),
            self.stiffness,
            self.phi,
            tuple(els),
            self.names,
            cpl,
            self.massless,
        )

    @property
    def mass(self) -> np.ndarray:
        """Modal masses (n_modes,): 1, or 0 for the coordinates of massless blocks."""
        ml = self.massless or (False,) * len(self.damping)
        return np.concatenate([np.full(b.shape[0], 0.0 if m else 1.0) for b, m in zip(self.damping, ml)])

    @property
    def n_modes(self) -> int:
        """Number of modal coordinates."""
        return self.phi.shape[1]

    @property
    def n_points(self) -> int:
        """Number of attachment points."""
        return self.phi.shape[0]

    def receptance(self, points: np.ndarray, freqs: np.ndarray) -> np.ndarray:
        """The blocks' receptance between attachment points, without the point elements and
        couplings: H(f) = sum_b Phi_pb (K_b - w^2 M_b + i w B_b)^-1 Phi_pb^T.

        Parameters
        ----------
        points : array of int
            Rows of ``phi`` (point components), 0-based.
        freqs : ndarray (nf,)
            Frequencies, Hz.

        Returns
        -------
        ndarray (nf, n, n) complex
            Displacement per force, m/N (in the rows' units), [f, response, load].
        """
        p = np.asarray(points, dtype=int)
        w = 2.0 * math.pi * np.atleast_1d(np.asarray(freqs, dtype=float))
        ml = self.massless or (False,) * len(self.stiffness)
        out = np.zeros((w.size, p.size, p.size), complex)
        j = 0
        for b, k, m in zip(self.damping, self.stiffness, ml):
            n = k.shape[0]
            ph = self.phi[np.ix_(p, np.arange(j, j + n))]
            j += n
            if not np.any(ph):
                continue
            mass = np.zeros((n, n)) if m else np.eye(n)
            dyn = k[None] - w[:, None, None] ** 2 * mass + 1j * w[:, None, None] * b[None]
            out += np.einsum("ab,fbc,dc->fad", ph, np.linalg.inv(dyn), ph)
        return out

    def max_frequency(self) -> float:
        """The largest undamped natural frequency of the blocks, rad/s: sqrt of the largest
        eigenvalue of each block's symmetric stiffness part (gyroscopic splitting ignored)."""
        ml = self.massless or (False,) * len(self.stiffness)
        lam = max(
            (float(np.max(np.linalg.eigvalsh(0.5 * (k + k.T)))) for k, m in zip(self.stiffness, ml) if not m),
            default=0.0,
        )
        return math.sqrt(max(lam, 0.0))

    def packed(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(bs, bb, kb): 1-based block starts (n_blocks + 1) and the blocks of B and K packed
        column-major, as the Fortran core stores them."""
        sizes = [b.shape[0] for b in self.damping]
        bs = np.concatenate([[1], 1 + np.cumsum(sizes)]).astype(np.int32)
        bb = np.concatenate([b.ravel(order="F") for b in self.damping])
        kb = np.concatenate([k.ravel(order="F") for k in self.stiffness])
        return bs, bb, kb

    def element_arrays(self, n_dofs: int) -> tuple[np.ndarray, ...]:
        """(ptype, prig, ppt, ppar) of the core (1-based; a zero dummy element when there is
        none, which keeps the arrays non-empty for f2py). InputError for a DOF outside
        0..n_dofs - 1."""
        els = self.elements or (PointElement("linear", 0, None),)
        for e in els:
            if e.dof is not None and not 0 <= e.dof < n_dofs:
                raise InputError(f"point element on DOF {e.dof}: the system has {n_dofs} DOFs")
        ptype = np.array([POINT_ELEMENT_KINDS[e.kind] for e in els], dtype=np.int32)
        prig = np.array([0 if e.dof is None else e.dof + 1 for e in els], dtype=np.int32)
        ppt = np.array([e.point + 1 for e in els], dtype=np.int32)
        ppar = np.asfortranarray(np.array([e.params for e in els], dtype=float).T)
        return ptype, prig, ppt, ppar


def compliance_block(compliance: np.ndarray, rtol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """A symmetric positive semi-definite point compliance R (m/N, rad/(N m)) as a massless
    modal block: rows Phi_r = V (n_points, r), R's unit eigenvectors, and stiffness
    K_r = diag(1 / lambda) (r, r), so that Phi_r K_r^-1 Phi_r^T = R and the coordinates are
    the points' residual displacements along V (m or rad, like the rigid DOFs: Newton's
    tolerance on the correction means the same for them). Eigenvalues below rtol times the
    largest (rounding) are dropped.

    Returns
    -------
    phi_r : ndarray (n_points, r)
    k_r : ndarray (r, r)
    """
    r = _checks.finite_array("compliance", compliance)
    if r.ndim != 2 or r.shape[0] != r.shape[1]:
        raise InputError(f"a compliance must be a square matrix, got {r.shape}")
    lam, vec = np.linalg.eigh(0.5 * (r + r.T))
    if lam.size and lam.min() < -1e-8 * max(lam.max(), 0.0):
        raise InputError(
            f"the compliance is not positive semi-definite (eigenvalue "
            f"{lam.min():.3g} against {lam.max():.3g})"
        )
    keep = lam > rtol * max(float(lam.max()), 0.0) if lam.size else lam > 0
    return vec[:, keep], np.diag(1.0 / lam[keep])


#: Damping ratio of residual coordinates given a mass (:func:`with_mass`; build_fr's and
#: build_rf's residual_hz).
RESIDUAL_ZETA = 0.05


def with_mass(
    phi_r: np.ndarray, k_r: np.ndarray, freq_hz: float, zeta: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A compliance block (:func:`compliance_block`) given a mass: each coordinate z_i with
    stiffness k_i gets the modal mass mu_i = k_i / w^2 (w = 2 pi freq_hz), rescaled to unit
    mass (z' = sqrt(mu_i) z): rows phi_i / sqrt(mu_i), stiffness w^2, damping 2 zeta w. The
    static compliance sum_i phi_i phi_i^T / k_i is unchanged; the block now stores kinetic
    energy and the step must resolve freq_hz (h w <= 2).

    Returns
    -------
    phi, stiffness, damping : ndarray (n_points, r), (r, r), (r, r)
    """
    w = 2.0 * np.pi * _checks.positive("residual_hz", freq_hz)
    k = np.diag(k_r)
    if np.any(k <= 0.0) or not np.allclose(k_r, np.diag(k)):
        raise InputError(
            "a compliance block to give a mass must have a positive diagonal stiffness (compliance_block's)"
        )
    mu = k / w**2
    eye = np.eye(k.size)
    return phi_r / np.sqrt(mu), eye * w**2, eye * 2.0 * zeta * w
