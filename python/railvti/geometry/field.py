"""Undeformed distance field around a contact point, and the rigid slip (creepages, spin).

Contact frame of a :class:`~railvti.geometry.ContactPoint` ``c``: origin ``c.position``
(on the rail surface), ``t_x`` = track x (rolling direction), ``t_y = n x t_x`` (lateral,
in the tangent plane, to the left of the track), ``n`` the rail's outward normal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..profiles import Profile
from .frames import SIGN
from .placement import ProfileLayout
from .table import ContactPoint

_SIDE = {"left": 0, "right": 1}


@dataclass(frozen=True)
class GapField:
    """Undeformed gap between wheel and rail on a grid in a contact's tangent plane.

    Attributes
    ----------
    gap : ndarray (nx, ny)
        Distance along the contact normal from the rail surface to the wheel surface, m,
        at element centres ``(x[i], y[j])``; 0 at a touching contact point, the point's
        separation otherwise; >= 0 in the rigid pose. Where the grid runs off a profile
        the gap is ``outside`` (a large value: no contact there).
    x, y : ndarray (nx,), (ny,)
        Element-centre coordinates along ``t_x`` (rolling) and ``t_y`` (lateral), m.
    dx, dy : float
        Element sizes, m.
    origin : ndarray (3,)
        Track coordinates of the frame origin (the contact point on the rail), m.
    t_x, t_y, normal : ndarray (3,)
        Frame vectors in track coordinates.
    """

    gap: np.ndarray
    x: np.ndarray
    y: np.ndarray
    dx: float
    dy: float
    origin: np.ndarray
    t_x: np.ndarray
    t_y: np.ndarray
    normal: np.ndarray


@dataclass(frozen=True)
class Creepages:
    """Rigid slip at a contact point, in its contact frame.

    Attributes
    ----------
    xi, eta : float
        Longitudinal and lateral creepage (dimensionless): (wheel - rail) material velocity
        at the contact point along ``t_x`` / ``t_y``, divided by the speed.
    phi : float
        Spin creepage, 1/m: (wheel - rail) angular velocity along the normal, over the speed.
    """

    xi: float
    eta: float
    phi: float


def _rail_zeta(
    lay: ProfileLayout, side: int, origin: np.ndarray, t_y: np.ndarray, n: np.ndarray, eta: np.ndarray
) -> np.ndarray:
    """Rail surface offset along n below the tangent plane (<= 0) at lateral coords eta
    (NaN off the rail)."""
    sg = SIGN[side]
    ys = lay.ry
    ty = sg * ys + sg * lay.rail_offset  # track y of the rail table points
    tz = lay.rail_top - lay.rz
    e = (ty - origin[1]) * t_y[1] + (tz - origin[2]) * t_y[2]
    z = (ty - origin[1]) * n[1] + (tz - origin[2]) * n[2]
    # the monotone branch of e(s) through the contact point
    k0 = int(np.argmin(np.abs(e) + np.abs(z)))
    de = np.sign(np.diff(e))
    sgn = de[min(k0, de.size - 1)]
    other = np.flatnonzero(de != sgn)  # segments that break the monotone branch
    before = other[other < k0]
    after = other[other >= k0]
    lo = int(before[-1]) + 1 if before.size else 0
    hi = int(after[0]) if after.size else de.size
    eb, zb = e[lo : hi + 1], z[lo : hi + 1]
    if sgn < 0:
        eb, zb = eb[::-1], zb[::-1]
    return np.interp(eta, eb, zb, left=np.nan, right=np.nan)


def gap_field(
    wheel: Profile,
    rail: Profile,
    contact: ContactPoint,
    dx: float,
    dy: float,
    nx: int,
    ny: int,
    *,
    x0: float | None = None,
    y0: float | None = None,
    outside: float = 1e-2,
) -> GapField:
    """Undeformed wheel-rail distance on an (nx, ny) grid in a contact's tangent plane.

    The wheel is the 3-D surface of revolution of ``wheel`` at the contact's wheelset pose
    (lateral shift, height, roll and yaw); the rail is the prismatic extrusion of ``rail``.
    For each grid point (x_i, y_j) the line origin + x t_x + y t_y + s n is intersected
    with both surfaces (Newton on the wheel's radius equation); the gap is the distance
    between the two intersections.

    Parameters
    ----------
    wheel, rail : Profile
        The profiles the contact was computed with.
    contact : ContactPoint
        From :func:`railvti.geometry.contact_points`.
    dx, dy : float
        Element sizes along t_x and t_y, m.
    nx, ny : int
        Number of elements.
    x0, y0 : float, optional
        Centre coordinates of element [0, 0]; by default the grid is centred on the
        contact point: x0 = -(nx - 1) dx / 2, y0 = -(ny - 1) dy / 2.
    outside : float
        Gap assigned where the grid leaves either profile, m.

    Returns
    -------
    GapField
        ``gap`` (nx, ny), Fortran-ordered float64, with coordinates and frame.

    Raises
    ------
    InputError
        Bad sizes, or profiles that are not the contact's.
    ConvergenceError
        The wheel-surface intersection did not converge (should not happen on a valid pose).
    """
    if not isinstance(contact, ContactPoint):
        raise InputError("contact must be a railvti.geometry.ContactPoint")
    lay = contact.pose.layout
    if wheel is not lay.wheel or rail is not lay.rail:
        raise InputError("gap_field needs the same wheel and rail Profile objects as the contact search")
    dx, dy = _checks.positive("dx", dx), _checks.positive("dy", dy)
    nx, ny = _checks.positive_int("nx", nx), _checks.positive_int("ny", ny)
    if nx * ny > 4_000_000:
        raise InputError(f"grid of {nx} x {ny} elements is too large")
    outside = _checks.positive("outside", outside)
    xs = (-(nx - 1) * dx / 2 if x0 is None else _checks.finite("x0", x0)) + dx * np.arange(nx)
    ys = (-(ny - 1) * dy / 2 if y0 is None else _checks.finite("y0", y0)) + dy * np.arange(ny)
    side = _SIDE[contact.side]
    o, tx, ty, n = contact.position, contact.t_x, contact.t_y, contact.normal
    zeta_r = _rail_zeta(lay, side, o, ty, n, ys)  # (ny,)
    # wheel: Newton on F(s) = rho - r(u) along each grid line, vectorised
    pose = contact.pose
    a = pose.axle
    c = pose.centre
    sg = SIGN[side]
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    base = o[None, None, :] + X[..., None] * tx + Y[..., None] * ty  # (nx, ny, 3)
    rel0 = base - c
    s = np.full(X.shape, contact.separation) + X * X / (2.0 * contact.rolling_radius)
    w_off = lay.wheelset.contact_y
    an = float(a @ n)
    bad = np.zeros(X.shape, dtype=bool)
    for _ in range(30):
        rel = rel0 + s[..., None] * n
        u = rel @ a
        radial = rel - u[..., None] * a
        rho = np.linalg.norm(radial, axis=-1)
        yw = sg * u - w_off  # wheel-local lateral coordinate
        inside = (yw >= wheel.y_min) & (yw <= wheel.y_max)
        bad |= ~inside
        ywc = np.clip(yw, wheel.y_min, wheel.y_max)
        r = lay.wheelset.wheel_radius + wheel.height(ywc)
        drdu = sg * wheel.slope(ywc)
        f = rho - r
        dfds = (radial @ n) / rho - drdu * an
        step = f / dfds
        s = s - step
        if np.all(np.abs(step[~bad]) < 1e-13):
            break
    else:
        # lines that graze the wheel (steep flanks far from the point) have no
        # intersection near the plane: no contact there; the point itself must converge
        stuck = np.abs(step) >= 1e-13
        i0 = int(np.argmin(np.abs(xs)))
        j0 = int(np.argmin(np.abs(ys)))
        if stuck[i0, j0] and not bad[i0, j0]:
            raise ConvergenceError(
                "wheel surface intersection did not converge at the contact point", iterations=30
            )
        bad |= stuck
    gap = s - zeta_r[None, :]
    gap[bad | np.isnan(gap)] = outside
    return GapField(
        gap=np.asfortranarray(gap),
        x=xs,
        y=ys,
        dx=dx,
        dy=dy,
        origin=o.copy(),
        t_x=tx.copy(),
        t_y=ty.copy(),
        normal=n.copy(),
    )


def creepages(
    contact: ContactPoint,
    speed: float,
    lateral_velocity: float = 0.0,
    yaw_rate: float = 0.0,
    angular_velocity: float | None = None,
    roll_rate: float = 0.0,
    vertical_velocity: float = 0.0,
) -> Creepages:
    """Rigid slip of the wheel over the (fixed) rail at a contact point.

    The wheel's material velocity at the contact point is v_c + omega x (p - c), with the
    wheelset centre velocity v_c = (V, lateral, vertical) and omega = Omega a + roll_rate
    e_x + yaw_rate e_z (a the axle, yaw and roll included); the rail is at rest.

    Parameters
    ----------
    contact : ContactPoint
        Contact point with its pose.
    speed : float
        Forward speed V of the wheelset, m/s (> 0).
    lateral_velocity, vertical_velocity : float
        Wheelset centre velocity components, m/s (y to the left, z up).
    yaw_rate, roll_rate : float
        rad/s.
    angular_velocity : float, optional
        Spin Omega of the wheelset about its axle, rad/s, positive rolling forward;
        default V / nominal radius.

    Returns
    -------
    Creepages
        xi, eta (dimensionless) along t_x, t_y and spin phi (1/m) along the normal.
        Small-angle checks: xi = 1 - Omega r / V, eta = lateral/V - yaw,
        phi = yaw_rate/V -+ sin(contact angle) Omega / V (left: -, right: +).
    """
    if not isinstance(contact, ContactPoint):
        raise InputError("contact must be a railvti.geometry.ContactPoint")
    v = _checks.positive("speed", speed)
    vy = _checks.finite("lateral_velocity", lateral_velocity)
    vz = _checks.finite("vertical_velocity", vertical_velocity)
    wz = _checks.finite("yaw_rate", yaw_rate)
    wx = _checks.finite("roll_rate", roll_rate)
    pose = contact.pose
    om = (
        v / pose.layout.wheelset.wheel_radius
        if angular_velocity is None
        else _checks.finite("angular_velocity", angular_velocity)
    )
    a = pose.axle
    omega = om * a + np.array([wx, 0.0, wz])
    # wheel-side contact point: the rail point lifted by the separation along n
    p = contact.position + contact.separation * contact.normal
    vel = np.array([v, vy, vz]) + np.cross(omega, p - pose.centre)
    return Creepages(
        xi=float(vel @ contact.t_x) / v,
        eta=float(vel @ contact.t_y) / v,
        phi=float(omega @ contact.normal) / v,
    )


__all__ = ["GapField", "Creepages", "gap_field", "creepages"]
