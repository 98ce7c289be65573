"""The wheel and rail profiles placed on the track: the track layout (gauge), the wheelset's
geometry (:class:`railvti.wheelset.WheelsetGeometry`: back-to-back, radius, tread datum) and
the placed profiles that the contact searches use.

Frame and sides: :mod:`railvti.geometry.frames`. The rail is placed so that its gauge point
(``gauge_depth`` below its top) lies at +-gauge/2; each wheel's tread datum (the wheel
profile's y = 0, the taping line) at +-``WheelsetGeometry.contact_y`` (half the back-to-back
plus ``contact_offset``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from .._roots import brent_root
from ..errors import InputError
from ..profiles import Profile
from ..wheelset.geometry import WheelsetGeometry


@dataclass(frozen=True)
class TrackLayout:
    """Where the rails stand: the track gauge and the depth at which it is measured.

    The rails' inclination (cant) is part of the rail profile (e.g.
    :func:`railvti.profiles.uic60`), not of the layout.

    Parameters
    ----------
    gauge : float
        Track gauge, m (1.435, standard gauge), between the rails' gauge faces ...
    gauge_depth : float
        ... measured this far below the top of rail, m (0.014; EN 13848-1).
    """

    gauge: float = 1.435
    gauge_depth: float = 0.014

    def __post_init__(self) -> None:
        object.__setattr__(self, "gauge", _checks.positive("gauge", self.gauge))
        object.__setattr__(self, "gauge_depth", _checks.non_negative("gauge_depth", self.gauge_depth))


@dataclass(frozen=True)
class ProfileLayout:
    """Wheel and rail profiles laid out on the track (built by :func:`layout`; cached).

    Attributes
    ----------
    wheel, rail : Profile
        The profiles (both wheels alike, both rails alike, mirrored left/right).
    track : TrackLayout
        Gauge.
    wheelset : WheelsetGeometry
        Back-to-back, nominal radius (``wheel_radius``) and tread datum (``contact_y``).
    rail_offset : float
        Track |y| of the rail profile's local origin: track y = ±(rail_offset + y_local).
    rail_top : float
        Smallest rail z (the top of rail), m; rail height in track z is rail_top - z_rail.
    gauge_point : float
        Local y of the rail's gauge point (gauge_depth below the top), m.
    flange_climb_y : float
        Wheel-local y of the flange's steepest point (on the tip side); a contact beyond
        it (towards the tip) is flange climb.
    max_flange_angle : float
        Steepest angle of the flange face, rad (about 70 degrees for S1002).
    ws, wz, wdz : ndarray
        Dense samples of the wheel profile: local y, z and dz/dy (the vectorised searches).
    ry, rz : ndarray
        The rail profile on a uniform 0.005 mm table of local y.
    """

    wheel: Profile
    rail: Profile
    track: TrackLayout
    wheelset: WheelsetGeometry
    rail_offset: float
    rail_top: float
    gauge_point: float
    flange_climb_y: float
    max_flange_angle: float
    ws: np.ndarray = field(repr=False)
    wz: np.ndarray = field(repr=False)
    wdz: np.ndarray = field(repr=False)
    ry: np.ndarray = field(repr=False)
    rz: np.ndarray = field(repr=False)


_CACHE: dict[tuple[int, int, TrackLayout, WheelsetGeometry, float], ProfileLayout] = {}
_DEFAULT_TRACK = TrackLayout()
_DEFAULT_WHEELSET = WheelsetGeometry()


def layout(
    wheel: Profile,
    rail: Profile,
    track: TrackLayout | None = None,
    wheelset: WheelsetGeometry | None = None,
    step: float = 5e-5,
) -> ProfileLayout:
    """Lay the profiles out on the track; results are cached per (profiles, layout, step).

    Parameters
    ----------
    wheel, rail : Profile
        Wheel profile (both wheels) and rail profile (both rails, already canted).
    track : TrackLayout, optional
        Gauge (default ``TrackLayout()``).
    wheelset : WheelsetGeometry, optional
        The wheelset (default ``WheelsetGeometry()``); the contact geometry uses its
        ``back_to_back``, ``wheel_radius`` and ``contact_offset``.
    step : float
        Sampling step of the wheel profile, m.

    Returns
    -------
    ProfileLayout

    Raises
    ------
    InputError
        Profiles of the wrong kind, a rail that does not reach the gauge depth on its gauge
        side, a wheel without a flange or a radius that the profile makes negative.
    """
    if not isinstance(wheel, Profile) or not isinstance(rail, Profile):
        raise InputError("wheel and rail must be railvti.profiles.Profile objects")
    if wheel.kind != "wheel":
        raise InputError(f"the wheel profile {wheel.name!r} is a {wheel.kind} profile")
    if rail.kind != "rail":
        raise InputError(f"the rail profile {rail.name!r} is a {rail.kind} profile")
    track = track or _DEFAULT_TRACK
    wheelset = wheelset or _DEFAULT_WHEELSET
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
        raise InputError(
            f"the rail profile {rail.name!r} does not reach {track.gauge_depth * 1e3:.1f} mm "
            "below its top on the gauge side: cannot place it at the gauge"
        )
    i = int(np.argmax(below))
    yg = brent_root(lambda t: float(rail.height(t)) - level, ry[i - 1], ry[i], xtol=1e-12)
    offset = 0.5 * track.gauge - yg
    # wheel samples
    ws, wz = wheel.sample(step)
    wdz = wheel.slope(ws)
    if wheelset.wheel_radius + wz.min() <= 0.0:
        raise InputError("wheel radius plus the profile's z is not positive somewhere")
    # flange climb point: steepest flange face point between the flange tip and the datum
    tip = int(np.argmax(wz))
    seg = slice(tip, int(np.searchsorted(ws, 0.0)) + 1)
    steep = -wdz[seg]
    if ws[tip] >= 0.0 or steep.size < 3 or steep.max() <= 0:
        raise InputError(f"the wheel profile {wheel.name!r} has no flange at negative y")
    kmax = int(np.argmax(steep >= 0.999 * steep.max()))
    out = ProfileLayout(
        wheel,
        rail,
        track,
        wheelset,
        rail_offset=offset,
        rail_top=top,
        gauge_point=yg,
        flange_climb_y=float(ws[seg][kmax]),
        max_flange_angle=float(np.arctan(steep.max())),
        ws=ws,
        wz=wz,
        wdz=wdz,
        ry=ry,
        rz=rz,
    )
    if len(_CACHE) > 16:
        _CACHE.clear()
    _CACHE[key] = out
    return out


__all__ = ["TrackLayout", "ProfileLayout", "layout"]
