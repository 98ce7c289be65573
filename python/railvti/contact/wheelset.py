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

The result types (:class:`WheelsetSolution`, :class:`WheelsetPatch`) are in
:mod:`railvti.contact.wheelset_results`.
"""

from __future__ import annotations

import logging

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..geometry import ContactPoint, WheelsetContact, WheelsetPose, contact_points
from ..material import Material
from ..profiles import Profile
from .hertz import hertz
from .wheelset_kinematics import WheelsetMotion, body_axes, patch_moment
from .wheelset_patch import GROW, PatchState, curvature_fit, solve_patch_normal, solve_patch_rolling
from .wheelset_pose import contact_points_at_roll
from .wheelset_reference import contact_references, moved
from .wheelset_results import WheelsetPatch, WheelsetSolution, count_regions, patch_result

__all__ = [
    "solve_wheelset",
    "WheelsetPatch",
    "WheelsetSolution",
    "count_regions",
    "REFERENCES",
    "LOOSE_TOL",
    "ROLLING_TOL",
]

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
#: solve_wheelset's rigid-body velocities, in the order _check_args receives them.
_MOTION_ARGS = ("omega", "lateral_velocity", "vertical_velocity", "roll_rate", "yaw_rate")


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
    bal: _Balance, targets: np.ndarray, ctx: dict, tol: float, max_iter: int, rolling: bool = True
) -> int:
    """Newton on u until sum_k Fn_k c_k equals the target of each wheel (relative tol); the
    profiles, material, element sizes and normal method are those of ``ctx``."""
    wheel, rail, material, dx, dy, method = (
        ctx[k] for k in ("wheel", "rail", "material", "dx", "dy", "method")
    )
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


def _check_args(y, yaw, fz, mu, speed, material, dx, dy, roll, side, rates) -> dict:
    """The checked arguments of :func:`solve_wheelset`: y, yaw, roll, sides, loads, material, dx,
    dy, mu and motion (None without rolling); ``rates`` the values of ``_MOTION_ARGS``."""
    motion_kw = dict(zip(_MOTION_ARGS, rates))
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
    out["material"] = material
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


def _check_solver(
    load_tol: float, max_iter: int, reference: str, d_sep: float, d_comb: float
) -> tuple[float, int, float, float]:
    """The checked tolerances of :func:`solve_wheelset`: load_tol, max_iter, d_sep, d_comb."""
    load_tol = _checks.positive("load_tol", load_tol)
    max_iter = _checks.positive_int("max_iter", max_iter)
    if reference not in REFERENCES:
        raise InputError(f"reference must be one of {REFERENCES}, got {reference!r}")
    d_sep, d_comb = _checks.positive("d_sep", d_sep), _checks.positive("d_comb", d_comb)
    if d_comb >= d_sep:
        raise InputError(f"d_comb must be smaller than d_sep, got d_comb = {d_comb} m, d_sep = {d_sep} m")
    return load_tol, max_iter, d_sep, d_comb


def _rigid_contact(
    wheel: Profile, rail: Profile, a: dict, track, wheelset, max_separation: float
) -> WheelsetContact:
    """The rigid pose and candidate points: both wheels touching (load-controlled roll) or each
    wheel a half wheelset at the prescribed roll."""
    if a["roll"] is None:
        return contact_points(
            wheel, rail, a["y"], a["yaw"], track=track, wheelset=wheelset, max_separation=max_separation
        )
    return contact_points_at_roll(
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
    rates = (omega, lateral_velocity, vertical_velocity, roll_rate, yaw_rate)
    a = _check_args(y, yaw, fz, mu, speed, material, dx, dy, roll, side, rates)
    load_tol, max_iter, d_sep, d_comb = _check_solver(load_tol, max_iter, reference, d_sep, d_comb)
    geo = _rigid_contact(wheel, rail, a, track, wheelset, max_separation)
    bal = _Balance(geo, a["sides"], a["roll"] is not None)
    _start(bal, wheel, rail, a["loads"], material, a["dx"], a["dy"])
    ctx = dict(a, wheel=wheel, rail=rail, method=method, rolling_method=rolling_method, load_tol=load_tol)
    tol_ref = (_REFERENCE_TOL * min(a["dx"], a["dy"]), _REFERENCE_ANGLE_TOL, d_sep, d_comb)
    iters, outer, om, torque = _balance_passes(
        bal, ctx, max_iter, tol_ref if reference == "contact" else None
    )
    return _solution(bal, geo, a["loads"], om, a["motion"], torque, iters, outer)


def _balance_passes(
    bal: _Balance, ctx: dict, max_iter: int, tol_ref: tuple | None
) -> tuple[int, int, float | None, float]:
    """The load control, then (rolling) the balance with tangential forces and, with
    ``tol_ref`` (``reference='contact'``: the tolerances of :func:`_relocate`), the passes
    that move the patches to CONTACT's reference points until they settle. Returns the
    load-control iterations, the rolling solves, omega and the axle torque."""
    loads, motion, load_tol = ctx["loads"], ctx["motion"], ctx["load_tol"]
    # with rolling, the first load control only needs to be close: its targets are corrected
    first_tol = max(_LOOSE_LOAD_TOL, load_tol) if motion is not None else load_tol
    iters = _load_control(bal, loads.copy(), ctx, first_tol, max_iter, rolling=motion is not None)
    at_contact = tol_ref is not None
    if at_contact and _relocate(bal, *tol_ref):
        iters += _load_control(bal, loads.copy(), ctx, first_tol, max_iter, rolling=motion is not None)
    outer, om, torque = 0, None, float("nan")
    for _ in range(_REFERENCE_PASSES):
        if motion is not None:
            roll, om, torque = _rolling_balance(bal, loads, ctx, max_iter)
            iters += roll.load_iterations
            outer += roll.solves
        if not at_contact or not _relocate(bal, *tol_ref):
            break
        if motion is None:
            iters += _load_control(bal, loads.copy(), ctx, load_tol, max_iter)
    else:
        raise ConvergenceError(
            f"the patches' contact reference points did not settle in {_REFERENCE_PASSES} "
            f"passes at y = {ctx['y'] * 1e3:.3f} mm",
            iterations=_REFERENCE_PASSES,
        )
    log.debug(
        "solve_wheelset y=%.4g: %d load-control iterations, %d rolling solves, omega %s",
        ctx["y"],
        iters,
        outer,
        om,
    )
    return iters, outer, om, torque


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
                    self.bal, self.targets, c, 0.25 * c["load_tol"], self.max_iter
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
                self.bal, self.targets, c, 0.25 * c["load_tol"], self.max_iter
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
                out[s].append(patch_result(pt))
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
