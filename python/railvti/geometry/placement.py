"""Track and wheelset layout, and the placement of the profiles in track coordinates.

Track frame: x forward (rolling direction), y lateral to the LEFT, z UP; right-handed.
The left rail is at y > 0. Profiles are placed mirror-symmetrically: a profile's local
y (towards the field side) becomes track +y on the left and -y on the right.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from .. import _checks
from ..errors import InputError
from ..profiles import Profile

LEFT, RIGHT = 0, 1
SIDES = ("left", "right")
#: +1 on the left wheel/rail, -1 on the right: track y = sign * (offset + local y).
SIGN = (1.0, -1.0)


@dataclass(frozen=True)
class Track:
    """Track layout.

    Parameters
    ----------
    gauge : float
        Track gauge, m (1.435), between the rails' gauge faces ...
    gauge_depth : float
        ... measured this far below the top of rail, m (0.014).
    """

    gauge: float = 1.435
    gauge_depth: float = 0.014

    def __post_init__(self) -> None:
        object.__setattr__(self, "gauge", _checks.positive("gauge", self.gauge))
        object.__setattr__(self, "gauge_depth", _checks.non_negative("gauge_depth", self.gauge_depth))


@dataclass(frozen=True)
class WheelsetGeometry:
    """Wheelset layout.

    Parameters
    ----------
    back_to_back : float
        Distance between the inner faces (flange backs) of the wheels, m (1.360).
    radius : float
        Nominal rolling radius at the tread datum (wheel profile y = 0), m (0.46).
    flange_back : float
        Lateral distance from the flange back to the wheel profile's y = 0 (the tread
        datum), m; 0.070 for EN 13715 profiles such as S1002.
    """

    back_to_back: float = 1.360
    radius: float = 0.46
    flange_back: float = 0.070

    def __post_init__(self) -> None:
        for nm in ("back_to_back", "radius", "flange_back"):
            object.__setattr__(self, nm, _checks.positive(nm, getattr(self, nm)))

    @property
    def datum_offset(self) -> float:
        """Lateral distance from the wheelset centre to each wheel's tread datum, m."""
        return 0.5 * self.back_to_back + self.flange_back


@dataclass(frozen=True)
class Layout:
    """Wheel and rail profiles placed on the track (built by :func:`layout`; cached).

    Attributes
    ----------
    rail_offset : float
        Track |y| of the rail profile's local origin: track y = ±(rail_offset + y_local).
    rail_top : float
        Smallest rail z (the top of rail), m; rail height in track z is rail_top - z_rail.
    gauge_point : float
        Local y of the rail's gauge point (gauge_depth below the top), m.
    flange_climb_y : float
        Wheel-local y of the flange's steepest point (on the tip side); a contact beyond
        it (towards the tip) is flange climb.
    """

    wheel: Profile
    rail: Profile
    track: Track
    wheelset: WheelsetGeometry
    rail_offset: float
    rail_top: float
    gauge_point: float
    flange_climb_y: float
    max_flange_angle: float
    # dense samples used by the vectorised searches
    ws: np.ndarray = field(repr=False)      # wheel local y, m
    wz: np.ndarray = field(repr=False)      # wheel z (radius increase), m
    wdz: np.ndarray = field(repr=False)     # dz/dy of the wheel
    ry: np.ndarray = field(repr=False)      # rail local y, uniform 0.005 mm table, m
    rz: np.ndarray = field(repr=False)      # rail z on that table, m


_CACHE: dict[tuple[int, int, Track, WheelsetGeometry, float], Layout] = {}


def layout(wheel: Profile, rail: Profile, track: Track | None = None,
           wheelset: WheelsetGeometry | None = None, step: float = 5e-5) -> Layout:
    """Place the profiles on the track; results are cached per (profiles, layout, step)."""
    if not isinstance(wheel, Profile) or not isinstance(rail, Profile):
        raise InputError("wheel and rail must be railvti.profiles.Profile objects")
    if wheel.kind != "wheel":
        raise InputError(f"the wheel profile {wheel.name!r} is a {wheel.kind} profile")
    if rail.kind != "rail":
        raise InputError(f"the rail profile {rail.name!r} is a {rail.kind} profile")
    track = track or Track()
    wheelset = wheelset or WheelsetGeometry()
    key = (id(wheel), id(rail), track, wheelset, step)
    hit = _CACHE.get(key)
    if hit is not None and hit.wheel is wheel and hit.rail is rail:
        return hit
    # rail: uniform table, top, gauge point
    n = int(np.ceil((rail.y_max - rail.y_min) / 5e-6)) + 1
    ry = np.linspace(rail.y_min, rail.y_max, n)
    rz = rail.height(ry)
    top = float(rz.min())
    level = top + track.gauge_depth
    below = rz <= level
    if not below.any() or below[0]:
        raise InputError(f"the rail profile {rail.name!r} does not reach {track.gauge_depth * 1e3:.1f} mm "
                         "below its top on the gauge side: cannot place it at the gauge")
    i = int(np.argmax(below))
    yg = brentq(lambda t: float(rail.height(t)) - level, ry[i - 1], ry[i], xtol=1e-12)
    offset = 0.5 * track.gauge - yg
    # wheel samples
    ws, wz = wheel.sample(step)
    wdz = wheel.slope(ws)
    if wheelset.radius + wz.min() <= 0.0:
        raise InputError("wheel radius plus the profile's z is not positive somewhere")
    # flange climb point: steepest flange face point between the flange tip and the datum
    tip = int(np.argmax(wz))
    seg = slice(tip, int(np.searchsorted(ws, 0.0)) + 1)
    steep = -wdz[seg]
    if ws[tip] >= 0.0 or steep.size < 3 or steep.max() <= 0:
        raise InputError(f"the wheel profile {wheel.name!r} has no flange at negative y")
    kmax = int(np.argmax(steep >= 0.999 * steep.max()))
    out = Layout(wheel, rail, track, wheelset, rail_offset=offset, rail_top=top, gauge_point=yg,
                 flange_climb_y=float(ws[seg][kmax]), max_flange_angle=float(np.arctan(steep.max())),
                 ws=ws, wz=wz, wdz=wdz, ry=ry, rz=rz)
    if len(_CACHE) > 16:
        _CACHE.clear()
    _CACHE[key] = out
    return out
