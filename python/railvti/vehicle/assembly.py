"""Assembly of the coach-track system: DOFs, linear matrices, nonlinear elements, preload.

Track frame x forward, y left, z up (railvti.geometry). Small rotations (roll about x, pitch
about y, yaw about z) except the wheels' rolling: the nominal rolling speed Omega0 = v0/r0
enters the creepages, and each wheelset's spin perturbation beta (rotation about the axle on
top of Omega0) is a DOF of which only the rate betadot matters (no stiffness, no angle in any
force). A linear spring between points P (body A) and Q
(body B) with stiffnesses (kx, ky, kz) adds G^T diag(k) G, G = G_P - G_Q, to K, where G_P is
the 3 x n map from the DOFs to P's displacement: u = t + w x p (p from the body's reference
point, w = (roll, pitch, yaw)).

DOFs (0-based), 53 in all (45 with ``wheelset_dofs=4``: no x, no beta, the layout of the
earlier model):

========  ==========================================  =========
carbody   y, z, roll, pitch, yaw                       0-4
bolsters  yaw (front, rear)                            5-6
bogies    y, z, roll, pitch, yaw (front, rear)         7-16
wheelsets x, y, z, roll, yaw, beta (1 leading .. 4)    17-40
track     y, z, roll under each wheelset               41-52
========  ==========================================  =========

Wheelset x is longitudinal, relative to the nominal position moving at v0 (the carbody and
bogies have no x DOF: they move at v0), held by the primary longitudinal springs/dampers at
the axleboxes; beta is the spin perturbation (inertia wheelset_pitch_inertia), driven only by
the longitudinal creep forces' moments about the axle.

The bolster follows the carbody in every motion but yaw: the secondary springs' upper
points, the lateral damper and the bump stops sit on it, and dry friction (tanh-regularised)
acts on its yaw relative to the carbody.

Gravity and preload: springs are pre-stressed so that with all suspension DOFs at zero the
carbody and bogies are in equilibrium (K_uu q_u = -F_g,u with the wheelsets held); the
wheelsets then carry the whole weight through the contact. The static solve finds the
contact and track deflections.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from ..material import STEEL
from .params import Coach
from .modal_blocks import ModalBlocks
from .model import VehicleModel
from .table import QUANTITIES, WheelTable

if TYPE_CHECKING:
    from .strip import StripGeometry

__all__ = [
    "WS_DOFS",
    "IWS_ROWS",
    "DOF_NAMES",
    "System",
    "build_coach",
    "build_single_wheelset",
    "build_rigid_system",
]

EL_FRICTION, EL_BUMP = 1, 2
_INT_FIELDS = ("etype", "iws", "itr")
#: Per-wheelset DOFs in the global order.
WS_DOFS = ("x", "y", "z", "roll", "yaw", "beta")
#: Row order of System.iws (the Fortran per-wheelset state qw, vw).
IWS_ROWS = ("y", "z", "roll", "yaw", "x", "beta")

DOF_NAMES = (
    ["carbody_y", "carbody_z", "carbody_roll", "carbody_pitch", "carbody_yaw", "bolster1_yaw", "bolster2_yaw"]
    + [f"bogie{b}_{c}" for b in (1, 2) for c in ("y", "z", "roll", "pitch", "yaw")]
    + [f"ws{w}_{c}" for w in (1, 2, 3, 4) for c in WS_DOFS]
    + [f"track{w}_{c}" for w in (1, 2, 3, 4) for c in ("y", "z", "roll")]
)


@dataclass(frozen=True)
class System:
    """An assembled second-order system M a = F(q, v) for the Fortran integrator.

    Attributes
    ----------
    m, c, k : ndarray (n, n)
        Mass, damping and stiffness of the linear part.
    f0 : ndarray (n,)
        Constant force (gravity and preload).
    etype : ndarray (ne,) int
        Nonlinear element kinds (1 friction, 2 bump stop).
    eg : ndarray (n, ne)
        Element directions: d = g . q.
    epar : ndarray (4, ne)
        Element parameters (friction: torque, regularisation rate, viscous part;
        bump stop: clearance, stiffness).
    iws : ndarray (6, nw) int
        1-based DOF indices (y, z, roll, yaw, x, beta) of each wheelset (IWS_ROWS); 0 for a
        DOF not modelled (held at zero).
    itr : ndarray (3, nw) int
        1-based DOF indices (y, z, roll) of each track element (0: rigid ground).
    table : WheelTable
    dof_names : tuple of str
    x_wheelsets : ndarray (nw,)
        Longitudinal positions of the wheelsets, m.
    wheel_load : float
        Static vertical wheel load expected from the masses, N.
    friction : float
        Wheel-rail friction coefficient.
    modal : ModalBlocks or None
        Flexible bodies as modal blocks coupled through attachment points (the state of
        :func:`~railvti.vehicle.simulate` is then the DOFs followed by the modal
        coordinates, :attr:`state_names`); None for a rigid model.
    strip : StripGeometry or None
        The strip contact (:mod:`railvti.vehicle.strip`): the Hertz + Kalker and Hertz +
        FASTSIM contacts then take their normal forces from the strip potential and their
        creep forces at each slot's load-weighted point; None: the table's points. The
        table still bounds the lateral range (derailment).
    spin_inertia : ndarray (nw,), optional
        Spin (polar) inertia I_y of each wheelset's rotating parts, kg m^2: the core adds the
        gyroscopic moments (forces on the right-hand side) roll +I_y Omega yaw', yaw
        -I_y Omega roll' (Omega = v0 / r0, the spin about +y) at each call's speed
        (vehicle_model add_gyroscopic; as C[roll, yaw] = -I_y Omega in M a + C v = F).
        Default zeros: none.

    Notes
    -----
    The arrays are read-only copies: the system is sent to the Fortran core once
    (:attr:`native`) and must not change afterwards; make a changed system with
    ``dataclasses.replace``.
    """

    m: np.ndarray
    c: np.ndarray
    k: np.ndarray
    f0: np.ndarray
    etype: np.ndarray
    eg: np.ndarray
    epar: np.ndarray
    iws: np.ndarray
    itr: np.ndarray
    table: WheelTable
    dof_names: tuple
    x_wheelsets: np.ndarray
    wheel_load: float
    friction: float = 0.3
    modal: ModalBlocks | None = None
    strip: "StripGeometry | None" = None
    spin_inertia: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.spin_inertia is None:
            object.__setattr__(self, "spin_inertia", np.zeros(self.iws.shape[1]))
        elif np.shape(self.spin_inertia) != (np.shape(self.iws)[1],):
            raise InputError(
                f"spin_inertia must have one entry per wheelset "
                f"({np.shape(self.iws)[1]}), got shape {np.shape(self.spin_inertia)}"
            )
        elif not np.all(np.asarray(self.spin_inertia, dtype=float) >= 0.0):
            raise InputError(f"spin_inertia must be finite and >= 0 (kg m^2), got {self.spin_inertia}")
        for f in fields(self):
            val = getattr(self, f.name)
            if isinstance(val, np.ndarray):
                dtype = np.int32 if f.name in _INT_FIELDS else np.float64
                arr = np.array(val, dtype=dtype, order="F")
                arr.setflags(write=False)
                object.__setattr__(self, f.name, arr)

    @property
    def native(self) -> VehicleModel:
        """The system in the Fortran core: made on first use (or after it was closed) and kept,
        and freed, with this System, so that every solve reuses it."""
        model = self.__dict__.get("_native")
        if model is None or not model.alive:
            model = VehicleModel(self)
            self.__dict__["_native"] = model  # a cache, not a field: the System stays frozen
        return model

    @property
    def n(self) -> int:
        """Number of DOFs (rigid, without the modal coordinates)."""
        return self.m.shape[0]

    @property
    def n_state(self) -> int:
        """Size of the integrated state: the DOFs and the modal coordinates."""
        return self.n + (self.modal.n_modes if self.modal is not None else 0)

    @property
    def state_names(self) -> tuple:
        """Names of the state's entries: dof_names, then the modal coordinates' names."""
        return self.dof_names + (self.modal.names if self.modal is not None else ())

    def with_modal(self, modal: ModalBlocks | None) -> "System":
        """The same system with these modal blocks (None: without); InputError for a point
        element on a DOF the system does not have."""
        if modal is not None:
            modal.element_arrays(self.n)  # checks the elements' DOFs
        return replace(self, modal=modal)

    def dense_equivalent(self) -> "System":
        """The system with its modal blocks assembled as ordinary DOFs into dense M, C, K over
        all n_state entries (linear point elements only): the reference of the condensed
        integrator, practical up to a few thousand modes. InputError for a Hertz element."""
        mb = self.modal
        if mb is None:
            return self
        if mb.couplings is not None:
            raise InputError("dense_equivalent: modal couplings (variant FR) are not assembled")
        if mb.massless is not None:
            raise InputError("dense_equivalent: massless blocks have no dense mass matrix")
        n, nm = self.n, mb.n_modes
        nt = n + nm
        m = np.zeros((nt, nt))
        c = np.zeros((nt, nt))
        k = np.zeros((nt, nt))
        f0 = np.zeros(nt)
        m[:n, :n], c[:n, :n], k[:n, :n], f0[:n] = self.m, self.c, self.k, self.f0
        m[n:, n:] = np.eye(nm)
        mb.place_blocks(c, k, n)
        for e in mb.elements:
            if e.kind != "linear":
                raise InputError("dense_equivalent: only linear point elements")
            g = np.zeros(nt)  # d = g . x = u_point - q_dof
            g[n:] = mb.phi[e.point]
            if e.dof is not None:
                g[e.dof] -= 1.0
            k += e.params[0] * np.outer(g, g)
            c += e.params[1] * np.outer(g, g)
            f0 -= e.params[2] * g
        eg = np.zeros((nt, self.eg.shape[1]))
        eg[:n] = self.eg
        return replace(self, m=m, c=c, k=k, f0=f0, eg=eg, dof_names=self.state_names, modal=None)

    def index(self, name: str) -> int:
        """0-based index of a DOF by name."""
        try:
            return self.dof_names.index(name)
        except ValueError:
            raise InputError(f"unknown DOF {name!r}") from None

    def without_damping(self) -> "System":
        """The same system with every damper and friction element removed (modal blocks: B
        reduced to its gyroscopic, skew part; point elements without dampers)."""
        epar = np.array(self.epar, copy=True, order="F")
        epar[:, self.etype == EL_FRICTION] = 0.0
        modal = self.modal.without_damping() if self.modal is not None else None
        return replace(self, c=np.zeros_like(self.c, order="F"), epar=epar, modal=modal)


class _Builder:
    def __init__(self, n: int) -> None:
        self.n = n
        self.m = np.zeros((n, n))
        self.c = np.zeros((n, n))
        self.k = np.zeros((n, n))
        self.elements: list[tuple[int, np.ndarray, tuple[float, float, float, float]]] = []

    def spring(self, gp: np.ndarray, gq: np.ndarray, k3, c3) -> None:
        g = gp - gq
        self.k += g.T @ np.diag(k3) @ g
        self.c += g.T @ np.diag(c3) @ g


def _body_point(
    n: int, dofs: dict[str, int], ref: tuple[float, float, float], p: tuple[float, float, float]
) -> np.ndarray:
    """3 x n map from a rigid body's DOFs to the displacement of point p (track coordinates)."""
    g = np.zeros((3, n))
    rx, ry, rz = p[0] - ref[0], p[1] - ref[1], p[2] - ref[2]
    if "x" in dofs:
        g[0, dofs["x"]] += 1.0
    if "y" in dofs:
        g[1, dofs["y"]] += 1.0
    if "z" in dofs:
        g[2, dofs["z"]] += 1.0
    if "roll" in dofs:  # w = (phi, 0, 0): w x r = (0, -phi rz, phi ry)
        g[1, dofs["roll"]] += -rz
        g[2, dofs["roll"]] += ry
    if "pitch" in dofs:  # w = (0, th, 0): (th rz, 0, -th rx)
        g[0, dofs["pitch"]] += rz
        g[2, dofs["pitch"]] += -rx
    if "yaw" in dofs:  # w = (0, 0, psi): (-psi ry, psi rx, 0)
        g[0, dofs["yaw"]] += -ry
        g[1, dofs["yaw"]] += rx
    return g


def build_coach(
    coach: Coach, table: WheelTable, *, track: bool = True, wheelset_dofs: int = 6, gyroscopic: bool = True
) -> System:
    """Assemble the coach on four track elements (RR model: rigid bodies, rigid track element).

    Parameters
    ----------
    coach : Coach
    table : WheelTable
    track : bool
        False puts the wheelsets on rigid ground (no track element DOFs).
    wheelset_dofs : int
        6 (x, y, z, roll, yaw, beta) or 4 (y, z, roll, yaw: no longitudinal motion, rolling
        exactly at v0/r0, as the model before the x and spin DOFs).
    gyroscopic : bool
        The wheelsets' gyroscopic moments from their spin inertia ``wheelset_pitch_inertia``
        (:attr:`System.spin_inertia`; the same term as variant FR's rigid part). False: none,
        the model before issue 30.
    """
    if wheelset_dofs not in (4, 6):
        raise InputError(f"wheelset_dofs must be 4 or 6, got {wheelset_dofs!r}")
    p = coach.params
    wnames = WS_DOFS if wheelset_dofs == 6 else ("y", "z", "roll", "yaw")
    nws = len(wnames)
    it0 = 17 + 4 * nws
    n = it0 + (12 if track else 0)
    b = _Builder(n)
    xb = (p["half_bogie_distance"], -p["half_bogie_distance"])
    a = p["half_wheelbase"]
    xw = np.array([xb[0] + a, xb[0] - a, xb[1] + a, xb[1] - a])
    car = {"y": 0, "z": 1, "roll": 2, "pitch": 3, "yaw": 4}
    frames = [
        {"y": 7 + 5 * i, "z": 8 + 5 * i, "roll": 9 + 5 * i, "pitch": 10 + 5 * i, "yaw": 11 + 5 * i}
        for i in range(2)
    ]
    wsd = [{c: 17 + nws * i + j for j, c in enumerate(wnames)} for i in range(4)]
    diag, fg = _coach_masses(p, n, frames, wsd)
    if track:  # the track elements under the wheelsets
        for i in range(4):
            j = it0 + 3 * i
            diag[j : j + 3] = [p["track_mass_y"], p["track_mass_z"], p["track_inertia_roll"]]
            b.k[j : j + 3, j : j + 3] += np.diag([p["track_ky"], p["track_kz"], p["track_kroll"]])
            b.c[j : j + 3, j : j + 3] += np.diag([p["track_cy"], p["track_cz"], p["track_croll"]])
    b.m = np.diag(diag)
    _primary_suspension(b, p, n, frames, wsd, xb, xw)
    _secondary_suspension(b, p, n, car, frames, xb)
    # preload: upper bodies in equilibrium at q = 0 with the wheelsets held
    up = np.arange(17)
    qu = np.zeros(n)
    qu[up] = np.linalg.solve(b.k[np.ix_(up, up)], -fg[up])
    f0 = fg + b.k @ qu
    iws = np.array([[w[c] + 1 if c in w else 0 for c in IWS_ROWS] for w in wsd]).T
    itr = (
        np.array([[it0 + 3 * i, it0 + 1 + 3 * i, it0 + 2 + 3 * i] for i in range(4)]).T + 1
        if track
        else np.zeros((3, 4), dtype=int)
    )
    names = tuple(
        DOF_NAMES[:17]
        + [f"ws{i + 1}_{c}" for i in range(4) for c in wnames]
        + DOF_NAMES[17 + 4 * len(WS_DOFS) :][: n - it0]
    )
    sy = _finish(b, f0, iws, itr, table, names, xw, coach.static_wheel_load, p["friction"])
    if gyroscopic:
        sy = replace(sy, spin_inertia=np.full(4, p["wheelset_pitch_inertia"]))
    return sy


def _coach_masses(
    p: dict[str, float], n: int, frames: list[dict[str, int]], wsd: list[dict[str, int]]
) -> tuple[np.ndarray, np.ndarray]:
    """The coach's mass diagonal (carbody, bolsters, bogie frames, wheelsets; the track
    elements' entries left 0) and gravity force vector, over the ``n`` DOFs."""
    grav = p["gravity"]
    diag = np.zeros(n)
    diag[0:5] = [
        p["carbody_mass"],
        p["carbody_mass"],
        p["carbody_roll_inertia"],
        p["carbody_pitch_inertia"],
        p["carbody_yaw_inertia"],
    ]
    diag[5:7] = p["bolster_yaw_inertia"]
    for f in frames:
        diag[[f["y"], f["z"], f["roll"], f["pitch"], f["yaw"]]] = [
            p["bogie_mass"],
            p["bogie_mass"],
            p["bogie_roll_inertia"],
            p["bogie_pitch_inertia"],
            p["bogie_yaw_inertia"],
        ]
    wmass = {
        "x": p["wheelset_mass"],
        "y": p["wheelset_mass"],
        "z": p["wheelset_mass"],
        "roll": p["wheelset_roll_inertia"],
        "yaw": p["wheelset_yaw_inertia"],
        "beta": p["wheelset_pitch_inertia"],
    }
    for w in wsd:
        for c, j in w.items():
            diag[j] = wmass[c]
    fg = np.zeros(n)
    fg[1] = -p["carbody_mass"] * grav
    for f in frames:
        fg[f["z"]] = -p["bogie_mass"] * grav
    for w in wsd:
        fg[w["z"]] = -p["wheelset_mass"] * grav
    return diag, fg


def _primary_suspension(
    b: _Builder,
    p: dict[str, float],
    n: int,
    frames: list[dict[str, int]],
    wsd: list[dict[str, int]],
    xb: tuple[float, float],
    xw: np.ndarray,
) -> None:
    """The primary springs and dampers, per axlebox: each wheelset against its bogie frame."""
    r0, hb = p["wheel_radius"], p["bogie_cg_height"]
    kp = (p["primary_kx"], p["primary_ky"], p["primary_kz"])
    cp = (p["primary_cx"], p["primary_cy"], p["primary_cz"])
    for i in range(4):
        f = frames[i // 2]
        for side in (1.0, -1.0):
            pt = (xw[i], side * p["primary_half_spacing"], r0)
            # the wheelset's x and the bogie's pitch/yaw stretch the longitudinal spring;
            # beta (spin) is not a motion of the axlebox
            wbody = {c: j for c, j in wsd[i].items() if c != "beta"}
            b.spring(
                _body_point(n, f, (xb[i // 2], 0.0, hb), pt),
                _body_point(n, wbody, (xw[i], 0.0, r0), pt),
                kp,
                cp,
            )


def _secondary_suspension(
    b: _Builder,
    p: dict[str, float],
    n: int,
    car: dict[str, int],
    frames: list[dict[str, int]],
    xb: tuple[float, float],
) -> None:
    """Per bogie: the secondary springs per side, air-spring bending and the anti-roll bar,
    the bolster anchor, the lateral damper, the bump stops and the bolster's yaw friction."""
    hc, hb, hs = p["carbody_cg_height"], p["bogie_cg_height"], p["secondary_height"]

    def bolster_pt(i, pt):
        # carbody motion except its yaw about the bolster centre, plus the bolster's yaw
        g = _body_point(n, {k: v for k, v in car.items() if k != "yaw"}, (0.0, 0.0, hc), pt)
        g[1, car["yaw"]] += xb[i]
        g += _body_point(n, {"yaw": 5 + i}, (xb[i], 0.0, hs), pt)
        return g

    # per side; lateral damper per bogie; bump stops; yaw friction
    ks = (p["secondary_kx"], p["secondary_ky"], p["secondary_kz"])
    cs = (0.0, 0.0, p["secondary_cz"])
    for i in range(2):
        f = frames[i]
        for side in (1.0, -1.0):
            pt = (xb[i], side * p["secondary_half_spacing"], hs)
            b.spring(bolster_pt(i, pt), _body_point(n, f, (xb[i], 0.0, hb), pt), ks, cs)
        # air-spring bending (per side, roll and pitch) and the anti-roll bar (roll): the
        # bolster rolls and pitches with the carbody, so against the frame: carbody - frame
        gr = np.zeros((2, n))
        gr[0, car["roll"]], gr[0, f["roll"]] = 1.0, -1.0
        gr[1, car["pitch"]], gr[1, f["pitch"]] = 1.0, -1.0
        kb = 2.0 * p["secondary_bending_stiffness"]
        b.spring(gr, np.zeros_like(gr), (kb + p["anti_roll_stiffness"], kb), (0.0, 0.0))
        gy = np.zeros((1, n))  # bolster anchor: yaw of the bolster relative to the frame
        gy[0, 5 + i] = 1.0
        gy[0, f["yaw"]] = -1.0
        b.spring(gy, np.zeros_like(gy), (p["bolster_yaw_stiffness"],), (0.0,))
        pt = (xb[i], 0.0, hs)
        grel = bolster_pt(i, pt) - _body_point(n, f, (xb[i], 0.0, hb), pt)
        b.spring(grel, np.zeros_like(grel), (0.0, 0.0, 0.0), (0.0, p["secondary_cy"], 0.0))
        if p["bumpstop_stiffness"] > 0:
            b.elements.append(
                (EL_BUMP, grel[1].copy(), (p["bumpstop_clearance"], p["bumpstop_stiffness"], 0.0, 0.0))
            )
        if p["yaw_friction_torque"] > 0:
            g = np.zeros(n)
            g[5 + i] = 1.0
            g[car["yaw"]] = -1.0
            b.elements.append(
                (EL_FRICTION, g, (p["yaw_friction_torque"], p["yaw_friction_velocity"], 0.0, 0.0))
            )


def build_single_wheelset(
    table: WheelTable,
    *,
    mass: float,
    roll_inertia: float,
    yaw_inertia: float,
    ky: float,
    kx: float,
    half_spacing: float,
    axle_load: float,
    kz: float = 0.0,
    gravity: float = 9.81,
    friction: float = 0.3,
    longitudinal: bool = False,
    spin_inertia: float | None = None,
) -> System:
    """One wheelset on rigid rails held by lateral and longitudinal springs to the ground.

    The longitudinal springs (kx each, at +-half_spacing) give the yaw stiffness
    2 kx half_spacing^2; ``axle_load`` (N, downwards, besides the wheelset's weight) loads the
    wheels. Used by the Wickens and Klingel validations. DOFs: y, z, roll, yaw (Wickens'
    classical model: no longitudinal motion, rolling exactly at v0/r0); ``longitudinal`` adds
    x (on the springs, 2 kx), ``spin_inertia`` (kg m^2) the spin perturbation beta.
    """
    names = ["ws1_y", "ws1_z", "ws1_roll", "ws1_yaw"]
    diag = [mass, mass, roll_inertia, yaw_inertia]
    if longitudinal:
        names.append("ws1_x")
        diag.append(mass)
    if spin_inertia is not None:
        names.append("ws1_beta")
        diag.append(_checks.positive("spin_inertia", spin_inertia))
    n = len(names)
    b = _Builder(n)
    b.m = np.diag(diag)
    b.k[0, 0] = 2.0 * ky
    b.k[3, 3] = 2.0 * kx * half_spacing**2
    b.k[1, 1] = kz
    if longitudinal:
        b.k[4, 4] = 2.0 * kx
    f0 = np.zeros(n)
    f0[1] = -mass * gravity - axle_load
    iws = np.array([[names.index(f"ws1_{c}") + 1 if f"ws1_{c}" in names else 0 for c in IWS_ROWS]]).T
    itr = np.zeros((3, 1), dtype=int)
    return _finish(
        b, f0, iws, itr, table, tuple(names), np.array([0.0]), 0.5 * (mass * gravity + axle_load), friction
    )


def _finish(b: _Builder, f0, iws, itr, table, names, xw, wheel_load, friction) -> System:
    if b.elements:
        etype = np.array([e[0] for e in b.elements], dtype=np.int32)
        eg = np.array([e[1] for e in b.elements]).T
        epar = np.array([e[2] for e in b.elements], dtype=float).T
    else:  # a dummy element keeps the arrays non-empty for f2py
        etype = np.zeros(1, dtype=np.int32)
        eg = np.zeros((b.n, 1))
        epar = np.zeros((4, 1))
    return System(
        m=np.asfortranarray(b.m),
        c=np.asfortranarray(b.c),
        k=np.asfortranarray(b.k),
        f0=f0,
        etype=etype,
        eg=np.asfortranarray(eg),
        epar=np.asfortranarray(epar),
        iws=np.asfortranarray(iws.astype(np.int32)),
        itr=np.asfortranarray(itr.astype(np.int32)),
        table=table,
        dof_names=names,
        x_wheelsets=np.asarray(xw, dtype=float),
        wheel_load=float(wheel_load),
        friction=float(friction),
    )


def build_rigid_system(
    m: np.ndarray,
    c: np.ndarray,
    k: np.ndarray,
    f0: np.ndarray | None = None,
    names: tuple | None = None,
    modal: ModalBlocks | None = None,
) -> System:
    """A System of rigid DOFs whose wheel never touches a rail: M a = f0 - K q - C v (plus
    the modal blocks' point elements if given); for tests and benchmarks of the integrator.

    The core needs one wheelset: it sits on DOF 0 (its y, z and roll) with a contact table
    whose gap is 1 m everywhere over |y| <= 1 m, so no contact force arises while
    |q_0| < 1 m (the integrator's default qmax).

    Parameters
    ----------
    m, c, k : ndarray (n, n)
        Mass (kg), damping (N s/m) and stiffness (N/m) of the rigid DOFs.
    f0 : ndarray (n,), optional
        Constant force, N (default zero).
    names : tuple of str, optional
        DOF names (default 'dof1', ...).
    modal : ModalBlocks, optional
    """
    m = _checks.finite_array("m", m, ndim=2)
    n = m.shape[0]
    c = _checks.finite_array("c", c, shape=(n, n))
    k = _checks.finite_array("k", k, shape=(n, n))
    f0 = np.zeros(n) if f0 is None else _checks.finite_array("f0", f0, shape=(n,))
    names = tuple(f"dof{i + 1}" for i in range(n)) if names is None else tuple(names)
    if len(names) != n:
        raise InputError(f"{len(names)} names for {n} DOFs")
    data = np.zeros((len(QUANTITIES), 2, 2))
    data[QUANTITIES.index("g")] = 1.0
    data[QUANTITIES.index("r")] = 0.46
    table = WheelTable(
        y=np.array([-1.0, 1.0]), data=data, r0=0.46, s_wheel=np.zeros((2, 2)), material=STEEL, n_clipped=0
    )
    iws = np.zeros((6, 1), dtype=np.int32)
    iws[:3] = 1
    sy = System(
        m=m,
        c=c,
        k=k,
        f0=f0,
        etype=np.zeros(1, dtype=np.int32),
        eg=np.zeros((n, 1)),
        epar=np.zeros((4, 1)),
        iws=iws,
        itr=np.zeros((3, 1), dtype=np.int32),
        table=table,
        dof_names=names,
        x_wheelsets=np.zeros(1),
        wheel_load=1.0,
        friction=0.0,
    )
    return sy.with_modal(modal)
