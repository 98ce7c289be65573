"""The coach in a curve: the tables the Fortran core reads per step (fortran/vehicle/
vehicle_curve.f90) and the steady curving quantities per wheel.

Moving track frames (docs/vehicle_curving.md): every body's coordinates stay relative to the
track frame at its own position along the track, s_B = s + x_B, so the wheel-rail contact
sees the same local coordinates as on straight track. The frames differ from body to body by
the curve's heading theta, lateral position Y and roll theta_x (cant), so a suspension element
between two bodies is stretched by their frames' offsets: in the frame of the vehicle's
reference position s (the carbody's centre), body B's frame origin lies at

    y_geo = Y(s_B) - Y(s) - theta(s) x_B - h_B (theta_x(s_B) - theta_x(s)),
    roll_geo = theta_x(s_B) - theta_x(s),   yaw_geo = theta(s_B) - theta(s)

(h_B its reference point's height above the rail), and the suspension's force is
-K (q + q_geo) - C (v + q_geo'), q_geo' = V dq_geo/ds. Each frame moves with the vehicle at
speed V, turns at V kappa and rolls with the cant, so its bodies feel, in the frame's axes,

    f_y = -m (g sin theta_x + V^2 kappa cos theta_x),   f_z = -m (g cos theta_x - V^2 kappa sin theta_x)

(against the -m g already in the system's force), the yaw and roll moments -I_z V^2 kappa'
and -I_x V^2 theta_x'', and each wheelset the gyroscopic roll moment I_y Omega V kappa of its
spin about the turning frame. The track elements and the ring are the ground's: no frame
force. The wheelsets' creepages take the frame's yaw rate V kappa (vehicle_contact).

Flexible wheelsets (variants FR and FF): the rigid part of each (its six DOFs, the whole
wheelset's mass and inertias, railvti.vehicle.wheelset_body) gets the frame's loads above, as
a rigid wheelset does; the free-free elastic modes are mass-orthogonal to the rigid motions,
so the frame's uniform acceleration fields do no work on them. The journal springs act on the
modal journal points through 'split' couplings k (g.q - u) + c (g.v - u'), whose g.q the
frames' offsets stretch as they stretch the rigid K: the points get k g.q_geo + c g.q_geo'
(``CurveTables.points``). The modes' Coriolis coupling with the wheelset's yaw rate ('gyro':
Omega g.v on the point) takes the frame's yaw rate V kappa too, as the rigid part's gyroscopic
moment does.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from .. import _checks
from .._native import core
from .._status import check
from ..errors import InputError
from ..track.curve import TrackCurve
from .assembly import System
from .params import Coach

__all__ = ["CurveTables", "attached_curve", "curve_tables", "TABLE_STEP"]

#: Spacing of the tables along the track, m (linear interpolation in between: the clothoid's
#: curvature is linear, so only the arc's ends are rounded over one step).
TABLE_STEP = 0.1

_BODY = re.compile(r"^(carbody|bolster\d|bogie\d|ws\d|track\d)_(\w+)$")


@dataclass(frozen=True)
class CurveTables:
    """The tables of one run (vehicle_curve), over s = s0 + i ds, m.

    Attributes
    ----------
    s0, ds : float
        First node and spacing, m.
    fext : ndarray (n, ns)
        Generalised forces on the system's DOFs, N or N m.
    doff, drate : ndarray (ne, ns)
        The nonlinear elements' deflection and rate offsets.
    kappa : ndarray (nw, ns)
        Curvature at each wheelset, 1/m.
    points : ndarray (np, ns), optional
        Forces on the modal part's attachment points (flexible wheelsets: the journal springs'
        share of the frames' offsets, the Coriolis coupling with the frame's yaw rate), N or
        N m; None without flexible wheelsets.
    """

    s0: float
    ds: float
    fext: np.ndarray
    doff: np.ndarray
    drate: np.ndarray
    kappa: np.ndarray
    points: np.ndarray | None = None


def _layout(system: System, coach: Coach) -> list[tuple[int, str, float, float]]:
    """(DOF index, component, x_B, h_B) of each vehicle-body DOF of the system (carbody,
    bolsters, bogie frames, wheelsets), from its DOF names and the coach's geometry."""
    p = coach.params
    xb = p["half_bogie_distance"]
    xw = np.array(
        [
            xb + p["half_wheelbase"],
            xb - p["half_wheelbase"],
            -xb + p["half_wheelbase"],
            -xb - p["half_wheelbase"],
        ]
    )
    if not np.allclose(np.asarray(system.x_wheelsets), xw, atol=1e-9):
        raise InputError(
            f"curve: the coach's wheelset positions {xw} m are not the system's {system.x_wheelsets} m "
            "(give the coach the system was built from)"
        )
    out = []
    for i, name in enumerate(system.dof_names):
        m = _BODY.match(name)
        if m is None:
            continue
        body, comp = m.groups()
        if body == "carbody":
            x, h = 0.0, p["carbody_cg_height"]
        elif body.startswith("bolster"):
            x, h = (xb if body[-1] == "1" else -xb), p["secondary_height"]
        elif body.startswith("bogie"):
            x, h = (xb if body[-1] == "1" else -xb), p["bogie_cg_height"]
        elif body.startswith("ws"):
            x, h = float(xw[int(body[2:]) - 1]), p["wheel_radius"]
        else:
            continue  # the track elements are the ground's
        out.append((i, comp, x, h))
    return out


def curve_tables(
    system: System, curve: TrackCurve, speed: float, s_first: float, s_last: float, coach: Coach | None = None
) -> CurveTables:
    """The tables of a run at ``speed`` (m/s) whose vehicle position s runs from ``s_first`` to
    ``s_last`` (m; module docstring for what they hold)."""
    coach = coach or Coach()
    v = _checks.positive("speed", speed)
    g = coach.params["gravity"]
    n_nodes = int(np.ceil((s_last - s_first) / TABLE_STEP)) + 2
    s = s_first - TABLE_STEP + TABLE_STEP * np.arange(n_nodes + 1)
    lay = _layout(system, coach)
    n = system.n
    qg = np.zeros((n, s.size))
    qgd = np.zeros((n, s.size))
    fict = np.zeros((n, s.size))
    mass = np.diag(system.m)
    eps = 1e-3

    def d_ds(f, x):
        return (f(x + eps) - f(x - eps)) / (2 * eps)

    th0, y0, r0 = curve.heading(s), curve.lateral(s), curve.roll(s)
    k0, rd0 = curve.curvature(s), d_ds(curve.roll, s)
    for i, comp, x, h in lay:
        sb = s + x
        thx = curve.roll(sb)
        kap = curve.curvature(sb)
        if comp == "y":
            qg[i] = curve.lateral(sb) - y0 - th0 * x - h * (thx - r0)
            qgd[i] = v * (curve.heading(sb) - th0 - k0 * x - h * (d_ds(curve.roll, sb) - rd0))
            fict[i] = -mass[i] * (g * np.sin(thx) + v * v * kap * np.cos(thx))
        elif comp == "z":
            fict[i] = -mass[i] * (g * np.cos(thx) - v * v * kap * np.sin(thx)) + mass[i] * g
        elif comp == "roll":
            qg[i] = thx - r0
            qgd[i] = v * (d_ds(curve.roll, sb) - rd0)
            # the cant ramp's kinks are impulses of roll acceleration: the second difference
            # over one table step spreads each over that step with the right integral
            d2 = (curve.roll(sb + TABLE_STEP) - 2 * thx + curve.roll(sb - TABLE_STEP)) / TABLE_STEP**2
            fict[i] = -mass[i] * v * v * d2
        elif comp == "yaw":
            qg[i] = curve.heading(sb) - th0
            qgd[i] = v * (kap - k0)
            fict[i] = -mass[i] * v * v * d_ds(curve.curvature, sb)
    kap_w = np.array([curve.curvature(s + x) for x in np.asarray(system.x_wheelsets)])
    iws_roll = np.asarray(system.iws)[2] - 1  # IWS_ROWS: y, z, roll, ...
    omega = v / coach.params["wheel_radius"]
    for w, j in enumerate(iws_roll):
        if j >= 0:  # the spin about the turning frame: roll + I_y Omega (V kappa)
            fict[j] += system.spin_inertia[w] * omega * v * kap_w[w]
    fext = -np.asarray(system.k) @ qg - np.asarray(system.c) @ qgd + fict
    eg = np.asarray(system.eg)
    return CurveTables(
        s0=float(s[0]),
        ds=TABLE_STEP,
        fext=np.asfortranarray(fext),
        doff=np.asfortranarray(eg.T @ qg),
        drate=np.asfortranarray(eg.T @ qgd),
        kappa=np.asfortranarray(kap_w),
        points=_point_forces(system, qg, qgd, v * kap_w),
    )


def _point_forces(system: System, qg: np.ndarray, qgd: np.ndarray, yaw_rate: np.ndarray) -> np.ndarray | None:
    """The forces (np, ns) on the attachment points of the system's flexible wheelsets from
    the frames' offsets qg, rates qgd (n, ns) and each wheelset frame's yaw rate (nw, ns,
    rad/s): a 'split' coupling (k, c) gets k g.qg + c g.qgd, a 'gyro' one (Omega) Omega g.w
    with w the frames' rates (yaw only, as the rigid wheelsets' gyroscopic moment). None
    without couplings."""
    mb = system.modal
    cpl = mb.couplings if mb is not None else None
    if cpl is None or len(cpl.kinds) == 0:
        return None
    w = np.zeros_like(qg)
    for i, j in enumerate(np.asarray(system.iws)[3] - 1):  # IWS_ROWS: y, z, roll, yaw, ...
        if j >= 0:
            w[j] = yaw_rate[i]
    g = np.asarray(cpl.directions)
    par = np.asarray(cpl.params)
    out = np.zeros((np.asarray(mb.phi).shape[0], qg.shape[1]))
    for e, kind in enumerate(cpl.kinds):
        if kind == "split":
            out[cpl.points[e]] += par[0, e] * (g[:, e] @ qg) + par[1, e] * (g[:, e] @ qgd)
        elif kind == "gyro":
            out[cpl.points[e]] += par[0, e] * (g[:, e] @ w)
    return np.asfortranarray(out)


@contextlib.contextmanager
def attached_curve(
    system: System,
    curve: TrackCurve | None,
    speed: float,
    x_start: float,
    duration: float,
    coach: Coach | None,
) -> Iterator[None]:
    """The system's Fortran model with the curve's tables attached for a run of ``duration``
    (s) at ``speed`` (m/s) from the vehicle position ``x_start`` (m), dropped afterwards (the
    model is shared by every later run of the system). No curve: nothing."""
    if curve is None:
        yield
        return
    if not isinstance(curve, TrackCurve):
        raise InputError(f"curve must be a railvti.track.TrackCurve, got {type(curve).__name__}")
    x0 = _checks.finite("x_start", x_start)
    tab = curve_tables(system, curve, speed, x0, x0 + speed * duration, coach)
    h = system.native.handle
    check(
        core.vehicle_curve_attach_c(h, tab.s0, tab.ds, x0, speed, tab.fext, tab.doff, tab.drate, tab.kappa),
        "curve tables",
    )
    if tab.points is not None:
        check(core.vehicle_curve_points_c(h, tab.points), "curve tables")
    try:
        yield
    finally:
        check(core.vehicle_curve_clear_c(h), "curve tables")
