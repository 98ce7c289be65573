"""Variant FR: the coach with flexible rotating wheelsets (issue 14, first coupled step).

Each flexible wheelset keeps its six rigid DOFs in the coach (as in RR) and adds the
free-free elastic coordinates of :meth:`railvti.wheelset.Wheelset.flexible_body` as one
modal block (M = I, B = G + D, K of the axle-fixed frame, constant). The modes talk to the
coach only through attachment points u = Phi Q (docs/vehicle_integrator.md, "Flexible
wheelsets (FR)"):

- per wheel (0 left, 1 right) the rim's lateral and vertical displacement at the taping
  line (s = 0) and its rotation about x (camber): the wheel-rail contact is evaluated on the
  wheel moved by them, and its generalised forces act on these points (vehicle_contact);
- per journal the x, y, z displacement of the journal centre: the primary springs and
  dampers (already in the rigid K, C and preload) act on the modes through them ('split'
  couplings: k (g.q - u) + c (g.v - u') + preload on the point, g (k u + c u') on the coach);
- the Coriolis coupling of the modes with the rigid wheelset's roll and yaw rates
  (``rigid_elastic``: 'gyro' couplings);
- the Eulerian term: the rim material under the (fixed) contact point moves at
  dW/dt + Omega dW/dtheta; points carrying the rows d/dtheta (``dtheta_rows``) of each rim
  point add Omega times their displacement to the rim rates the creepages see.

The truncated modes' quasi-static contribution (the body's residual flexibility R over the
rim and journal points) enters as a block per wheelset: u = Phi Q + R g_p in the statics
(``compliance_block``), its coordinates given a mass at the highest kept mode's frequency
(``with_mass``; ``residual_mass=False``: massless, a point compliance in the condensed Newton
system).

The state is the coach's DOFs followed by 4 x nq modal coordinates, then the residual
block's coordinates of each flexible wheelset (at most 12 each).

What the attachment points carry at a state (point forces, rim deformation and camber):
:mod:`railvti.vehicle.flexible_points`; the linear analyses (M, C, K, receptances, tangents,
eigenvalues): :mod:`railvti.vehicle.flexible_linear`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .. import _checks
from ..errors import InputError
from .assembly import System, _body_point, build_coach
from .modal_blocks import RESIDUAL_ZETA, ModalBlocks, ModalCouplings, RimFollow, compliance_block, with_mass
from .params import Coach
from .table import WheelTable
from ..wheelset import Wheelset
from ..wheelset.fe import check_harmonic
from ..wheelset.flexible import free_modes, rigid_mask
from ..wheelset.residual import residual_flexibility, residual_table

__all__ = [
    "POINTS_PER_WHEELSET",
    "MIN_MODAL_STEP",
    "RIM_POINTS",
    "FRLayout",
    "primary_preload",
    "build_fr",
    "coach_body",
    "body_labels",
    "mode_labels",
    "mode_index",
    "residual_points",
    "body_radius",
]

#: Points per flexible wheelset: rim (y, z, rx) of the left and right wheel, journal (x, y, z)
#: of the left and right journal, the roll and yaw Coriolis rows, then the rims' Eulerian rows
#: d/dtheta (y, z, rx) of the left and right wheel.
POINTS_PER_WHEELSET = 20
#: The smallest time step, s, the kept modes may ask for (h omega_max <= 2): a stiffer
#: wheelset (``wheelset_stiffness_scale``) is refused before any run.
MIN_MODAL_STEP = 1.0e-6
RIM_POINTS = ("rim_left_y", "rim_left_z", "rim_left_rx", "rim_right_y", "rim_right_z", "rim_right_rx")


@dataclass(frozen=True)
class FRLayout:
    """Where a flexible wheelset's coordinates and points are in an FR System.

    Attributes
    ----------
    wheelset : int
        0-based wheelset (0 leading).
    modes : slice
        Its modal coordinates in the state (after the rigid DOFs: ``System.n + ...``).
    points : slice
        Its attachment points (rows of ``System.modal.phi``): RIM_POINTS, then journal left
        x, y, z, right x, y, z, then the roll and yaw Coriolis rows, then the rims' Eulerian
        rows (d/dtheta of RIM_POINTS).
    residual : slice
        The massless coordinates of its residual flexibility in the state (empty without).
    labels : tuple of str
        The label of each modal coordinate (:func:`body_labels`: harmonic, family, order,
        e.g. 'k1A_2'); the state's names stay ``ws<i>_q<j>``.
    k : ndarray of int
        Harmonic of each modal coordinate.
    family : ndarray of str
        '0' (k = 0), 'A' or 'B' of each modal coordinate.
    freq_hz : ndarray
        Free-free non-rotating natural frequency of each coordinate's mode, Hz.
    """

    wheelset: int
    modes: slice
    points: slice
    residual: slice = field(default_factory=lambda: slice(0, 0))
    labels: tuple = ()
    k: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    family: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype="<U1"))
    freq_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))


#: ATTACHMENT_DOFS index of each displacement point of a flexible wheelset (rim left y, z, rx,
#: rim right y, z, rx, journal left x, y, z, journal right x, y, z).
_ATTACH_INDEX = np.array([5, 6, 7, 1, 2, 3, 11, 12, 13, 8, 9, 10])


def primary_preload(coach: Coach, system: System) -> np.ndarray:
    """The static displacement qu of the sprung bodies that build_coach's preload stands for
    (K_uu qu = -F_g,u with the wheelsets held), over the system's DOFs."""
    p = coach.params
    n = system.n
    fg = np.zeros(n)
    fg[1] = -p["carbody_mass"] * p["gravity"]
    fg[system.index("bogie1_z")] = -p["bogie_mass"] * p["gravity"]
    fg[system.index("bogie2_z")] = -p["bogie_mass"] * p["gravity"]
    up = np.arange(17)
    qu = np.zeros(n)
    qu[up] = np.linalg.solve(system.k[np.ix_(up, up)], -fg[up])
    return qu


def _journal_directions(coach: Coach, system: System, i: int) -> list[tuple[int, int, np.ndarray]]:
    """(side w [0 left, 1 right], component c, g = G_bogie - G_wheelset row c) of the primary
    springs of wheelset i, as build_coach assembles them."""
    p = coach.params
    n = system.n
    r0 = p["wheel_radius"]
    hb = p["bogie_cg_height"]
    xb = (p["half_bogie_distance"], -p["half_bogie_distance"])
    xw = system.x_wheelsets
    f = {c: system.index(f"bogie{i // 2 + 1}_{c}") for c in ("y", "z", "roll", "pitch", "yaw")}
    wb = {
        c: system.index(f"ws{i + 1}_{c}")
        for c in ("x", "y", "z", "roll", "yaw")
        if f"ws{i + 1}_{c}" in system.dof_names
    }
    out = []
    for w, side in enumerate((1.0, -1.0)):
        pt = (xw[i], side * p["primary_half_spacing"], r0)
        g = _body_point(n, f, (xb[i // 2], 0.0, hb), pt) - _body_point(n, wb, (xw[i], 0.0, r0), pt)
        for c in range(3):
            out.append((w, c, g[c]))
    return out


def build_fr(
    coach: Coach,
    table: WheelTable,
    speed: float,
    *,
    wheelset=None,
    k_max: int = 2,
    f_max: float = 800.0,
    damping_ratio: float = 0.005,
    flexible: tuple = (0, 1, 2, 3),
    zero_rows: bool = False,
    body=None,
    residual: bool = True,
    euler: bool = True,
    s_contact: float = 0.0,
    rigid_gyro: bool = True,
    track: bool = True,
    residual_mass: bool = True,
    residual_hz: float | None = None,
    follow_contact: bool = False,
    residual_grid=None,
) -> tuple[System, list[FRLayout]]:
    """The coach with flexible wheelsets (variant FR) at one speed.

    Parameters
    ----------
    coach : Coach
    table : WheelTable
    speed : float
        Running speed, m/s (the modal matrices depend on the spin Omega = speed / r0).
    wheelset : railvti.wheelset.Wheelset, optional
        The FE wheelset (default: ``Wheelset()``, the passenger wheelset of the coach).
    k_max, f_max, damping_ratio
        Mode selection and modal damping (:meth:`Wheelset.flexible_body`). The coach's
        ``wheelset_stiffness_scale`` s multiplies Young's modulus; f_max then selects among
        the unscaled wheelset's frequencies (the FE's up to f_max sqrt(s): the same modes).
    flexible : tuple of int
        0-based wheelsets made flexible (the others stay rigid).
    zero_rows : bool
        Set every attachment row to zero (the modes decouple: the coach must then run
        exactly as RR; a check of the coupling's bookkeeping).
    body : FlexibleWheelset, optional
        A ready flexible body (skips the modal solve; built from the wheelset scaled by the
        coach's ``wheelset_stiffness_scale``, :meth:`Wheelset.stiffness_scaled`).
    residual : bool
        Add the body's residual flexibility (its ``residual`` at the taping lines) over the rim
        and journal points as a block per wheelset: the static deflection then does not
        depend on the truncation (docs/vehicle_integrator.md, "Residual flexibility").
    euler : bool
        Add the Eulerian term Omega dW/dtheta to the rims' rates in the contact.
    s_contact : float
        Wheel-profile coordinate (m, + towards the field side) of the rim points, both
        wheels: the rows (``FlexibleWheelset.rows``: the element's shape functions at that
        point of the rim edge), the Eulerian rows, the residual flexibility
        (``residual_flexibility``, recomputed unless s_contact is the body's ``residual_s``)
        and the reference point's lateral arm (l0 + s_contact) are taken there. 0: the taping
        line; the static contact point of the centred S1002/UIC60 pair is at about +3 mm.
        Fixed for the run (the rows do not follow the contact point).
    rigid_gyro : bool
        Keep the flexible wheelsets' rigid gyroscopic moments (in M a + C v = F: C[roll, yaw]
        = -I_y Omega, C[yaw, roll] = +I_y Omega; I_y the coach's ``wheelset_pitch_inertia``:
        the FE wheelset's polar
        moment plus the rotating lumped parts, railvti.vehicle.wheelset_body), as variant RR
        has them (:func:`~railvti.vehicle.assembly.build_coach`); False drops them (with
        ``zero_rows``, FR then reproduces RR built with ``gyroscopic=False``).
    track : bool
        False puts the wheelsets on rigid ground instead of the four track elements (model
        FF: :func:`railvti.vehicle.ring_coupling.build_rf` then adds the ring track under them).
    residual_mass : bool
        Give the residual coordinates a mass (:func:`railvti.vehicle.modal_blocks.with_mass`): each
        at the natural frequency ``residual_hz`` with the damping ratio
        :data:`railvti.vehicle.modal_blocks.RESIDUAL_ZETA`, the static compliance unchanged (the same
        static deflection). False: massless coordinates, a quasi-static point compliance;
        Newton then stops in flange-only contact at high speed, where the saturated creep
        force drives the massless coordinates' rates (docs/vehicle.md, "Residual flexibility
        with a mass").
    residual_hz : float, optional
        The residual coordinates' frequency, Hz; default: the highest kept mode's (the
        default step then resolves them without a change).
    follow_contact : bool
        The rims' rows, Eulerian rows, residual flexibility and reference arm follow each
        wheel's contact point along the profile in the time loop (Kaiser eq. 3; tread and
        flange normal-force weighted, at the last accepted step's point): interpolated in the
        body's 1 mm ``rim_rows`` / ``rim_dtheta_rows`` and in ``residual_grid``, the
        residual as 12 coordinates with rows L (L L^T = R(s), Cholesky) and constant
        stiffness. The statics and linear analysis see the taping line. Needs s_contact = 0.
    residual_grid : ResidualTable, optional
        The residual over the contact points (:func:`railvti.wheelset.residual.residual_table`,
        about 30 s for the default mesh); default: made here at 5 mm (follow_contact only).

    Returns
    -------
    System, list of FRLayout
    """
    sy = build_coach(coach, table, track=track)
    if "ws1_x" not in sy.dof_names:
        raise InputError("variant FR needs the six-DOF wheelsets")
    flexible = tuple(sorted(set(int(i) for i in flexible)))
    if not flexible or any(i not in (0, 1, 2, 3) for i in flexible):
        raise InputError(f"flexible wheelsets must be a non-empty subset of 0..3, got {flexible}")
    if body is None:
        wheelset, body = coach_body(coach, wheelset, speed, k_max, f_max, damping_ratio)
    else:
        _check_body_step(body, coach["wheelset_stiffness_scale"])
    if body.n == 0:
        raise InputError(f"no elastic mode below f_max = {f_max} Hz")
    s_contact = _check_s_contact(body, s_contact)
    blocks, cpl = _modal_rows(coach, sy, body, flexible, s_contact, zero_rows, euler)
    follow = None
    if follow_contact:
        if s_contact != 0.0:
            raise InputError("follow_contact: the rows start at the taping line, s_contact must be 0")
        follow = _follow_tables(wheelset, body, residual and bool(np.any(body.residual)), residual_grid)
    if follow is not None and follow[1] is not None:
        post = _add_followed_residual(
            blocks, sy, body, flexible, follow[1], residual_mass, residual_hz, zero_rows
        )
        cpl = replace(cpl, rim_follow=_placed_follow(follow[0], body.n, len(flexible), post))
    else:
        if residual and np.any(body.residual):
            _add_residual(
                blocks, sy, body, flexible, wheelset, s_contact, residual_mass, residual_hz, zero_rows
            )
        if follow is not None:
            cpl = replace(cpl, rim_follow=_placed_follow(follow[0], body.n, len(flexible), None))
    mb = ModalBlocks(
        damping=tuple(blocks.damp),
        stiffness=tuple(blocks.stiff),
        phi=blocks.phi,
        names=tuple(blocks.names),
        couplings=cpl,
        massless=tuple(blocks.massless),
    )
    if not rigid_gyro:
        ispin = np.array(sy.spin_inertia, copy=True)
        ispin[list(flexible)] = 0.0
        sy = replace(sy, spin_inertia=ispin)
    return sy.with_modal(mb), blocks.layouts


@dataclass
class _Blocks:
    """The modal blocks of an FR system while :func:`build_fr` assembles them: the rows over
    all attachment points (columns: the coordinates), each block's name, damping, stiffness and
    masslessness, and each flexible wheelset's layout."""

    phi: np.ndarray
    names: list
    damp: list
    stiff: list
    massless: list
    layouts: list

    def add_residual(
        self,
        sy: System,
        flexible: tuple,
        phi_r: np.ndarray,
        c_r: np.ndarray,
        k_r: np.ndarray,
        massless: bool,
        zero_rows: bool,
    ) -> None:
        """Add one residual block (rows phi_r over a wheelset's 12 displacement points,
        damping c_r, stiffness k_r) per flexible wheelset, after the elastic coordinates."""
        nq = self.layouts[0].k.size
        npt, nr = self.phi.shape[0], phi_r.shape[1]
        cols = [self.phi]
        for j, i in enumerate(flexible):
            c = np.zeros((npt, nr))
            if not zero_rows:
                c[POINTS_PER_WHEELSET * j : POINTS_PER_WHEELSET * j + 12] = phi_r
            cols.append(c)
            self.names += [f"ws{i + 1}_r{k + 1}" for k in range(nr)]
            self.damp.append(c_r)
            self.stiff.append(k_r)
            self.massless.append(massless)
            m0 = sy.n + nq * len(flexible) + nr * j
            self.layouts[j] = replace(self.layouts[j], residual=slice(m0, m0 + nr))
        self.phi = np.hstack(cols)


def _check_s_contact(body, s_contact: float) -> float:
    """The rim points' wheel-profile coordinate (m), checked to lie on the tread."""
    s_contact = float(s_contact)
    e = body.edges[0]
    if not (np.isfinite(s_contact) and e.s_face <= s_contact <= e.s_max):
        raise InputError(
            f"s_contact = {s_contact * 1e3:.1f} mm: the rim points must lie on the "
            f"tread ({e.s_face * 1e3:.1f}..{e.s_max * 1e3:.1f} mm)"
        )
    return s_contact


def _modal_rows(
    coach: Coach, sy: System, body, flexible: tuple, s_contact: float, zero_rows: bool, euler: bool
) -> tuple[_Blocks, ModalCouplings]:
    """The elastic coordinates of each flexible wheelset: their rows at the rims, journals,
    Coriolis and Eulerian points, the journal springs ('split') and Coriolis ('gyro')
    couplings to the coach, the rims' reference arms."""
    nq = body.n
    p = coach.params
    qu = primary_preload(coach, sy)
    kp = (p["primary_kx"], p["primary_ky"], p["primary_kz"])
    cp = (p["primary_cx"], p["primary_cy"], p["primary_cz"])
    npt = POINTS_PER_WHEELSET * len(flexible)
    phi = np.zeros((npt, nq * len(flexible)))
    kinds, pts, dirs, pars = [], [], [], []
    rim_pts = np.zeros((3, 2, len(flexible)), dtype=int)
    eul_pts = np.zeros((3, 2, len(flexible)), dtype=int)
    layouts = []
    geo_y = _rim_lateral(body) + s_contact
    for j, i in enumerate(flexible):
        p0, m0 = POINTS_PER_WHEELSET * j, nq * j
        rows = np.zeros((POINTS_PER_WHEELSET, nq))
        for w, side in enumerate((1, 0)):  # vehicle wheel 0 left = FE side 1
            rows[3 * w : 3 * w + 3] = body.rows(side, s_contact)[1:4]
            rows[6 + 3 * w : 9 + 3 * w] = body.journal[side][0:3]
            rows[14 + 3 * w : 17 + 3 * w] = body.dtheta_rows(side, s_contact)[1:4]
            rim_pts[:, w, j] = p0 + 3 * w + np.arange(3)
            eul_pts[:, w, j] = p0 + 14 + 3 * w + np.arange(3)
        rows[12] = body.rigid_elastic[:, 0]
        rows[13] = body.rigid_elastic[:, 1]
        if not zero_rows:
            phi[p0 : p0 + POINTS_PER_WHEELSET, m0 : m0 + nq] = rows
        for w, c, g in _journal_directions(coach, sy, i):
            kinds.append("split")
            pts.append(p0 + 6 + 3 * w + c)
            dirs.append(g)
            pars.append((kp[c], cp[c], -kp[c] * float(g @ qu)))  # preload: f0 = fg + K qu
        for r, name in ((12, "roll"), (13, "yaw")):
            g = np.zeros(sy.n)
            g[sy.index(f"ws{i + 1}_{name}")] = 1.0
            kinds.append("gyro")
            pts.append(p0 + r)
            dirs.append(g)
            pars.append((body.omega, 0.0, 0.0))
        layouts.append(
            FRLayout(
                i,
                slice(sy.n + m0, sy.n + m0 + nq),
                slice(p0, p0 + POINTS_PER_WHEELSET),
                labels=body_labels(body),
                k=np.array(body.k),
                family=np.array(body.family),
                freq_hz=np.array(body.freq_hz),
            )
        )
    cpl = ModalCouplings(
        kinds=tuple(kinds),
        points=np.array(pts),
        directions=np.array(dirs).T,
        params=np.array(pars).T,
        rim_wheelsets=np.array(flexible),
        rim_points=rim_pts,
        rim_arms=np.tile([[geo_y], [body_radius(body)]], (1, len(flexible))),
        rim_euler=eul_pts if euler else None,
        rim_omega=np.full(len(flexible), body.omega) if euler else None,
    )
    b = body.gyro + body.damping
    blocks = _Blocks(
        phi=phi,
        names=[f"ws{i + 1}_q{k + 1}" for i in flexible for k in range(nq)],
        damp=[b for _ in flexible],
        stiff=[body.stiffness for _ in flexible],
        massless=[False for _ in flexible],
        layouts=layouts,
    )
    return blocks, cpl


def _add_followed_residual(
    blocks: _Blocks,
    sy: System,
    body,
    flexible: tuple,
    res: np.ndarray,
    residual_mass: bool,
    residual_hz: float | None,
    zero_rows: bool,
) -> float:
    """Add the residual flexibility that follows the contact points: 12 coordinates per
    wheelset with rows post L (L L^T = R at the taping lines) and stiffness post^2; returns
    post (2 pi residual_hz with a mass, else 1)."""
    l0 = _cholesky_psd(res)
    hz = float(body.freq_hz.max()) if residual_hz is None else residual_hz
    post = 2.0 * np.pi * _checks.positive("residual_hz", hz) if residual_mass else 1.0
    nr = 12
    blocks.add_residual(
        sy,
        flexible,
        post * l0,
        np.eye(nr) * (2.0 * RESIDUAL_ZETA * post if residual_mass else 0.0),
        np.eye(nr) * post**2,
        not residual_mass,
        zero_rows,
    )
    return post


def _add_residual(
    blocks: _Blocks,
    sy: System,
    body,
    flexible: tuple,
    wheelset,
    s_contact: float,
    residual_mass: bool,
    residual_hz: float | None,
    zero_rows: bool,
) -> None:
    """Add the body's residual flexibility at the rim points s_contact (fixed for the run) as a
    compliance block per wheelset, with a mass unless ``residual_mass`` is False."""
    res = residual_points(
        body,
        None
        if s_contact in body.residual_s and body.residual_s[0] == body.residual_s[1]
        else _residual_at(wheelset, body, s_contact),
    )
    phi_r, k_r = compliance_block(res)
    c_r = np.zeros_like(k_r)
    if residual_mass:
        hz = float(body.freq_hz.max()) if residual_hz is None else residual_hz
        phi_r, k_r, c_r = with_mass(phi_r, k_r, hz, RESIDUAL_ZETA)
    blocks.add_residual(sy, flexible, phi_r, c_r, k_r, not residual_mass, zero_rows)


def _placed_follow(rf: RimFollow, nq: int, nflex: int, post: float | None) -> RimFollow:
    """The followed rows' tables placed in the state: each wheelset's modes, its residual
    coordinates (post: their scale; None: no residual block) and its 12 points."""
    has_res = post is not None
    return replace(
        rf,
        modes=np.arange(nflex) * nq,
        residual=(nq * nflex + 12 * np.arange(nflex)) if has_res else np.full(nflex, -1),
        points=np.array([POINTS_PER_WHEELSET * j + np.arange(12) for j in range(nflex)]).T,
        post=post if has_res else 1.0,
    )


def coach_body(coach: Coach, wheelset, speed: float, k_max: int, f_max: float, damping_ratio: float = 0.005):
    """The coach's flexible wheelset at a speed: (the FE wheelset scaled by the coach's
    ``wheelset_stiffness_scale`` s, its :class:`FlexibleWheelset`).

    Young's modulus times s (:meth:`Wheelset.stiffness_scaled`); f_max (Hz) selects among
    the unscaled wheelset's frequencies (the FE's up to f_max sqrt(s): the same modes kept).
    InputError for no elastic mode below f_max, or kept modes that would need a time step
    below :data:`MIN_MODAL_STEP`.
    """
    scale = coach["wheelset_stiffness_scale"]
    ws = (wheelset if wheelset is not None else Wheelset()).stiffness_scaled(scale)
    k_max = check_harmonic(k_max, "k_max")
    f_max = _checks.positive("f_max", f_max)
    f_fe = f_max * np.sqrt(scale)
    if not any(np.any(~rigid_mask(free_modes(ws, k, f_fe))) for k in range(k_max + 1)):
        raise InputError(
            f"no elastic mode below f_max = {f_max} Hz for harmonics k <= "
            f"{k_max}: raise f_max (the first, k = 0 or 1, is near 70-90 Hz)"
        )
    body = ws.flexible_body(speed, k_max=k_max, f_max=f_fe, damping_ratio=damping_ratio)
    _check_body_step(body, scale)
    return ws, body


def _check_body_step(body, scale: float) -> None:
    """InputError when the body's highest kept mode needs a step below MIN_MODAL_STEP."""
    if body.n and 2.0 / (2.0 * np.pi * float(np.max(body.freq_hz))) < MIN_MODAL_STEP:
        raise InputError(
            f"wheelset_stiffness_scale = {scale:g}: the highest kept mode "
            f"({float(np.max(body.freq_hz)):.4g} Hz) would need a time step below "
            f"{MIN_MODAL_STEP * 1e6:g} us; lower the scale or f_max"
        )


def _follow_tables(wheelset, body, with_residual: bool, grid):
    """The rim rows and residual blocks of :class:`RimFollow` in the vehicle's order (wheel 0
    left = FE side 1; journals left, right) and the 12 x 12 residual at the taping lines
    (None without residual)."""
    sides = (1, 0)
    rows = np.stack([body.rim_rows[sd][:, 1:4, :].transpose(1, 2, 0) for sd in sides], axis=-1)
    drows = np.stack([body.rim_dtheta_rows[sd][:, 1:4, :].transpose(1, 2, 0) for sd in sides], axis=-1)
    if with_residual:
        if grid is None:
            grid = residual_table(wheelset if wheelset is not None else Wheelset(), body)
        perm = [3, 4, 5, 0, 1, 2]
        rcc = np.stack([grid.cc[sd][:, 1:4, 1:4].transpose(1, 2, 0) for sd in sides], axis=-1)
        # left (FE 1) at a against right (FE 0) at b: cross[b, a] is right rows, left columns
        rcx = grid.cross[:, :, 1:4, 1:4].transpose(3, 2, 1, 0)
        rcj = np.stack([grid.cj[sd][:, 1:4, :][:, :, perm].transpose(1, 2, 0) for sd in sides], axis=-1)
        rjj = grid.jj[np.ix_(perm, perm)]
        rs0, rds = grid.s0, grid.ds
        res0 = residual_points(body, grid.interpolate((0.0, 0.0)))
    else:
        rcc, rcx, rcj = np.zeros((3, 3, 2, 2)), np.zeros((3, 3, 2, 2)), np.zeros((3, 6, 2, 2))
        rjj, rs0, rds, res0 = np.zeros((6, 6)), -1.0, 2.0, None
    rf = RimFollow(
        s0=body.s0,
        ds=body.ds,
        rows=rows,
        drows=drows,
        rs0=rs0,
        rds=rds,
        rcc=rcc,
        rcx=rcx,
        rcj=rcj,
        rjj=rjj,
        modes=np.zeros(1, int),
        residual=np.zeros(1, int),
        points=np.zeros((12, 1), int),
        post=1.0,
    )
    return rf, res0


def _cholesky_psd(r: np.ndarray) -> np.ndarray:
    """Lower Cholesky factor of a symmetric positive semi-definite matrix, a non-positive
    pivot giving a zero column (vehicle_modal%cholesky)."""
    n = r.shape[0]
    lo = np.zeros_like(r)
    for j in range(n):
        d = r[j, j] - lo[j, :j] @ lo[j, :j]
        if not d > 1e-14 * abs(r[j, j]):
            continue
        lo[j, j] = np.sqrt(d)
        lo[j + 1 :, j] = (r[j + 1 :, j] - lo[j + 1 :, :j] @ lo[j, :j]) / lo[j, j]
    return lo


def body_labels(body) -> tuple[str, ...]:
    """Labels of a flexible body's coordinates: 'k<k>_<j>' for harmonic 0 and
    'k<k><family>_<j>' (family A or B) above, j counting from 1 upward in frequency within its
    harmonic and family (e.g. 'k0_1', 'k1A_1', 'k1B_1', 'k2A_3')."""
    count: dict[tuple[int, str], int] = {}
    out = []
    for k, f in zip(np.asarray(body.k).tolist(), np.asarray(body.family).tolist()):
        count[(k, f)] = count.get((k, f), 0) + 1
        out.append(f"k{k}{'' if f == '0' else f}_{count[(k, f)]}")
    return tuple(out)


def mode_labels(system: System, layouts: list[FRLayout]) -> tuple[str, ...]:
    """Labels of an FR system's modal coordinates in state order (``system.modal.names``):
    'ws<i>_<body label>' (:func:`body_labels`) for the elastic coordinates and
    'ws<i>_residual_<j>' for the residual flexibility's massless coordinates."""
    mb = system.modal
    if mb is None:
        raise InputError("mode labels need an FR system (modal blocks)")
    out = [""] * mb.n_modes
    n = system.n
    for lay in layouts:
        w = lay.wheelset + 1
        for j, lab in enumerate(lay.labels):
            out[lay.modes.start - n + j] = f"ws{w}_{lab}"
        for j in range(lay.residual.stop - lay.residual.start):
            out[lay.residual.start - n + j] = f"ws{w}_residual_{j + 1}"
    return tuple(out)


def mode_index(system: System, layouts: list[FRLayout], label: str) -> int:
    """Index in the state of the modal coordinate with this label (:func:`mode_labels`).

    Raises
    ------
    InputError
        An unknown label (the message lists the system's labels of that wheelset).
    """
    labels = mode_labels(system, layouts)
    if isinstance(label, str) and label in labels:
        return system.n + labels.index(label)
    pre = str(label).split("_", 1)[0] + "_"
    known = [x for x in labels if x.startswith(pre) and "residual" not in x] or [
        x for x in labels if "residual" not in x
    ]
    raise InputError(
        f"unknown mode label {label!r}: this FR system keeps "
        f"{', '.join(known[:40])}{' ...' if len(known) > 40 else ''} "
        "(labels 'ws<i>_k<k><family>_<j>'; more modes: raise k_max or f_max)"
    )


def residual_points(body, residual: np.ndarray | None = None) -> np.ndarray:
    """The residual flexibility (12, 12) over one flexible wheelset's displacement points
    (rim left y, z, rx, rim right y, z, rx, journal left x, y, z, right x, y, z), from
    ``residual`` over ATTACHMENT_DOFS (default ``body.residual`` at ``body.residual_s``; the
    rims' x is not coupled)."""
    r = body.residual if residual is None else residual
    return np.asarray(r)[np.ix_(_ATTACH_INDEX, _ATTACH_INDEX)]


def _residual_at(wheelset, body, s: float) -> np.ndarray:
    """The body's residual flexibility with both contact points at profile coordinate s."""
    ws = wheelset if wheelset is not None else Wheelset()
    return residual_flexibility(ws, body, (s, s))


def _rim_lateral(body) -> float:
    """Lateral distance of the taping line (s = 0) from the wheelset centre, m."""
    return float(abs(body.edges[0].y_contact))


def body_radius(body) -> float:
    """The tread radius of the rim edge (depth of the taping line below the axle), m."""
    return float(body.edges[0].r_tread)
