"""Per-wheel contact tables for the time simulation (the vehicle's look-up tables).

For the left wheel of a wheelset shifted laterally by ``y`` relative to the track, at its
nominal height (axle at the wheel radius above the rail-top plane) and zero roll/yaw, the
vertical gap between the wheel's lower outline and the rail is a function of the wheel
profile coordinate s. Its minimum over the tread side (s > ``split``) and over the flange
side (s <= ``split``) are the two candidate points (slot 0 tread, slot 1 flange). Each
slot's minimum is a continuous function of y even where the point jumps across the wheel,
so a flange point appears smoothly as its gap closes. The right wheel is the mirror image
(its table is the left one at -y). Per point the table holds:

=====  =====================================================================
 g      vertical gap, m (the wheel's vertical interference is -(g + dz + roll l))
 l      lateral position of the point from the wheelset centre, m (left wheel, > 0)
 delta  contact angle (rail normal from the vertical, + towards the track centre), rad
 r      rolling radius, m
 a1,b1  Hertz semi-axes (rolling x, lateral y) under 1 N, m N^(-1/3)
 kH     normal law N = kH d^1.5 (d the normal approach), N m^(-1.5)
 c11, c22, c23  Kalker's creep coefficients at a1/b1 and the material's Poisson ratio
 branch label of the point's branch (a local minimum followed continuously in y; -1: the
        slot has no local minimum there and is empty, gap 1 m)
=====  =====================================================================

Branches. A slot's point is the lowest local minimum of the gap on its side of the split.
Where it jumps to another local minimum (S1002 / UIC60 1:40 between y = 0.20 and 0.25 mm,
about 10 mm across the tread), the label changes and the Fortran look-up never
interpolates across it (vehicle_contact.table_at). A minimum pinned on the split itself is
no contact point: the slot is empty there.

Hertz curvatures: A = cos(delta) / (2 r) (the wheel's normal curvature along the rolling
direction), B = (k_rail - k_wheel) / 2 from the profile curvatures (Profile.curvature), with
B/A clipped into [1/25, 25] (conformal or concave pairs are outside Hertz's assumptions and
outside Kalker's table; the clip is logged).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _cache, _checks
from .._native import core
from .._status import Status, error
from ..contact.hertz import hertz
from ..contact.kalker import kalker_coefficients
from ..errors import InputError
from ..geometry import layout
from ..material import STEEL, Material
from ..profiles import Profile

log = logging.getLogger(__name__)

#: Names of the table quantities, in the Fortran order (first index).
QUANTITIES = ("g", "l", "delta", "r", "a1", "b1", "kH", "c11", "c22", "c23", "branch", "zarm", "rlink", "rzz")
IBRANCH = QUANTITIES.index("branch")
IZARM = QUANTITIES.index("zarm")
IRLINK = QUANTITIES.index("rlink")
IRZZ = QUANTITIES.index("rzz")
#: Default relative-roll range and step of the table, rad (validation/contact_pose_table.py).
ROLL_MAX = 0.02
ROLL_STEP = 0.00125
_RATIO_CLIP = 25.0


@dataclass(frozen=True)
class WheelTable:
    """The left wheel's contact table (right wheel: mirror).

    Attributes
    ----------
    y : ndarray (n,)
        Lateral shift of the wheelset relative to the track, m (uniform).
    data : ndarray (14, 2, n)
        Quantities :data:`QUANTITIES` for slot 0 (tread side) and 1 (flange side) at zero
        relative roll (the row the BEM gap fields are built on).
    roll : ndarray (nr,)
        Relative roll of wheel against rail of the table's rows, rad (uniform, symmetric,
        one row at 0).
    data_roll : ndarray (14, 2, n, nr) or None
        All rows, Fortran-ordered, as the Fortran kernel reads it (None: ``data`` only).
    r0 : float
        Rolling radius at y = 0 (the nominal rolling speed is v0 / r0), m.
    s_wheel : ndarray (2, n)
        Wheel profile coordinate of each point, m.
    material : Material
    n_clipped : int
        Table entries whose curvature ratio was clipped.
    wheel, rail : Profile or None
        The profiles the table was built from (the BEM contact needs them; None for a
        linearised table).
    split : float
        Wheel profile coordinate separating the two slots' points, m (each slot's point is
        the lowest local minimum of the gap on its side).
    s_own : ndarray (n,) or None
        Wheel profile coordinate dividing the wheel between the two slots' BEM gap fields,
        m: the ridge of the gap between the two points (+-inf where a slot is empty).
    """

    y: np.ndarray
    data: np.ndarray
    r0: float
    s_wheel: np.ndarray
    material: Material
    n_clipped: int
    wheel: Profile | None = None
    rail: Profile | None = None
    split: float = -0.022
    s_own: np.ndarray | None = None
    roll: np.ndarray | None = None
    data_roll: np.ndarray | None = None
    r_nominal: float | None = None

    def __post_init__(self) -> None:
        # read-only copies: the table is cached (wheel_table) and sent to the Fortran core
        # with its System once (System.native)
        if self.roll is None:
            object.__setattr__(self, "roll", np.zeros(1))
        if self.data_roll is None:
            object.__setattr__(self, "data_roll", np.asarray(self.data)[..., None])
        if self.r_nominal is None:
            object.__setattr__(self, "r_nominal", float(self.r0))
        for name in ("y", "data", "s_wheel", "roll", "data_roll"):
            arr = np.array(getattr(self, name), dtype=np.float64, order="F")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if self.data_roll.shape[:3] != self.data.shape or self.data_roll.shape[3] != self.roll.size:
            raise InputError("contact table: data_roll must be (quantities, 2, n_y, n_roll)")

    @property
    def roll0(self) -> float:
        """First roll row, rad."""
        return float(self.roll[0])

    @property
    def droll(self) -> float:
        """Roll step, rad (1 for a single row)."""
        return float(self.roll[1] - self.roll[0]) if self.roll.size > 1 else 1.0

    @property
    def y0(self) -> float:
        """First table position, m."""
        return float(self.y[0])

    @property
    def dy(self) -> float:
        """Table step, m."""
        return float(self.y[1] - self.y[0])

    def at(self, name: str, slot: int = 0) -> np.ndarray:
        """One quantity of one slot over the table, shape (n,)."""
        if name not in QUANTITIES:
            raise InputError(f"unknown table quantity {name!r}; one of {QUANTITIES}")
        return self.data[QUANTITIES.index(name), slot]

    @property
    def gap_min(self) -> np.ndarray:
        """The wheel's smallest gap over both slots at each node, (n,), m."""
        return np.minimum(self.data[0, 0], self.data[0, 1])

    @property
    def l_carrying(self) -> np.ndarray:
        """Lateral position of the slot with the smaller gap at each node, (n,), m."""
        return np.where(self.data[0, 0] <= self.data[0, 1], self.data[1, 0], self.data[1, 1])

    def delta_r(self, y: np.ndarray) -> np.ndarray:
        """Rolling-radius difference left minus right of the tread points at y, m."""
        r = self.at("r", 0)
        return np.interp(y, self.y, r) - np.interp(-np.asarray(y), self.y, r)


_CACHE: dict[tuple, WheelTable] = {}


def wheel_table(
    wheel: Profile,
    rail: Profile,
    *,
    y_max: float = 0.015,
    step: float = 5e-5,
    roll_max: float = ROLL_MAX,
    roll_step: float = ROLL_STEP,
    split: float = -0.022,
    material: Material = STEEL,
) -> WheelTable:
    """Build (or fetch from the cache) the left wheel's contact table.

    Parameters
    ----------
    wheel, rail : Profile
        Wheel and canted rail profiles (as for :func:`railvti.geometry.geometry_table`).
    y_max : float
        The table covers -y_max..y_max, m (a wheelset beyond it stops the simulation).
    step : float
        Table step in y, m (0.05 mm).
    roll_max, roll_step : float
        The table covers the relative roll of wheel against rail -roll_max..roll_max in
        steps of roll_step, rad (a pose beyond it stops the simulation). roll_max = 0 gives
        a single zero-roll row (roll then enters to first order only).
        The defaults come from the speed-against-accuracy study
        ``validation/contact_pose_table.py``.
    split : float
        Wheel profile coordinate separating the tread (s > split) from the flange side, m.
        The default lies between the tread and the flange root of S1002 (the contact jumps
        from about -15 mm to -28 mm).
    material : Material
        Wheel and rail steel.
    """
    y_max = _checks.positive("y_max", y_max)
    step = _checks.positive("step", step)
    roll_max = _checks.non_negative("roll_max", roll_max)
    roll_step = _checks.positive("roll_step", roll_step)
    if roll_max > 0.1:
        raise InputError(f"roll_max = {roll_max} rad: the table is for small relative roll (<= 0.1 rad)")
    split = _checks.finite("split", split)
    key = (id(wheel), id(rail), y_max, step, roll_max, roll_step, split, material)
    hit = _CACHE.get(key)
    if hit is not None and hit.wheel is wheel and hit.rail is rail:
        return hit
    # on disk (railvti._cache): a new process (a Dask worker) loads in ms what takes ~3.5 s
    dkey = _cache.digest(_DISK_KIND, wheel, rail, y_max, step, roll_max, roll_step, split, material)
    out = _table_from(_cache.load(_DISK_KIND, dkey), wheel, rail, split, material, y_max, step)
    if out is None:
        out = _build(wheel, rail, y_max, step, roll_max, roll_step, split, material)
        _cache.store(_DISK_KIND, dkey, _table_arrays(out))
    if out.n_clipped:
        log.info(
            "contact table: %d entries with the Hertz curvature ratio clipped to [1/%g, %g]",
            out.n_clipped,
            _RATIO_CLIP,
            _RATIO_CLIP,
        )
    if len(_CACHE) > 8:
        _CACHE.clear()
    _CACHE[key] = out
    return out


#: The disk cache's kind of the contact tables, and the arrays and numbers it stores.
_DISK_KIND = "wheel_table"
_DISK_ARRAYS = ("y", "data", "s_wheel", "s_own", "roll", "data_roll")
_DISK_NUMBERS = ("r0", "n_clipped", "r_nominal")


def _table_arrays(t: WheelTable) -> dict[str, np.ndarray]:
    """The arrays and numbers of a built table, as the disk cache stores them."""
    out = {k: getattr(t, k) for k in _DISK_ARRAYS}
    out.update({k: np.array(getattr(t, k)) for k in _DISK_NUMBERS})
    return out


def _table_from(
    arrays: dict[str, np.ndarray] | None,
    wheel: Profile,
    rail: Profile,
    split: float,
    material: Material,
    y_max: float,
    step: float,
) -> WheelTable | None:
    """The table of a disk-cache entry (None: no entry, or one without this table's arrays
    or positions)."""
    if arrays is None:
        return None
    y = np.linspace(-y_max, y_max, int(round(2 * y_max / step)) + 1)
    if set(arrays) != set(_DISK_ARRAYS + _DISK_NUMBERS) or not np.array_equal(arrays["y"], y):
        log.warning("railvti cache: a contact table entry without this table's arrays; built again")
        return None
    return WheelTable(
        y=arrays["y"],
        data=arrays["data"],
        r0=float(arrays["r0"]),
        s_wheel=arrays["s_wheel"],
        material=material,
        n_clipped=int(arrays["n_clipped"]),
        wheel=wheel,
        rail=rail,
        split=split,
        s_own=arrays["s_own"],
        roll=arrays["roll"],
        data_roll=arrays["data_roll"],
        r_nominal=float(arrays["r_nominal"]),
    )


def _build(
    wheel: Profile,
    rail: Profile,
    y_max: float,
    step: float,
    roll_max: float,
    roll_step: float,
    split: float,
    material: Material,
) -> WheelTable:
    """Build the table of :func:`wheel_table` (checked arguments)."""
    lay = layout(wheel, rail)
    n = int(round(2 * y_max / step)) + 1
    y = np.linspace(-y_max, y_max, n)
    nr = int(round(roll_max / roll_step))
    roll = roll_step * np.arange(-nr, nr + 1) if nr > 0 else np.zeros(1)
    # the first coordinate is u = y + r_nom roll, the lateral position of the rolled wheel's
    # lowest point: a rotation about the centre moves the contact point by r roll sideways,
    # so branch changes lie almost along constant u and few cells mix branches
    r_nom = lay.wheelset.wheel_radius
    # row by row, keeping only the previous row's gap samples (13 MB a row) for the links
    data = np.empty((len(QUANTITIES), 2, n, roll.size))
    prev = z = None
    n_clip = 0
    for j, p in enumerate(roll):
        cur = _row(lay, y - r_nom * float(p), float(p), split, material)
        data[..., j] = cur.data
        if prev is not None:
            data[IRLINK, :, :, j - 1] = _links(prev, cur)
        if j == roll.size // 2:
            z = cur
        n_clip += cur.n_clipped
        prev = cur
    data[IRLINK, :, :, -1] = 0.0
    r0 = float(np.interp(0.0, y, z.data[3, 0]))
    return WheelTable(
        y=y,
        data=np.asfortranarray(z.data),
        r0=r0,
        s_wheel=z.s_wheel,
        material=material,
        n_clipped=n_clip,
        wheel=wheel,
        rail=rail,
        split=split,
        s_own=z.s_own,
        roll=roll,
        data_roll=np.asfortranarray(data),
        r_nominal=float(lay.wheelset.wheel_radius),
    )


@dataclass(frozen=True)
class _Row:
    """One roll row of the table and what the branch links need."""

    data: np.ndarray  # (nq, 2, n)
    s_wheel: np.ndarray  # (2, n)
    s_own: np.ndarray  # (n,)
    gap: np.ndarray  # (n, m) vertical gap of every wheel sample
    kglob: np.ndarray  # (2, n) sample index of each slot's point
    real: np.ndarray  # (2, n) whether the slot has a point
    n_clipped: int


def rolled_gap(lay, y: np.ndarray, roll: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertical gap between the left wheel and rail for the wheelset at lateral shift y
    (m, track frame) and relative roll ``roll`` (rad, about +x: the left wheel rises) about
    its centre, which stands at the nominal radius above the rail top.

    A rolled wheelset keeps its axle in the y-z plane, so the meridian section at x = 0 is
    the wheel's lowest outline; the rotation is exact (no small-angle step).

    Returns
    -------
    gap : ndarray (n, m)
        Gap at each wheel sample ``lay.ws`` (+inf off the rail), m.
    arm_y, arm_z : ndarray (m,)
        Each sample's lateral offset from the wheelset centre and its depth below it, m.
    """
    r_nom = lay.wheelset.wheel_radius
    y0w = lay.wheelset.contact_y + lay.ws  # from the centre, unrolled
    z0w = -(r_nom + lay.wz)  # up from the centre, unrolled
    c, s = np.cos(roll), np.sin(roll)
    arm_y = c * y0w - s * z0w
    zc = s * y0w + c * z0w
    yrail = y[:, None] + arm_y[None, :] - lay.rail_offset
    zr = np.interp(yrail, lay.ry, lay.rz, left=np.nan, right=np.nan)
    gap = (r_nom + zc)[None, :] + zr - lay.rail_top
    gap[~np.isfinite(gap)] = np.inf
    return gap, arm_y, -zc


def _row(lay, y: np.ndarray, roll: float, split: float, material: Material) -> _Row:
    """The table quantities of both slots over y at one relative roll."""
    wheel, rail = lay.wheel, lay.rail
    n = y.size
    ws = lay.ws
    gap, arm_y, arm_z = rolled_gap(lay, y, roll)
    data = np.empty((len(QUANTITIES), 2, n))
    s_w = np.empty((2, n))
    rows = np.arange(n)
    lmin = _local_minima(gap)
    kglob = np.empty((2, n), dtype=np.int64)
    real = np.empty((2, n), dtype=bool)
    n_clip = 0
    for slot, mask in enumerate((ws > split, ws <= split)):
        idx = np.nonzero(mask)[0]
        graw = gap[:, idx]
        # the lowest local minimum of the wheel's gap on this side (a minimum pinned on the
        # split with the gap falling across it is no contact point: no phantoms)
        gg = np.where(lmin[:, idx], graw, np.inf)
        k = np.argmin(gg, axis=1)
        fin = np.isfinite(gg[rows, k])
        if not fin.any():
            # no contact point on this side anywhere in the table (e.g. a table that does
            # not reach flange contact): empty slot, the lowest sample's geometry
            k = np.argmin(np.where(np.isfinite(graw), graw, np.inf), axis=1)
        elif not fin.all():
            # no contact point on this side here (beyond the rail's end, or no local
            # minimum): the nearest position's point geometry, with a 1 m gap (empty slot)
            near = np.nonzero(fin)[0]
            pos = np.searchsorted(near, rows)
            j = near[np.clip(pos, 0, near.size - 1)]
            jl = near[np.clip(pos - 1, 0, near.size - 1)]
            j = np.where(np.abs(jl - rows) < np.abs(j - rows), jl, j)
            k = np.where(fin, k, k[j])
        kglob[slot] = idx[k]
        real[slot] = fin
        # parabolic refinement of the minimum
        km = np.clip(k - 1, 0, idx.size - 1)
        kp = np.clip(k + 1, 0, idx.size - 1)
        g0, gm, gp = graw[rows, k], graw[rows, km], graw[rows, kp]
        ok3 = np.isfinite(g0) & np.isfinite(gm) & np.isfinite(gp)
        g0, gm, gp = (np.where(ok3, v, 0.0) for v in (g0, gm, gp))
        den = gm - 2 * g0 + gp
        inner = (km != k) & (kp != k) & ok3 & (den > 0)
        t = np.zeros(n)
        t[inner] = np.clip(0.5 * (gm[inner] - gp[inner]) / den[inner], -0.5, 0.5)
        gmin = g0 - 0.25 * (gm - gp) * t
        gmin[~inner] = g0[~inner]
        gmin[~fin] = 1.0
        t[~fin] = 0.0
        ds = ws[1] - ws[0]
        s = ws[idx[k]] + t * ds
        s_w[slot] = s
        data[IBRANCH, slot] = _branches(gap, idx[k], fin)
        ly = np.interp(s, ws, arm_y)
        lz = np.interp(s, ws, arm_z)
        yrail = np.clip(y + ly - lay.rail_offset, rail.y_min, rail.y_max)  # y: the centre's
        delta = -np.arctan(rail.slope(yrail))
        r = lay.wheelset.wheel_radius + wheel.height(s)
        # the wheel's normal curvature along x: its surface normal makes the angle
        # delta - roll with the wheel's own radius
        A = np.cos(delta - roll) / (2.0 * r)
        B = 0.5 * (rail.curvature(yrail) - wheel.curvature(s))
        data[0, slot] = gmin
        data[1, slot] = ly
        data[2, slot] = delta
        data[3, slot] = r
        data[4:7, slot] = _hertz_unit(A, B, material)
        n_clip += int(getattr(_hertz_unit, "last_clipped", 0))
        data[7:10, slot] = kalker_coefficients(data[4, slot] / data[5, slot], material.poisson)
        data[IZARM, slot] = lz
        # d2 Z_rail / dY2 at the point (track frame, Z up): carries a node's gap along u and
        # roll in the Fortran look-up (vehicle_contact%pose_at)
        hstep = 1e-5
        data[IRZZ, slot] = -(
            rail.slope(np.clip(yrail + hstep, rail.y_min, rail.y_max))
            - rail.slope(np.clip(yrail - hstep, rail.y_min, rail.y_max))
        ) / (2 * hstep)
    data[IRLINK] = 0.0
    s_own = _ownership(gap, ws, kglob, real)
    return _Row(data=data, s_wheel=s_w, s_own=s_own, gap=gap, kglob=kglob, real=real, n_clipped=n_clip)


def _links(a: _Row, b: _Row) -> np.ndarray:
    """(2, n) 1 where each slot's point at roll row a and the next row b (same y) is the same
    local minimum of the gap (one basin at both rolls, the test of :func:`_branches`), or
    both slots are empty; else 0."""
    out = np.zeros(a.kglob.shape)
    tol = 1e-9
    for slot in range(2):
        for i in range(out.shape[1]):
            ra, rb = a.real[slot, i], b.real[slot, i]
            if not (ra or rb):
                out[slot, i] = 1.0
                continue
            if ra != rb:
                continue
            ka, kb = a.kglob[slot, i], b.kglob[slot, i]
            same = True
            for g, frm, to in ((a.gap[i], kb, ka), (b.gap[i], ka, kb)):
                stp = 1 if to >= frm else -1
                seg = g[frm : to + stp if to + stp >= 0 else None : stp]
                if seg.size > 1 and (np.diff(seg) > tol).any():
                    same = False
            out[slot, i] = 1.0 if same else 0.0
    return out


def pose_values(table: WheelTable, u, roll, members: bool = False):
    """The table read by the Fortran time loop's look-up at poses (u, roll) of the left wheel.

    Parameters
    ----------
    table : WheelTable
    u : array_like (n,)
        Lateral position of the rolled wheel's lowest point, u = Y + r_nom roll, m.
    roll : array_like (n,)
        Relative roll of wheel against rail, rad.

    members : bool
        Also return each slot's second branch and the load shares.

    Returns
    -------
    ndarray (14, 2, n)
        Quantities :data:`QUANTITIES` of each slot's lowest branch at each pose; with
        ``members``, (14, 2 members, 2 slots, n), the members' load shares (2, 2, n) and
        the gradients of their gaps (d/du, d/droll; 2, 2, 2, n)
        (a slot's second member carries load only where two branches' gaps are within a
        few micrometres: vehicle_contact%pose_at).

    Raises
    ------
    InputError
        A pose outside the table.
    """
    ua = _checks.finite_array("u", np.atleast_1d(np.asarray(u, dtype=float)))
    pa = _checks.finite_array("roll", np.atleast_1d(np.asarray(roll, dtype=float)), shape=ua.shape)
    vals, wt, grad, ibad, info = core.vehicle_pose_at_c(
        table.data_roll, table.y0, table.dy, table.roll0, table.droll, table.r_nominal, ua, pa
    )
    if info != Status.OK:
        raise error(
            info,
            f"contact table look-up (pose {int(ibad) - 1}: u = "
            f"{ua[max(int(ibad) - 1, 0)]:.6g} m, roll = {pa[max(int(ibad) - 1, 0)]:.6g} rad)",
            exc=InputError,
        )
    return (vals, wt, grad) if members else vals[:, 0, :, :]


def _local_minima(gap: np.ndarray) -> np.ndarray:
    """(n, m) mask of the wheel samples that are local minima of the gap at each position
    (the left neighbour higher, the right one not lower; finite)."""
    g = gap
    out = np.zeros(g.shape, dtype=bool)
    out[:, 1:-1] = (g[:, 1:-1] < g[:, :-2]) & (g[:, 1:-1] <= g[:, 2:])
    return out & np.isfinite(g)


def _ownership(gap: np.ndarray, ws: np.ndarray, kglob: np.ndarray, real: np.ndarray) -> np.ndarray:
    """Wheel coordinate (n,) that divides the wheel between the two slots' gap fields: the
    highest gap between the two points (the ridge between their basins); -inf where the
    flange slot is empty (the tread point owns the whole wheel), +inf where the tread slot
    is."""
    out = np.empty(kglob.shape[1])
    for i in range(out.size):
        if not real[1, i]:
            out[i] = -np.inf
        elif not real[0, i]:
            out[i] = np.inf
        else:
            a, b = sorted((kglob[0, i], kglob[1, i]))
            out[i] = ws[a + int(np.argmax(gap[i, a : b + 1]))]
    return out


def _branches(gap: np.ndarray, k: np.ndarray, real: np.ndarray) -> np.ndarray:
    """Branch labels of one slot's point over the table: consecutive positions share a label
    while the point is the same local minimum of the gap followed continuously, i.e. at
    either position the gap falls monotonically from the other position's point to this
    one's (one basin: the point slid, it did not jump to another minimum). Empty positions
    (no local minimum) get -1."""
    lab = np.empty(k.size)
    cur = 0.0
    tol = 1e-9  # m: samples' round-off
    for i in range(k.size):
        if not real[i]:
            lab[i] = -1.0
            continue
        if i > 0 and real[i - 1]:
            # at either position, the gap descends monotonically from the other position's
            # point to this position's point (both lie in one basin, they are one minimum)
            same = True
            for row, frm, to in ((i - 1, k[i], k[i - 1]), (i, k[i - 1], k[i])):
                step = 1 if to >= frm else -1
                seg = gap[row, frm : to + step if to + step >= 0 else None : step]
                if seg.size > 1 and (np.diff(seg) > tol).any():
                    same = False
            if not same:
                cur += 1.0
        elif i > 0:
            cur += 1.0
        lab[i] = cur
    return lab


def _hertz_unit(
    A: np.ndarray, B: np.ndarray, material: Material, clip: float = _RATIO_CLIP, exact: bool = False
) -> np.ndarray:
    """Hertz a, b (1 N) and kH for each (A, B); B/A clipped to 1/25..clip. Returns (3, n).

    a, b and the approach d scale as N^(1/3), N^(1/3), N^(2/3), so N = d^1.5 / d1^1.5.
    The ratio B/A is rounded to 1e-3 in log scale and each distinct value solved once; with
    ``exact`` every distinct ratio is solved as it is (a table that is differentiated, such
    as the strips' ratio table: the rounding is a staircase whose spline has a derivative
    that oscillates from node to node).
    """
    ratio = B / A
    lo, hi = 1.0 / _RATIO_CLIP, clip
    clipped = ~((ratio >= lo) & (ratio <= hi))
    ratio = np.clip(np.where(np.isfinite(ratio), ratio, hi), lo, hi)
    if exact:
        uniq, inv = np.unique(ratio, return_inverse=True)
        values = uniq
    else:
        key = np.round(np.log(ratio) * 1000.0).astype(np.int64)
        uniq, inv = np.unique(key, return_inverse=True)
        values = np.exp(uniq / 1000.0)
    sol = np.empty((uniq.size, 3))
    for i, rk in enumerate(values):
        h = hertz(1.0, float(rk), 1.0, material)
        sol[i] = (h.a, h.b, h.approach)
    a = sol[inv, 0]
    b = sol[inv, 1]
    d1 = sol[inv, 2]
    # scale from A = 1 to the actual A: lengths scale as A^(-1/3), approach as A^(1/3)
    sa = A ** (-1.0 / 3.0)
    a, b, d1 = a * sa, b * sa, d1 / sa
    _hertz_unit.last_clipped = int(clipped.sum())  # type: ignore[attr-defined]
    return np.stack([a, b, d1**-1.5])


def linearised_table(
    table: WheelTable,
    conicity: float,
    *,
    contact_angle: float | None = None,
    gravitational: bool = True,
    spin: bool = True,
) -> WheelTable:
    """A table with the rolling radius linear in y (equivalent conicity) and no flange.

    Used for the linear stability analysis and the validations: r(y) = r0 + conicity * y on
    the left wheel; the tread point keeps its centred position, Hertz constants and creep
    coefficients; its gap follows the contact angle (g = g0 - tan(delta0) y, the wheel
    climbing its cone) unless ``gravitational`` is False (then delta = 0 and g = g0: no
    gravitational stiffness, the Wickens model). ``spin`` False zeroes c23 (no spin-creep
    force). The flange slot is moved 1 m away.
    """
    c = _checks.positive("conicity", conicity)
    d = np.array(table.data, copy=True)
    i0 = int(np.argmin(np.abs(table.y)))
    y = table.y
    for q in range(len(QUANTITIES)):
        d[q, 0, :] = table.data[q, 0, i0]
    d[3, 0] = table.r0 + c * y
    d0 = table.data[2, 0, i0] if contact_angle is None else float(contact_angle)
    if gravitational:
        d[2, 0] = d0
        d[0, 0] = table.data[0, 0, i0] - np.tan(d0) * y
    else:
        d[2, 0] = 0.0
        d[0, 0] = table.data[0, 0, i0]
    if not spin:
        d[QUANTITIES.index("c23"), 0] = 0.0
    d[:, 1, :] = d[:, 0, :]
    d[0, 1, :] = 1.0
    d[IBRANCH] = 0.0
    # roll rows: the wheel's point rotates rigidly about the centre, which moves by -r_nom roll
    # at fixed u = y + r_nom roll, over a rail of slope tan(delta) (the look-up's own carry,
    # vehicle_contact%pose_at, so the rows are consistent with it); to first order the gap
    # gains (l + (r_nom - zarm) tan(delta)) roll. r stays r0 + conicity u (the classic model).
    d[IRZZ] = 0.0
    roll = table.roll
    dr = np.repeat(d[..., None], roll.size, axis=-1)
    l, za, td = d[1, 0][:, None], d[IZARM, 0][:, None], np.tan(d[2, 0])[:, None]
    c, s = np.cos(roll)[None, :], np.sin(roll)[None, :]
    l1, za1 = l * c + za * s, za * c - l * s
    dr[0, 0] += (za - za1) - td * (-table.r_nominal * roll[None, :] + l1 - l)
    dr[1, 0] = l1  # the rotated point's arms
    dr[IZARM, 0] = za1
    dr[IRLINK] = 1.0
    dr[IRLINK, :, :, -1] = 0.0
    return WheelTable(
        y=y,
        data=np.asfortranarray(d),
        r0=table.r0,
        s_wheel=table.s_wheel,
        material=table.material,
        n_clipped=table.n_clipped,
        roll=roll,
        data_roll=np.asfortranarray(dr),
        r_nominal=table.r_nominal,
    )


__all__ = [
    "QUANTITIES",
    "IBRANCH",
    "IZARM",
    "IRLINK",
    "IRZZ",
    "ROLL_MAX",
    "ROLL_STEP",
    "WheelTable",
    "wheel_table",
    "rolled_gap",
    "pose_values",
    "linearised_table",
]
