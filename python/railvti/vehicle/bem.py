"""BEM contact in the time simulation (``contact='bem'``): gap fields, grid, state handle.

The Fortran time loop (``vehicle_bem.f90``) solves at every contact evaluation, per wheel and
candidate point in contact, the normal problem under approach control (projected CG with FFT
products, warm-started from the last pressure) and then steady rolling ('fftgs', warm-started
from the last tractions) with the creepages of the Hertz path, on a fixed grid of 0.75 mm
elements; a patch whose inputs moved little since its last solve takes its forces from its
linear model instead (``BemOptions.update_band``, issue 33). The normal approach is the Hertz
path's: the wheel's vertical interference at the point times cos(delta). This module builds
the undeformed gap fields the Fortran side interpolates in the lateral shift y.

Gap field of candidate point k at table node y (left wheel, nominal height, zero roll): the
grid lies in the contact plane, x along the rolling direction, lateral coordinate t along
t_y = (0, cos delta, sin delta); the element at (x, t) sees the wheel profile coordinate
s = s_k + t cos(delta) and the normal gap

    h(x, t) = [G(s) - G(s_k) + R(s) - sqrt(R(s)^2 - x^2)] cos(delta),

G the vertical wheel-rail gap at nominal height and R(s) the wheel's radius there (the
wheel is a body of revolution, the rail prismatic). This is the normal gap to second order
(the vertical gap's curvature is the profiles' curvature difference over cos^3 delta). Elements
on the other candidate point's part of the wheel get a 1 m gap, so the two points of one
wheel never share elements. The wheel is divided between the two points at the ridge of the
gap between them (``WheelTable.s_own``), not at a fixed split: a point owns its whole basin,
and the whole wheel when the other slot is empty. The right wheel reads the field at -y with
the lateral index reversed (the grid is symmetric about t = 0).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._fft_size import fft_size
from .._native import core
from .._status import Status, check, error
from ..errors import InputError
from ..geometry import layout
from .table import WheelTable

__all__ = [
    "COUNTERS",
    "TIMERS",
    "UPDATE_COUNTERS",
    "BemOptions",
    "BemGrid",
    "grid_for",
    "gap_fields",
    "BemState",
    "BemPatch",
]

log = logging.getLogger(__name__)

#: Counter names returned by the Fortran state (``vehicle_bem_counts_c``).
COUNTERS = (
    "normal_solves",
    "cg_iterations",
    "rolling_solves",
    "rolling_sweeps",
    "open_points",
    "max_normal_residual",
    "max_rolling_residual",
)
#: Wall-time counters of the Fortran state after :data:`COUNTERS` (s; :meth:`BemState.timers`):
#: normal solves, rolling solves, and whole patches (the solves, the gap field and the sums).
TIMERS = ("normal_seconds", "rolling_seconds", "patch_seconds")
#: Counters of the linear updates after :data:`TIMERS` (:meth:`BemState.counts` returns them
#: with :data:`COUNTERS`): patches whose forces came from their linear model without a solve
#: (``BemOptions.update_band``), and the largest force error of that model measured at the
#: solves whose inputs lay within twice the band (N).
UPDATE_COUNTERS = ("linear_updates", "max_linear_error")


@dataclass(frozen=True)
class BemOptions:
    """Settings of the BEM contact in the time simulation.

    Attributes
    ----------
    dx : float
        Element size (square elements), m. The paper's 0.75 mm.
    nx, ny : int or None
        Grid size (rolling x lateral); None: sized to cover the Hertz patch of every table
        point at ``load_factor`` times the static wheel load, plus 3 elements a side.
    load_factor : float
        Design normal load of the automatic grid, in static wheel loads.
    y_range : float
        The automatic grid covers the table nodes with |y| <= y_range, m (flange contact
        starts near 7 mm for S1002 / UIC60 1:40).
    tol_normal : float
        Relative complementarity residual of the normal solver. The default 1e-6 (a force
        error near 1e-6 Fn, 0.06 N) lies far below what Newton's tolerance of 1e-8 m resolves
        (the contact stiffness times 1e-8 m, about 10 N).
    tol_rolling : float
        Relative residual of the steady-rolling solver. The default 3e-5 (issue 18): hunting
        at 350 km/h from 4 mm, RR, 3 s, against 1e-5 the leading wheelset's amplitude per
        second moves by at most 0.41 % (1e-4: 0.80 %) and Q max by 1 N, at 0.79x the wall
        time (1e-4: 0.61x) (docs/vehicle.md, "Fewer solves per step").
    max_iter_normal, max_iter_rolling : int
        Iteration limits (CG iterations, sweeps).
    window : bool
        Solve each patch on the window of the grid around its rigid interpenetration (its
        bounding box plus 3 elements a side, sides rounded up to multiples of 4) instead of
        the whole grid: the same solution to the solvers' tolerances (the contact area lies
        inside the interpenetration), with FFTs of the window (``vehicle_bem.f90``).
    jacobian_age : int
        The Newton tangent's model of each patch (issue 18): its Jacobian over (approach,
        relative roll, xi, eta, spin, lateral position) from forward differences of its own
        solves (3 normal + 6 rolling solves), made again after this many solves of the point
        or when its approach or lateral position moved far (``vehicle_bem.f90``,
        ``bem_linear``). 0: Hertz + Kalker scaled to the last BEM solves instead (the cheap
        model before; FF at 200 km/h then needs about 1.7x the Newton iterations).
    update_band : float
        Linear updates in the time loop (issue 33): a patch whose inputs moved little since
        its last solve takes its forces from its linear model (the Newton tangent's, which
        needs ``jacobian_age`` > 0) without a solve, while each input's own first-order
        change of each force stays within ``update_band`` x the patch's normal force (of the
        moments, x 10 mm), the lateral position within one table node, friction and speed
        unchanged, and no new Jacobian due. The error is the linear model's: second order in
        the inputs' moves plus the Jacobian's age; ``stats['bem_max_linear_error']`` gives
        the model's force error measured at the solves within twice the band
        (docs/vehicle_contact.md, "Linear updates"). 0: every patch solved (as before). The
        static equilibrium always solves every patch.
    update_reach : float
        Linear updates in motion (issue 33): a patch whose approach and relative roll (the
        gap's inputs) moved beyond the band, each one's first-order force terms within
        ``update_reach`` x ``update_band`` x Fn, while the creepages and the lateral position
        stayed within the band (in the base's table cell), also takes its forces from its
        linear model when the model's Jacobian was made near them (their normal-force terms
        from the Jacobian's inputs within 4.5 % of Fn, the approach within 3 %; else the patch
        is solved, with a new Jacobian); within the band such a Jacobian serves too. On the
        ring track (FF, RF) the sleeper passing moves every patch's approach by 6-30 bands
        between solves, beyond the band alone. The error admitted is ~20 times the band's
        (docs/vehicle_contact.md, "Updates in motion"). 0: the band's updates only (as
        before).
    """

    dx: float = 7.5e-4
    nx: int | None = None
    ny: int | None = None
    load_factor: float = 1.5
    y_range: float = 0.010
    tol_normal: float = 1e-6
    tol_rolling: float = 3e-5
    max_iter_normal: int = 300
    max_iter_rolling: int = 500
    window: bool = True
    jacobian_age: int = 128
    update_band: float = 5e-4
    update_reach: float = 20.0

    def __post_init__(self) -> None:
        _checks.positive("dx", self.dx)
        _checks.positive("load_factor", self.load_factor)
        _checks.positive("y_range", self.y_range)
        _checks.positive("tol_normal", self.tol_normal)
        _checks.positive("tol_rolling", self.tol_rolling)
        _checks.positive_int("max_iter_normal", self.max_iter_normal)
        _checks.positive_int("max_iter_rolling", self.max_iter_rolling)
        if not (isinstance(self.update_band, (int, float)) and 0.0 <= self.update_band < 1.0):
            raise InputError(f"update_band must be a number in [0, 1), got {self.update_band!r}")
        r = self.update_reach
        if not (isinstance(r, (int, float)) and not isinstance(r, bool) and 0.0 <= r < float("inf")):
            raise InputError(f"update_reach must be a finite number >= 0, got {r!r}")
        if not isinstance(self.jacobian_age, (int, np.integer)) or self.jacobian_age < 0:
            raise InputError(f"jacobian_age must be an integer >= 0, got {self.jacobian_age!r}")
        for name in ("nx", "ny"):
            v = getattr(self, name)
            if v is not None and _checks.positive_int(name, v) < 8:
                raise InputError(f"{name} must be at least 8, got {v}")


@dataclass(frozen=True)
class BemGrid:
    """The fixed contact grid of every patch: nx x ny elements of dx x dy, centred on the
    candidate point (element centres x0 + i dx, y0 + j dy)."""

    nx: int
    ny: int
    dx: float
    dy: float

    @property
    def x0(self) -> float:
        return -0.5 * (self.nx - 1) * self.dx

    @property
    def y0(self) -> float:
        return -0.5 * (self.ny - 1) * self.dy

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Element centres (x, y), each (nx, ny), m."""
        x = self.x0 + self.dx * np.arange(self.nx)
        y = self.y0 + self.dy * np.arange(self.ny)
        return np.meshgrid(x, y, indexing="ij")


def grid_for(table: WheelTable, wheel_load: float, options: BemOptions) -> BemGrid:
    """The grid of ``options``, sized automatically where nx/ny are None.

    For every table node and candidate point that can carry load (its gap within the design
    approach of the wheel's smallest gap), the region where the rigid interpenetration at
    the design approach is positive, h(x, t) < d, with d the Hertz approach of the point at
    ``load_factor`` x ``wheel_load`` (the contact area lies inside it: for Hertz its
    semi-axes are 1/sqrt(2) of the region's). The grid covers the largest such extent along
    x and along t, plus 3 elements a side, rounded up to 2,3,5-smooth sizes. The gap is not
    Hertzian (S1002 on UIC60 1:40 is nearly two-point at the centre), hence the gap itself
    rather than the Hertz semi-axes.
    """
    d = options.dx
    if options.nx is not None and options.ny is not None:
        return BemGrid(options.nx, options.ny, d, d)
    n = options.load_factor * _checks.positive("wheel_load", wheel_load)
    probe = BemGrid(161, 161, d, d)  # 12 cm lines, centre element at 0
    hx, ht = _centre_lines(table, probe)  # (n, 2, 161) each
    kh = table.data[6]  # (2, n)
    cd = np.cos(table.data[2])
    dn = (n / kh) ** (2.0 / 3.0)  # design normal approach per point
    gmin = np.minimum(table.data[0, 0], table.data[0, 1])
    active = ((table.data[0] - gmin[None, :]) * cd < dn) & (np.abs(table.y) <= options.y_range)[None, :]
    c = np.arange(probe.nx) - (probe.nx - 1) // 2
    half_x = half_t = 1
    for k in range(2):
        for i in np.nonzero(active[k])[0]:
            inx = np.abs(c[hx[i, k] < dn[k, i]])
            itn = np.abs(c[ht[i, k] < dn[k, i]])
            if inx.size:
                half_x = max(half_x, int(inx.max()))
            if itn.size:
                half_t = max(half_t, int(itn.max()))
    nx = options.nx or fft_size(2 * half_x + 1 + 6)
    ny = options.ny or fft_size(2 * half_t + 1 + 6)
    if max(nx, ny) >= probe.nx:
        raise InputError("the BEM contact grid would exceed 120 mm: check the profiles and load")
    return BemGrid(nx, ny, d, d)


def _centre_lines(table: WheelTable, grid: BemGrid) -> tuple[np.ndarray, np.ndarray]:
    """Gap along the grid's centre lines t = 0 and x = 0, each (n_table, 2, n)."""
    full = _fields(table, grid, lines=True)
    return full


_CACHE: dict[tuple, np.ndarray] = {}


def _fields(table: WheelTable, grid: BemGrid, lines: bool = False):
    """Gap fields (nx, ny, 2, n) or, with lines, the (n, 2, nx) line t = 0 and the
    (n, 2, ny) line x = 0 (nx, ny odd)."""
    if table.wheel is None or table.rail is None:
        raise InputError(
            "contact='bem' needs a contact table built from profiles "
            "(a linearised table has no contact geometry)"
        )
    lay = layout(table.wheel, table.rail)
    off = lay.wheelset.contact_y
    r_nom = lay.wheelset.wheel_radius
    x = grid.x0 + grid.dx * np.arange(grid.nx)
    t = grid.y0 + grid.dy * np.arange(grid.ny)
    if lines:
        lx = np.empty((table.y.size, 2, grid.nx))
        lt = np.empty((table.y.size, 2, grid.ny))
    else:
        out = np.empty((grid.nx, grid.ny, 2, table.y.size), order="F")
    for k in range(2):
        sc = table.s_wheel[k][:, None]  # (n, 1)
        dl = table.data[2, k][:, None]
        g0 = table.data[0, k][:, None]
        cd = np.cos(dl)
        s = sc + t[None, :] * cd  # (n, ny)
        yrail = table.y[:, None] + off + s - lay.rail_offset
        zw = np.interp(s, lay.ws, lay.wz, left=np.nan, right=np.nan)
        zr = np.interp(yrail, lay.ry, lay.rz, left=np.nan, right=np.nan)
        gv = zr - lay.rail_top - zw
        cut = (table.s_own if table.s_own is not None else np.full(table.y.size, table.split))[:, None]
        own = (s > cut) if k == 0 else (s <= cut)
        ok = own & np.isfinite(gv) & (g0 < 0.5)
        radius = r_nom + np.where(np.isfinite(zw), zw, 0.0)  # (n, ny)
        if lines:
            j0 = (grid.ny - 1) // 2
            rc = radius[:, j0 : j0 + 1]
            lx[:, k] = (rc - np.sqrt(np.maximum(rc**2 - x[None, :] ** 2, 0.0))) * cd
            lt[:, k] = np.where(ok, (gv - g0) * cd, 1.0)
            continue
        bulge = radius[:, None, :] - np.sqrt(np.maximum(radius[:, None, :] ** 2 - x[None, :, None] ** 2, 0.0))
        h = ((gv - g0)[:, None, :] + bulge) * cd[:, None, :]  # (n, nx, ny)
        h = np.where(ok[:, None, :], h, 1.0)
        out[:, :, k, :] = np.moveaxis(h, 0, -1)
    return (lx, lt) if lines else out


def gap_fields(table: WheelTable, grid: BemGrid) -> np.ndarray:
    """Undeformed normal gap fields of the left wheel's two candidate points on the table's
    y nodes, relative to each point: array (nx, ny, 2, n_table), Fortran order, m.

    Raises
    ------
    InputError
        The table carries no profiles (e.g. a linearised table).
    """
    key = (id(table), grid)
    hit = _CACHE.get(key)
    if hit is not None:
        return hit
    out = _fields(table, grid)
    if len(_CACHE) > 4:
        _CACHE.clear()
    _CACHE[key] = out
    return out


class BemState:
    """The Fortran BEM contact state of one run (gap table, FFT workspace, warm starts);
    a context manager that frees it.

    Parameters
    ----------
    table : WheelTable
    wheel_load : float
        Static wheel load, N (grid sizing).
    n_wheelsets : int
    options : BemOptions, optional
    """

    def __init__(
        self, table: WheelTable, wheel_load: float, n_wheelsets: int, options: BemOptions | None = None
    ) -> None:
        self.options = options or BemOptions()
        if not isinstance(self.options, BemOptions):
            raise InputError("bem_options must be a railvti.vehicle.BemOptions")
        self.grid = grid_for(table, wheel_load, self.options)
        gap = gap_fields(table, self.grid)
        m = table.material
        o = self.options
        self.handle, info = core.vehicle_bem_create_c(
            self.grid.dx,
            self.grid.dy,
            table.y0,
            table.dy,
            gap,
            int(n_wheelsets),
            m.shear_modulus,
            m.poisson,
            o.tol_normal,
            o.tol_rolling,
            o.max_iter_normal,
            o.max_iter_rolling,
        )
        if info != Status.OK:
            self.handle = 0
            raise error(info, "could not create the BEM contact state")
        info = core.vehicle_bem_window_c(self.handle, int(bool(o.window)))
        check(info, "could not set the BEM solve windows")
        info = core.vehicle_bem_jacobian_c(self.handle, int(o.jacobian_age))
        check(info, "could not set the BEM patch Jacobians")
        self.set_update_band(o.update_band)
        log.debug(
            "BEM contact state %d: grid %d x %d of %.2f mm",
            self.handle,
            self.grid.nx,
            self.grid.ny,
            self.grid.dx * 1e3,
        )

    def __enter__(self) -> "BemState":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Free the Fortran state (idempotent)."""
        if self.handle:
            core.vehicle_bem_free_c(self.handle)
            self.handle = 0

    def __del__(self) -> None:  # pragma: no cover - safety net
        try:
            self.close()
        except Exception:
            pass

    def set_update_band(self, band: float) -> None:
        """Set the linear updates' band (:attr:`BemOptions.update_band`; 0: solve every patch)."""
        info = core.vehicle_bem_update_c(self.handle, float(band), float(self.options.update_reach))
        check(info, f"could not set the BEM update band {band!r}")
        self.update_band = float(band)

    def counts(self, reset: bool = False) -> dict:
        """Solver counters since creation or the last reset (:data:`COUNTERS`, then
        :data:`UPDATE_COUNTERS`)."""
        c, info = core.vehicle_bem_counts_c(self.handle, int(reset))
        check(info, "BEM contact state already freed")
        n = len(COUNTERS) + len(TIMERS)
        names = COUNTERS + UPDATE_COUNTERS
        vals = list(c[: len(COUNTERS)]) + list(c[n : n + len(UPDATE_COUNTERS)])
        return {k: (float(v) if k.startswith("max") else int(v)) for k, v in zip(names, vals)}

    def timers(self) -> dict:
        """Wall seconds spent in the BEM patches since creation or the last reset
        (:data:`TIMERS`): the profile of ``benchmarks/bench_vehicle.py``."""
        c, info = core.vehicle_bem_counts_c(self.handle, 0)
        check(info, "BEM contact state already freed")
        return {k: float(v) for k, v in zip(TIMERS, c[len(COUNTERS) :])}

    def linear_model(self, wheelset: int, wheel: int, point: int) -> dict | None:
        """The Newton tangent's linear model of one candidate point (0-based indices as
        :meth:`patch`): ``jac`` (6, 6) = dy/dx with inputs x = (approach m, relative roll rad,
        xi, eta, spin 1/m, lateral position in table nodes) and outputs y = (Fn, Fx, Fy N,
        Mz N m, Fn xc, Fn yc N m), the last solve's ``x`` and ``y``, and ``age`` (solves since
        the Jacobian); None when the point has none (out of contact, Jacobians off)."""
        jac, xb, yb, age, ok, info = core.vehicle_bem_point_jacobian_c(
            self.handle, wheelset + 1, wheel + 1, point + 1
        )
        check(info, f"no BEM point wheelset {wheelset}, wheel {wheel}, point {point}")
        if not ok:
            return None
        return {"jac": np.array(jac), "x": np.array(xb), "y": np.array(yb), "age": int(age)}

    def probe(self, wheelset: int, wheel: int, point: int, x) -> np.ndarray:
        """Solve one point's patch at the linear model's inputs ``x`` (see
        :meth:`linear_model`; the lateral position within its last solve's table cell) on the
        full grid, warm-started from its fields, without changing the state: the outputs y."""
        x = np.asarray(x, dtype=np.float64)
        if x.shape != (6,):
            raise InputError(f"x must have 6 entries, got shape {x.shape}")
        y, info = core.vehicle_bem_probe_c(self.handle, wheelset + 1, wheel + 1, point + 1, x)
        check(info, f"BEM probe of wheelset {wheelset}, wheel {wheel}, point {point}")
        return np.array(y)

    def patch(
        self, wheelset: int, wheel: int, point: int, speed: float, fn_hint: float = 0.0
    ) -> "BemPatch | None":
        """The last fields of one candidate point (wheelset and wheel 0-based, wheel 0 left /
        1 right, point 0 tread / 1 flange); None when it is out of contact."""
        g = self.grid
        p, tx, ty, sx, sy, info = core.vehicle_bem_fields_c(
            self.handle, wheelset + 1, wheel + 1, point + 1, g.nx, g.ny
        )
        check(info, f"no BEM fields for wheelset {wheelset}, wheel {wheel}, point {point}")
        if not (p > 0).any():
            return None
        x, y = g.mesh()
        da = g.dx * g.dy
        pd = np.hypot(tx, ty) * np.hypot(sx, sy)
        inside = p > 0
        return BemPatch(
            x=x,
            y=y,
            pressure=p,
            tx=tx,
            ty=ty,
            slip_velocity_x=sx,
            slip_velocity_y=sy,
            power_density=pd,
            power=float(pd.sum() * da),
            fn=float(p.sum() * da),
            fx=float(tx.sum() * da),
            fy=float(ty.sum() * da),
            a=0.5 * float(np.ptp(x[inside])) + 0.5 * g.dx,
            b=0.5 * float(np.ptp(y[inside])) + 0.5 * g.dy,
            point=point,
            speed=speed,
        )


@dataclass(frozen=True)
class BemPatch:
    """Fields of one BEM contact patch (the contact frame: x rolling, y along t_y).

    Attributes
    ----------
    x, y : ndarray (nx, ny)
        Element centres, m.
    pressure, tx, ty : ndarray (nx, ny)
        Pressure and tangential tractions on the wheel, Pa.
    slip_velocity_x, slip_velocity_y : ndarray (nx, ny)
        Slip velocity, m/s.
    power_density : ndarray (nx, ny)
        Friction power density |t| |s|, W/m^2.
    power : float
        Friction power, W.
    fn, fx, fy : float
        Integrated forces, N.
    a, b : float
        Half extents of the contact area along x and y, m.
    point : int
        0 tread, 1 flange candidate point.
    speed : float
        Rolling speed, m/s.
    """

    x: np.ndarray
    y: np.ndarray
    pressure: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    slip_velocity_x: np.ndarray
    slip_velocity_y: np.ndarray
    power_density: np.ndarray
    power: float
    fn: float
    fx: float
    fy: float
    a: float
    b: float
    point: int
    speed: float
