"""Accelerations of points on the coach's rigid bodies from a run's histories.

A :class:`~railvti.vehicle.SimulationResult` holds displacements ``q`` and velocities ``v``
of every DOF at its output times, not accelerations: they are the time derivative of ``v``
by second-order central differences (numpy.gradient, one-sided second order at the ends).
For a harmonic of frequency f sampled every dt the central difference returns the
amplitude times sin(w dt) / (w dt), w = 2 pi f: a relative error (w dt)^2 / 6, 0.26 % at
10 Hz and 1.05 % at 20 Hz for the default 2 ms output interval (:func:`derivative_error`).

A point (x, y, z) of a body whose reference point (its centre of gravity) is (x0, 0, z0)
moves laterally by y + psi (x - x0) - phi (z - z0) and vertically by z + phi y -
theta (x - x0) (small rotations roll phi, pitch theta, yaw psi about the track axes x
forward, y left, z up: railvti.vehicle.assembly._body_point).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["dof_acceleration", "point_acceleration", "derivative_error"]


def derivative_error(f: float, dt: float) -> float:
    """Relative amplitude error of the central-difference derivative of a harmonic of
    frequency ``f`` (Hz) sampled every ``dt`` (s): 1 - sin(w dt) / (w dt)."""
    x = 2.0 * math.pi * f * dt
    return 1.0 - math.sin(x) / x if x > 0 else 0.0


def dof_acceleration(result, name: str) -> np.ndarray:
    """Acceleration history (nt,) of DOF ``name`` (m/s^2 or rad/s^2): d v / d t."""
    names = tuple(result.dof_names)
    if name not in names:
        raise InputError(f"the run has no DOF {name!r} (its bodies' DOFs: see dof_names)")
    t = np.asarray(result.t, dtype=float)
    if t.size < 3:
        raise InputError(f"accelerations need at least 3 output times, the run has {t.size}")
    v = np.asarray(result.v, dtype=float)[:, names.index(name)]
    return np.gradient(v, t, edge_order=2)


def point_acceleration(result, body: str, ref: tuple, point: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Lateral and vertical acceleration (m/s^2) of ``point`` (x, y, z in m, track axes, z
    above the rail top) on ``body`` ('carbody', 'bogie1', 'bogie2') whose reference point
    is ``ref`` (x0, y0, z0): returns (a_y, a_z), each (nt,)."""
    rx, ry, rz = (point[i] - ref[i] for i in range(3))
    names = tuple(result.dof_names)

    def acc(c: str) -> np.ndarray:
        n = f"{body}_{c}"
        return dof_acceleration(result, n) if n in names else np.zeros(len(result.t))

    if f"{body}_y" not in names:
        raise InputError(f"the run has no body {body!r} (its DOFs: {', '.join(names[:12])}, ...)")
    roll, pitch, yaw = acc("roll"), acc("pitch"), acc("yaw")
    ay = acc("y") + yaw * rx - roll * rz
    az = acc("z") + roll * ry - pitch * rx
    return ay, az
