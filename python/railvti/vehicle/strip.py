"""The strip contact: a conservative wheel-rail normal contact without contact points.

The table contact (:mod:`railvti.vehicle.table`) puts one Hertz point at each slot's lowest
local minimum of the gap; where that minimum jumps to another part of the profiles (S1002 on
UIC60 1:40 near y = 0.2 mm) the point, its curvatures and the force jump with it, and the
vertical interference under the wheel load is up to 50 % off the half-space BEM
(``validation/contact_table_stiffness.py``). The strip contact integrates the whole rigid
interpenetration instead (Fortran ``vehicle_strip``):

    V = sum_j c(B_j / A_j) cos(delta_j) w_j P_j^2,    c = 3/8 kH(1, rho) sqrt(rho),

over wheel-profile samples j of lateral width w_j and vertical interference P_j, with the
local relative curvatures A (rolling direction) and B (across). A parabolic gap gives Hertz's
N = kH d^1.5 exactly; any other gap is integrated strip by strip. The forces are the exact
gradient of V: the contact stores and returns energy without loss or gain.

The pose is the wheelset centre's lateral position and height and its roll and yaw against
the rail; under yaw each sample's interference is the deepest point of its wheel circle (the
contact leads the wheel's lowest point), and each slot reports its longitudinal position.

Vehicle y points to the left; the geometry is the left wheel's and the right wheel is read
mirrored (as for the table; the yaw changes sign, the longitudinal position does not).
"""

from __future__ import annotations

import dataclasses
import logging
from dataclasses import dataclass

import numpy as np

from .. import _cache, _checks
from .._native import core
from .._status import check
from ..contact.kalker import kalker_coefficients
from ..geometry import layout
from ..errors import InputError
from ..material import STEEL, Material
from ..profiles import Profile
from .table import _RATIO_CLIP, _hertz_unit

log = logging.getLogger(__name__)

#: Outputs of one wheel's slot (Fortran vehicle_strip SO_*), in order.
STRIP_OUTPUTS = (
    "N",
    "V",
    "dV_dy",
    "dV_dz",
    "dV_droll",
    "l",
    "zarm",
    "delta",
    "r",
    "x",
    "A",
    "P_max",
    "dV_dyaw",
    "xc",
)
_N_TABLE = 441
#: The curvature ratio rho = B/A of the strips' Hertz constants: ln(rho) as it is within
#: (-X_LINEAR, UPPER_LINEAR), then saturated C1 to the clips ln(1/25) and ln(UPPER_CLIP)
#: (constant beyond X_FLAT, UPPER_FLAT: no force jump where a ratio is clipped). Kalker's
#: coefficients (a/b in 0.1..10) take the ratio saturated at 1/25..25 on both sides.
X_LINEAR, X_FLAT = 2.0, 5.5
UPPER_CLIP = 400.0
UPPER_LINEAR = np.log(UPPER_CLIP) - 1.2
UPPER_FLAT = UPPER_LINEAR + 3.0 * 1.2
#: Gaussian width of the rail curvature's smoothing, m (C1 curvature: continuous forces).
RAIL_SMOOTHING = 2.5e-4


@dataclass(frozen=True)
class StripGeometry:
    """The arrays of the strip contact of one wheel-rail pair (left wheel).

    Attributes
    ----------
    ws : ndarray (7, nw)
        Wheel samples: arms y0, z0 about the wheelset centre (z0 up), radius r, profile
        curvature (z down), profile slope, the tread slot's weight (0..1), and the profile's
        curvature along y |kappa| (1 + slope^2)^1.5 (the coarse scan's bound), m and 1/m.
    ds : float
        Sample step along the wheel profile, m.
    r_nominal : float
        Height of the wheelset centre above the rail top at zero shift, m.
    rail_y0, rail_dy : float
        Uniform grid of the rail spline (rail-local y), m.
    rail_z, rail_m : ndarray (nr,)
        The rail profile's z (down, canted) and its second derivative on that grid.
    rail_k, rail_k1 : ndarray (nr,)
        The rail profile's curvature (z down, smoothed over RAIL_SMOOTHING) and its rate.
    offset, top : float
        Track y of the rail's local origin, and the rail's top z (track height = top - z).
    x0, dx : float
        Uniform grid of x = ln(B / A) of the ratio table.
    fv, fm : ndarray (nf, 6)
        Ratio table and its second derivatives: c, a1, b1 (Hertz for 1 N at A = 1), c11,
        c22, c23 (Kalker at a1 / b1).
    """

    ws: np.ndarray
    ds: float
    r_nominal: float
    rail_y0: float
    rail_dy: float
    rail_z: np.ndarray
    rail_m: np.ndarray
    rail_k: np.ndarray
    rail_k1: np.ndarray
    offset: float
    top: float
    x0: float
    dx: float
    fv: np.ndarray
    fm: np.ndarray

    def args(self) -> tuple:
        """The arrays in the order of the Fortran shims (after the handle)."""
        return (
            self.ws,
            self.ds,
            self.r_nominal,
            self.rail_y0,
            self.rail_dy,
            self.rail_z,
            self.rail_m,
            self.rail_k,
            self.rail_k1,
            self.offset,
            self.top,
            self.x0,
            self.dx,
            self.fv,
            self.fm,
        )


def strip_geometry(
    wheel: Profile,
    rail: Profile,
    *,
    step: float = 2e-4,
    rail_step: float = 5e-5,
    split: float = -0.022,
    split_width: float = 1e-3,
    material: Material = STEEL,
) -> StripGeometry:
    """The strip contact's arrays for a wheel on a (canted) rail, laid out as the table is.

    Parameters
    ----------
    wheel, rail : Profile
    step : float
        Wheel-profile sample step, m (0.2 mm: within 0.1 % of 0.1 mm on the tread and 3 %
        on the flank of the sink under the wheel load).
    rail_step : float
        Step of the rail's uniform C2 spline, m.
    split : float
        Wheel profile coordinate between the tread slot (s > split) and the flange slot, m
        (as the table's).
    split_width : float
        Half width of the smooth hand-over between the slots, m.
    material : Material

    Returns
    -------
    StripGeometry
    """
    step = _checks.positive("step", step)
    rail_step = _checks.positive("rail_step", rail_step)
    split_width = _checks.positive("split_width", split_width)
    split = _checks.finite("split", split)
    # on disk (railvti._cache): a Dask worker loads it without importing scipy (issue 33)
    key = _cache.digest(_DISK_KIND, wheel, rail, step, rail_step, split, split_width, material)
    hit = _cache.load(_DISK_KIND, key)
    if hit is not None and set(hit) == set(_DISK_FIELDS):
        return StripGeometry(**{k: _DISK_FIELDS[k](v) for k, v in hit.items()})
    if hit is not None:
        log.warning("railvti cache: a strip geometry entry without its arrays; built again")
    out = _build(wheel, rail, step, rail_step, split, split_width, material)
    _cache.store(_DISK_KIND, key, {k: np.asarray(getattr(out, k)) for k in _DISK_FIELDS})
    return out


def _array(a: np.ndarray) -> np.ndarray:
    return np.asfortranarray(a)


#: The disk cache's kind of the strip geometry, and how each field is read back.
_DISK_KIND = "strip_geometry"
_DISK_FIELDS = {
    f.name: (_array if f.type == "np.ndarray" else float) for f in dataclasses.fields(StripGeometry)
}


def _build(
    wheel: Profile,
    rail: Profile,
    step: float,
    rail_step: float,
    split: float,
    split_width: float,
    material: Material,
) -> StripGeometry:
    """Build :func:`strip_geometry`'s arrays (checked arguments)."""
    # on first use: scipy.interpolate costs ~0.2 s at start-up, paid by every run that
    # imports railvti.vehicle without a strip contact (issue 33)
    from scipy.interpolate import CubicSpline

    lay = layout(wheel, rail)
    r_nom = lay.wheelset.wheel_radius
    s = np.arange(wheel.y_min, wheel.y_max + 1e-12, step)
    wz = wheel.height(s)
    t = np.clip((s - split) / split_width, -1.0, 1.0)
    tread = 0.5 + t * (15.0 - 10.0 * t * t + 3.0 * t**4) / 16.0  # C2 step from 0 to 1
    kw, sw = wheel.curvature(s), wheel.slope(s)
    ws = np.stack(
        [
            lay.wheelset.contact_y + s,
            -(r_nom + wz),
            r_nom + wz,
            kw,
            sw,
            tread,
            np.abs(kw) * (1.0 + sw * sw) ** 1.5,
        ]
    )
    n = int(np.floor((rail.y_max - rail.y_min) / rail_step)) + 1
    ry = rail.y_min + rail_step * np.arange(n)
    sp = CubicSpline(ry, rail.height(ry), bc_type="not-a-knot")
    kappa, kappa1 = _smoothed_curvature(rail, ry)
    x = np.linspace(-X_FLAT, UPPER_FLAT, _N_TABLE)
    rho = np.exp(saturated_log_ratio(x, UPPER_LINEAR, UPPER_FLAT, np.log(UPPER_CLIP)))
    # solved at every node (exact): the table is differentiated (the strips' forces take
    # dc/dx, times dx/dy = kappa_rail' / (2 B), ~3e6 1/m in a near-conformal flange-root
    # strip), and ratios rounded to 1e-3 in ln make a staircase whose spline slope
    # alternates from node to node (docs/vehicle.md, "Variants RF and FF: limits")
    a1, b1, kh = _hertz_unit(np.ones_like(rho), rho, material, clip=UPPER_CLIP, exact=True)
    ak, bk, _ = _hertz_unit(np.ones_like(rho), np.exp(saturated_log_ratio(x)), material, exact=True)
    c11, c22, c23 = kalker_coefficients(ak / bk, material.poisson)
    fv = np.stack([0.375 * kh * np.sqrt(rho), a1, b1, c11, c22, c23], axis=1)
    fm = np.stack([CubicSpline(x, col, bc_type="clamped")(x, 2) for col in fv.T], axis=1)
    f = np.asfortranarray
    return StripGeometry(
        ws=f(ws),
        ds=step,
        r_nominal=r_nom,
        rail_y0=float(ry[0]),
        rail_dy=rail_step,
        rail_z=f(sp(ry)),
        rail_m=f(sp(ry, 2)),
        rail_k=f(kappa),
        rail_k1=f(kappa1),
        offset=float(lay.rail_offset),
        top=float(lay.rail_top),
        x0=float(x[0]),
        dx=float(x[1] - x[0]),
        fv=f(fv),
        fm=f(fm),
    )


def saturated_log_ratio(
    x: np.ndarray,
    hi_linear: float = X_LINEAR,
    hi_flat: float = X_FLAT,
    hi_limit: float = float(np.log(_RATIO_CLIP)),
) -> np.ndarray:
    """ln(rho) for x = ln(B/A): x itself within (-X_LINEAR, hi_linear), then on either side a
    monotone cubic with slope 1 at the linear end and 0 at the flat end, reaching the limit
    (-ln 25 below, hi_limit above), constant beyond (C1: a clipped ratio makes no force
    jump)."""
    x = np.asarray(x, dtype=float)
    out = np.array(x, copy=True)
    for sgn, lin, flat, lim in (
        (-1.0, X_LINEAR, X_FLAT, np.log(_RATIO_CLIP)),
        (1.0, hi_linear, hi_flat, hi_limit),
    ):
        a = (flat - lin) / (lim - lin)  # <= 3 keeps the cubic monotone
        t = np.clip((sgn * x - lin) / (flat - lin), 0.0, 1.0)
        sat = lin + (lim - lin) * (a * t + (3.0 - 2.0 * a) * t**2 + (a - 2.0) * t**3)
        out = np.where(sgn * x > lin, sgn * sat, out)
    return out


def _smoothed_curvature(rail: Profile, ry: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rail profile's curvature (z down) smoothed by a Gaussian of width RAIL_SMOOTHING,
    and its rate, at ry: the profile spline's curvature has kinks at its knots."""
    h = 5e-6
    yf = np.arange(ry[0] - 4 * RAIL_SMOOTHING, ry[-1] + 4 * RAIL_SMOOTHING + h, h)
    k = rail.curvature(np.clip(yf, rail.y_min, rail.y_max))
    ker = np.exp(-0.5 * (np.arange(-4 * RAIL_SMOOTHING, 4 * RAIL_SMOOTHING + h / 2, h) / RAIL_SMOOTHING) ** 2)
    ker /= ker.sum()
    ks = np.convolve(k, ker, mode="same")
    k1 = np.gradient(ks, h)
    return np.interp(ry, yf, ks), np.interp(ry, yf, k1)


def strip_wheel(geometry: StripGeometry, y, zc, roll, yaw=0.0) -> tuple[np.ndarray, np.ndarray]:
    """The strip contact of the left wheel at poses (y, zc, roll, yaw).

    Parameters
    ----------
    geometry : StripGeometry
    y, zc, roll, yaw : float or array_like (broadcast together)
        The wheelset centre's lateral position (m, + left), its height above the nominal
        (m, + up), the relative roll of wheel against rail (rad, + the left wheel rises) and
        the wheelset's yaw against the rail (rad, + about the vertical: the left wheel moves
        back).

    Returns
    -------
    out : ndarray (..., 2, 14)
        Per pose and slot (0 tread, 1 flange) the quantities :data:`STRIP_OUTPUTS`: normal
        force N (N), potential V (J), its gradient over (y, zc, roll), the load-weighted
        arm l and depth zarm about the centre (m), contact angle (rad), rolling radius (m),
        x = ln(B/A), A (1/m), the largest vertical interference (m), the gradient of V over
        the yaw (J/rad) and the load-weighted longitudinal position xc of the contact (m,
        ahead of the axle positive).
    props : ndarray (..., 2, 5)
        Per slot: Hertz a1, b1 for 1 N (m N^(-1/3)) and Kalker's c11, c22, c23.
    """
    shape, pose = _poses("strip_wheel", y, zc, roll, yaw)
    out, props, info = core.vehicle_strip_eval_c(*geometry.args(), pose, len(STRIP_OUTPUTS))
    check(info, "strip contact")
    return _reshape(out, shape, len(STRIP_OUTPUTS)), _reshape(props, shape, 5)


def strip_linearise(geometry: StripGeometry, y, zc, roll, yaw=0.0) -> tuple[np.ndarray, np.ndarray]:
    """The strip outputs of the left wheel and their exact derivatives over the pose (the
    linearisation the Newton tangent reads; the potential's Hessian among them).

    Parameters
    ----------
    geometry : StripGeometry
    y, zc, roll, yaw : float or array_like (broadcast together)
        As for :func:`strip_wheel` (m, m, rad, rad).

    Returns
    -------
    out : ndarray (..., 2, 14)
        As :func:`strip_wheel`'s.
    dout : ndarray (..., 2, 14, 4)
        Their derivatives over (y, zc, roll, yaw), per metre or per radian.
    """
    shape, pose = _poses("strip_linearise", y, zc, roll, yaw)
    n = len(STRIP_OUTPUTS)
    out, dout, info = core.vehicle_strip_lin_c(*geometry.args(), pose, n)
    check(info, "strip contact")
    dout = np.transpose(dout, (3, 1, 0, 2)).reshape(shape + (2, n, 4))
    return _reshape(out, shape, n), dout


def _poses(name: str, y, zc, roll, yaw) -> tuple[tuple, np.ndarray]:
    """Broadcast shape and the (4, np) Fortran array of finite poses (InputError otherwise)."""
    yb, zb, pb, sb = np.broadcast_arrays(
        np.asarray(y, float), np.asarray(zc, float), np.asarray(roll, float), np.asarray(yaw, float)
    )
    pose = np.asfortranarray(np.stack([yb.ravel(), zb.ravel(), pb.ravel(), sb.ravel()]))
    if not np.all(np.isfinite(pose)):
        raise InputError(f"{name}: the poses must be finite")
    return yb.shape, pose


def _reshape(a: np.ndarray, shape: tuple, n: int) -> np.ndarray:
    """(n, 2, np) Fortran output -> (*shape, 2, n)."""
    return np.transpose(a, (2, 1, 0)).reshape(shape + (2, n))


__all__ = [
    "STRIP_OUTPUTS",
    "UPPER_CLIP",
    "UPPER_LINEAR",
    "UPPER_FLAT",
    "RAIL_SMOOTHING",
    "StripGeometry",
    "strip_geometry",
    "saturated_log_ratio",
    "strip_wheel",
    "strip_linearise",
]
