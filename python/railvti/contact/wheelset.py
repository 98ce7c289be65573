"""The loaded wheelset: normal and steady-rolling contact in every patch of both wheels, each
wheel's vertical load balanced by the normal AND tangential contact forces, with the wheel's
angular velocity prescribed or found from free rolling.

Geometry. With the roll load-controlled (``roll=None``), :func:`railvti.geometry.contact_points`
gives the rigid pose (roll and height from the constraint that both wheels touch) and the
candidate points of each wheel. From that pose the wheelset sinks by w and rolls by theta
(about the track x axis through its centre c); a wheel point p moves by
u = (0, 0, -w) + theta e_x x (p - c), and the approach of patch k along its rail normal n_k is

    delta_k = a_k w + b_k theta,   a_k = n_k,z,   b_k = r_z n_k,y - r_y n_k,z,   r = p_k - c.

With the roll prescribed (CONTACT's ROLL), :func:`railvti.contact.wheelset_pose.contact_points_at_roll`
places each wheel as a half wheelset at that roll (CONTACT's module 1) and each wheel sinks by
its own w_s: delta_k = a_k w_s. Around each candidate point :func:`railvti.geometry.gap_field`
gives the gap on a grid in its tangent plane; the gap fields stay those of the rigid pose.

Balance. Each wheel's vertical load is the track-z component of its patches' forces on the
wheel, Fz = sum_k (Fn n_z + Fy t_y,z)_k (t_x is horizontal). With n = (0, -s sin d, cos d) and
t_y = n x e_x = (0, cos d, s sin d) (s = +1 on the left, -1 on the right wheel, d the contact
angle) that is sum_k (Fn cos d + s Fy sin d)_k: on the flange (d > 1 rad) the lateral creep
force carries a large part of the load. Newton's method on the unknown motion makes
sum_k Fn_k c_k equal to a target per wheel, c_k the vertical force per unit Fn of patch k
(n_z at first, then held at the value of its first rolling solve); the Jacobian uses each
patch's stiffness dFn/ddelta (Hertz's 1.5 Fn / (delta - min h) at first, then the secant of
its last two solves). Then the steady-rolling problem of every loaded patch is solved on its
pressure and the targets are corrected (a secant per wheel) until the actual vertical
forces, tangential ones included, equal the loads within ``load_tol``. The first rolling
solve is loose (it only gives c_k); the last ones are converged.

Kinematics (:mod:`railvti.contact.wheelset_kinematics`). The creepages at each patch's
reference point (the candidate point on the rail surface, of the rigid pose) follow from
the wheelset's forward speed, lateral and vertical velocity, roll and yaw rates and its
angular velocity omega about the axle (CONTACT's VS..VPITCH), over the rolling speed
V_ref = (V + omega r) / 2. omega is prescribed, or (``omega=None``) found so that the
contact forces and moments exert no torque about the axle: free rolling of a wheelset
without drive or brake torque. (Each wheel's Fx = 0 is impossible with one omega for two
rolling radii; the wheelset's net Fx = 0 is a force balance, which the axleboxes take: the
torque about the axle is what omega must balance.) Patches are independent half-spaces.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..geometry import ContactPoint, Creepages, WheelsetContact, WheelsetPose, contact_points
from ..material import Material
from ..profiles import Profile
from .grid import Grid
from .hertz import hertz
from .wheelset_kinematics import WheelsetMotion, body_axes, patch_moment
from .wheelset_patch import GROW, PatchState, curvature_fit, solve_patch_normal, solve_patch_rolling
from .wheelset_pose import contact_points_at_roll
from .wheelset_reference import contact_references, moved

log = logging.getLogger(__name__)

_SIDES = ("left", "right")
#: Relative residual of the first rolling solve: an estimate of each patch's tangential force
#: per unit Fn (forces to ~1e-4), and the start of the converged solves.
LOOSE_TOL = 1e-3
#: Relative load tolerance of the load control before the first rolling solve (its targets
#: are corrected afterwards).
_LOOSE_LOAD_TOL = 1e-2
#: Relative residual of the final rolling solves (solve_tangential's default).
ROLLING_TOL = 1e-7
#: With loose rolling solves free rolling is balanced to this many times the tolerance.
_LOOSE_TORQUE = 100.0
#: The patches' reference points (solve_wheelset's ``reference``).
REFERENCES = ("minimum", "contact")
#: CONTACT's reference points are settled when no patch's point moves by more than this
#: fraction of an element, or by more than _REFERENCE_ANGLE_TOL (rad) in contact angle.
_REFERENCE_TOL = 0.01
_REFERENCE_ANGLE_TOL = 1e-4
#: Passes of the balance (each after the reference points moved) before giving up.
_REFERENCE_PASSES = 6


@dataclass(frozen=True)
class WheelsetPatch:
    """One contact patch of a loaded wheelset.

    Forces act on the wheel. ``fn`` along the rail normal (into the wheel), ``fx``, ``fy``
    along the contact frame's ``t_x`` (rolling) and ``t_y`` (lateral, to the track's left).

    Attributes
    ----------
    side : str
        'left' or 'right'.
    contact : ContactPoint
        The candidate point (rigid pose) the patch grows from: its reference point (the grid's
        origin, where the creepages are taken and the forces and moments are reduced to).
    contact_angle : float
        rad.
    creepage : Creepages or None
        Rigid creepages xi, eta (-) and spin phi (1/m) at the reference point, over
        ``reference_speed``; None without rolling.
    reference_speed : float
        Rolling speed V_ref of the patch, m/s (nan without rolling).
    approach : float
        Approach of the patch along its normal, m.
    fn, fx, fy : float
        Forces on the wheel in the contact frame, N (fx = fy = 0 without rolling).
    mz : float
        Spin moment of the tangential tractions about the normal through the reference
        point, N m.
    centre_of_pressure : tuple of float
        (x, y) of the pressure's centre in the contact frame, m.
    force_track : ndarray (3,)
        The force in track coordinates (x forward, y left, z up), N.
    moment_track : ndarray (3,)
        Moment of the tractions about the reference point, track coordinates, N m:
        Fn (y_cp t_x - x_cp t_y) + Mz n.
    pmax : float
        Largest pressure, Pa.
    n_contact, n_adhesion, n_slip : int
        Elements in contact, in adhesion, in slip (adhesion = contact without rolling).
    grid : Grid
        The patch's grid (x along t_x, y along t_y, origin at the reference point).
    gap, pressure : ndarray (nx, ny)
        Undeformed gap (m) and pressure (Pa).
    tx, ty : ndarray (nx, ny) or None
        Tangential tractions on the wheel, Pa; None without rolling.
    rolling : RollingResult or None
        The full steady-rolling result (slip, slip velocity, power density, power, ...).
    """

    side: str
    contact: ContactPoint
    contact_angle: float
    creepage: Creepages | None
    reference_speed: float
    approach: float
    fn: float
    fx: float
    fy: float
    mz: float
    centre_of_pressure: tuple[float, float]
    force_track: np.ndarray
    moment_track: np.ndarray
    pmax: float
    n_contact: int
    n_adhesion: int
    n_slip: int
    grid: Grid
    gap: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray | None = None
    ty: np.ndarray | None = None
    rolling: object | None = None

    @property
    def n_regions(self) -> int:
        """Separate contact areas in the patch (edge-connected elements in contact): a patch
        grows around one candidate point but may hold two areas joined by a low ridge."""
        return count_regions(self.pressure > 0.0)


@dataclass(frozen=True)
class WheelsetSolution:
    """Contact of a loaded wheelset at one position.

    Attributes
    ----------
    geometry : WheelsetContact
        The rigid-pose contact search (pose, candidate points, status per wheel).
    left, right : list of WheelsetPatch
        Loaded patches of each wheel (unloaded candidates, and a wheel not solved, are empty).
    fz : tuple of float
        Vertical (track z) force on the left and right wheel from all their patches, normal
        and tangential forces, N (nan for a wheel not solved).
    sink, roll : float
        Load-controlled roll: vertical motion w (m, down) and extra roll theta (rad) of the
        wheelset from the rigid pose. Prescribed roll: the mean sink of the half wheelsets
        solved, and 0.
    sinks : tuple of float
        Downward motion of each wheel's profile reference circle centre (on the axle at the
        tread datum), m: w -+ theta * contact_y, or each half wheelset's own sink.
    pose_roll : float
        Roll angle of the pose the geometry was taken at, rad (prescribed, or from the two
        wheels' contact constraint).
    roll_prescribed : bool
        The roll was prescribed (each wheel a half wheelset).
    omega : float or None
        Angular velocity about the axle, rad/s (prescribed or free-rolling); None without rolling.
    free_rolling : bool
        omega was found from the torque balance about the axle.
    axle_torque : float
        Torque of the contact forces and moments about the axle, N m (the wheels solved);
        ~0 with free rolling; nan without rolling.
    iterations : int
        Load-control Newton iterations (all outer iterations together).
    outer_iterations : int
        Rolling solves per patch (balance with tangential forces and free rolling); 0
        without rolling.
    """

    geometry: WheelsetContact
    left: list[WheelsetPatch]
    right: list[WheelsetPatch]
    fz: tuple[float, float]
    sink: float
    roll: float
    sinks: tuple[float, float]
    pose_roll: float
    roll_prescribed: bool
    omega: float | None
    free_rolling: bool
    axle_torque: float
    iterations: int
    outer_iterations: int

    @property
    def patches(self) -> list[WheelsetPatch]:
        """All patches, left wheel first."""
        return self.left + self.right

    def wheel(self, side: str) -> list[WheelsetPatch]:
        """Patches of 'left' or 'right'."""
        if side not in _SIDES:
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.left if side == "left" else self.right


def count_regions(mask: np.ndarray) -> int:
    """Number of edge-connected regions of True in a 2-D mask (4-neighbourhood): the runs of
    True along axis 0 in each column, joined (union-find) with the runs they overlap in the
    next column."""
    parent: list[int] = []

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    prev: list[tuple[int, int, int]] = []
    m = np.asarray(mask, dtype=np.int8)
    pad = np.zeros((1, m.shape[1]), dtype=np.int8)
    edges = np.diff(np.concatenate([pad, m, pad]), axis=0)
    for j in range(m.shape[1]):
        starts, ends = np.flatnonzero(edges[:, j] == 1), np.flatnonzero(edges[:, j] == -1)
        cur = []
        for a, b in zip(starts.tolist(), ends.tolist()):
            k = len(parent)
            parent.append(k)
            for pa, pb, pk in prev:
                if pa < b and a < pb:  # the runs [a, b) and [pa, pb) touch
                    parent[root(pk)] = root(k)
            cur.append((a, b, k))
        prev = cur
    return sum(1 for k in range(len(parent)) if root(k) == k)


class _Balance:
    """The wheels solved, their candidate patches and the unknown motion u of the wheelset:
    (w, theta) with the roll load-controlled, one sink per wheel solved with it prescribed."""

    def __init__(self, geo: WheelsetContact, sides: tuple[str, ...], prescribed: bool) -> None:
        self.geo = geo
        self.sides = sides
        self.prescribed = prescribed
        n = len(sides) if prescribed else 2
        self.u = np.zeros(n)
        self.down = np.ones(n) if prescribed else np.array([1.0, 0.0])
        self.patches: list[list[PatchState]] = []
        for i, s in enumerate(sides):
            row = [PatchState(cp, i, self.gradient(cp, i)) for cp in geo.wheel(s)]
            if not row:
                raise InputError(
                    f"the {s} wheel has no contact candidate at y = {geo.pose.y * 1e3:.2f} mm "
                    f"({geo.status[_SIDES.index(s)]})"
                )
            self.patches.append(row)

    def gradient(self, cp: ContactPoint, i: int) -> np.ndarray:
        """d(approach)/du of a patch of wheel i with reference point cp."""
        n_ = cp.normal
        if self.prescribed:
            grad = np.zeros(self.u.size)
            grad[i] = n_[2]
            return grad
        r = cp.position - self.geo.pose.centre
        return np.array([n_[2], r[2] * n_[1] - r[1] * n_[2]])

    def loaded_pose(self, i: int) -> WheelsetPose:
        """The loaded pose of the (half) wheelset of wheel i: its rigid pose lowered by the
        sink (and rolled by the extra roll)."""
        pose = self.patches[i][0].seed.pose
        if self.prescribed:
            return WheelsetPose(pose.y, pose.z - float(self.u[i]), pose.roll, pose.yaw, pose.layout)
        return WheelsetPose(
            pose.y, pose.z - float(self.u[0]), pose.roll + float(self.u[1]), pose.yaw, pose.layout
        )

    @property
    def all(self) -> list[PatchState]:
        return [p for row in self.patches for p in row]

    def centre(self, i: int) -> np.ndarray:
        """Loaded centre of the (half) wheelset of wheel i."""
        pose = self.patches[i][0].cp.pose
        w = self.u[i] if self.prescribed else self.u[0]
        return pose.centre - np.array([0.0, 0.0, w])

    def axle(self) -> np.ndarray:
        """Axle direction of the loaded wheelset (the extra roll theta included)."""
        a = body_axes(self.geo.pose)[1]
        if self.prescribed:
            return a
        t = self.u[1]
        return np.array([a[0], a[1] * np.cos(t) - a[2] * np.sin(t), a[1] * np.sin(t) + a[2] * np.cos(t)])

    def sinks(self) -> tuple[float, float]:
        out = [np.nan, np.nan]
        for i, s in enumerate(self.sides):
            k = _SIDES.index(s)
            if self.prescribed:
                out[k] = float(self.u[i])
            else:
                cy = self.geo.pose.layout.wheelset.contact_y
                out[k] = float(self.u[0] - self.u[1] * (cy if s == "left" else -cy))
        return out[0], out[1]


def _start(
    bal: _Balance, wheel: Profile, rail: Profile, loads: np.ndarray, material: Material, dx: float, dy: float
) -> None:
    """Hertz estimate of each patch's approach (grid size) and the start of u: the carrying
    points get their Hertz approaches."""
    s_fit = 5.0 * max(dx, dy)
    rows, rhs = [], []
    for i, row in enumerate(bal.patches):
        for pt in row:
            A, B = curvature_fit(wheel, rail, pt.seed, s_fit)
            pt.A = max(A, 1e-3)
            ref = hertz(pt.A, max(B, 0.05 * pt.A, 1e-3), loads[i] / max(pt.vertical, 0.2), material)
            pt.reach = GROW * ref.approach
        carry = row[0]
        rows.append(carry.grad)
        rhs.append(carry.reach / GROW + carry.cp.separation)
    bal.u = np.linalg.solve(np.array(rows), np.array(rhs))


def _load_control(
    bal: _Balance,
    targets: np.ndarray,
    wheel: Profile,
    rail: Profile,
    material: Material,
    dx: float,
    dy: float,
    method: str,
    tol: float,
    max_iter: int,
    rolling: bool = True,
) -> int:
    """Newton on u until sum_k Fn_k c_k equals the target of each wheel (relative tol)."""
    err = np.full(len(targets), np.inf)
    for it in range(1, max_iter + 1):
        J = np.zeros((len(targets), bal.u.size))
        load = np.zeros(len(targets))
        for i, row in enumerate(bal.patches):
            for pt in row:
                solve_patch_normal(wheel, rail, pt, float(pt.grad @ bal.u), material, dx, dy, method, rolling)
                load[i] += pt.fn * pt.vertical
                J[i] += pt.stiffness * pt.vertical * pt.grad
        err = load - targets
        if np.all(np.abs(err) <= tol * np.abs(targets)):
            return it
        if np.any(np.abs(np.diag(J)) <= 0.0) or abs(np.linalg.det(J)) < 1e-30:
            # a wheel lost contact: push the wheels down by the Hertz scale
            bal.u = bal.u + bal.down * 0.5 * max(pt.reach for pt in bal.all) / GROW
            continue
        bal.u = bal.u + np.linalg.solve(J, -err)
    raise ConvergenceError(
        f"wheelset load control did not converge: vertical loads {load} N against targets "
        f"{targets} N after {max_iter} iterations",
        iterations=max_iter,
        residual=float(np.max(np.abs(err) / np.abs(targets))),
    )


def _axle_torque(bal: _Balance) -> float:
    """Torque of all loaded patches' forces and moments about the (loaded) axle, N m."""
    a = bal.axle()
    total = 0.0
    for i, row in enumerate(bal.patches):
        c = bal.centre(i)
        for pt in row:
            if not pt.carrying:
                continue
            x_cp, y_cp = pt.centre_of_pressure()
            mz = pt.rolling.mz if pt.rolling is not None else 0.0
            total += float(a @ patch_moment(pt.cp, c, pt.force(), pt.fn, x_cp, y_cp, mz))
    return total


class _Secant:
    """Secant iteration for a scalar root (a fixed slope until two points are known; regula
    falsi, Illinois-modified, once the root is bracketed)."""

    def __init__(self, x: float, slope: float) -> None:
        self.x, self.slope = x, slope
        self.reset()

    def reset(self) -> None:
        """Forget the points (the function changed); keep x and the last slope."""
        self.prev: tuple[float, float] | None = None
        self.lo: tuple[float, float] | None = None
        self.hi: tuple[float, float] | None = None
        self.side = 0

    def step(self, f: float) -> float:
        """Record f(x) at the current x and return the next x."""
        x = self.x
        if self.prev is not None and x != self.prev[0] and f != self.prev[1]:
            self.slope = (f - self.prev[1]) / (x - self.prev[0])
        self.prev = (x, f)
        if f < 0:
            if self.side == -1 and self.hi is not None:
                self.hi = (self.hi[0], 0.5 * self.hi[1])  # Illinois: the stale end's value halved
            self.lo, self.side = (x, f), -1
        else:
            if self.side == 1 and self.lo is not None:
                self.lo = (self.lo[0], 0.5 * self.lo[1])
            self.hi, self.side = (x, f), 1
        new = x - f / self.slope if self.slope != 0.0 else x
        if self.lo is not None and self.hi is not None and self.lo[0] != self.hi[0]:
            (x0, f0), (x1, f1) = self.lo, self.hi
            if not min(x0, x1) < new < max(x0, x1):
                new = x0 - f0 * (x1 - x0) / (f1 - f0)
        self.x = new
        return new


def _check_args(y, yaw, fz, mu, speed, material, dx, dy, roll, side, motion_kw) -> dict:
    out = {"y": _checks.finite("y", y), "yaw": _checks.finite("yaw", yaw)}
    if side is not None and side not in _SIDES:
        raise InputError(f"side must be None, 'left' or 'right', got {side!r}")
    out["roll"] = None if roll is None else _checks.finite("roll", roll)
    if side is not None and roll is None:
        raise InputError(f"side={side!r} solves one wheel as a half wheelset: prescribe its roll")
    sides = _SIDES if side is None else (side,)
    if np.ndim(fz) == 0:
        loads = (fz,) * len(sides)
    else:
        pair = tuple(fz)
        if len(pair) != 2:
            raise InputError("fz must be one load or a (left, right) pair")
        loads = tuple(pair[_SIDES.index(s)] for s in sides)
    out["loads"] = np.array([_checks.positive("fz", f) for f in loads])
    out["sides"] = sides
    if not isinstance(material, Material):
        raise InputError("material must be a railvti.Material")
    out["dx"] = _checks.positive("dx", dx)
    out["dy"] = out["dx"] if dy is None else _checks.positive("dy", dy)
    given = {k: v for k, v in motion_kw.items() if v is not None and v != 0.0}
    if mu is None and speed is None:
        if given:
            raise InputError(f"{sorted(given)} need rolling contact: give mu and speed")
        out["mu"], out["motion"] = None, None
        return out
    if mu is None or speed is None:
        raise InputError("give both mu and speed for rolling contact, or neither")
    out["mu"] = _checks.non_negative("mu", mu)
    out["motion"] = WheelsetMotion(
        speed=speed, **{k: (0.0 if v is None and k != "omega" else v) for k, v in motion_kw.items()}
    )
    if side is not None and out["motion"].omega is None:
        raise InputError(f"side={side!r}: free rolling needs both wheels; prescribe omega")
    return out


def solve_wheelset(
    wheel: Profile,
    rail: Profile,
    y: float,
    yaw: float,
    fz: float | tuple[float, float],
    mu: float | None,
    speed: float | None,
    material: Material,
    dx: float,
    *,
    dy: float | None = None,
    omega: float | None = None,
    roll: float | None = None,
    lateral_velocity: float = 0.0,
    vertical_velocity: float = 0.0,
    roll_rate: float = 0.0,
    yaw_rate: float = 0.0,
    side: str | None = None,
    method: str = "cg",
    rolling_method: str | None = None,
    track=None,
    wheelset=None,
    max_separation: float = 5e-3,
    load_tol: float = 1e-5,
    max_iter: int = 30,
    reference: str = "minimum",
    d_sep: float = 8e-3,
    d_comb: float = 4e-3,
) -> WheelsetSolution:
    """Normal and steady-rolling contact of a loaded rigid wheelset on rigid rails.

    Parameters
    ----------
    wheel, rail : Profile
        Wheel and (canted) rail profiles, as for :func:`railvti.geometry.contact_points`.
    y : float
        Lateral shift of the wheelset, m (to the left).
    yaw : float
        Yaw angle, rad.
    fz : float or (float, float)
        Vertical load per wheel (left, right), N (> 0): the track-z component of the
        contact forces on the wheel, normal and tangential. With ``side``, one load (or
        the pair, of which that wheel's is used).
    mu : float or None
        Coulomb friction coefficient; None: normal contact only.
    speed : float or None
        Forward speed of the wheelset, m/s (> 0; CONTACT's VS); None: normal contact only.
    material : Material
        Wheel and rail material.
    dx : float
        Element size along the rolling direction, m.
    dy : float, optional
        Lateral element size, m (default dx).
    omega : float, optional
        Angular velocity about the axle, rad/s (> 0 rolling forward; CONTACT's -VPITCH).
        None: free rolling, omega such that the contact forces and moments exert no torque
        about the axle (both wheels together).
    roll : float, optional
        Prescribed roll angle, rad (positive raises the left wheel; CONTACT's ROLL): each
        wheel is a half wheelset lowered until it carries its load. None: the roll is
        load-controlled (both wheels touch in the rigid pose; the extra roll theta makes
        each wheel carry its load).
    lateral_velocity, vertical_velocity, roll_rate, yaw_rate : float
        Further rigid-body velocities of the wheelset, m/s and rad/s, track frame (y left,
        z up; CONTACT's VY, VZ, VROLL, VYAW with y and z flipped); rolling only.
    side : {'left', 'right'}, optional
        Solve this wheel only (CONTACT's half wheelset): needs ``roll`` and, rolling,
        ``omega``.
    method : str
        Normal solver ('cg', 'pk', 'gs').
    rolling_method : str, optional
        Tangential solver of :func:`railvti.contact.solve_tangential` (its default if None).
    track, wheelset : optional
        Layout (see :func:`railvti.geometry.contact_points`).
    max_separation : float
        Candidate points up to this rigid separation are patches that may close, m.
    load_tol : float
        Relative tolerance on each wheel's vertical load and, with free rolling, on the
        axle torque (relative to mu sum Fn r).
    max_iter : int
        Newton iterations of each load control, and outer (rolling) iterations.
    reference : {'minimum', 'contact'}
        Each loaded patch's reference point (grid origin and contact frame, where the
        creepages are taken): 'minimum', the candidate point of smallest gap of the rigid pose
        (creepages of the rigid pose); 'contact', CONTACT's contact reference point, the
        weighted centre of the interpenetration at the loaded pose with the weighted contact
        angle (:mod:`railvti.contact.wheelset_reference`; creepages of the loaded wheelset,
        as CONTACT evaluates them). The loaded pose depends on the forces, so the points are
        found by a fixed-point iteration (a patch moved by more than 1 % of an element or
        1e-4 rad is rebuilt and the balance repeated).
    d_sep, d_comb : float
        ``reference='contact'`` only: CONTACT's D_SEP and D_COMB, m (0 < d_comb < d_sep).
        A patch whose interpenetration at the loaded pose holds areas further apart than
        d_comb has their elastic interaction in the normal problem reduced by CONTACT's factor
        ((d_sep - d) / (d_sep - d_comb))^0.8 (:class:`railvti.contact.SubPatches`;
        docs/contact_decks.md). railvti's own rule decides what is one patch.

    Returns
    -------
    WheelsetSolution

    Raises
    ------
    InputError
        Bad arguments (named: omega <= 0, a NaN roll, ...), or a wheel without any contact
        candidate.
    ConvergenceError
        The load control, the vertical balance with tangential forces, the free-rolling
        torque balance or (``reference='contact'``) the reference points did not converge.
    GridTooSmallError
        A patch keeps outgrowing its grid.
    """
    a = _check_args(
        y,
        yaw,
        fz,
        mu,
        speed,
        material,
        dx,
        dy,
        roll,
        side,
        dict(
            omega=omega,
            lateral_velocity=lateral_velocity,
            vertical_velocity=vertical_velocity,
            roll_rate=roll_rate,
            yaw_rate=yaw_rate,
        ),
    )
    load_tol = _checks.positive("load_tol", load_tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    if reference not in REFERENCES:
        raise InputError(f"reference must be one of {REFERENCES}, got {reference!r}")
    d_sep, d_comb = _checks.positive("d_sep", d_sep), _checks.positive("d_comb", d_comb)
    if d_comb >= d_sep:
        raise InputError(f"d_comb must be smaller than d_sep, got d_comb = {d_comb} m, d_sep = {d_sep} m")
    dx, dy, loads, motion = a["dx"], a["dy"], a["loads"], a["motion"]
    if a["roll"] is None:
        geo = contact_points(
            wheel, rail, a["y"], a["yaw"], track=track, wheelset=wheelset, max_separation=max_separation
        )
    else:
        geo = contact_points_at_roll(
            wheel,
            rail,
            a["y"],
            a["roll"],
            a["yaw"],
            track=track,
            wheelset=wheelset,
            max_separation=max_separation,
            sides=a["sides"],
        )
    bal = _Balance(geo, a["sides"], a["roll"] is not None)
    _start(bal, wheel, rail, loads, material, dx, dy)
    # with rolling, the first load control only needs to be close: its targets are corrected
    first_tol = max(_LOOSE_LOAD_TOL, load_tol) if motion is not None else load_tol
    iters = _load_control(
        bal,
        loads.copy(),
        wheel,
        rail,
        material,
        dx,
        dy,
        method,
        first_tol,
        max_iter,
        rolling=motion is not None,
    )
    at_contact = reference == "contact"
    tol_ref = (_REFERENCE_TOL * min(dx, dy), _REFERENCE_ANGLE_TOL, d_sep, d_comb)
    if at_contact and _relocate(bal, *tol_ref):
        iters += _load_control(
            bal,
            loads.copy(),
            wheel,
            rail,
            material,
            dx,
            dy,
            method,
            first_tol,
            max_iter,
            rolling=motion is not None,
        )
    outer, om, torque = 0, None, float("nan")
    ctx = dict(
        wheel=wheel,
        rail=rail,
        material=material,
        mu=a["mu"],
        motion=motion,
        dx=dx,
        dy=dy,
        method=method,
        rolling_method=rolling_method,
        load_tol=load_tol,
    )
    for _ in range(_REFERENCE_PASSES):
        if motion is not None:
            roll, om, torque = _rolling_balance(bal, loads, ctx, max_iter)
            iters += roll.load_iterations
            outer += roll.solves
        if not at_contact or not _relocate(bal, *tol_ref):
            break
        if motion is None:
            iters += _load_control(
                bal, loads.copy(), wheel, rail, material, dx, dy, method, load_tol, max_iter
            )
    else:
        raise ConvergenceError(
            f"the patches' contact reference points did not settle in {_REFERENCE_PASSES} "
            f"passes at y = {a['y'] * 1e3:.3f} mm",
            iterations=_REFERENCE_PASSES,
        )
    log.debug(
        "solve_wheelset y=%.4g: %d load-control iterations, %d rolling solves, omega %s",
        a["y"],
        iters,
        outer,
        om,
    )
    return _solution(bal, geo, loads, om, motion, torque, iters, outer)


def _relocate(bal: _Balance, tol_position: float, tol_angle: float, d_sep: float, d_comb: float) -> bool:
    """Move every carrying patch to CONTACT's reference point at the current loaded pose; a
    patch whose point moved more than the tolerances (m, rad) is rebuilt (new grid and gap
    field, solved afresh, with its sub-patches). Returns whether any patch was rebuilt."""
    changed = False
    for i, row in enumerate(bal.patches):
        carrying = [k for k, pt in enumerate(row) if pt.carrying]
        if not carrying:
            continue
        loaded = bal.loaded_pose(i)
        refs = contact_references([row[k].seed for k in carrying], loaded, d_sep, d_comb)
        for k, ref in zip(carrying, refs):
            pt = row[k]
            if ref is None:
                continue
            pt.loaded = loaded
            if pt.cp is not pt.seed and not moved(ref.point, pt.cp, tol_position, tol_angle):
                continue
            new = PatchState(ref.point, i, bal.gradient(ref.point, i), seed=pt.seed, loaded=loaded)
            new.A, new.reach, new.subpatches = pt.A, pt.reach, ref.subpatches
            row[k] = new
            changed = True
    return changed


class _Rolling:
    """The rolling part of the balance: rolling solves of every loaded patch at a given
    omega, the wheels' vertical balance with the tangential forces (a secant per wheel on its
    load-control target, each patch's vertical force per unit Fn held at its first rolling
    solve's value) and the torque about the axle."""

    def __init__(self, bal: _Balance, loads: np.ndarray, ctx: dict, max_iter: int) -> None:
        self.bal, self.loads, self.ctx, self.max_iter = bal, loads, ctx, max_iter
        self.targets = loads.copy()
        self.secants: list[_Secant] | None = None
        self.solves = 0  # rolling solves of every patch
        self.load_iterations = 0

    def solve(self, omega: float, tol: float) -> None:
        c = self.ctx
        for pt in self.bal.all:
            if pt.loaded is not None:
                pt.loaded = self.bal.loaded_pose(pt.side_index)  # CONTACT: the loaded wheelset's motion
            solve_patch_rolling(pt, c["material"], c["mu"], c["motion"], omega, c["rolling_method"], tol=tol)
        self.solves += 1

    def residual(self) -> np.ndarray:
        return np.array([sum(pt.force()[2] for pt in row) for row in self.bal.patches]) - self.loads

    def balance(self, omega: float, tol: float, first_tol: float | None = None) -> None:
        """Rolling solves (to ``tol``; the first one to ``first_tol`` if given) and load
        control until each wheel's vertical force, tangential forces included, equals its load
        within the load tolerance."""
        c = self.ctx
        for s_ in self.secants or []:
            s_.reset()  # omega or the tolerance changed: a new function of the targets
        for k in range(self.max_iter):
            self.solve(omega, first_tol if k == 0 and first_tol is not None else tol)
            if k == 0 and first_tol is not None:
                resid = self.residual()
                if self.secants is None:
                    for pt in self.bal.all:
                        if pt.carrying:
                            pt.vertical = float(pt.force()[2] / pt.fn)
                    self.secants = [_Secant(t, 1.0) for t in self.targets]
                self.load_iterations += _load_control(
                    self.bal,
                    self.targets,
                    c["wheel"],
                    c["rail"],
                    c["material"],
                    c["dx"],
                    c["dy"],
                    c["method"],
                    0.25 * c["load_tol"],
                    self.max_iter,
                )
                continue
            resid = self.residual()
            if np.all(np.abs(resid) <= c["load_tol"] * self.loads):
                return
            if self.secants is None:
                for pt in self.bal.all:
                    if pt.carrying:
                        pt.vertical = float(pt.force()[2] / pt.fn)
                self.secants = [_Secant(t, 1.0) for t in self.targets]
            else:
                self.targets = np.array([s_.step(f) for s_, f in zip(self.secants, resid)])
            self.load_iterations += _load_control(
                self.bal,
                self.targets,
                c["wheel"],
                c["rail"],
                c["material"],
                c["dx"],
                c["dy"],
                c["method"],
                0.25 * c["load_tol"],
                self.max_iter,
            )
        raise ConvergenceError(
            f"the wheels' vertical balance with tangential forces did not converge in "
            f"{self.max_iter} rolling solves: residual {resid} N",
            iterations=self.max_iter,
            residual=float(np.max(np.abs(resid) / self.loads)),
        )

    def torque_ok(self, torque: float, factor: float = 1.0) -> bool:
        """|torque| <= factor * load_tol * mu sum_k Fn_k r_k (the largest friction torque)."""
        scale = self.ctx["mu"] * sum(pt.fn * pt.cp.rolling_radius for pt in self.bal.all)
        return abs(torque) <= factor * self.ctx["load_tol"] * max(scale, 1e-30)


def _free_rolling(roll: _Rolling, omega: float) -> tuple[float, float]:
    """omega of zero torque about the axle: a secant on T(omega), each T taken after the
    vertical balance at that omega; its first slope by a difference at fixed pressures.
    The rolling solves are loose (their forces resolve the torque to ~1e-4 of its scale)
    until the torque is within ``_LOOSE_TORQUE`` times the tolerance, then converged."""
    tol = LOOSE_TOL
    sec: _Secant | None = None
    for _ in range(roll.max_iter):
        roll.balance(omega, tol)
        torque = _axle_torque(roll.bal)
        if roll.torque_ok(torque, 1.0 if tol == ROLLING_TOL else _LOOSE_TORQUE):
            if tol == ROLLING_TOL:
                return omega, torque
            tol = ROLLING_TOL
            if sec is not None:
                sec.reset()
            continue
        if sec is None:
            d_om = 1e-4 * omega
            roll.solve(omega + d_om, tol)
            sec = _Secant(omega, (_axle_torque(roll.bal) - torque) / d_om)
        omega = sec.step(torque)
        if not omega > 0.0:
            raise ConvergenceError(
                "free rolling: the torque balance drove omega to <= 0", iterations=roll.solves
            )
    raise ConvergenceError(
        f"free rolling did not converge in {roll.max_iter} steps of omega: torque about the "
        f"axle {torque:.4g} N m at omega = {omega:.6g} rad/s",
        iterations=roll.max_iter,
    )


def _rolling_balance(
    bal: _Balance, loads: np.ndarray, ctx: dict, max_iter: int
) -> tuple[_Rolling, float, float]:
    """Rolling solves, vertical balance with tangential forces and (free rolling) the
    torque balance: the first rolling solve (or, free rolling, those until the torque is
    near zero) is loose (``LOOSE_TOL``), the others converged (``ROLLING_TOL``). Returns the
    state, omega and the axle torque."""
    roll = _Rolling(bal, loads, ctx, max_iter)
    motion = ctx["motion"]
    if motion.omega is None:
        fn = np.array([pt.fn for pt in bal.all])
        r = np.array([pt.cp.rolling_radius for pt in bal.all])
        if not fn.sum() > 0:  # no element in contact: no rolling radius to roll at
            raise InputError(
                "no contact patch carries a normal force on this grid: its elements "
                "(dx, dy) are larger than the contact patch; make dx and dy smaller"
            )
        omega, torque = _free_rolling(roll, motion.speed / float((fn * r).sum() / fn.sum()))
        return roll, omega, torque
    roll.balance(motion.omega, ROLLING_TOL, first_tol=LOOSE_TOL)
    return roll, motion.omega, _axle_torque(bal)


def _solution(
    bal: _Balance,
    geo: WheelsetContact,
    loads: np.ndarray,
    om: float | None,
    motion: WheelsetMotion | None,
    torque: float,
    iters: int,
    outer: int,
) -> WheelsetSolution:
    out: dict[str, list[WheelsetPatch]] = {"left": [], "right": []}
    fz = [np.nan, np.nan]
    for i, s in enumerate(bal.sides):
        fz[_SIDES.index(s)] = float(sum(pt.force()[2] for pt in bal.patches[i]))
        for pt in bal.patches[i]:
            if pt.carrying:
                out[s].append(_patch_result(pt))
    sinks = bal.sinks()
    solved = [v for v in sinks if np.isfinite(v)]
    return WheelsetSolution(
        geometry=geo,
        left=out["left"],
        right=out["right"],
        fz=(fz[0], fz[1]),
        sink=float(np.mean(solved)) if bal.prescribed else float(bal.u[0]),
        roll=0.0 if bal.prescribed else float(bal.u[1]),
        sinks=sinks,
        pose_roll=float(geo.pose.roll),
        roll_prescribed=bal.prescribed,
        omega=None if motion is None else float(om),
        free_rolling=motion is not None and motion.omega is None,
        axle_torque=float(torque),
        iterations=iters,
        outer_iterations=outer,
    )


def _patch_result(pt: PatchState) -> WheelsetPatch:
    cp = pt.cp
    x_cp, y_cp = pt.centre_of_pressure()
    r = pt.rolling
    fx, fy, mz = (r.fx, r.fy, r.mz) if r is not None else (0.0, 0.0, 0.0)
    n_adh = int(r.adhesion.sum()) if r is not None else pt.n_contact
    n_slip = int(r.slip.sum()) if r is not None else 0
    return WheelsetPatch(
        side=cp.side,
        contact=cp,
        contact_angle=cp.contact_angle,
        creepage=pt.slip.creepage if r is not None else None,
        reference_speed=pt.slip.reference_speed if r is not None else float("nan"),
        approach=pt.approach,
        fn=pt.fn,
        fx=fx,
        fy=fy,
        mz=mz,
        centre_of_pressure=(x_cp, y_cp),
        force_track=pt.force(),
        moment_track=pt.fn * (y_cp * cp.t_x - x_cp * cp.t_y) + mz * cp.normal,
        pmax=pt.pmax,
        n_contact=pt.n_contact,
        n_adhesion=n_adh,
        n_slip=n_slip,
        grid=pt.grid,
        gap=pt.gap,
        pressure=pt.p,
        tx=None if r is None else r.tx,
        ty=None if r is None else r.ty,
        rolling=r,
    )
