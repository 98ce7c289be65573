"""A curve in the track's plan and cant: straight, clothoid transition, circular arc, clothoid
transition, straight.

Along the track (s, m, from the start of the route) the curvature rises linearly over the
entry transition (a clothoid), stays 1 / R over the arc and falls linearly over the exit
transition; the cant h (the outer rail's height over the inner one, m) ramps with it (a
straight-line cant ramp, the usual pairing with a clothoid). Conventions (the vehicle's frame:
x forward, y to the left, z up): ``radius > 0`` is a curve to the left (its centre at +y, the
right rail outer), ``radius < 0`` one to the right. The track's roll angle about x is
``theta_x = -sign(kappa) asin(h / rail_spacing)``: positive roll lifts the left rail, so a
left-hand curve, whose outer rail is the right one, rolls negatively.

The heading theta(s) = int kappa ds and the lateral position Y(s) = int theta ds (small
angles, in the frame of the route's start) are exact integrals of the piecewise-linear
curvature (:meth:`TrackCurve.heading`, :meth:`TrackCurve.lateral`).

Steady-state quantities: the unbalanced lateral acceleration in the canted track plane
``V^2 / R cos(phi) - g sin(phi)`` and its common approximation ``V^2 / R - g h / s``
(EN 13803: the cant deficiency ``I = s V^2 / (g R) - h``, m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["RAIL_SPACING", "TrackCurve"]

#: Distance between the rails' running circles (standard gauge), m: cant h over it gives the
#: cant angle (EN 13803 uses 1.5 m for 1435 mm gauge).
RAIL_SPACING = 1.5


@dataclass(frozen=True)
class TrackCurve:
    """One curve of the route (module docstring).

    Attributes
    ----------
    radius : float
        Radius of the circular arc, m; > 0 to the left, < 0 to the right; |R| >= 100 m.
    cant : float
        Cant h of the arc, m (>= 0; the outer rail raised), at most 0.2 m.
    transition_in, arc_length, transition_out : float
        Lengths of the entry clothoid, the arc and the exit clothoid, m (>= 0).
    start : float
        Where the entry transition begins, m along the track (the straight before it).
    rail_spacing : float
        Distance between the rails' running circles, m.
    """

    radius: float
    cant: float = 0.0
    transition_in: float = 0.0
    arc_length: float = 100.0
    transition_out: float = 0.0
    start: float = 0.0
    rail_spacing: float = RAIL_SPACING

    def __post_init__(self) -> None:
        r = _checks.finite("radius", self.radius)
        if abs(r) < 100.0:
            raise InputError(
                f"radius: |R| = {abs(r):g} m is below 100 m, the smallest curve a main-line coach is "
                "built for (its bogies' bump stops and the flange limit sharper ones)"
            )
        h = _checks.non_negative("cant", self.cant)
        if h > 0.2:
            raise InputError(f"cant: {h:g} m above 0.2 m (EN 13803's largest is 0.18-0.20 m)")
        for name in ("transition_in", "arc_length", "transition_out"):
            _checks.non_negative(name, getattr(self, name))
        _checks.finite("start", self.start)
        _checks.positive("rail_spacing", self.rail_spacing)

    @property
    def kappa(self) -> float:
        """Signed curvature of the arc, 1/m."""
        return 1.0 / self.radius

    @property
    def end(self) -> float:
        """Where the exit transition ends, m along the track."""
        return self.start + self.transition_in + self.arc_length + self.transition_out

    def _shape(self, s: np.ndarray) -> np.ndarray:
        """The fraction of the arc's curvature (and cant) at s: 0 - ramp - 1 - ramp - 0."""
        s = np.asarray(s, dtype=float)
        a = self.start
        b = a + self.transition_in
        c = b + self.arc_length
        d = c + self.transition_out
        up = np.clip((s - a) / self.transition_in, 0.0, 1.0) if self.transition_in > 0 else (s >= a) * 1.0
        down = np.clip((d - s) / self.transition_out, 0.0, 1.0) if self.transition_out > 0 else (s <= c) * 1.0
        return np.where(s < b, up, np.where(s > c, down, 1.0)) * (s >= a) * (s <= d)

    def curvature(self, s: np.ndarray | float) -> np.ndarray:
        """Signed curvature kappa(s), 1/m."""
        return self.kappa * self._shape(s)

    def cant_at(self, s: np.ndarray | float) -> np.ndarray:
        """Cant h(s), m (the outer rail's height over the inner one)."""
        return self.cant * self._shape(s)

    def roll(self, s: np.ndarray | float) -> np.ndarray:
        """The track's roll angle about x, rad: -sign(kappa) asin(h(s) / rail_spacing)."""
        return -math.copysign(1.0, self.radius) * np.arcsin(self.cant_at(s) / self.rail_spacing)

    def _integrals(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(int_start^s shape ds, int_start^s int shape ds ds) of the piecewise-linear shape."""
        s = np.asarray(s, dtype=float)
        knots = np.array(
            [
                self.start,
                self.start + self.transition_in,
                self.start + self.transition_in + self.arc_length,
                self.end,
            ]
        )
        vals = np.array([0.0, 1.0, 1.0, 0.0])
        i1 = np.zeros_like(s)
        i2 = np.zeros_like(s)
        c1 = 0.0  # the first integral at the segment's start
        c2 = 0.0  # the second integral there
        for k in range(3):
            x0, x1 = knots[k], knots[k + 1]
            f0, f1 = vals[k], vals[k + 1]
            L = x1 - x0
            slope = (f1 - f0) / L if L > 0 else 0.0
            u = np.clip(s - x0, 0.0, L)
            inside = s > x0
            # f = f0 + slope u: int f = f0 u + slope u^2/2; int int f = c1 u + f0 u^2/2 + slope u^3/6
            j1 = f0 * u + 0.5 * slope * u * u
            j2 = c1 * u + 0.5 * f0 * u * u + slope * u**3 / 6.0
            i1 = np.where(inside, c1 + j1, i1)
            i2 = np.where(inside, c2 + j2, i2)
            c2 = c2 + c1 * L + 0.5 * f0 * L * L + slope * L**3 / 6.0
            c1 = c1 + f0 * L + 0.5 * slope * L * L
        beyond = s > knots[-1]
        i2 = np.where(beyond, c2 + c1 * (s - knots[-1]), i2)
        i1 = np.where(beyond, c1, i1)
        return i1, i2

    def heading(self, s: np.ndarray | float) -> np.ndarray:
        """The track's heading theta(s) = int kappa ds, rad (0 on the straight before)."""
        return self.kappa * self._integrals(np.asarray(s, dtype=float))[0]

    def lateral(self, s: np.ndarray | float) -> np.ndarray:
        """The centreline's lateral position Y(s) = int theta ds, m (small angles; 0 before)."""
        return self.kappa * self._integrals(np.asarray(s, dtype=float))[1]

    def unbalanced_acceleration(self, speed: float, gravity: float = 9.81) -> float:
        """Lateral acceleration left over in the arc's canted track plane, m/s^2:
        V^2 / |R| cos(phi) - g sin(phi), phi = asin(h / rail_spacing); > 0 outwards."""
        phi = math.asin(self.cant / self.rail_spacing)
        return speed * speed / abs(self.radius) * math.cos(phi) - gravity * math.sin(phi)

    def cant_deficiency(self, speed: float, gravity: float = 9.81) -> float:
        """EN 13803's cant deficiency I = s V^2 / (g |R|) - h, m (speed in m/s)."""
        return self.rail_spacing * speed * speed / (gravity * abs(self.radius)) - self.cant
