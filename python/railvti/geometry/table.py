"""Rigid wheelset on rigid rails: contact constraint, contact points and the geometry table.

Method. The rail is prismatic (invariant along x), so the vertical gap between the wheel
and the rail at track lateral position y is the height of the wheel's lower silhouette
(its envelope seen along x) above the rail profile. For each circle of the wheel (a
sample of the wheel profile) the silhouette point is where the surface normal has no x
component; with the axle direction a (yaw and roll included) it is found in closed form.
The gap along the silhouette is a function of the wheel profile coordinate; its local
minima are the candidate contact points (tread and flange); the global minimum on each
wheel must be zero. The wheelset's roll is the root of  min gap(left) - min gap(right)
(safeguarded regula falsi, vectorised over all positions), its height follows.
Everything is numpy-vectorised over positions and wheel samples.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, InputError
from ..profiles import Profile
from ..wheelset.geometry import WheelsetGeometry
from .frames import LEFT, RIGHT, SIDES, SIGN, axle_direction
from .placement import ProfileLayout, TrackLayout, layout

__all__ = [
    "OK",
    "NO_CONTACT",
    "FLANGE_CLIMB",
    "STATUS_NAMES",
    "WheelsetPose",
    "ContactPoint",
    "WheelsetContact",
    "TABLE_ARRAYS",
    "GeometryTable",
    "prominent_peaks",
    "gap_minima",
    "contact_points",
    "geometry_table",
]

log = logging.getLogger(__name__)

#: Status codes of a wheel or a position.
OK, NO_CONTACT, FLANGE_CLIMB = 0, 1, 2
STATUS_NAMES = {OK: "ok", NO_CONTACT: "no contact", FLANGE_CLIMB: "flange climb"}

_ROLL_BRACKET = 0.05  # rad; a rigid wheelset on its rails never rolls this much


@dataclass(frozen=True)
class WheelsetPose:
    """Rigid-body position of the wheelset in track coordinates (x forward, y left, z up).

    Attributes
    ----------
    y : float
        Lateral shift of the wheelset centre, m (positive to the left).
    z : float
        Height of the wheelset centre above the rail-top plane, m (nominal radius + rise).
    roll : float
        Roll angle about x, rad (positive raises the left wheel).
    yaw : float
        Yaw angle about z, rad (positive turns the axle's left end backwards).
    layout : ProfileLayout
        The profiles, the track layout and the wheelset it refers to.
    """

    y: float
    z: float
    roll: float
    yaw: float
    layout: ProfileLayout = field(repr=False)

    @property
    def axle(self) -> np.ndarray:
        """Unit vector of the axle (pointing to the left wheel)."""
        return axle_direction(np.array([self.roll]), np.array([self.yaw]))[0]

    @property
    def centre(self) -> np.ndarray:
        """Wheelset centre (3,), m."""
        return np.array([0.0, self.y, self.z])


@dataclass(frozen=True)
class ContactPoint:
    """One candidate contact point of a wheel (a local minimum of the wheel-rail gap).

    Attributes
    ----------
    side : str
        'left' or 'right'.
    separation : float
        Gap between the bodies at this point in the rigid pose, m (0 for the point that
        carries the wheel; > 0 for a second point that is near but not touching).
    in_contact : bool
        separation <= the tolerance given to the search.
    position : ndarray (3,)
        Contact point on the rail surface, track coordinates, m (x is the lead / lag of
        the point, non-zero with yaw and roll).
    y_wheel, y_rail : float
        Lateral coordinate of the point in the wheel and rail profiles, m.
    contact_angle : float
        Angle of the contact normal from the vertical, rad, positive when the rail normal
        leans towards the track centre (both wheels alike: ~cant on the tread, ~1.2 on the flange).
    rolling_radius : float
        Distance from the axle to the wheel's contact point, m.
    normal, t_x, t_y : ndarray (3,)
        Contact frame in track coordinates: ``normal`` the rail's outward normal (from rail
        into wheel), ``t_x`` = track x (rolling direction), ``t_y = normal x t_x``
        (lateral in the tangent plane, pointing to the left of the track on both wheels).
    flange_climb : bool
        The point lies on the flange beyond its steepest point (towards the tip).
    pose : WheelsetPose
        Wheelset position this point belongs to.
    """

    side: str
    separation: float
    in_contact: bool
    position: np.ndarray
    y_wheel: float
    y_rail: float
    contact_angle: float
    rolling_radius: float
    normal: np.ndarray
    t_x: np.ndarray
    t_y: np.ndarray
    flange_climb: bool
    pose: WheelsetPose = field(repr=False)


@dataclass(frozen=True)
class WheelsetContact:
    """Contact points of both wheels at one wheelset position.

    ``left`` and ``right`` list the candidate points ordered by separation (the carrying
    point first). ``status`` per wheel: 'ok', 'no contact' or 'flange climb'.
    """

    pose: WheelsetPose
    left: list[ContactPoint]
    right: list[ContactPoint]
    status: tuple[str, str]

    def wheel(self, side: str) -> list[ContactPoint]:
        """Contact points of 'left' or 'right'."""
        if side not in SIDES:
            raise InputError(f"side must be 'left' or 'right', got {side!r}")
        return self.left if side == "left" else self.right


#: The array fields of a :class:`GeometryTable`.
TABLE_ARRAYS = (
    "y",
    "yaw",
    "rise",
    "roll",
    "status",
    "n_contact",
    "separation",
    "contact_angle",
    "rolling_radius",
    "y_wheel",
    "y_rail",
    "x",
    "y_track",
    "z_track",
)


@dataclass(frozen=True)
class GeometryTable:
    """Rigid contact geometry tabulated against the lateral shift.

    Index ``[i, w, k]``: position i, wheel w (0 left, 1 right), candidate point k ordered
    by separation (k = 0 carries the wheel). Missing points are NaN.

    Attributes
    ----------
    y, yaw : ndarray (n,)
        Lateral shift (m, to the left) and yaw (rad) of the wheelset.
    rise : ndarray (n,)
        Height of the wheelset centre above its nominal height (radius over the rail top), m.
    roll : ndarray (n,)
        Roll angle, rad.
    status : ndarray (n, 2) int
        Per wheel: 0 ok, 1 no contact, 2 flange climb.
    n_contact : ndarray (n, 2) int
        Points within the contact tolerance.
    separation, contact_angle, rolling_radius, y_wheel, y_rail, x, y_track, z_track : ndarray (n, 2, m)
        Per candidate point (see :class:`ContactPoint`).
    wheel_radius : float
        Nominal wheel radius (at the tread datum), m.
    tolerance : float
        Separation up to which a point counts as in contact, m.
    """

    y: np.ndarray
    yaw: np.ndarray
    rise: np.ndarray
    roll: np.ndarray
    status: np.ndarray
    n_contact: np.ndarray
    separation: np.ndarray
    contact_angle: np.ndarray
    rolling_radius: np.ndarray
    y_wheel: np.ndarray
    y_rail: np.ndarray
    x: np.ndarray
    y_track: np.ndarray
    z_track: np.ndarray
    wheel_radius: float
    tolerance: float

    @property
    def delta_r(self) -> np.ndarray:
        """Rolling radius difference left minus right at the carrying points, m."""
        return self.rolling_radius[:, LEFT, 0] - self.rolling_radius[:, RIGHT, 0]

    @property
    def ok(self) -> np.ndarray:
        """Positions where both wheels have status ok."""
        return np.all(self.status == OK, axis=1)

    def as_dict(self) -> dict[str, np.ndarray]:
        """The arrays by name (:data:`TABLE_ARRAYS` and ``delta_r``; for HDF5 / decks)."""
        d = {k: getattr(self, k) for k in TABLE_ARRAYS}
        d["delta_r"] = self.delta_r
        return d


# ------------------------------------------------------------------------------------


def prominent_peaks(x: np.ndarray, prominence: float) -> np.ndarray:
    """Indices of the local maxima of x whose topographic prominence is at least ``prominence``
    (what scipy.signal.find_peaks(x, prominence=...) returns; scipy.signal costs ~0.5 s to
    import).

    A maximum is a sample, or a flat run of equal samples (its middle, rounded down), with a
    lower sample on either side; the ends of x are none. Its prominence is its height above
    the higher of its two bases, the lowest sample on each side before x first exceeds it
    (or the end of x).
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    out = []
    i = 1
    while i < n - 1:
        if x[i - 1] < x[i]:
            j = i
            while j + 1 < n - 1 and x[j + 1] == x[i]:
                j += 1
            if x[j + 1] < x[i]:
                out.append((i + j) // 2)
                i = j
        i += 1
    keep = []
    for k in out:
        top = x[k]
        higher = np.flatnonzero(x[:k] > top)
        left = x[(higher[-1] + 1 if higher.size else 0) : k + 1].min()
        higher = np.flatnonzero(x[k:] > top)
        right = x[k : (k + higher[0] if higher.size else n)].min()
        if top - max(left, right) >= prominence:
            keep.append(k)
    return np.array(keep, dtype=np.intp)


def _silhouette(
    lay: ProfileLayout, cy: np.ndarray, cz: np.ndarray, roll: np.ndarray, yaw: np.ndarray, side: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Lower silhouette of one wheel and its vertical gap to the rail.

    Returns gap (n, K), px, py (n, K) and the rail-local y (n, K); gap is +inf off the rail.
    """
    sg = SIGN[side]
    a = axle_direction(roll, yaw)  # (n, 3)
    ax = a[:, 0]
    q = np.sqrt(1.0 - ax * ax)
    e1 = (np.array([1.0, 0.0, 0.0]) - ax[:, None] * a) / q[:, None]
    e2 = np.cross(a, e1)
    down = -np.sign(e2[:, 2])
    w = sg * (lay.wheelset.contact_y + lay.ws)  # (K,) axial coordinate
    r = lay.wheelset.wheel_radius + lay.wz
    drdw = sg * lay.wdz
    ct = np.clip(drdw[None, :] * (ax / q)[:, None], -1.0, 1.0)  # silhouette: n . e_x = 0
    st = down[:, None] * np.sqrt(1.0 - ct * ct)
    rc, rs = r[None, :] * ct, r[None, :] * st
    px = w[None, :] * a[:, 0:1] + rc * e1[:, 0:1] + rs * e2[:, 0:1]
    py = cy[:, None] + w[None, :] * a[:, 1:2] + rc * e1[:, 1:2] + rs * e2[:, 1:2]
    pz = cz[:, None] + w[None, :] * a[:, 2:3] + rc * e1[:, 2:3] + rs * e2[:, 2:3]
    yr = sg * py - lay.rail_offset  # rail-local lateral coordinate
    zr = np.interp(yr, lay.ry, lay.rz, left=np.nan, right=np.nan)
    gap = pz - (lay.rail_top - zr)
    gap[np.isnan(gap)] = np.inf
    return gap, px, py, yr


def _min_refined(gap: np.ndarray) -> np.ndarray:
    """Row-wise minimum with a parabolic refinement through the neighbours."""
    k = np.argmin(gap, axis=1)
    rows = np.arange(gap.shape[0])
    g0 = gap[rows, k]
    km, kp = np.clip(k - 1, 0, gap.shape[1] - 1), np.clip(k + 1, 0, gap.shape[1] - 1)
    gm, gp = gap[rows, km], gap[rows, kp]
    with np.errstate(invalid="ignore"):
        den = gm - 2.0 * g0 + gp
    good = np.isfinite(gm) & np.isfinite(gp) & (den > 0) & (km != k) & (kp != k)
    out = g0.copy()
    out[good] = g0[good] - (gm[good] - gp[good]) ** 2 / (8.0 * den[good])
    return out


def _solve_pose(
    lay: ProfileLayout, y: np.ndarray, yaw: np.ndarray, tol: float = 1e-12, maxiter: int = 80
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roll and rise from the two-wheel contact constraint, vectorised (Illinois regula falsi).

    Returns roll (n,), rise (n,) and a bool array ``bracketed`` (False: no contact).
    """
    r0 = lay.wheelset.wheel_radius
    cz = np.full_like(y, r0)

    def f(phi: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        gl = _min_refined(_silhouette(lay, y[idx], cz[idx], phi, yaw[idx], LEFT)[0])
        gr = _min_refined(_silhouette(lay, y[idx], cz[idx], phi, yaw[idx], RIGHT)[0])
        return gl - gr, 0.5 * (gl + gr)

    n = y.size
    allidx = np.arange(n)
    lo, hi = np.full(n, -_ROLL_BRACKET), np.full(n, _ROLL_BRACKET)
    flo, _ = f(lo, allidx)
    fhi, _ = f(hi, allidx)
    bracketed = np.isfinite(flo) & np.isfinite(fhi) & (flo < 0) & (fhi > 0)
    phi = np.zeros(n)
    gmid = np.full(n, np.nan)
    active = np.nonzero(bracketed)[0]
    # first guess: the linear model  F ~ 2 * contact_y * roll
    phi[active] = np.clip(
        -f(np.zeros(active.size), active)[0] / (2 * lay.wheelset.contact_y),
        lo[active] * 0.9,
        hi[active] * 0.9,
    )
    side_lo = np.zeros(n, dtype=int)
    for _it in range(maxiter):
        if active.size == 0:
            break
        fv, gm = f(phi[active], active)
        gmid[active] = gm
        done = np.abs(fv) <= tol
        # update the bracket (Illinois: halve the stale end's value when it is kept twice)
        neg = fv < 0
        a_ = active
        lo[a_[neg]], flo[a_[neg]] = phi[a_[neg]], fv[neg]
        hi[a_[~neg]], fhi[a_[~neg]] = phi[a_[~neg]], fv[~neg]
        same = side_lo[a_] == np.where(neg, 1, -1)
        fhi[a_[neg & same]] *= 0.5
        flo[a_[~neg & same]] *= 0.5
        side_lo[a_] = np.where(neg, 1, -1)
        nxt = lo[a_] - flo[a_] * (hi[a_] - lo[a_]) / (fhi[a_] - flo[a_])
        narrow = (hi[a_] - lo[a_]) < 1e-13
        keep = ~(done | narrow)
        phi[a_[keep]] = nxt[keep]
        active = a_[keep]
    else:
        raise ConvergenceError(
            f"wheelset roll did not converge in {maxiter} iterations at {active.size} position(s)",
            iterations=maxiter,
        )
    rise = -gmid
    phi[~bracketed] = np.nan
    rise[~bracketed] = np.nan
    return phi, rise, bracketed


def _args(y, yaw) -> tuple[np.ndarray, np.ndarray]:
    ya = _checks.finite_array("y", np.atleast_1d(np.asarray(y, dtype=float)), ndim=1)
    yw = np.atleast_1d(np.asarray(yaw, dtype=float))
    if yw.size == 1:
        yw = np.full(ya.shape, float(yw[0]))
    yw = _checks.finite_array("yaw", yw, shape=ya.shape)
    if np.any(np.abs(ya) > 0.05):
        raise InputError("lateral shift |y| must be below 0.05 m (50 mm)")
    if np.any(np.abs(yw) > 0.2):
        raise InputError("|yaw| must be below 0.2 rad")
    return np.ascontiguousarray(ya), np.ascontiguousarray(yw)


def gap_minima(gap: np.ndarray, prominence: float) -> list[tuple[float, int, int, float]] | None:
    """Local minima of a gap sampled along the wheel profile, parabolically refined.

    Parameters
    ----------
    gap : ndarray
        Gap, m, at the wheel profile's samples (inf or NaN where the rail is not below).
    prominence : float
        Minima joined to a lower one by a ridge lower than this, m, belong to its patch
        (conformal treads: one wide patch with several pressure maxima).

    Returns
    -------
    list of (gap_min, k, j, lam) or None
        None when no sample is finite or the smallest lies on an edge of the finite range
        (the wheel rests on a profile's edge: no proper contact). Otherwise, per minimum, the
        refined gap and the refined point's position (1 - lam) * s[k] + lam * s[j] between
        samples k and j.
    """
    fin = np.isfinite(gap)
    if not fin.any():
        return None
    first, last = int(np.argmax(fin)), len(gap) - 1 - int(np.argmax(fin[::-1]))
    gg = np.where(fin, gap, gap[fin].max() + 1.0)
    kmin = int(np.argmin(gg))
    if kmin <= first or kmin >= last:
        return None
    peaks = prominent_peaks(-gg, prominence)
    if kmin not in peaks:
        peaks = np.append(peaks, kmin)
    out = []
    for k in peaks:
        if k <= first or k >= last:
            continue
        gm, g0, gp = gg[k - 1], gg[k], gg[k + 1]
        den = gm - 2 * g0 + gp
        t = 0.5 * (gm - gp) / den if den > 0 else 0.0
        t = float(np.clip(t, -0.5, 0.5))
        out.append((g0 - 0.25 * (gm - gp) * t, int(k), int(k + 1 if t >= 0 else k - 1), abs(t)))
    return out


def _points(
    lay: ProfileLayout,
    y: np.ndarray,
    yaw: np.ndarray,
    tol: float,
    max_separation: float,
    prominence: float = 5e-5,
) -> list[dict]:
    """Solve the pose and extract the candidate points: per position a dict with the roll,
    the rise, the status per wheel and per wheel the points (separation, wheel y, rail y,
    track x, track y)."""
    roll, rise, ok = _solve_pose(lay, y, yaw)
    r0 = lay.wheelset.wheel_radius
    out = []
    sil = {}
    for side in (LEFT, RIGHT):
        idx = np.nonzero(ok)[0]
        sil[side] = (
            (idx, _silhouette(lay, y[idx], r0 + rise[idx], roll[idx], yaw[idx], side))
            if idx.size
            else (idx, None)
        )
    for i in range(y.size):
        rec = {"roll": roll[i], "rise": rise[i], "status": [NO_CONTACT, NO_CONTACT], "points": [[], []]}
        out.append(rec)
    for side in (LEFT, RIGHT):
        idx, s = sil[side]
        if s is None:
            continue
        gap, px, py, yr = s
        for row, i in enumerate(idx):
            g = gap[row]
            minima = gap_minima(g, prominence)
            if minima is None:
                continue  # no finite gap, or the wheel rests on an edge of a profile
            pts = []
            for sep, k, j, lam in minima:
                if sep > max_separation:
                    continue
                pts.append(
                    (
                        sep,
                        (1 - lam) * lay.ws[k] + lam * lay.ws[j],
                        (1 - lam) * yr[row, k] + lam * yr[row, j],
                        (1 - lam) * px[row, k] + lam * px[row, j],
                        (1 - lam) * py[row, k] + lam * py[row, j],
                    )
                )
            pts.sort(key=lambda p: p[0])
            if pts:
                base = pts[0][0]  # the refined minimum is ~0; measure separations from it
                pts = [(p[0] - base,) + p[1:] for p in pts]
            out[i]["points"][side] = pts
            climb = any(p[1] < lay.flange_climb_y and p[0] <= tol for p in pts)
            out[i]["status"][side] = FLANGE_CLIMB if climb else (OK if pts else NO_CONTACT)
    return out


def _frame(
    lay: ProfileLayout, side: int, yr: float
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, float]:
    slope = float(lay.rail.slope(yr))
    delta = -np.arctan(slope)
    sg = SIGN[side]
    n = np.array([0.0, -sg * np.sin(delta), np.cos(delta)])
    tx = np.array([1.0, 0.0, 0.0])
    ty = np.cross(n, tx)
    z = lay.rail_top - float(lay.rail.height(yr))
    return delta, n, tx, ty, z


def contact_points(
    wheel: Profile,
    rail: Profile,
    y: float,
    yaw: float = 0.0,
    *,
    track: TrackLayout | None = None,
    wheelset: WheelsetGeometry | None = None,
    tol: float = 1e-5,
    max_separation: float = 2e-3,
) -> WheelsetContact:
    """Contact points of a rigid wheelset on rigid rails at one position.

    Parameters
    ----------
    wheel, rail : Profile
        Wheel profile (both wheels) and rail profile (both rails, already canted), mirrored
        left/right.
    y : float
        Lateral shift of the wheelset, m (positive to the left).
    yaw : float
        Yaw angle, rad.
    track : TrackLayout, optional
        Gauge (default ``TrackLayout()``).
    wheelset : railvti.wheelset.WheelsetGeometry, optional
        Back-to-back, nominal radius and tread datum (default ``WheelsetGeometry()``).
    tol : float
        A candidate point whose separation is at most this is in contact, m (0.01 mm).
        Local gap minima joined to a lower one by a ridge under 0.05 mm are not separate
        points: they lie in the same (wide, non-elliptic) patch.
    max_separation : float
        Candidate points (local gap minima) up to this separation are reported, m.

    Returns
    -------
    WheelsetContact
        Pose (roll and height from the constraint that both wheels touch) and the
        candidate points of each wheel; status 'no contact' / 'flange climb' per wheel.
    """
    lay = layout(wheel, rail, track, wheelset)
    ya, yw = _args(y, yaw)
    tol = _checks.non_negative("tol", tol)
    max_separation = _checks.positive("max_separation", max_separation)
    rec = _points(lay, ya, yw, tol, max_separation)[0]
    pose = WheelsetPose(
        float(ya[0]), lay.wheelset.wheel_radius + float(rec["rise"]), float(rec["roll"]), float(yw[0]), lay
    )
    lists: list[list[ContactPoint]] = [[], []]
    for side in (LEFT, RIGHT):
        for sep, s_w, s_r, x, ytr in rec["points"][side]:
            delta, n, tx, ty, z = _frame(lay, side, s_r)
            lists[side].append(
                ContactPoint(
                    side=SIDES[side],
                    separation=float(sep),
                    in_contact=bool(sep <= tol),
                    position=np.array([x, ytr, z]),
                    y_wheel=float(s_w),
                    y_rail=float(s_r),
                    contact_angle=float(delta),
                    rolling_radius=float(lay.wheelset.wheel_radius + wheel.height(s_w)),
                    normal=n,
                    t_x=tx,
                    t_y=ty,
                    flange_climb=bool(s_w < lay.flange_climb_y),
                    pose=pose,
                )
            )
    st = tuple(STATUS_NAMES[s] for s in rec["status"])
    if any(s != "ok" for s in st):
        log.warning("wheelset at y = %.4g mm, yaw = %.4g mrad: %s", ya[0] * 1e3, yw[0] * 1e3, st)
    return WheelsetContact(pose, lists[LEFT], lists[RIGHT], st)  # type: ignore[arg-type]


def geometry_table(
    wheel: Profile,
    rail: Profile,
    y,
    yaw=0.0,
    *,
    track: TrackLayout | None = None,
    wheelset: WheelsetGeometry | None = None,
    tol: float = 1e-5,
    max_separation: float = 2e-3,
    max_points: int = 3,
) -> GeometryTable:
    """Rigid contact geometry tabulated against the lateral shift (the vehicle model's table).

    Parameters
    ----------
    wheel, rail : Profile
        Wheel and (canted) rail profiles.
    y : array_like (n,)
        Lateral shifts, m (e.g. ``np.linspace(-0.01, 0.01, 201)``).
    yaw : float or array_like (n,)
        Yaw angle(s), rad.
    track, wheelset, tol, max_separation
        As in :func:`contact_points`.
    max_points : int
        Candidate points kept per wheel (ordered by separation).

    Returns
    -------
    GeometryTable
        Positions where a wheel has no contact carry NaN and status 1; flange climb is
        status 2 (the geometry is still given).
    """
    lay = layout(wheel, rail, track, wheelset)
    ya, yw = _args(y, yaw)
    tol = _checks.non_negative("tol", tol)
    max_separation = _checks.positive("max_separation", max_separation)
    m = _checks.positive_int("max_points", max_points)
    recs = _points(lay, ya, yw, tol, max_separation)
    n = ya.size
    shape = (n, 2, m)
    arr = {
        k: np.full(shape, np.nan)
        for k in (
            "separation",
            "contact_angle",
            "rolling_radius",
            "y_wheel",
            "y_rail",
            "x",
            "y_track",
            "z_track",
        )
    }
    status = np.zeros((n, 2), dtype=np.int64)
    ncon = np.zeros((n, 2), dtype=np.int64)
    # gather all points, then evaluate profile slopes/heights in one call each
    sel = [
        (i, side, k, p)
        for i, rc in enumerate(recs)
        for side in (LEFT, RIGHT)
        for k, p in enumerate(rc["points"][side][:m])
    ]
    for i, rc in enumerate(recs):
        status[i] = rc["status"]
    if sel:
        ii = np.array([s[0] for s in sel])
        ww = np.array([s[1] for s in sel])
        kk = np.array([s[2] for s in sel])
        p = np.array([s[3] for s in sel])
        sep, s_w, s_r, x, ytr = p.T
        arr["separation"][ii, ww, kk] = sep
        arr["y_wheel"][ii, ww, kk] = s_w
        arr["y_rail"][ii, ww, kk] = s_r
        arr["x"][ii, ww, kk] = x
        arr["y_track"][ii, ww, kk] = ytr
        arr["z_track"][ii, ww, kk] = lay.rail_top - rail.height(s_r)
        arr["contact_angle"][ii, ww, kk] = -np.arctan(rail.slope(s_r))
        arr["rolling_radius"][ii, ww, kk] = lay.wheelset.wheel_radius + wheel.height(s_w)
        np.add.at(ncon, (ii, ww), (sep <= tol).astype(np.int64))
    roll = np.array([rc["roll"] for rc in recs])
    rise = np.array([rc["rise"] for rc in recs])
    bad = np.any(status == NO_CONTACT, axis=1)
    if bad.any():
        log.warning("%d of %d positions without proper contact on a wheel", int(bad.sum()), n)
    return GeometryTable(
        y=ya,
        yaw=yw,
        rise=rise,
        roll=roll,
        status=status,
        n_contact=ncon,
        wheel_radius=lay.wheelset.wheel_radius,
        tolerance=tol,
        **arr,
    )
