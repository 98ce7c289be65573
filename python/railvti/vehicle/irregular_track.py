"""A vehicle on an irregular track: the irregularity (:class:`railvti.track.TrackIrregularity`)
sent to the Fortran model behind a System's handle for one run, and the rail inputs it gives
under each wheel (docs/vehicle_irregularity.md).

The core (fortran/vehicle/vehicle_irregularity.f90) reads the four channels by cubic Hermite
interpolation on the irregularity's own nodes, with the slopes :func:`node_slopes` gives, at
each wheelset's track position x_w(t) = x_start + v t + a_w (a_w: ``System.x_wheelsets``, the
leading wheelset ahead), and moves the track element under each wheel by

    T_y = alignment +- gauge / 2,  T_z = vertical level,  T_roll = cross level / CROSS_LEVEL_BASE

(+ left wheel), with the rates v dT/dx and the rail's yaw dT_y/dx, on top of the track
element's own motion (RR, FR) or the ring's rail head (RF, FF). The time loop sets them once per
(sub-)step at its end time; static solves and the force shims see t = 0.
"""

from __future__ import annotations

import contextlib
from typing import Iterator

import numpy as np

from .. import _checks
from .._native import core
from .._status import check
from ..errors import InputError
from ..track.irregularity import TrackIrregularity
from .assembly import System
from .equilibrium import wait_idle

__all__ = [
    "run_span",
    "CROSS_LEVEL_BASE",
    "INPUTS",
    "node_slopes",
    "check_irregularity",
    "check_coverage",
    "fade_in",
    "on_track",
    "rail_inputs",
    "source_of",
]

#: The base of the cross level (EN 13848-1: the distance of the rails' running circles for
#: standard gauge), m: the track element under the wheels rolls by cross level / base.
CROSS_LEVEL_BASE = 1.5

#: The inputs per wheel of :func:`rail_inputs` (second axis), SI units: the pose of the rail
#: element under the wheel (m, m, rad), its rates (m/s, m/s, rad/s), the rail's yaw (rad).
INPUTS = ("y", "z", "roll", "y_rate", "z_rate", "roll_rate", "yaw")


def node_slopes(x: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Slopes dc/dx at the nodes for the cubic Hermite interpolant: the derivative of the
    parabola through each node and its neighbours (one-sided at the ends; 2 nodes: the chord).

    Parameters
    ----------
    x : ndarray (n,)
        Strictly increasing nodes, m.
    c : ndarray (k, n)
        Values at the nodes.

    Returns
    -------
    ndarray (k, n)
    """
    x = np.asarray(x, dtype=float)
    c = np.atleast_2d(np.asarray(c, dtype=float))
    if x.size == 2:
        s = (c[:, 1] - c[:, 0]) / (x[1] - x[0])
        return np.stack([s, s], axis=1)
    h = np.diff(x)
    dc = np.diff(c, axis=1) / h
    d = np.empty_like(c)
    h0, h1 = h[:-1], h[1:]
    d[:, 1:-1] = (h1 * dc[:, :-1] + h0 * dc[:, 1:]) / (h0 + h1)
    d[:, 0] = dc[:, 0] - h[0] * (dc[:, 1] - dc[:, 0]) / (h[0] + h[1])
    d[:, -1] = dc[:, -1] + h[-1] * (dc[:, -1] - dc[:, -2]) / (h[-1] + h[-2])
    return d


def check_irregularity(irregularity: object) -> TrackIrregularity:
    """The irregularity itself; InputError naming it when it is not a TrackIrregularity."""
    if not isinstance(irregularity, TrackIrregularity):
        raise InputError(
            "irregularity must be a railvti.track.TrackIrregularity (x and the four channels in m), "
            f"got {type(irregularity).__name__}"
        )
    return irregularity


def check_coverage(
    system: System, irregularity: TrackIrregularity, speed: float, duration: float, x_start: float
) -> None:
    """InputError when a wheel would leave the irregularity during the run: the wheelsets run
    over x_start + a_w .. x_start + speed duration + a_w, m."""
    xw = np.asarray(system.x_wheelsets, dtype=float)
    lo = x_start + float(xw.min())
    hi = x_start + speed * duration + float(xw.max())
    x0, x1 = float(irregularity.x[0]), float(irregularity.x[-1])
    if lo < x0 or hi > x1:
        src = f" ({irregularity.source})" if irregularity.source else ""
        raise InputError(
            f"irregularity{src} covers x = {x0:.6g} .. {x1:.6g} m, but the wheels run over "
            f"{lo:.6g} .. {hi:.6g} m (x_start {x_start:.6g} m, {speed:.6g} m/s for {duration:.6g} s, "
            f"wheelsets at {xw.min():+.4g} .. {xw.max():+.4g} m in the coach): give a longer "
            "irregularity, another x_start or a shorter duration"
        )


def fade_in(irregularity: TrackIrregularity, x_from: float, length: float) -> TrackIrregularity:
    """The irregularity zero up to x_from and faded in by a raised cosine over the next
    ``length`` m (a lead-in: the coach starts on perfect track, from its static equilibrium).

    Parameters
    ----------
    irregularity : TrackIrregularity
    x_from : float
        Start of the fade, m.
    length : float
        Length of the fade, m (>= 0; 0: a step at x_from).
    """
    irr = check_irregularity(irregularity)
    x_from = _checks.finite("x_from", x_from)
    length = _checks.finite("lead_in", length)
    if length < 0.0:
        raise InputError(f"lead_in must be >= 0 m, got {length}")
    s = (irr.x - x_from) / length if length > 0.0 else np.where(irr.x >= x_from, 1.0, 0.0)
    fade = 0.5 - 0.5 * np.cos(np.pi * np.clip(s, 0.0, 1.0))
    src = irr.source or "TrackIrregularity (no source given)"
    return TrackIrregularity(
        irr.x,
        irr.vertical_level * fade,
        irr.alignment * fade,
        irr.cross_level * fade,
        irr.gauge * fade,
        source=f"{src}; lead-in: faded in over {length:.6g} m from x = {x_from:.6g} m",
    )


@contextlib.contextmanager
def on_track(
    system: System, irregularity: TrackIrregularity, speed: float, x_start: float = 0.0
) -> Iterator[None]:
    """Put the system's Fortran model on the irregular track for the block (static solves,
    forces and runs inside it see the irregularity; t = 0 at x_start), then back on the
    perfect track."""
    irr = check_irregularity(irregularity)
    speed = _checks.positive("speed", speed)
    x_start = _checks.finite("x_start", x_start)
    c = np.asfortranarray(irr.channels())
    d = np.asfortranarray(node_slopes(irr.x, c))
    xw = np.asarray(system.x_wheelsets, dtype=float)
    model = system.native
    wait_idle(system)  # an interrupted static solve may still run on the model: not under it
    info = core.vehicle_irregularity_attach_c(
        model.handle, irr.x.size, irr.x, c, d, xw, x_start, speed, CROSS_LEVEL_BASE
    )
    check(info, "irregular track")
    try:
        yield
    finally:
        wait_idle(system)
        if model.alive:
            z = np.zeros((4, 1), order="F")
            check(
                core.vehicle_irregularity_attach_c(
                    model.handle, 0, np.zeros(1), z, z, xw, 0.0, 1.0, CROSS_LEVEL_BASE
                ),
                "irregular track",
            )


def rail_inputs(system: System, t: np.ndarray) -> np.ndarray:
    """The irregular track's inputs under each wheel at times t (inside :func:`on_track`; zero
    outside it), as the time loop uses them.

    Returns
    -------
    ndarray (nt, 7, 2, nw)
        Per time, input (:data:`INPUTS`), wheel (0 left, 1 right) and wheelset.
    """
    model = system.native
    nw = int(system.iws.shape[1])
    out = []
    for ti in np.atleast_1d(np.asarray(t, dtype=float)):
        u, info = core.vehicle_irregularity_inputs_c(model.handle, float(ti), nw)
        check(info, "irregular track inputs")
        out.append(u)
    return np.array(out).reshape(-1, len(INPUTS), 2, nw)


def source_of(irregularity: TrackIrregularity, x_start: float) -> str:
    """The text a result stores of its track: the irregularity's source and the start."""
    src = irregularity.source or "TrackIrregularity (no source given)"
    return (
        f"{src}; x = {irregularity.x[0]:.6g} .. {irregularity.x[-1]:.6g} m, "
        f"{irregularity.x.size} samples; x_start = {x_start:.6g} m"
    )


def run_span(
    irregularity: TrackIrregularity,
    x_wheelsets: np.ndarray,
    speed: float,
    h: float,
    x_start: float | None = None,
    duration: float | None = None,
) -> tuple[float, float]:
    """The start and duration of a run over an irregularity: x_start (m) default the trailing
    wheelset at its start, duration (s) default a whole number of steps h until the leading
    wheelset reaches its end (InputError when the coach does not fit)."""
    xw = np.asarray(x_wheelsets, dtype=float)
    irr = irregularity
    x0 = float(irr.x[0]) - float(xw.min()) if x_start is None else _checks.finite("x_start", x_start)
    if duration is None:
        reach = (float(irr.x[-1]) - x0 - float(xw.max())) / speed
        duration = float(np.floor(reach / h * (1.0 - 1e-12)) * h)
        if duration < h:
            raise InputError(
                f"irregularity ({irr.source or 'no source'}) too short for a run: the coach "
                f"({xw.max() - xw.min():.4g} m between its wheelsets) does not fit on "
                f"x = {irr.x[0]:.6g} .. {irr.x[-1]:.6g} m from x_start {x0:.6g} m"
            )
    return x0, duration
