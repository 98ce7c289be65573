"""Vehicle-track scenarios on straight track: centred running, hunting, critical speed.

Model 'RR': rigid wheelsets on the rigid track element (one per wheelset). Model 'FR'
(every scenario): the same with flexible rotating wheelsets (railvti.vehicle.flexible:
free-free elastic modes coupled through the rims and journals, docs/vehicle_integrator.md
"Flexible wheelsets (FR)"); its modal matrices depend on the spin, so it is built at each
speed (:func:`fr_system`) with the mode selection ``k_max``, ``f_max``. Model 'RF': rigid
wheelsets on the flexible ring track (railvti.vehicle.ring_coupling, docs/vehicle.md "Model
RF"), built per speed (:func:`rf_system`) with ``n_sleepers``, ``f_limit``,
``track_params``, ``x_offset``, ``ring_residual``. Model 'FF': the
flexible wheelsets on the ring (:func:`ff_system`, the keys of both). RF and FF also run in
``bifurcation`` and the nonlinear ``critical_speed``. Contact models:
'hertz-kalker' (Hertz + Kalker's linear theory with the Shen-Hedrick-Elkins saturation),
'hertz-fastsim' (Hertz + FASTSIM) and 'bem' (the BEM normal + steady-rolling solvers on
0.75 mm grids at every wheel, railvti.vehicle.bem). S1002 wheels on UIC60 rails inclined 1:40.

Examples
--------
>>> from railvti import scenarios
>>> c = scenarios.centred_running(speed_kmh=200)
>>> c.Q          # (2, 4) vertical wheel loads, N
>>> r = scenarios.hunting(400, duration=3.0, y0=0.004)
>>> r.y_ws1      # leading wheelset lateral displacement, m
>>> scenarios.critical_speed(method='linear').kmh    # km/h (float(...) works too)
"""
from __future__ import annotations

import contextlib
import logging
import warnings
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from . import _checks
from ._cluster import check_client, client_from
from ._threads import serial_blas
from .contact.fastsim import fastsim
from .errors import InputError
from .geometry import geometry_table as ctab
from .geometry import equivalent_conicity as eqc
from .profiles import s1002, uic60
from .track.ring import RingTrack
from .vehicle import output as _output
from .vehicle.assembly import System, build_coach
from .vehicle.flexible import build_fr, coach_body, mode_labels
from .vehicle.flexible_linear import eigenvalues as fr_eigenvalues
from .vehicle.flexible_points import rail_head_roll, rim_camber_change
from .vehicle.params import Coach, speed_m_s
from .vehicle.ring_coupling import build_rf, check_ring_length
from .vehicle.simulate import (WHEEL_OUTPUTS, SimulationResult, bem_state, check_modal_step, contact_id,
                               eigenvalues, lateral_disturbance, simulate, static_equilibrium)
from .vehicle.strip import strip_geometry
from .vehicle.table import WheelTable, linearised_table, wheel_table
from .wheelset import Wheelset
from .wheelset.residual import residual_table

log = logging.getLogger(__name__)

MODELS = ("RR", "FR", "RF", "FF")
#: Scenarios that run model FR.
_FR_SCENARIOS = ("centred_running", "coach_system", "hunting", "bifurcation", "critical_speed",
                 "linear_critical_speed")
#: Scenarios that run the models on the ring track, RF and FF.
RF_SCENARIOS = ("centred_running", "coach_system", "hunting", "bifurcation", "critical_speed",
                 "linear_critical_speed")
#: The models with flexible wheelsets (mode selection k_max, f_max) and on the ring track.
FLEXIBLE_WHEELSETS, RING_TRACK = ("FR", "FF"), ("RF", "FF")
#: Default ring of model RF: sleepers on the ring, kept ring modes up to f_limit (Hz).
RF_N_SLEEPERS, RF_F_LIMIT = 40, 500.0
#: Model RF's keys (the ring and its mode selection).
_RF_KEYS = ("n_sleepers", "f_limit", "track_params", "x_offset", "ring_residual",
            "ring_residual_hz", "ring_residual_inertia")
_RINGS: dict[Any, Any] = {}
#: Default mode selection of model FR: harmonics k <= 2, modes up to 800 Hz.
FR_K_MAX, FR_F_MAX = 2, 800.0
#: The highest harmonic model FR accepts (as the wheelset deck's k_max).
MAX_HARMONIC = 30
_PROFILES: dict[str, Any] = {}


def _profiles():
    if "wheel" not in _PROFILES:
        _PROFILES["wheel"] = s1002()
        _PROFILES["rail"] = uic60(cant=1.0 / 40.0)
    return _PROFILES["wheel"], _PROFILES["rail"]


#: The lateral range of the contact table on the ring track (models RF and FF), m: the
#: relative wheel-rail position there is the wheelset's plus the rail's lateral deflection and
#: roll under the flange (up to ~4.5 mm and ~14 mrad with the ring's residual flexibility in FF
#: flange hunting at 400 km/h), so the non-flanging wheel ran past the rigid track's
#: 15 mm (docs/vehicle.md, "Models RF and FF: limits").
RING_TABLE_Y_MAX = 0.020


def contact_table(y_max: float = 0.015) -> WheelTable:
    """The S1002 / UIC60 1:40 per-wheel contact table used by the scenarios (cached), over
    -y_max..y_max (m; the ring track's systems take :data:`RING_TABLE_Y_MAX`)."""
    w, r = _profiles()
    return wheel_table(w, r, y_max=y_max)


#: Contact geometries of the time simulation: the table's Hertz points, or the strip
#: potential (railvti.vehicle.strip).
GEOMETRIES = ("table", "strip")


#: The contact geometry of each contact model when none is given: the strip potential for the
#: Hertz models (the table's contact-point jumps sustain tread cycles that the strips and the
#: BEM do not have: docs/speed_accuracy.md), the table's gap fields for the BEM.
DEFAULT_GEOMETRY = {"hertz-kalker": "strip", "hertz-fastsim": "strip", "bem": "table"}


def resolve_geometry(contact: str, geometry: str | None) -> str:
    """The contact geometry of a run: ``geometry``, or the contact model's default
    (:data:`DEFAULT_GEOMETRY`) when None; checked against the contact model."""
    g = DEFAULT_GEOMETRY.get(contact, "strip") if geometry is None else geometry
    _check_geometry(contact, g)
    return g


def _system_geometry(geometry: str | None, linear_conicity: float | None = None) -> str:
    """A system builder's geometry: the given one, else the strips (the Hertz models'
    default; the BEM ignores them), or the table under a linearised table (a cone has no
    strips)."""
    if geometry is None:
        return "table" if linear_conicity is not None else "strip"
    return geometry


def _check_geometry(contact: str, geometry: str) -> None:
    """InputError for an unknown geometry or the strip geometry with the BEM contact."""
    if geometry not in GEOMETRIES:
        raise InputError(f"unknown contact geometry {geometry!r}: one of {GEOMETRIES}")
    if geometry == "strip" and contact == "bem":
        raise InputError("geometry='strip' is the geometry of 'hertz-kalker' and 'hertz-fastsim'; "
                         "the BEM contact reads the table's gap fields")


def _with_geometry(sy: System, geometry: str) -> System:
    """The system with the contact geometry ``geometry`` (GEOMETRIES)."""
    _check_geometry("", geometry)
    if geometry == "table":
        return sy
    if "strip" not in _PROFILES:
        w, r = _profiles()
        _PROFILES["strip"] = strip_geometry(w, r, material=sy.table.material)
    return replace(sy, strip=_PROFILES["strip"])


def equivalent_conicity(amplitude: float = 0.003) -> float:
    """EN 15302 equivalent conicity of S1002 / UIC60 1:40 at the given amplitude (m)."""
    w, r = _profiles()
    a = _checks.positive("amplitude", amplitude)
    y = np.linspace(-a - 1e-3, a + 1e-3, int(round((2 * a + 2e-3) / 5e-5)) + 1)
    return float(eqc(ctab(w, r, y), a))


def _speeds(speed_kmh: float | None, speed: float | None, default_kmh: float | None = None
            ) -> tuple[float, float]:
    """(m/s, km/h) from exactly one of ``speed`` (m/s, the SI argument) and ``speed_kmh`` (its
    suffixed alias), or the default (km/h) when neither is given."""
    if speed is not None and speed_kmh is not None:
        raise InputError("give the speed once: speed (m/s) or speed_kmh (km/h), not both")
    if speed is not None:
        v = _checks.finite("speed", speed)
        if not 0.0 < v <= _checks.MAX_SPEED:
            raise InputError(f"speed = {v:g} m/s must be in (0, {_checks.MAX_SPEED:.4g}] m/s")
        return v, v * 3.6
    if speed_kmh is None:
        if default_kmh is None:
            raise InputError("the speed is required: speed (m/s) or speed_kmh (km/h)")
        speed_kmh = default_kmh
    return speed_m_s(speed_kmh), float(speed_kmh)


def _fr_wheelset():
    """The FE wheelset of model FR (cached: its harmonic solves and statics are reused by
    every FR system built at another speed)."""
    if "wheelset" not in _PROFILES:
        _PROFILES["wheelset"] = Wheelset()
    return _PROFILES["wheelset"]


def check_fr_selection(k_max: Any, f_max: Any) -> tuple[int, float]:
    """(k_max, f_max) of model FR's mode selection, checked: k_max an integer harmonic in
    0..MAX_HARMONIC, f_max a positive finite frequency (Hz).

    Raises
    ------
    InputError
        Naming the bad value and what is allowed.
    """
    ok = False
    try:
        ok = (not isinstance(k_max, bool) and float(k_max).is_integer()
              and 0 <= int(k_max) <= MAX_HARMONIC)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise InputError(f"k_max = {k_max!r} is not a harmonic of the wheelset model: the "
                         f"highest circumferential harmonic of model FR's modes must be an "
                         f"integer in 0..{MAX_HARMONIC}")
    try:
        f = float(f_max)
    except (TypeError, ValueError):
        f = float("nan")
    if isinstance(f_max, bool) or not (np.isfinite(f) and f > 0.0):
        raise InputError(f"f_max = {f_max!r} must be a positive finite frequency, Hz (the "
                         "highest non-rotating frequency of model FR's kept modes)")
    return int(k_max), f


def _check_model(model: str, contact: str, scenario: str = "") -> None:
    if model not in MODELS:
        raise InputError(f"unknown model {model!r}: the time simulation has {MODELS}")
    if model in FLEXIBLE_WHEELSETS and scenario not in _FR_SCENARIOS:
        raise InputError(f"model {model!r} is not available in {scenario or 'this scenario'} "
                         f"yet (flexible wheelsets: only {_FR_SCENARIOS}); use model='RR'")
    if model in RING_TRACK and scenario not in RF_SCENARIOS:
        raise InputError(f"model {model!r} is not available in {scenario or 'this scenario'} "
                         f"yet (ring track: only {RF_SCENARIOS}); use model='RR'")
    contact_id(contact)


def coach_system(model: str = "RR", coach: Coach | None = None, *,
                 linear_conicity: float | None = None, speed_kmh: float | None = None,
                 k_max: int = FR_K_MAX, f_max: float = FR_F_MAX, speed: float | None = None,
                 geometry: str | None = None, follow_contact: bool = False, **rf: Any) -> System:
    """The assembled coach-track system; ``linear_conicity`` replaces the table by its
    equivalent linearisation (rolling radius linear in y, no flange).

    ``geometry`` is the contact geometry of the Hertz + Kalker and Hertz + FASTSIM contacts:
    'strip' (default: the strip potential over the whole interpenetration,
    :mod:`railvti.vehicle.strip`; exactly conservative, no jumps) or 'table' (one Hertz point
    per slot at the table's lowest gap: the fast option, whose contact-point jumps sustain
    spurious tread cycles). The BEM contact always reads the table. Default under
    ``linear_conicity``: 'table'.

    Model 'FR' (flexible wheelsets, :func:`fr_system`) needs the speed, ``speed`` (m/s) or
    ``speed_kmh`` (its modal matrices depend on the spin), and takes the mode selection
    ``k_max``, ``f_max`` (Hz); the state is then the DOFs followed by the modal coordinates.
    Model 'RF' (the ring track, :func:`rf_system`) needs the speed too and takes
    ``n_sleepers``, ``f_limit``, ``track_params`` and ``x_offset``; model 'FF' (flexible
    wheelsets on the ring, :func:`ff_system`) takes the keys of both. Models 'FR' and 'FF'
    take ``follow_contact`` (the rims' rows follow the contact point, :func:`fr_system`).
    """
    _check_model(model, "hertz-kalker", "coach_system")
    if follow_contact and model not in FLEXIBLE_WHEELSETS:
        raise InputError(f"follow_contact: a key of models 'FR' and 'FF' (flexible wheelsets); "
                         f"model {model!r} has rigid wheelsets")
    geometry = _system_geometry(geometry, linear_conicity)
    if model in RING_TRACK:
        if speed is None and speed_kmh is None:
            raise InputError(f"model {model!r} needs the speed, speed (m/s) or speed_kmh (the "
                             "contact points move along the ring at it)")
        if linear_conicity is not None:
            raise InputError(f"model {model!r} has no linearised table (linear_conicity)")
        if model == "FF":
            return ff_system(coach, speed_kmh=speed_kmh, speed=speed, k_max=k_max, f_max=f_max,
                             geometry=geometry, follow_contact=follow_contact, **rf)[0]
        if (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
            _no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
        return rf_system(coach, speed_kmh=speed_kmh, speed=speed, geometry=geometry, **rf)
    if rf:
        raise InputError(f"{', '.join(sorted(rf))}: not a key of model {model!r} "
                         f"(models 'RF' and 'FF' take {_RF_KEYS})")
    if model == "FR":
        if speed is None and speed_kmh is None:
            raise InputError("model 'FR' needs the speed, speed (m/s) or speed_kmh (the modes "
                             "depend on the spin)")
        return fr_system(coach, speed_kmh=speed_kmh, speed=speed, k_max=k_max, f_max=f_max,
                         linear_conicity=linear_conicity, geometry=geometry,
                         follow_contact=follow_contact)[0]
    tab = contact_table()
    if linear_conicity is not None:
        _linear_table_geometry(geometry)
        tab = linearised_table(tab, linear_conicity)
    return _with_geometry(build_coach(coach or Coach(), tab), geometry)


def _linear_table_geometry(geometry: str) -> None:
    if geometry != "table":
        raise InputError("linear_conicity replaces the profiles by a cone: it has no strip "
                         "geometry (geometry='table')")


def fr_system(coach: Coach | None = None, *, speed_kmh: float | None = None,
              speed: float | None = None, k_max: int = FR_K_MAX, f_max: float = FR_F_MAX,
              linear_conicity: float | None = None, geometry: str | None = None,
              follow_contact: bool = False) -> tuple[System, list]:
    """Model FR at one speed: the coach with four flexible wheelsets and their layouts.

    Parameters
    ----------
    coach : Coach, optional
    speed_kmh, speed : float
        The speed, km/h or m/s (exactly one): the spin Omega = speed / r0 enters the modal
        matrices (gyroscopic and centrifugal terms), so a speed sweep builds one per speed.
    k_max, f_max : int, float
        Mode selection: harmonics 0..k_max, non-rotating frequencies up to f_max (Hz); the
        truncated modes stay as residual flexibility.
    linear_conicity : float, optional
        Replace the contact table by its equivalent linearisation (linear analyses).
    geometry : str
        Contact geometry, 'strip' (default) or 'table' (:func:`coach_system`).
    follow_contact : bool
        The rims' rows and residual flexibility follow each wheel's contact point along the
        profile in the time loop (Kaiser eq. 3; ``build_fr``'s ``follow_contact``; the
        residual's 5 mm table is made once per speed, about 30 s).

    Returns
    -------
    System, list of railvti.vehicle.flexible.FRLayout
        The layouts carry the mode labels (``labels``, ``k``, ``family``, ``freq_hz``).
    """
    v, _ = _speeds(speed_kmh, speed)
    k_max, f_max = check_fr_selection(k_max, f_max)
    geometry = _system_geometry(geometry, linear_conicity)
    tab = contact_table()
    if linear_conicity is not None:
        _linear_table_geometry(geometry)
        tab = linearised_table(tab, linear_conicity)
    sy, lays = _fr_build(coach or Coach(), tab, v, k_max, f_max, follow_contact=follow_contact)
    return _with_geometry(sy, geometry), lays


def _fr_build(coach: Coach, table: WheelTable, v: float, k_max: int, f_max: float, *,
              track: bool = True, follow_contact: bool = False) -> tuple[System, list]:
    """build_fr on the scenarios' cached FE wheelset (scaled by the coach's
    wheelset_stiffness_scale); with follow_contact, the residual's 5 mm table over the contact
    points made once per speed and selection (about 30 s)."""
    if not follow_contact:
        return build_fr(coach, table, v, wheelset=_fr_wheelset(), k_max=k_max, f_max=f_max,
                        track=track)
    ws, body = coach_body(coach, _fr_wheelset(), v, k_max, f_max)
    key = ("residual_grid", float(v), k_max, float(f_max), coach["wheelset_stiffness_scale"])
    if key not in _PROFILES:
        _PROFILES[key] = residual_table(ws, body)
    return build_fr(coach, table, v, wheelset=ws, body=body, follow_contact=True,
                    residual_grid=_PROFILES[key], track=track)


def _ring(n_sleepers: Any, track_params: dict | None):
    """The ring track of model RF (cached per n_sleepers and parameters)."""
    n = _checks.positive_int("n_sleepers", n_sleepers, minimum=2)
    tp = dict(track_params or {})
    key = (n, tuple(sorted((k, repr(v)) for k, v in tp.items())))
    if key not in _RINGS:
        _RINGS.clear()          # one ring at a time: they are large
        _RINGS[key] = RingTrack(n, **tp)
    return _RINGS[key]


def rf_system(coach: Coach | None = None, *, speed_kmh: float | None = None,
              speed: float | None = None, n_sleepers: int = RF_N_SLEEPERS,
              f_limit: float | None = RF_F_LIMIT, track_params: dict | None = None,
              x_offset: float = 0.0, geometry: str | None = None, ring_residual: bool = True,
              ring_residual_hz: float | None = None, ring_residual_inertia: bool = False):
    """Model RF at one speed: the coach's rigid wheelsets on the flexible ring track.

    Parameters
    ----------
    coach : Coach, optional
    speed_kmh, speed : float
        The speed, km/h or m/s (exactly one): the wheels' contact points move along the ring
        at it.
    n_sleepers : int
        Sleepers on the ring (length n_sleepers x spacing; the paper's is 128); the ring must
        hold the wheelsets' span plus two sleeper bays.
    f_limit : float or None
        Keep the ring modes up to this frequency, Hz (None: all the ring's modes).
    track_params : dict, optional
        Parameters of :class:`railvti.track.RingTrack` (physics and numerics).
    x_offset : float
        The coach centre's position along the ring at t = 0, m.
    geometry : str
        Contact geometry, 'strip' (default) or 'table' (:func:`coach_system`).
    ring_residual : bool
        Keep the truncated ring modes' static compliance at the contact points (residual
        flexibility, massless coordinates; default). False drops it: the rail under a wheel
        is then stiffer than the ring by the truncated modes' share (docs/vehicle.md,
        "Model RF"); runs with flange-only contact at 400 km/h need it off or massive today
        (a Newton failure with the massless coordinates, docs/vehicle.md "Models RF and FF:
        limits").
    ring_residual_hz : float, optional
        Give the residual coordinates a mass: each contact point's block at this natural
        frequency, Hz, with the same static compliance
        (:func:`railvti.vehicle.ring_coupling.build_rf`'s ``residual_hz``); the default step
        then resolves it. None (default): massless.
    ring_residual_inertia : bool
        Give the residual coordinates the truncated ring modes' own inertia and damping
        (:func:`railvti.vehicle.ring_coupling.build_rf`'s ``residual_inertia``): the rail's
        point receptance then follows the full ring to f_limit / 2 within 1 %
        (docs/vehicle.md, "Residual inertia of the ring"). Default False: massless.

    Returns
    -------
    railvti.vehicle.ring_coupling.RingSystem

    Raises
    ------
    InputError
        A ring too short for the coach (checked before it is built), no ring mode up to
        f_limit, bad track parameters.
    """
    v, _ = _speeds(speed_kmh, speed)
    sy, _ = _on_ring("RF", coach or Coach(), contact_table(RING_TABLE_Y_MAX), v, n_sleepers=n_sleepers,
                     f_limit=f_limit, track_params=track_params, x_offset=x_offset,
                     ring_residual=ring_residual, ring_residual_hz=ring_residual_hz,
                     ring_residual_inertia=ring_residual_inertia)
    return _with_geometry(sy, _system_geometry(geometry))


def _on_ring(model: str, coach: Coach, table: WheelTable, v: float, *, k_max: int = FR_K_MAX,
             f_max: float = FR_F_MAX, n_sleepers: Any = RF_N_SLEEPERS,
             f_limit: float | None = RF_F_LIMIT, track_params: dict | None = None,
             x_offset: float = 0.0, ring_residual: bool = True,
             ring_residual_hz: float | None = None,
             ring_residual_inertia: bool = False,
             fr_base: tuple | None = None, follow_contact: bool = False
             ) -> tuple[System, list]:
    """Model RF or FF on ``table`` at v (m/s), without the speed bound of the scenarios (the
    linear method's bisection may pass it): the ring checked and built (cached), FR's
    wheelsets on rigid ground for FF (``fr_base``: that (system, layouts) already built at v),
    the ring's block appended. Returns (system, FR layouts or [])."""
    track = _checked_ring(coach, n_sleepers, track_params)
    base, lays = None, []
    if model == "FF" and fr_base is not None:
        base, lays = fr_base
    elif model == "FF":
        base, lays = _fr_build(coach, table, v, k_max, f_max, track=False,
                               follow_contact=follow_contact)
    sy = build_rf(coach, table, v, track, f_limit=f_limit, x_offset=x_offset, base=base,
                  residual=bool(ring_residual), residual_hz=ring_residual_hz,
                  residual_inertia=bool(ring_residual_inertia))
    return sy, lays


def _checked_ring(coach: Coach, n_sleepers: Any, track_params: dict | None):
    """The ring of n_sleepers bays, its length checked against the coach before it is built."""
    n = _checks.positive_int("n_sleepers", n_sleepers, minimum=2)
    spacing = dict(track_params or {}).get("sleeper_spacing", 0.6)
    check_ring_length(n, spacing, coach)
    return _ring(n, track_params)


def ff_system(coach: Coach | None = None, *, speed_kmh: float | None = None,
              speed: float | None = None, k_max: int = FR_K_MAX, f_max: float = FR_F_MAX,
              n_sleepers: int = RF_N_SLEEPERS, f_limit: float | None = RF_F_LIMIT,
              track_params: dict | None = None, x_offset: float = 0.0,
              geometry: str | None = None, ring_residual: bool = True,
              ring_residual_hz: float | None = None,
              ring_residual_inertia: bool = False,
              follow_contact: bool = False) -> tuple[System, list]:
    """Model FF at one speed: the coach's flexible rotating wheelsets on the ring track.

    The FR system on rigid ground (:func:`fr_system`'s wheelsets: mode selection ``k_max``,
    ``f_max``, residual flexibility at the rims and journals) with the ring's modal block
    appended (:func:`rf_system`'s ring: ``n_sleepers``, ``f_limit``, ``track_params``,
    ``x_offset``, ``ring_residual``, ``ring_residual_hz``, ``ring_residual_inertia``). Each
    wheel's contact is evaluated between its deformed
    rim and the ring's rail head under it (vehicle_model%add_contact with both the rim and
    the rail points); nothing couples the two flexible bodies but the contact.
    ``follow_contact``: the rims' rows follow the contact point (:func:`fr_system`).

    Returns
    -------
    railvti.vehicle.ring_coupling.RingSystem, list of railvti.vehicle.flexible.FRLayout
        State: the coach's DOFs, the wheelsets' modal and residual coordinates, then the ring's
        modes and residual coordinates (the layouts' slices stay valid).

    Raises
    ------
    InputError
        As :func:`fr_system` and :func:`rf_system`.
    """
    v, _ = _speeds(speed_kmh, speed)
    k_max, f_max = check_fr_selection(k_max, f_max)
    sy, lays = _on_ring("FF", coach or Coach(), contact_table(RING_TABLE_Y_MAX), v, k_max=k_max, f_max=f_max,
                        n_sleepers=n_sleepers, f_limit=f_limit, track_params=track_params,
                        x_offset=x_offset, ring_residual=ring_residual,
                        ring_residual_hz=ring_residual_hz,
                        ring_residual_inertia=ring_residual_inertia,
                        follow_contact=bool(follow_contact))
    return _with_geometry(sy, _system_geometry(geometry)), lays


@dataclass(frozen=True)
class CentredRunning:
    """Centred running: static equilibrium and a short run from it.

    Attributes
    ----------
    Q, Y : ndarray (2, 4)
        Vertical and lateral (track y, + left) wheel forces at the end of the run,
        [wheel 0 left / 1 right, wheelset], N.
    static_wheel_load : float
        Weight of the coach / 8, N.
    q_static : ndarray
        Static equilibrium state.
    run : SimulationResult
    patch : FastsimResult or BemPatch
        The leading wheelset's right contact patch at the end of the run (the paper's
        Figs 11-14). contact='bem': the BEM fields themselves (pressure, tractions, slip
        velocity, friction power density on the 0.75 mm grid). Otherwise: Hertz pressure,
        FASTSIM tractions, slip and friction power density on a 40 x 40 strip grid of the
        Hertz ellipse, from the run's normal force, semi-axes and creepages.
    model : str
        'RR', 'FR' or 'RF'.
    rim_angle : ndarray (2, 4) or None
        Models FR and FF: the change of the rim-rail relative angle at the end of the run,
        rad [wheel, wheelset]: rim_camber - rail_roll (+: the inner edge, towards the track
        centre, rises; railvti.vehicle.flexible.rim_rail_angle_change); None for RR and RF.
    rim_camber : ndarray (2, 4) or None
        Models FR and FF: the rims' elastic camber alone, rad, same convention
        (railvti.vehicle.flexible.rim_camber_change); None for RR and RF.
    rail_roll : ndarray (2, 4) or None
        Models FR and FF: the rail head's elastic roll under each wheel, rad, same convention
        (railvti.vehicle.flexible.rail_head_roll; zero on FR's rigid track); None otherwise.
    rail : ndarray (nt, 3, 2, 4) or None
        Model RF: the rail head's motion under each wheel at the run's outputs, the pose
        (y m, z m, roll rad) of the element under wheel [., ., wheel, wheelset] in the
        vehicle's frame (RingSystem.rail_deflection); None otherwise.
    """

    Q: np.ndarray
    Y: np.ndarray
    static_wheel_load: float
    q_static: np.ndarray
    run: SimulationResult
    speed_kmh: float
    contact: str
    patch: Any = None
    model: str = "RR"
    rim_angle: np.ndarray | None = None
    rail: np.ndarray | None = None
    rim_camber: np.ndarray | None = None
    rail_roll: np.ndarray | None = None

    @property
    def q_error(self) -> float:
        """max |Q / static load - 1| over the eight wheels."""
        return float(np.max(np.abs(self.Q / self.static_wheel_load - 1.0)))


def centred_running(speed_kmh: float | None = None, model: str = "RR",
                    contact: str = "hertz-kalker", *, speed: float | None = None,
                    duration: float = 1.0, h: float | None = None, coach: Coach | None = None,
                    **kw: Any) -> CentredRunning:
    """Centred running on straight ideal track: the steady state and Q, Y per wheel.

    Parameters
    ----------
    speed_kmh : float, optional
        Speed, km/h (> 0): the suffixed alias of ``speed``; default 200 km/h.
    model, contact : str
        'RR', 'FR' or 'RF'; 'hertz-kalker', 'hertz-fastsim' or 'bem'.
    speed : float, optional
        Speed, m/s (give it or speed_kmh, not both).
    duration : float
        Simulated time after the static equilibrium, s.
    h : float, optional
        Time step, s (default 1 ms; model FR: 1 ms divided into as many parts as the highest
        kept mode needs, h omega_max <= 2).
    coach : Coach, optional
        Vehicle parameters (default: Manchester benchmark coach).
    **kw
        Passed to simulate; model FR also takes k_max and f_max (Hz), the mode selection;
        model RF n_sleepers, f_limit, track_params, x_offset (:func:`rf_system`).
        ``output_dt`` (s): the interval of the stored history. Default: 10 ms, shortened
        so that the known periodic excitations get 10 samples per period each
        (railvti.vehicle.output): the sleeper passing v / sleeper spacing on the ring track
        (RF, FF: 1 ms at 200 km/h on 0.6 m with the 0.5 ms step) and hunting; the elastic
        modes only when asked with a finer ``output_dt``. A given ``output_dt`` coarser
        than the Nyquist limit of one of them gives an AliasingWarning.
    """
    v, speed_kmh = _speeds(speed_kmh, speed, 200.0)
    _check_model(model, contact, "centred_running")
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy = _system(model, coach, speed_kmh, kw)
    h = _step(sy, h)
    kw["output_dt"] = _output_dt(sy, v, h, kw.get("output_dt"), 0.01)
    if contact == "bem":
        with bem_state(sy, kw.pop("bem_options", None)) as st:
            q0, v0, _ = static_equilibrium(sy, v, contact, bem=st, return_velocity=True)
            run = simulate(sy, v, duration, contact=contact, h=h, q0=q0, v0=v0, bem=st, **kw)
        patch = (run.bem_patches or {}).get((0, 1))
    else:
        q0, v0, _ = static_equilibrium(sy, v, contact, return_velocity=True)
        run = simulate(sy, v, duration, contact=contact, h=h, q0=q0, v0=v0, **kw)
        patch = contact_patch(sy, run, -1, wheel=1, wheelset=0)
    rim = camber = roll = None
    if model in FLEXIBLE_WHEELSETS:
        camber = rim_camber_change(sy, run.q[-1])
        roll = rail_head_roll(sy, run.q[-1], run.t[-1])
        rim = camber - roll
    rail = None
    if model in RING_TRACK:
        rail = sy.rail_deflection(run.t, run.q)
    return CentredRunning(Q=run.Q[-1], Y=run.Y[-1], static_wheel_load=sy.wheel_load, q_static=q0,
                          run=run, speed_kmh=float(speed_kmh), contact=contact, patch=patch,
                          model=model, rim_angle=rim, rail=rail, rim_camber=camber,
                          rail_roll=roll)


def contact_patch(system: System, run: SimulationResult, index: int = -1, *, wheel: int = 1,
                  wheelset: int = 0, n: int = 40):
    """FASTSIM fields (Hertz pressure) of one wheel's more loaded contact point at output
    ``index`` of a run: pressure, tractions, slip, friction power density."""
    w = run.wheel[index, :, wheel, wheelset]
    fn = max(w[WHEEL_OUTPUTS.index("N_tread")], w[WHEEL_OUTPUTS.index("N_flange")])
    if fn <= 0:
        return None
    return fastsim(w[WHEEL_OUTPUTS.index("a")], w[WHEEL_OUTPUTS.index("b")], fn, system.table.material, system.friction,
                   (w[WHEEL_OUTPUTS.index("xi")], w[WHEEL_OUTPUTS.index("eta")], w[WHEEL_OUTPUTS.index("spin")]), nx=n, ny=n,
                   speed=run.speed, pressure="hertz")


def hunting(speed_kmh: float | None = None, model: str = "RR", contact: str = "hertz-kalker", *,
            speed: float | None = None, duration: float = 5.0, y0: float = 0.004, h: float | None = None,
            output_dt: float | None = None, alpha: float = 0.0, coach: Coach | None = None,
            q0: np.ndarray | None = None, v0: np.ndarray | None = None,
            **kw: Any) -> SimulationResult:
    """Hunting test: the leading bogie's wheelsets shifted by y0, then released.

    Returns the SimulationResult (``t``, ``y_ws1``, ``vy_ws1``, ``q``, ``Q``, ``Y``, ...).
    ``q0``/``v0`` continue from a given state instead (speed sweeps); on the ring track (RF,
    FF) the ring's rows start at ``x_offset``, so a state carried from a run of duration T
    at speed v continues only with ``x_offset`` advanced by v T (modulo the ring's length:
    critical_search does this), not from 0. ``h`` defaults to 1 ms
    (RR) or, for model 'FR', to 1 ms divided so that h omega_max <= 2 for the highest kept mode
    (as centred_running); model 'FR' also takes ``k_max`` and ``f_max`` (Hz). The speed is
    ``speed`` in m/s or its suffixed alias ``speed_kmh`` in km/h (exactly one).
    ``output_dt`` (s) defaults to 2 ms, shortened so that the known periodic excitations get
    10 samples per period each (railvti.vehicle.output: hunting, and the sleeper passing on
    the ring track, RF and FF); a given one that aliases either gives an AliasingWarning.
    """
    v, speed_kmh = _speeds(speed_kmh, speed)
    _check_model(model, contact, "hunting")
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy = _system(model, coach, speed_kmh, kw)
    h = _step(sy, h)
    output_dt = _output_dt(sy, v, h, output_dt, 0.002)
    if q0 is None:
        qs, _ = static_equilibrium(sy, v, contact, bem_options=kw.get("bem_options"))
        q0 = lateral_disturbance(sy, qs, _checks.finite("y0", y0), wheelsets=(0, 1))
    return simulate(sy, v, duration, contact=contact, h=h, output_dt=output_dt, alpha=alpha,
                    q0=q0, v0=v0, **kw)


def _system(model: str, coach: Coach | None, speed_kmh: float, kw: dict) -> System:
    """The scenario's system: RR, or FR, RF, FF at this speed with their keys (the mode
    selection, the ring's) popped from kw."""
    geometry = kw.pop("geometry", None)
    follow = {"follow_contact": kw.pop("follow_contact")} if "follow_contact" in kw else {}
    if model in RING_TRACK:
        rf = {k: kw.pop(k) for k in _RF_KEYS if k in kw}
        if model == "RF":
            _no_fr_keys(kw)
        else:
            rf.update(k_max=kw.pop("k_max", FR_K_MAX), f_max=kw.pop("f_max", FR_F_MAX))
        return coach_system(model, coach, speed_kmh=speed_kmh, geometry=geometry, **follow, **rf)
    extra = sorted(k for k in _RF_KEYS if k in kw)
    if extra:
        raise InputError(f"{', '.join(extra)}: keys of models 'RF' and 'FF' (the ring track); "
                         f"model {model!r} has none")
    if model == "FR":
        return coach_system(model, coach, speed_kmh=speed_kmh, k_max=kw.pop("k_max", FR_K_MAX),
                            f_max=kw.pop("f_max", FR_F_MAX), geometry=geometry, **follow)
    _no_fr_keys(kw)
    return coach_system(model, coach, geometry=geometry, **follow)


def _no_fr_keys(kw: dict) -> None:
    """InputError for model FR's mode selection given to model RR."""
    extra = sorted(k for k in ("k_max", "f_max") if k in kw)
    if extra:
        raise InputError(f"{', '.join(extra)}: the mode selection of models 'FR' and 'FF'; "
                         "models 'RR' and 'RF' have rigid wheelsets (no modes)")


def _default_step(sy: System) -> float:
    """1 ms, divided for a modal model so that h omega_max <= 2 (every kept mode resolved by the
    trapezoidal rule without the step-size refusal of simulate)."""
    h = 1e-3
    if sy.modal is not None:
        h = 1e-3 / np.ceil(1e-3 * sy.modal.max_frequency() / 2.0)
    return h


def _step(sy: System, h: float | None) -> float:
    """The time step of a run of sy: h checked against the kept modes
    (:func:`railvti.vehicle.simulate.check_modal_step`, before any work), or the default."""
    if h is None:
        return _default_step(sy)
    h = _checks.positive("h", h)
    check_modal_step(sy, h)
    return h


def hunting_conicity() -> float:
    """The equivalent conicity at 3 mm of the profiles (computed once, ~0.6 s)."""
    if "conicity" not in _PROFILES:
        _PROFILES["conicity"] = equivalent_conicity(0.003)
    return _PROFILES["conicity"]


def _excitations(sy: System, v: float) -> list:
    """The known periodic excitations of a run of sy at v (m/s), railvti.vehicle.output:
    hunting (Klingel's frequency at the profiles' equivalent conicity at 3 mm), and on the
    ring track the sleeper passing."""
    out = [_output.hunting(v, hunting_conicity(), float(sy.table.r0))]
    ring = getattr(sy, "ring", None)
    if ring is not None:
        out.append(_output.sleeper_passing(v, float(ring.bay)))
    return out


def _output_dt(sy: System, v: float, h: float, output_dt: float | None, base: float,
               check: bool = True) -> float:
    """The output interval of a run of sy at v (m/s) with step h: the given ``output_dt``
    (an AliasingWarning when it aliases a known excitation, unless ``check`` is False) or
    the scene's ``base`` shortened to resolve the excitations (railvti.vehicle.output)."""
    if output_dt is not None and not check:
        return _checks.positive("output_dt", output_dt)
    return _output.output_interval(output_dt, h, _excitations(sy, v), base)


#: The window of :func:`amplitude` (s): a run's amplitude is that of its last second.
AMPLITUDE_WINDOW = 1.0


def amplitude(res: SimulationResult, window: float = AMPLITUDE_WINDOW) -> float:
    """Half the peak-to-peak leading wheelset lateral displacement over the last window, m."""
    k = res.t >= res.t[-1] - window
    return 0.5 * float(np.ptp(res.y_ws1[k]))


@dataclass(frozen=True)
class Bifurcation:
    """Limit-cycle amplitude of the leading wheelset against speed.

    The speeds are stored in km/h (the fields ``*_kmh``, as the sweep is usually written);
    their SI twins in m/s are the properties ``speeds``, ``critical``, ``flange``,
    ``extended``, ``no_decay_below`` and ``no_cycle_up_to``.

    Attributes
    ----------
    speeds_kmh : ndarray
        Swept speeds, km/h (``speeds``: m/s).
    upper : ndarray
        Amplitude (m) on the branch followed down in speed from a large limit cycle.
    decay : ndarray
        Amplitude (m) after ``duration`` from a small disturbance ``y_small`` (0: decayed).
    critical_kmh : float
        Nonlinear critical speed, km/h (``critical``: m/s): the lowest speed with a sustained
        limit cycle on the upper branch (amplitude > threshold), to the sweep's step. NaN when
        there is none: see ``no_decay_below_kmh`` and ``no_cycle_up_to_kmh``.
    flange_kmh : float
        Lowest speed of the upper branch with an amplitude above ``flange_amplitude``
        (flange-contact hunting), km/h (``flange``: m/s).
    linear_kmh : float or None
    branch : str
        Which cycle defines ``critical_kmh``: 'flange cycle' (the leading bogie's flanges
        carry load in the cycle at that speed: max flange normal force above 1 % of the static
        wheel load over the last second), 'tread cycle' (no flange contact), or 'none'.
    branch_amplitude : float
        The leading wheelset's amplitude in that cycle, m (compare with the flange clearance,
        about 6.3 mm for S1002 / UIC60 1:40).
    branch_flange_force : float
        Max flange normal force on the leading bogie's wheels in that cycle (last second), N.
    extended_kmh : ndarray
        Speeds below the requested sweep that were added because the cycle had not died at
        its bottom (empty when the sweep sufficed), km/h (``extended``: m/s).
    no_decay_below_kmh : float
        NaN when the branch died within the (extended) sweep; otherwise the floor ``v_min_kmh``
        at which the extension stopped with the cycle still alive: the critical speed is
        below it and ``critical_kmh`` is NaN ("below X km/h: no decay found"); km/h
        (``no_decay_below``: m/s).
    no_cycle_up_to_kmh : float
        NaN, or the top of the sweep when no cycle was sustained even there (critical speed
        above the sweep; ``critical_kmh`` NaN), km/h (``no_cycle_up_to``: m/s).
    model : str
        'RR', 'FR', 'RF' or 'FF'.
    details : dict
        'flange_force' (N, per speed); model FR also 'h' (the step at each speed, s) and
        'modal_restarts' (speeds, km/h, at which the upper branch's modal coordinates were
        restarted from the static state instead of carried over; empty when every mode
        set matched).
    """

    speeds_kmh: np.ndarray
    upper: np.ndarray
    decay: np.ndarray
    critical_kmh: float
    threshold: float
    flange_kmh: float = float("nan")
    linear_kmh: float | None = None
    details: dict = field(default_factory=dict)
    branch: str = "none"
    branch_amplitude: float = float("nan")
    branch_flange_force: float = float("nan")
    extended_kmh: np.ndarray = field(default_factory=lambda: np.zeros(0))
    no_decay_below_kmh: float = float("nan")
    no_cycle_up_to_kmh: float = float("nan")
    model: str = "RR"

    @property
    def speeds(self) -> np.ndarray:
        """Swept speeds, m/s."""
        return self.speeds_kmh / 3.6

    @property
    def critical(self) -> float:
        """Nonlinear critical speed, m/s (NaN: none, see :attr:`message`)."""
        return self.critical_kmh / 3.6

    @property
    def flange(self) -> float:
        """Lowest speed of flange-contact hunting on the upper branch, m/s."""
        return self.flange_kmh / 3.6

    @property
    def extended(self) -> np.ndarray:
        """Speeds added below the requested sweep, m/s."""
        return np.asarray(self.extended_kmh) / 3.6

    @property
    def no_decay_below(self) -> float:
        """The extended sweep's floor with the cycle still alive, m/s (NaN otherwise)."""
        return self.no_decay_below_kmh / 3.6

    @property
    def no_cycle_up_to(self) -> float:
        """The top of a sweep without a sustained cycle, m/s (NaN otherwise)."""
        return self.no_cycle_up_to_kmh / 3.6

    @property
    def message(self) -> str:
        """One line: the nonlinear critical speed and its branch, or why there is none."""
        if np.isfinite(self.no_decay_below_kmh):
            return (f"below {self.no_decay_below_kmh:.0f} km/h: no decay found (the cycle is "
                    f"sustained at every speed swept down to there)")
        if np.isfinite(self.no_cycle_up_to_kmh):
            return f"no sustained cycle up to {self.no_cycle_up_to_kmh:.0f} km/h"
        ext = (f"; sweep extended down to {self.extended_kmh.min():.0f} km/h"
               if self.extended_kmh.size else "")
        return (f"nonlinear critical speed {self.critical_kmh:.0f} km/h ({self.branch}, "
                f"amplitude {self.branch_amplitude * 1e3:.2f} mm, max flange force "
                f"{self.branch_flange_force / 1e3:.1f} kN{ext})")


def _sweep_speeds(speeds_kmh: Sequence[float] | None, speeds: Sequence[float] | None
                  ) -> np.ndarray:
    """The sweep's speeds in km/h, descending, from exactly one of ``speeds`` (m/s) and
    ``speeds_kmh`` (its suffixed alias), or the default 200..460 km/h by 20."""
    if speeds is not None and speeds_kmh is not None:
        raise InputError("give the sweep's speeds once: speeds (m/s) or speeds_kmh (km/h), "
                         "not both")
    if speeds is not None:
        v = np.atleast_1d(_checks.finite_array("speeds", speeds))
        if v.size < 2 or np.any(~np.isfinite(v)) or np.any(v <= 0) or np.any(v > _checks.MAX_SPEED):
            raise InputError(f"speeds must hold at least two speeds in (0, "
                             f"{_checks.MAX_SPEED:.4g}] m/s, got {np.asarray(speeds).tolist()}")
        sp = v * 3.6
    else:
        sp = _checks.finite_array("speeds_kmh", speeds_kmh if speeds_kmh is not None
                                  else np.arange(200.0, 461.0, 20.0))
        if sp.ndim != 1 or sp.size < 2 or np.any(sp <= 0):
            raise InputError("speeds_kmh must hold at least two speeds > 0")
        for s_kmh in sp:
            _checks.speed_kmh("speeds_kmh", s_kmh)
    return np.sort(sp)[::-1]


def _floor_kmh(v_min_kmh: float | None, v_min: float | None) -> float:
    """The sweep extension's floor, km/h, from exactly one of v_min (m/s) and v_min_kmh."""
    if v_min is not None and v_min_kmh is not None:
        raise InputError("give the sweep's floor once: v_min (m/s) or v_min_kmh (km/h), not both")
    if v_min is not None:
        return _checks.positive("v_min", v_min) * 3.6
    return _checks.positive("v_min_kmh", 20.0 if v_min_kmh is None else v_min_kmh)


class _SweepSystems:
    """The systems of a speed sweep: RR's one system, or models FR, RF, FF built per speed
    (cached by speed; the wheelsets' modes depend on the spin, the ring's rows move at the
    speed) with their step and static states. ``ring``: the ring's keys (_RF_KEYS)."""

    def __init__(self, model: str, coach: Coach | None, contact: str, h: float | None,
                 k_max: int, f_max: float, geometry: str | None = None,
                 ring: dict | None = None) -> None:
        self.model, self.coach, self.contact, self.h = model, coach, contact, h
        self.k_max, self.f_max = k_max, f_max
        self.geometry = resolve_geometry(contact, geometry)
        self.ring = dict(ring or {})
        self._cache: dict[float, tuple] = {}
        self._rr = coach_system(model, coach, geometry=geometry) if model == "RR" else None
        self.steps: dict[float, float] = {}

    def at(self, s_kmh: float) -> tuple[System, list, float]:
        """(system, FR layouts or [], step h) at s_kmh."""
        if self._rr is not None:
            return self._rr, [], 1e-3 if self.h is None else self.h
        key = float(s_kmh)
        if key not in self._cache:
            if len(self._cache) >= 4 and self.model in RING_TRACK:
                self._cache.pop(next(iter(self._cache)))     # ring systems are large
            self._cache[key] = self._build(key, self.ring)
            self.steps[key] = self._cache[key][2]
        return self._cache[key]

    def _build(self, key: float, ring: dict) -> tuple:
        if self.model == "FR":
            sy, lay = fr_system(self.coach, speed_kmh=key, k_max=self.k_max,
                                f_max=self.f_max, geometry=self.geometry)
        elif self.model == "FF":
            sy, lay = ff_system(self.coach, speed_kmh=key, k_max=self.k_max,
                                f_max=self.f_max, geometry=self.geometry, **ring)
        else:
            sy, lay = rf_system(self.coach, speed_kmh=key, geometry=self.geometry, **ring), []
        return sy, lay, _step(sy, self.h)

    def upper_at(self, s_kmh: float, travel: float) -> tuple[System, list, float]:
        """The system of the upper branch's run at s_kmh: ``at(s_kmh)``, except on the ring
        track, where its contact points start ``travel`` (m, the distance run along the ring
        by the branch so far) beyond x_offset, so that a ring state carried from the previous
        run belongs to them (the ring repeats: travel is taken modulo its length)."""
        base = self.at(s_kmh)
        if self.model not in RING_TRACK or travel == 0.0:
            return base
        ring = dict(self.ring)
        length = float(base[0].ring.length)
        ring["x_offset"] = (float(ring.get("x_offset", 0.0)) + travel) % length
        return self._build(float(s_kmh), ring)

    def carry(self, q: np.ndarray, v: np.ndarray, s_from: float, s_to: float,
              static_to: Any) -> tuple[np.ndarray, np.ndarray, bool]:
        """Map a state (q, v) of the system at s_from onto the system at s_to.

        The rigid DOFs carry over. Model FR's modal coordinates (elastic and residual) carry
        over by label when both systems keep the same labelled modes (the mode selection is by
        non-rotating frequency, so it is the same set at every speed unless a mode crosses
        f_max); otherwise they restart from the static state at s_to (``static_to()``: its
        modal part, velocities zero). Returns (q, v, restarted)."""
        if self._rr is not None:
            return q, v, False
        a, la, _ = self.at(s_from)
        b, lb, _ = self.at(s_to)
        n = a.n
        same = a.state_names == b.state_names and (
            self.model not in FLEXIBLE_WHEELSETS or mode_labels(a, la) == mode_labels(b, lb))
        if same and self.model not in RING_TRACK:
            return q, v, False
        qs = static_to()
        qn, vn = np.array(qs, dtype=float), np.zeros(b.n_state)
        if same:
            # everything carries over: the upper branch's next run starts its contact points
            # where the previous run's ended (upper_at), so the ring's state belongs to them
            return q, v, False
        qn[:n], vn[:n] = q[:n], v[:n]
        return qn, vn, True


def _sweep_setup(speeds_kmh: Sequence[float] | None, speeds: Sequence[float] | None,
                 v_min_kmh: float | None, v_min: float | None, model: str, contact: str,
                 coach: Coach | None, h: float | None, k_max: int, f_max: float,
                 geometry: str, ring: dict | None = None, output_dt: float | None = None
                 ) -> tuple[np.ndarray, float, float, _SweepSystems]:
    """A bifurcation sweep's speeds (km/h), floor (km/h), smallest step (km/h) and systems,
    every input checked and the step checked against the first speed's system before any
    run (serial continuation and independent points alike)."""
    sp = _sweep_speeds(speeds_kmh, speeds)
    v_min_kmh = _floor_kmh(v_min_kmh, v_min)
    step = float(np.min(-np.diff(sp)[np.diff(sp) < 0])) if np.any(np.diff(sp) < 0) else 10.0
    _check_model(model, contact, "bifurcation")
    if model in FLEXIBLE_WHEELSETS:
        k_max, f_max = check_fr_selection(k_max, f_max)
    elif (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
        _no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
    ring = _ring_keys(model, ring)
    geometry = resolve_geometry(contact, geometry)
    systems = _point_systems(model, coach, contact, h, k_max, f_max, geometry, ring)
    sy, _, hs = systems.at(sp[0])
    if output_dt is not None:           # the top speed's excitations are the highest
        _output_dt(sy, sp[0] / 3.6, hs, output_dt, 0.002)
    return sp, v_min_kmh, step, systems


def _ring_keys(model: str, ring: dict | None) -> dict:
    """The ring's keys of a sweep, checked: only _RF_KEYS, and only for RF and FF."""
    ring = dict(ring or {})
    bad = sorted(k for k in ring if k not in _RF_KEYS)
    if bad:
        raise InputError(f"{', '.join(bad)}: unknown keyword(s) (the ring track's keys of "
                         f"models 'RF' and 'FF' are {_RF_KEYS})")
    if ring and model not in RING_TRACK:
        raise InputError(f"{', '.join(sorted(ring))}: keys of models 'RF' and 'FF' (the ring "
                         f"track); model {model!r} has none")
    return ring


def bifurcation(speeds_kmh: Sequence[float] | None = None, model: str = "RR",
                contact: str = "hertz-kalker", *, speeds: Sequence[float] | None = None,
                duration: float = 4.0, y_large: float = 0.006,
                y_small: float = 0.0005, threshold: float = 0.5e-3, h: float | None = None,
                flange_amplitude: float = 5e-3, v_min_kmh: float | None = None,
                v_min: float | None = None, coach: Coach | None = None, progress: bool = True,
                k_max: int = FR_K_MAX, f_max: float = FR_F_MAX, client: Any = None,
                independent: bool = False, geometry: str | None = None,
                output_dt: float | None = None, **ring: Any) -> Bifurcation:
    """Bifurcation diagram by a downward speed sweep with continuation and decay tests.

    The upper (limit-cycle) branch: start at the highest speed with ``y_large``, run
    ``duration``, lower the speed and continue from the last state; where the cycle dies the
    branch ends (nonlinear critical speed). If it is still alive at the sweep's bottom, the
    sweep is extended downward by its smallest step until the cycle dies or the speed would
    fall below ``v_min_kmh``; then the result says "below X km/h: no decay found"
    (``no_decay_below_kmh``, ``critical_kmh`` NaN, and a RuntimeWarning), never the bottom
    of the sweep as a critical speed. The decay tests: from each speed's static state
    with a small disturbance ``y_small``; growth there means the centred running itself is
    unstable (the linear critical speed is below that speed).

    Parameters
    ----------
    speeds_kmh : sequence of float, optional
        The speeds, km/h: the suffixed alias of ``speeds`` (give one of them; default 200 to
        460 km/h by 20).
    model, contact : str
        'RR', 'FR', 'RF' or 'FF'; the contact model.
    speeds : sequence of float, optional
        The speeds, m/s (at least two).
    duration : float
        Simulated time per speed and branch, s.
    y_large, y_small, threshold, flange_amplitude : float
        Disturbances, the living-cycle threshold and the flange-hunting amplitude, m.
    h : float, optional
        Time step, s: default 1 ms (RR) or, model FR, 1 ms divided so that h omega_max <= 2 at
        each speed; a given h is checked against the kept modes at every speed.
    v_min_kmh, v_min : float, optional
        The floor of the downward extension, km/h or m/s (one of them; default 20 km/h).
    coach : Coach, optional
    progress : bool
        Progress bar.
    k_max, f_max : int, float
        Model FR's mode selection (harmonics, Hz). Model FR is built at each speed; the
        upper branch carries the rigid DOFs over from one speed to the next and the modal
        coordinates by mode label when the mode sets match, else restarts them from the new
        speed's static state (``details['modal_restarts']``).
    client : distributed.Client or str, optional
        Run on a Dask cluster: a Client, a scheduler address (``tcp://host:8786``) or
        'local' (a LocalCluster for the call, railvti.runner.sweeps); an address where no scheduler
        answers is an InputError within seconds. The client never changes the answer: the
        same call returns the same numbers bit for bit with and without it. The upper
        branch's continuation is one sequential chain, one task
        (:func:`bifurcation_upper`); the decay tests run beside it, one task per speed
        (:func:`bifurcation_point`); with ``independent`` every run is a task.
    independent : bool
        Every speed is a point of its own: the upper branch starts at each speed from its
        static state shifted by ``y_large`` (as the top speed does in the continuation), instead
        of carrying the state down from the speed above. The cycle found at a speed can then
        differ from the continuation's where two cycles coexist (the continuation follows one
        branch down; the independent start lands on the cycle whose basin holds ``y_large``).
        A downward extension runs one speed at a time. Serial (``client=None``) and on any
        cluster the results are the same bit for bit (railvti.runner.sweeps). Never implied by
        ``client``.
    geometry : str
        Contact geometry, 'strip' (default) or 'table' (:func:`coach_system`).
    output_dt : float, optional
        Output interval of every run, s (the amplitudes and flange forces are read from
        it). Default 2 ms, shortened so that the known periodic excitations get 10 samples
        per period (railvti.vehicle.output: the sleeper passing on the ring track, RF and
        FF; hunting); a given one that aliases them at the top speed gives an
        AliasingWarning.
    **ring
        Models 'RF' and 'FF': the ring track's keys ``n_sleepers``, ``f_limit``,
        ``track_params``, ``x_offset`` (:func:`rf_system`). The ring is built once and its
        rows per speed. The upper branch carries the whole state down, the ring's
        coordinates too: each of its runs starts the contact points where the previous run
        left them (x_offset plus the distance run so far, modulo the ring's length), so the
        carried rail deflection lies under the wheels. The decay runs start at x_offset.
    """
    if client is not None:
        check_client(client)            # an unreachable address: InputError before any work
    kw = dict(duration=duration, y_large=y_large, y_small=y_small, threshold=threshold,
              h=h, v_min_kmh=v_min_kmh, v_min=v_min, coach=coach, k_max=k_max, f_max=f_max,
              geometry=geometry, ring=ring, output_dt=output_dt)
    if independent:
        return _bifurcation_independent(speeds_kmh, speeds, model, contact, client=client,
                                        flange_amplitude=flange_amplitude, progress=progress,
                                        **kw)
    sp, v_min_kmh, step, systems = _sweep_setup(speeds_kmh, speeds, v_min_kmh, v_min, model,
                                                contact, coach, h, k_max, f_max, geometry, ring,
                                                output_dt)
    point = dict(model=model, contact=contact, coach=coach, h=h, k_max=systems.k_max,
                 f_max=systems.f_max, duration=duration, geometry=systems.geometry,
                 ring=systems.ring, output_dt=output_dt)
    chain = dict(point, y_large=y_large, threshold=threshold, step=step, v_min_kmh=v_min_kmh)
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=2 * sp.size, desc="bifurcation", leave=False)
    decay: list[float] = []
    if client is None:
        def decay_at(s: float) -> None:       # after the upper run at s, as one loop
            if bar is not None:
                bar.total = max(bar.total, bar.n + 2)   # an extension below the sweep
                bar.update()
            decay.append(bifurcation_point(s, y_small, **point)[0])
            if bar is not None:
                bar.update()
        up = bifurcation_upper(list(sp), each=decay_at, **chain)
    else:
        up, decay = _bifurcation_on_client(client, sp, y_small, point, chain, bar)
    if bar is not None:
        bar.close()
    systems.steps.update(up["steps"])
    return _bifurcation_result(sp, up["speeds"], up["upper"], up["flange"], decay, up["alive"],
                               threshold, flange_amplitude, systems, model, up["restarts"])


def bifurcation_upper(speeds_kmh: Sequence[float], *, y_large: float, threshold: float,
                      step: float, v_min_kmh: float, model: str, contact: str,
                      coach: Coach | None, h: float | None, k_max: int, f_max: float,
                      duration: float, geometry: str | None = None, ring: dict | None = None,
                      output_dt: float | None = None, each: Any = None) -> dict:
    """The upper branch of a :func:`bifurcation` sweep, one sequential chain (one task on a
    Dask client): from the static state at the first (highest) speed shifted by ``y_large``
    (m), ``duration`` s at each speed, each speed starting from the state carried down from
    the speed above, until the cycle dies (amplitude <= threshold); while it lives at the
    bottom, the sweep is extended by ``step`` (km/h) down to ``v_min_kmh``.

    ``each(s_kmh)``, when given, is called after each speed's run (the serial sweep runs the
    decay test there). Returns a dict: 'speeds' (km/h, the sweep's and the extension's),
    'upper' (amplitude, m; 0 below the speed where the cycle died), 'flange' (max flange
    normal force on the leading bogie over the last second, N), 'alive' (at the last speed),
    'restarts' (km/h, :class:`Bifurcation` ``details``) and 'steps' (km/h -> h, s).
    """
    systems = _point_systems(model, coach, contact, h, k_max, f_max, geometry, ring)
    speeds_out: list[float] = []
    upper: list[float] = []
    flange: list[float] = []
    restarts: list[float] = []
    q = v = None
    alive = True
    todo = [float(s) for s in speeds_kmh]
    prev = None
    travel = 0.0        # distance run along the ring by the upper branch, m
    with serial_blas():      # one BLAS thread, in the caller as in a worker: the same bits
        while todo:
            s = todo.pop(0)
            vv = s / 3.6
            sy, _, hs = systems.at(s)
            up, fl = 0.0, 0.0
            if alive:
                if q is None:
                    q = lateral_disturbance(sy, static_equilibrium(sy, vv, contact)[0], y_large)
                    v = np.zeros(sy.n_state)
                su = systems.upper_at(s, travel)[0]
                if prev is not None:
                    q, v, restarted = systems.carry(
                        q, v, prev, s, lambda: static_equilibrium(su, vv, contact)[0])
                    if restarted:
                        restarts.append(float(s))
                r = simulate(su, vv, duration, contact=contact, h=hs, q0=q, v0=v,
                             output_dt=_output_dt(su, vv, hs, output_dt, 0.002, check=False),
                             progress=False)
                travel += vv * float(r.t[-1])
                up = amplitude(r)
                last = r.t >= r.t[-1] - 1.0
                fl = float(r.wheel_output("N_flange")[last][:, :, :2].max())
                q, v = r.q[-1], r.v[-1]
                alive = up > threshold
                prev = s
            speeds_out.append(s)
            upper.append(up)
            flange.append(fl)
            if each is not None:
                each(s)
            if not todo and alive and s - step >= v_min_kmh - 1e-9:
                todo.append(s - step)      # the cycle has not died: extend the sweep downward
    return {"speeds": speeds_out, "upper": upper, "flange": flange, "alive": alive,
            "restarts": restarts, "steps": {k: systems.steps[k] for k in systems.steps}}


def _bifurcation_on_client(client: Any, sp: np.ndarray, y_small: float, point: dict,
                           chain: dict, bar: Any) -> tuple[dict, list[float]]:
    """The continuation sweep on a Dask client: the upper branch as one task
    (:func:`bifurcation_upper`), the decay tests (independent by nature) as one task per
    speed beside it; the same runs as the serial sweep, so the same numbers."""
    from distributed import as_completed
    with client_from(client) as c:
        fut_up = c.submit(bifurcation_upper, list(map(float, sp)), pure=False, **chain)
        fut_decay = c.map(bifurcation_point, list(map(float, sp)), [y_small] * sp.size,
                          pure=False, **point)
        pending = as_completed([fut_up, *fut_decay])
        up = None
        for f in pending:
            if f is fut_up:
                up = f.result()
                extra = up["speeds"][sp.size:]
                if extra:                           # the sweep was extended downward
                    more = c.map(bifurcation_point, extra, [y_small] * len(extra), pure=False,
                                 **point)
                    fut_decay += more
                    pending.update(more)
                    if bar is not None:
                        bar.total += 2 * len(extra)
            if bar is not None:
                bar.update(len(up["speeds"]) if f is fut_up else 1)
        decay = [f.result()[0] for f in fut_decay]
    return up, decay


def _bifurcation_result(sp: np.ndarray, speeds_out: list, upper: list, flange: list,
                        decay: list, alive: bool, threshold: float, flange_amplitude: float,
                        systems: Any, model: str, restarts: list) -> Bifurcation:
    """The Bifurcation of a finished sweep (its critical speed, branch and messages)."""
    spa, upa, fla = np.array(speeds_out), np.array(upper), np.array(flange)
    on = upa > threshold
    crit = float(spa[on].min()) if on.any() else float("nan")
    no_decay = no_cycle = float("nan")
    branch, amp_b, fl_b = "none", float("nan"), float("nan")
    if on.any() and alive:
        no_decay = float(spa.min())
        crit = float("nan")
        msg = (f"bifurcation: below {no_decay:.0f} km/h: no decay found (the cycle is "
               f"sustained at every speed swept; lower v_min_kmh to search further)")
        log.warning(msg)
        warnings.warn(msg, RuntimeWarning, stacklevel=3)
    elif not on.any():
        no_cycle = float(spa.max())
        log.warning("bifurcation: no sustained cycle up to %.0f km/h", no_cycle)
    wheel_load = systems.at(sp[0])[0].wheel_load
    if np.isfinite(crit):
        k = int(np.argmin(np.where(on, spa, np.inf)))
        amp_b, fl_b = float(upa[k]), float(fla[k])
        branch = "flange cycle" if fl_b > 0.01 * wheel_load else "tread cycle"
    fl = upa > flange_amplitude
    order = np.argsort(spa)
    details: dict[str, Any] = {"flange_force": fla[order]}
    if model != "RR":
        details["h"] = np.array([systems.steps[float(x)] for x in spa[order]])
        details["modal_restarts"] = np.array(sorted(restarts))
    return Bifurcation(speeds_kmh=spa[order], upper=upa[order], decay=np.array(decay)[order],
                       critical_kmh=crit, threshold=threshold,
                       flange_kmh=float(spa[fl].min()) if fl.any() else float("nan"),
                       details=details,
                       branch=branch, branch_amplitude=amp_b, branch_flange_force=fl_b,
                       extended_kmh=np.sort(spa[spa < sp.min()]), no_decay_below_kmh=no_decay,
                       no_cycle_up_to_kmh=no_cycle, model=model)


#: The sweep systems of bifurcation runs in this process (a worker keeps its own).
_POINT_SYSTEMS: dict[str, "_SweepSystems"] = {}


def _point_systems(model: str, coach: Coach | None, contact: str, h: float | None,
                   k_max: int, f_max: float, geometry: str | None, ring: dict | None
                   ) -> _SweepSystems:
    """The sweep systems of these settings in this process: one set at a time, shared by a
    sweep's upper branch and its decay runs (each run starts from its own state)."""
    geometry = resolve_geometry(contact, geometry)
    key = repr((model, coach, contact, h, k_max, f_max, geometry, sorted((ring or {}).items())))
    if key not in _POINT_SYSTEMS:
        _POINT_SYSTEMS.clear()
        _POINT_SYSTEMS[key] = _SweepSystems(model, coach, contact, h, k_max, f_max, geometry,
                                            ring)
    return _POINT_SYSTEMS[key]


def bifurcation_point(s_kmh: float, y: float, *, model: str, contact: str,
                      coach: Coach | None, h: float | None, k_max: int, f_max: float,
                      duration: float, geometry: str | None = None, ring: dict | None = None,
                      output_dt: float | None = None) -> tuple[float, float, float]:
    """One run of an independent bifurcation sweep (a task): from the static state at
    ``s_kmh`` with the leading bogie's wheelsets shifted by ``y`` (m), ``duration`` s.

    Returns
    -------
    amplitude : float
        Leading wheelset's amplitude over the last second, m (:func:`amplitude`).
    flange_force : float
        Max flange normal force on the leading bogie's wheels over the last second, N.
    h : float
        The time step used, s.
    """
    sy, _, hs = _point_systems(model, coach, contact, h, k_max, f_max, geometry, ring).at(s_kmh)
    vv = s_kmh / 3.6
    with serial_blas():      # one BLAS thread, in the caller as in a worker: the same bits
        q0 = lateral_disturbance(sy, static_equilibrium(sy, vv, contact)[0], y)
        r = simulate(sy, vv, duration, contact=contact, h=hs, q0=q0,
                     output_dt=_output_dt(sy, vv, hs, output_dt, 0.002, check=False),
                     progress=False)
    last = r.t >= r.t[-1] - 1.0
    return amplitude(r), float(r.wheel_output("N_flange")[last][:, :, :2].max()), hs


def _bifurcation_independent(speeds_kmh: Sequence[float] | None, speeds: Sequence[float] | None,
                             model: str, contact: str, *, duration: float, y_large: float,
                             y_small: float, threshold: float, h: float | None,
                             flange_amplitude: float, v_min_kmh: float | None,
                             v_min: float | None, coach: Coach | None, k_max: int, f_max: float,
                             client: Any, geometry: str | None = None,
                             ring: dict | None = None, output_dt: float | None = None,
                             progress: bool = False) -> Bifurcation:
    """:func:`bifurcation` with every speed independent, serial or on a Dask client."""
    sp, v_min_kmh, step, systems = _sweep_setup(speeds_kmh, speeds, v_min_kmh, v_min, model,
                                                contact, coach, h, k_max, f_max, geometry, ring,
                                                output_dt)
    kw = dict(model=model, contact=contact, coach=coach, h=h, k_max=systems.k_max,
              f_max=systems.f_max, duration=duration, geometry=systems.geometry,
              ring=systems.ring, output_dt=output_dt)
    with contextlib.ExitStack() as stack:
        c = None
        if client is not None:
            c = stack.enter_context(client_from(client))

        bar = None
        if progress:
            from tqdm import tqdm
            bar = stack.enter_context(tqdm(total=2 * sp.size, desc="bifurcation", leave=False))

        def runs(todo: list[float]) -> list[tuple[float, float, float]]:
            s_all = [s for s in todo for _ in (0, 1)]
            y_all = [y for _ in todo for y in (y_large, y_small)]
            if bar is not None:
                bar.total = max(bar.total, bar.n + len(s_all))
            if c is None:
                out = []
                for s, y in zip(s_all, y_all):
                    out.append(bifurcation_point(s, y, **kw))
                    if bar is not None:
                        bar.update()
                return out
            futures = c.map(bifurcation_point, s_all, y_all, pure=False, **kw)
            out = c.gather(futures)
            if bar is not None:
                bar.update(len(out))
            return out
        speeds_out = [float(s) for s in sp]
        out = runs(speeds_out)
        while out[-2][0] > threshold and speeds_out[-1] - step >= v_min_kmh - 1e-9:
            speeds_out.append(speeds_out[-1] - step)   # alive at the bottom: extend downward
            out += runs(speeds_out[-1:])
    upper, flange = [o[0] for o in out[0::2]], [o[1] for o in out[0::2]]
    decay = [o[0] for o in out[1::2]]
    if model != "RR":
        systems.steps.update({float(s): o[2] for s, o in zip(speeds_out, out[0::2])})
    return _bifurcation_result(sp, speeds_out, upper, flange, decay, upper[-1] > threshold,
                               threshold, flange_amplitude, systems, model, [])


#: The linear method's treatment of the ring's contact rows (:func:`linear_critical_speed`).
RING_ROWS = ("bay_average", "frozen")
#: Contact-point positions across one sleeper bay in the bay average.
BAY_OFFSETS = 8
#: The dry-friction yaw damper's states of the linear method.
DAMPER_STATES = {
    "stuck": ("stuck: friction torque T tanh(rate / w0) linearised at rest, a viscous slope "
              "T / w0 (1.5e7 N m s/rad for the defaults), practically locked"),
    "sliding": ("sliding: the friction torque saturated at +-T, no incremental stiffness or "
                "damping (yaw_friction_torque set to 0 in the linearisation)"),
}


def linear_critical_speed(model: str = "RR", coach: Coach | None = None, *,
                          conicity: float | None = None, amplitude_m: float = 0.003,
                          v_lo_kmh: float = 50.0, v_hi_kmh: float = 800.0,
                          tol_kmh: float = 0.5, damper: str = "stuck",
                          k_max: int = FR_K_MAX, f_max: float = FR_F_MAX,
                          ring_rows: str = "bay_average", n_offsets: int = BAY_OFFSETS,
                          **ring: Any) -> tuple[float, float]:
    """Linear critical speed (km/h) and the hunting frequency there (Hz).

    Eigenvalues of the system linearised about centred running with the contact table
    replaced by its equivalent linearisation at the EN 15302 equivalent conicity for the
    amplitude ``amplitude_m`` (Kalker's linear creep). The dry-friction yaw damper enters in
    the state ``damper`` (:data:`DAMPER_STATES`): 'stuck' (default; its tangent at rest, a
    steep viscous slope) or 'sliding' (its torque saturated: no incremental contribution).
    Bisection on the largest real part of the oscillatory eigenvalues below 20 Hz.

    Model 'FR' (mode selection ``k_max``, ``f_max``): the flexible DOFs are in the
    linearisation (:func:`railvti.vehicle.flexible.eigenvalues`: elastic and residual
    coordinates, about FR's own steady state); its modes depend on the spin, so the system is
    rebuilt at every speed of the bisection. The wheelsets' elastic modes lie above 70 Hz,
    outside the 20 Hz band searched: they change the hunting eigenvalue, not the band.

    Models 'RF' and 'FF' (the ring's keys ``**ring``, :func:`rf_system`): the ring's kept
    modes and residual coordinates are in the linearisation; the ring's modes lie above the
    20 Hz band. The contact rows move along the ring with the load, so the linearised system
    is periodic in time with the sleeper-passing period spacing / v. ``ring_rows`` says how
    that is made time-invariant:

    - 'bay_average' (default): the sleeper-bay average. The system is linearised with the
      contact points frozen at ``n_offsets`` positions across one bay, x_offset + k spacing
      / n_offsets (each about its own static state), and the bisection runs on the mean of
      the hunting eigenvalue's real part over the offsets (the frequency: its mean too).
      Why the growth rates and not the system matrices: the ring's coordinates are fast
      (modes above 20 Hz) or massless (residual flexibility) and follow the load, so the
      compliance the wheel sees at x is L(x) K^-1 L(x)^T; averaging the rows L in the
      matrices gives mean(L) K^-1 mean(L)^T, smaller, a rail stiffer than at any offset
      (measured, RF at 320 km/h, 4 offsets: growth 0.16 1/s from averaged matrices against
      0.22-0.24 1/s at every single offset). Each frozen linearisation is exact for its
      position; the mean of their exponents over equispaced offsets (the trapezoidal rule,
      spectrally accurate for the periodic integrand) is the time average of the growth
      rate the hunting mode sees as it crosses the bay.
    - 'frozen': the contact points frozen at their t = 0 positions (x_offset + x_wheelset),
      one evaluation per speed; the method before the bay average.

    The exact alternative is Floquet analysis over one bay (the monodromy matrix of the
    periodic linear system over spacing / v). The average leaves out what links the
    positions: the ring's dynamic response carried from one position to the next (the
    frozen systems each assume the load stays put), the parametric coupling of the hunting
    mode with the ring's modes through the bay's harmonics, and the drift of the moving-load
    state within the bay (each offset is linearised about its own static state). The spread
    of the frozen critical speeds over the offsets (each linearly
    interpolated between the bisection's speeds) goes to the log (INFO).

    Raises
    ------
    InputError
        Unknown ``ring_rows`` or ``damper``; ``n_offsets`` not a positive integer; the
        ring's and FR's keys as :func:`rf_system`, :func:`fr_system`.
    """
    if damper not in DAMPER_STATES:
        raise InputError(f"damper must be one of {sorted(DAMPER_STATES)}, got {damper!r}")
    if ring_rows not in RING_ROWS:
        raise InputError(f"ring_rows must be one of {RING_ROWS}, got {ring_rows!r}")
    n_offsets = _checks.positive_int("n_offsets", n_offsets)
    _check_model(model, "hertz-kalker", "linear_critical_speed")
    if model in FLEXIBLE_WHEELSETS:
        k_max, f_max = check_fr_selection(k_max, f_max)
    elif (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
        _no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
    ring = _ring_keys(model, ring)
    coach = coach or Coach()
    if damper == "sliding":
        coach = coach.with_(yaw_friction_torque=0.0)
    lam = conicity if conicity is not None else equivalent_conicity(amplitude_m)
    if model == "RR":
        sy = coach_system(model, coach, linear_conicity=lam)
    bay = model in RING_TRACK and ring_rows == "bay_average"
    frozen_growth: dict[float, np.ndarray] = {}   # bay average: speed -> growth per offset

    def spectrum(kmh: float) -> np.ndarray:
        if model == "RR":
            return eigenvalues(sy, kmh / 3.6)
        # built directly: the bisection's bracket may pass the scenarios' 600 km/h bound
        tab = linearised_table(contact_table(), lam)
        if model in RING_TRACK:
            sf = _on_ring(model, coach, tab, kmh / 3.6, k_max=k_max, f_max=f_max, **ring)[0]
        else:
            sf = build_fr(coach, tab, kmh / 3.6, wheelset=_fr_wheelset(), k_max=k_max,
                          f_max=f_max)[0]
        return fr_eigenvalues(sf, kmh / 3.6)

    seen: dict[float, tuple[float, float]] = {}

    def growth(kmh: float) -> tuple[float, float]:
        if kmh in seen:
            return seen[kmh]
        if bay:
            tab = linearised_table(contact_table(), lam)
            rates, freqs = _bay_rates(model, coach, tab, kmh / 3.6, n_offsets, k_max=k_max,
                                      f_max=f_max, ring=ring)
            frozen_growth[kmh] = rates
            seen[kmh] = float(np.mean(rates)), float(np.mean(freqs))
        else:
            seen[kmh] = _hunting(spectrum(kmh))
        return seen[kmh]

    lo, hi = float(v_lo_kmh), float(v_hi_kmh)
    if growth(lo)[0] > 0:
        return lo, growth(lo)[1]
    if growth(hi)[0] < 0:
        return float("inf"), float("nan")
    while hi - lo > tol_kmh:
        mid = 0.5 * (lo + hi)
        if growth(mid)[0] > 0:
            hi = mid
        else:
            lo = mid
    if bay:
        per = _frozen_crossings(frozen_growth)
        log.info("%s linear critical speed, bay average over %d offsets: %.1f km/h; frozen "
                 "rows per offset: %.1f .. %.1f km/h (%s)", model, n_offsets, 0.5 * (lo + hi),
                 np.nanmin(per), np.nanmax(per),
                 ", ".join(f"{v:.1f}" for v in per))
    return 0.5 * (lo + hi), growth(hi)[1]


def _hunting(ev: np.ndarray) -> tuple[float, float]:
    """Growth rate (1/s) and frequency (Hz) of the least damped oscillatory eigenvalue in the
    hunting band (0.1 rad/s < |imag| < 20 Hz)."""
    osc = ev[(np.abs(ev.imag) > 0.1) & (np.abs(ev.imag) < 2 * np.pi * 20)]
    i = int(np.argmax(osc.real))
    return float(osc[i].real), float(abs(osc[i].imag) / (2 * np.pi))


def _bay_rates(model: str, coach: Coach, table: WheelTable, v: float, n_offsets: int, *,
               k_max: int, f_max: float, ring: dict) -> tuple[np.ndarray, np.ndarray]:
    """Model RF or FF at v (m/s): the hunting growth rate (1/s) and frequency (Hz) with the
    contact rows frozen at each of n_offsets positions across one sleeper bay
    (:func:`linear_critical_speed`)."""
    ring = dict(ring)
    x0 = float(ring.pop("x_offset", 0.0))
    spacing = _checked_ring(coach, ring.get("n_sleepers", RF_N_SLEEPERS),
                            ring.get("track_params")).params["sleeper_spacing"]
    base = None
    if model == "FF":   # the wheelsets do not depend on the ring's rows: built once per speed
        base = build_fr(coach, table, v, wheelset=_fr_wheelset(), k_max=k_max, f_max=f_max,
                        track=False)
    out = []
    for k in range(n_offsets):
        sy = _on_ring(model, coach, table, v, k_max=k_max, f_max=f_max, fr_base=base,
                      x_offset=x0 + k * spacing / n_offsets, **ring)[0]
        out.append(_hunting(fr_eigenvalues(sy, v)))
    rates, freqs = np.array(out).T
    return rates, freqs


def _frozen_crossings(samples: dict[float, np.ndarray]) -> np.ndarray:
    """Per offset: the lowest speed (km/h) where its frozen growth rate turns positive,
    linearly interpolated between the sampled speeds (NaN: no sign change sampled)."""
    kmh = np.array(sorted(samples))
    g = np.array([samples[v] for v in kmh])
    out = np.full(g.shape[1], np.nan)
    for k in range(g.shape[1]):
        up = np.nonzero((g[:-1, k] <= 0) & (g[1:, k] > 0))[0]
        if up.size:
            i = up[0]
            out[k] = kmh[i] + (kmh[i + 1] - kmh[i]) * -g[i, k] / (g[i + 1, k] - g[i, k])
    return out


@dataclass(frozen=True)
class CriticalSpeed:
    """A critical speed and what defines it.

    Attributes
    ----------
    kmh : float
        The critical speed, km/h; NaN when the nonlinear sweep found none (see ``message``).
        Its SI twin: the property ``speed`` (m/s).
    method : str
        'linear' or 'nonlinear'.
    branch : str
        nonlinear: 'tread cycle', 'flange cycle' or 'none' (:class:`Bifurcation`); linear:
        'linear (equivalent conicity)'.
    damper_state : str
        The dry-friction yaw damper's state: linear, :data:`DAMPER_STATES`; nonlinear, 'as
        simulated (stick-slip, regularised)'.
    frequency_hz : float
        linear: the hunting frequency at the critical speed; nonlinear: NaN.
    no_decay_below_kmh : float
        nonlinear: the floor of the extended sweep where the cycle was still alive (NaN
        otherwise), km/h (``no_decay_below``: m/s).
    bifurcation : Bifurcation or None
    model : str
        'RR', 'FR', 'RF' or 'FF'.
    """

    kmh: float
    method: str
    branch: str
    damper_state: str
    frequency_hz: float = float("nan")
    no_decay_below_kmh: float = float("nan")
    bifurcation: Bifurcation | None = None
    model: str = "RR"

    def __float__(self) -> float:
        return float(self.kmh)

    @property
    def speed(self) -> float:
        """The critical speed, m/s (NaN: none found)."""
        return self.kmh / 3.6

    @property
    def no_decay_below(self) -> float:
        """nonlinear: the extended sweep's floor with the cycle still alive, m/s (else NaN)."""
        return self.no_decay_below_kmh / 3.6

    @property
    def message(self) -> str:
        """One line: the value, its method, branch and damper state, or why there is none."""
        if self.method == "nonlinear" and self.bifurcation is not None:
            return self.bifurcation.message
        return (f"linear critical speed {self.kmh:.1f} km/h, {self.frequency_hz:.2f} Hz; yaw "
                f"damper {self.damper_state}")


def critical_speed(model: str = "RR", contact: str = "hertz-kalker", method: str = "nonlinear",
                   *, coach: Coach | None = None, **kw: Any) -> CriticalSpeed:
    """Critical speed (:class:`CriticalSpeed`; ``.kmh`` or ``float()`` for the value in km/h).

    method 'linear': :func:`linear_critical_speed` (eigenvalues; contact model irrelevant;
    ``damper='stuck'`` or ``'sliding'`` for the dry-friction yaw damper, reported in
    ``damper_state``). method 'nonlinear': :func:`bifurcation` (lowest speed with a
    sustained limit cycle; the sweep is extended downward until the cycle dies, otherwise
    ``kmh`` is NaN and ``no_decay_below_kmh`` says down to where it was searched; ``branch``
    names the tread or flange cycle that defines it; its speeds in m/s as ``speeds`` or in
    km/h as ``speeds_kmh``). Model 'FR' takes ``k_max`` and ``f_max`` (Hz) in both methods
    and is built at every speed. ``.speed`` is the result in m/s.
    """
    _check_model(model, contact, "critical_speed")
    if method == "linear":
        damper = kw.get("damper", "stuck")
        v, f = linear_critical_speed(model, coach, **kw)
        return CriticalSpeed(kmh=v, method="linear", branch="linear (equivalent conicity)",
                             damper_state=DAMPER_STATES.get(damper, damper), frequency_hz=f,
                             model=model)
    if method == "nonlinear":
        b = bifurcation(model=model, contact=contact, coach=coach, **kw)
        return CriticalSpeed(kmh=b.critical_kmh, method="nonlinear", branch=b.branch,
                             damper_state="as simulated (stick-slip, torque T tanh(rate / w0))",
                             no_decay_below_kmh=b.no_decay_below_kmh, bifurcation=b,
                             model=model)
    raise InputError(f"method must be 'linear' or 'nonlinear', got {method!r}")
