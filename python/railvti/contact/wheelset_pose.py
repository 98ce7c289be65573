"""Rigid contact of a wheelset whose roll is prescribed: CONTACT's half wheelset.

:func:`railvti.geometry.contact_points` finds the roll from the constraint that both wheels
touch their rails. When the roll is prescribed instead (CONTACT's ``ROLL``, the Manchester
benchmark's decks), the two wheels cannot in general both touch at one wheelset height:
each wheel is then a *half wheelset* with its own vertical position (as in CONTACT's module
1, where each case is one wheel on one rail). For each wheel, at the given lateral shift,
roll and yaw, the lower silhouette of the wheel (the envelope seen along the track, in
closed form per wheel-profile circle, as in :mod:`railvti.geometry.table`) is compared
with the rail; the wheel is lowered until its smallest gap is zero, and the local minima
of the gap are its candidate contact points (minima joined to a lower one by a ridge under
0.05 mm belong to its patch, as in the geometry module).

Each returned :class:`~railvti.geometry.ContactPoint` carries the pose of its own half
wheelset (its ``pose.z``), so :func:`railvti.geometry.gap_field` evaluates its gap exactly.
Implements no equation of the paper (rigid geometry).
"""

from __future__ import annotations

import logging

import numpy as np

from .. import _checks
from ..errors import InputError
from ..geometry import (
    FLANGE_CLIMB,
    NO_CONTACT,
    OK,
    STATUS_NAMES,
    ContactPoint,
    TrackLayout,
    WheelsetContact,
    WheelsetPose,
    layout,
)
from ..geometry.frames import SIDES, SIGN, axle_direction
from ..geometry.placement import ProfileLayout
from ..geometry.table import gap_minima
from ..profiles import Profile
from ..wheelset.geometry import WheelsetGeometry

log = logging.getLogger(__name__)

#: Largest roll a rigid wheelset takes on its rails, rad (as the geometry module's bracket).
MAX_ROLL = 0.05
#: Status of a wheel that was not asked for.
NOT_PLACED = "not placed"
#: Minima joined to a lower one by a ridge below this belong to its patch, m.
_PROMINENCE = 5e-5


def _silhouette_gap(
    lay: ProfileLayout, side: int, y: float, roll: float, yaw: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Vertical gap (m) between one wheel's lower silhouette and its rail, with the wheelset
    centre at height 0; and the silhouette's track x, y and rail-local y. +inf off the rail."""
    sg = SIGN[side]
    a = axle_direction(np.array([roll]), np.array([yaw]))[0]
    q = np.sqrt(1.0 - a[0] * a[0])
    e1 = (np.array([1.0, 0.0, 0.0]) - a[0] * a) / q
    e2 = np.cross(a, e1)
    down = -np.sign(e2[2])
    w = sg * (lay.wheelset.contact_y + lay.ws)  # axial coordinate of each circle
    r = lay.wheelset.wheel_radius + lay.wz
    ct = np.clip(sg * lay.wdz * (a[0] / q), -1.0, 1.0)  # silhouette: the normal has no x part
    st = down * np.sqrt(1.0 - ct * ct)
    p = w[:, None] * a + (r * ct)[:, None] * e1 + (r * st)[:, None] * e2
    py = y + p[:, 1]
    yr = sg * py - lay.rail_offset
    zr = np.interp(yr, lay.ry, lay.rz, left=np.nan, right=np.nan)
    gap = p[:, 2] - (lay.rail_top - zr)
    gap[np.isnan(gap)] = np.inf
    return gap, p[:, 0], py, yr


def _candidates(
    lay: ProfileLayout, gap: np.ndarray, px: np.ndarray, py: np.ndarray, yr: np.ndarray, max_separation: float
) -> tuple[float, list[tuple[float, float, float, float, float]]]:
    """The smallest gap (parabolically refined) and the candidate points
    (separation, wheel y, rail y, track x, track y), ordered by separation."""
    minima = gap_minima(gap, _PROMINENCE)
    if not minima:
        return np.nan, []  # no finite gap, or the wheel rests on an edge of a profile
    pts = []
    for sep, k, j, lam in minima:

        def mix(v: np.ndarray) -> float:
            return float((1 - lam) * v[k] + lam * v[j])

        pts.append((sep, mix(lay.ws), mix(yr), mix(px), mix(py)))
    pts.sort(key=lambda p: p[0])
    base = pts[0][0]
    return base, [(p[0] - base,) + p[1:] for p in pts if p[0] - base <= max_separation]


def _point(lay: ProfileLayout, side: int, pose: WheelsetPose, rec: tuple, tol: float) -> ContactPoint:
    sep, s_w, s_r, x, y_track = rec
    sg = SIGN[side]
    delta = -float(np.arctan(lay.rail.slope(s_r)))
    n = np.array([0.0, -sg * np.sin(delta), np.cos(delta)])
    tx = np.array([1.0, 0.0, 0.0])
    return ContactPoint(
        side=SIDES[side],
        separation=float(sep),
        in_contact=bool(sep <= tol),
        position=np.array([x, y_track, lay.rail_top - float(lay.rail.height(s_r))]),
        y_wheel=float(s_w),
        y_rail=float(s_r),
        contact_angle=delta,
        rolling_radius=float(lay.wheelset.wheel_radius + lay.wheel.height(s_w)),
        normal=n,
        t_x=tx,
        t_y=np.cross(n, tx),
        flange_climb=bool(s_w < lay.flange_climb_y),
        pose=pose,
    )


def contact_points_at_roll(
    wheel: Profile,
    rail: Profile,
    y: float,
    roll: float,
    yaw: float = 0.0,
    *,
    track: TrackLayout | None = None,
    wheelset: WheelsetGeometry | None = None,
    tol: float = 1e-5,
    max_separation: float = 2e-3,
    sides: tuple[str, ...] = SIDES,
) -> WheelsetContact:
    """Candidate contact points of each wheel of a wheelset with a prescribed roll.

    Parameters
    ----------
    wheel, rail : Profile
        Wheel profile and (canted) rail profile, as for :func:`railvti.geometry.contact_points`.
    y : float
        Lateral shift of the wheelset, m (to the left).
    roll : float
        Roll angle, rad (positive raises the left wheel), |roll| < 0.05.
    yaw : float
        Yaw angle, rad.
    track, wheelset : optional
        Layout (see :func:`railvti.geometry.contact_points`).
    tol : float
        A point whose separation is at most this is in contact, m.
    max_separation : float
        Candidate points up to this separation from the wheel's smallest gap are kept, m.
    sides : tuple of str
        The wheels to place ('left', 'right'); a wheel left out has no points and the
        status 'not placed'.

    Returns
    -------
    WheelsetContact
        ``pose`` has the prescribed roll and the mean height of the two half wheelsets;
        each point's ``pose`` is its own wheel's (same shift, roll and yaw; its own height
        ``z``, with which that wheel just touches). Status per wheel as in the geometry
        module ('ok', 'no contact', 'flange climb'; 'not placed' for a wheel not in ``sides``).

    Raises
    ------
    InputError
        NaN or out-of-range arguments (named).
    """
    lay = layout(wheel, rail, track, wheelset)
    y = _checks.finite("y", y)
    roll = _checks.finite("roll", roll)
    yaw = _checks.finite("yaw", yaw)
    if abs(y) > 0.05:
        raise InputError(f"lateral shift |y| must be below 0.05 m (50 mm), got {y}")
    if abs(roll) >= MAX_ROLL:
        raise InputError(f"|roll| must be below {MAX_ROLL} rad, got {roll}")
    if abs(yaw) > 0.2:
        raise InputError(f"|yaw| must be below 0.2 rad, got {yaw}")
    tol = _checks.non_negative("tol", tol)
    max_separation = _checks.positive("max_separation", max_separation)
    lists: list[list[ContactPoint]] = [[], []]
    status = [NO_CONTACT, NO_CONTACT]
    heights = []
    if not sides or any(s not in SIDES for s in sides):
        raise InputError(f"sides must name 'left' and/or 'right', got {sides!r}")
    for side in (SIDES.index(s) for s in sides):
        gap, px, py, yr = _silhouette_gap(lay, side, y, roll, yaw)
        base, recs = _candidates(lay, gap, px, py, yr, max_separation)
        if not recs:
            continue
        z = -base  # the height at which this wheel just touches its rail
        heights.append(z)
        pose = WheelsetPose(y, z, roll, yaw, lay)
        lists[side] = [_point(lay, side, pose, rec, tol) for rec in recs]
        climb = any(p.flange_climb and p.in_contact for p in lists[side])
        status[side] = FLANGE_CLIMB if climb else OK
    z_mean = float(np.mean(heights)) if heights else float("nan")
    st = tuple(STATUS_NAMES[s] if SIDES[k] in sides else NOT_PLACED for k, s in enumerate(status))
    if any(st[SIDES.index(s)] != "ok" for s in sides):
        log.warning(
            "wheelset at y = %.4g mm, roll = %.4g mrad, yaw = %.4g mrad: %s",
            y * 1e3,
            roll * 1e3,
            yaw * 1e3,
            st,
        )
    return WheelsetContact(WheelsetPose(y, z_mean, roll, yaw, lay), lists[0], lists[1], st)  # type: ignore[arg-type]


__all__ = ["MAX_ROLL", "NOT_PLACED", "contact_points_at_roll"]
