"""The coach-track systems of the scenarios, built and cached: variants RR, FR, RF, FF.

Variant 'RR': rigid wheelsets on the rigid track element (one per wheelset). Variant 'FR':
the same with flexible rotating wheelsets (railvti.vehicle.flexible: free-free elastic
modes coupled through the rims and journals, docs/vehicle_integrator.md "Flexible
wheelsets (FR)"); its modal matrices depend on the spin, so it is built at each speed
(:func:`fr_system`) with the mode selection ``k_max``, ``f_max``. Variant 'RF': rigid
wheelsets on the flexible ring track (railvti.vehicle.ring_coupling, docs/vehicle.md "Model
RF"), built per speed (:func:`rf_system`) with ``n_sleepers``, ``f_limit``,
``track_params``, ``x_offset``, ``ring_residual``. Variant 'FF': the flexible wheelsets on the
ring (:func:`ff_system`, the keys of both). S1002 wheels on UIC60 rails inclined 1:40
(:func:`wheel_table`, cached with the FE wheelset, the ring and the strip geometry).

Also the scenarios' shared settings: the contact geometry of a run
(:func:`resolve_geometry`), the time step (:func:`time_step`) and the output interval
(:func:`run_output_dt`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from .. import _cache, _checks
from ..errors import InputError
from ..geometry import geometry_table
from ..geometry import equivalent_conicity as eqc
from ..profiles import s1002, uic60
from ..track.ring import RingTrack
from ..wheelset import Wheelset
from ..wheelset.residual import residual_table
from . import output as _output
from .assembly import System, build_coach
from .flexible import build_fr, coach_body
from .params import Coach
from .ring_coupling import build_rf, check_ring_length
from .contact_models import CONTACT_MODELS, GEOMETRIES, ContactModel, contact_id, parse_contact_model
from .simulate import check_modal_step, exact_modal
from .strip import strip_geometry
from .table import WheelTable, linearised_table
from .table import wheel_table as profile_table

__all__ = [
    "VARIANTS",
    "FR_SCENARIOS",
    "RF_SCENARIOS",
    "FLEXIBLE_WHEELSETS",
    "RING_TRACK",
    "RF_N_SLEEPERS",
    "RF_F_LIMIT",
    "RF_KEYS",
    "FR_K_MAX",
    "FR_F_MAX",
    "MAX_HARMONIC",
    "RING_TABLE_Y_MAX",
    "GEOMETRIES",
    "DEFAULT_GEOMETRY",
    "profiles",
    "wheel_table",
    "resolve_geometry",
    "with_geometry",
    "equivalent_conicity",
    "hunting_conicity",
    "fr_wheelset",
    "check_fr_selection",
    "check_variant",
    "coach_system",
    "system_and_layouts",
    "fr_system",
    "ring_track",
    "rf_system",
    "on_ring",
    "checked_ring",
    "ff_system",
    "scenario_system",
    "no_fr_keys",
    "ring_keys",
    "default_step",
    "time_step",
    "run_output_dt",
]

VARIANTS = ("RR", "FR", "RF", "FF")
#: Scenarios that run variant FR.
FR_SCENARIOS = (
    "centred_running",
    "coach_system",
    "curving",
    "hunting",
    "bifurcation",
    "critical_speed",
    "linear_critical",
    "irregular_track",
    "line_run",
)
#: Scenarios that run the variants on the ring track, RF and FF.
RF_SCENARIOS = (
    "centred_running",
    "coach_system",
    "curving",
    "hunting",
    "bifurcation",
    "critical_speed",
    "linear_critical",
    "irregular_track",
    "line_run",
)
#: The variants with flexible wheelsets (mode selection k_max, f_max) and on the ring track.
FLEXIBLE_WHEELSETS, RING_TRACK = ("FR", "FF"), ("RF", "FF")
#: Default ring of variant RF: sleepers on the ring, kept ring modes up to f_limit (Hz).
RF_N_SLEEPERS, RF_F_LIMIT = 40, 500.0
#: Variant RF's keys (the ring and its mode selection).
RF_KEYS = (
    "n_sleepers",
    "f_limit",
    "track_params",
    "x_offset",
    "ring_residual",
    "ring_residual_hz",
    "ring_residual_inertia",
)
_RINGS: dict[Any, Any] = {}
#: Default mode selection of variant FR: harmonics k <= 2, modes up to 800 Hz.
FR_K_MAX, FR_F_MAX = 2, 800.0
#: The highest harmonic variant FR accepts (as the wheelset deck's k_max).
MAX_HARMONIC = 30
_PROFILES: dict[str, Any] = {}


def profiles() -> tuple[Any, Any]:
    """The scenarios' profiles (cached): the S1002 wheel and the UIC60 rail inclined 1:40."""
    if "wheel" not in _PROFILES:
        _PROFILES["wheel"] = s1002()
        _PROFILES["rail"] = uic60(cant=1.0 / 40.0)
    return _PROFILES["wheel"], _PROFILES["rail"]


#: The lateral range of the contact table on the ring track (variants RF and FF), m: the
#: relative wheel-rail position there is the wheelset's plus the rail's lateral deflection and
#: roll under the flange (up to ~4.5 mm and ~14 mrad with the ring's residual flexibility in FF
#: flange hunting at 400 km/h), so the non-flanging wheel ran past the rigid track's
#: 15 mm (docs/vehicle.md, "Variants RF and FF: limits").
RING_TABLE_Y_MAX = 0.020


def wheel_table(y_max: float = 0.015) -> WheelTable:
    """The S1002 / UIC60 1:40 wheel table (per-wheel contact geometry) used by the scenarios
    (cached), over
    -y_max..y_max (m; the ring track's systems take :data:`RING_TABLE_Y_MAX`)."""
    w, r = profiles()
    return profile_table(w, r, y_max=y_max)


#: The contact geometry of each contact model when none is given (the spec's
#: ``default_geometry``): the strip potential for the Hertz models (the table's contact-point
#: jumps sustain tread cycles that the strips and the BEM do not have:
#: docs/speed_accuracy.md), the table's gap fields for the BEM.
DEFAULT_GEOMETRY = {m.name: m.default_geometry for m in CONTACT_MODELS.values()}


def resolve_geometry(contact: str | ContactModel, geometry: str | None) -> str:
    """The contact geometry of a run: ``geometry``, or the contact model's default
    (:data:`DEFAULT_GEOMETRY`) when None; checked against the contact model
    (:meth:`railvti.vehicle.contact_models.ContactModel.resolve_geometry`)."""
    return parse_contact_model(contact).resolve_geometry(geometry)


def _system_geometry(geometry: str | None, linear_conicity: float | None = None) -> str:
    """A system builder's geometry: the given one, else the strips (the Hertz models'
    default; the BEM ignores them), or the table under a linearised table (a cone has no
    strips)."""
    if geometry is None:
        return "table" if linear_conicity is not None else "strip"
    return geometry


def _check_geometry(geometry: str) -> None:
    """InputError for an unknown geometry."""
    if geometry not in GEOMETRIES:
        raise InputError(f"unknown contact geometry {geometry!r}: one of {GEOMETRIES}")


def with_geometry(sy: System, geometry: str) -> System:
    """The system with the contact geometry ``geometry`` (GEOMETRIES)."""
    _check_geometry(geometry)
    if geometry == "table":
        return sy
    if "strip" not in _PROFILES:
        w, r = profiles()
        _PROFILES["strip"] = strip_geometry(w, r, material=sy.table.material)
    return replace(sy, strip=_PROFILES["strip"])


def equivalent_conicity(amplitude: float = 0.003) -> float:
    """EN 15302 equivalent conicity of S1002 / UIC60 1:40 at the given amplitude (m)."""
    w, r = profiles()
    a = _checks.positive("amplitude", amplitude)
    y = np.linspace(-a - 1e-3, a + 1e-3, int(round((2 * a + 2e-3) / 5e-5)) + 1)
    return float(eqc(geometry_table(w, r, y), a))


def fr_wheelset():
    """The FE wheelset of variant FR (cached: its harmonic solves and statics are reused by
    every FR system built at another speed)."""
    if "wheelset" not in _PROFILES:
        _PROFILES["wheelset"] = Wheelset()
    return _PROFILES["wheelset"]


def check_fr_selection(k_max: Any, f_max: Any) -> tuple[int, float]:
    """(k_max, f_max) of variant FR's mode selection, checked: k_max an integer harmonic in
    0..MAX_HARMONIC, f_max a positive finite frequency (Hz).

    Raises
    ------
    InputError
        Naming the bad value and what is allowed.
    """
    ok = False
    try:
        ok = not isinstance(k_max, bool) and float(k_max).is_integer() and 0 <= int(k_max) <= MAX_HARMONIC
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise InputError(
            f"k_max = {k_max!r} is not a harmonic of the wheelset model: the "
            f"highest circumferential harmonic of variant FR's modes must be an "
            f"integer in 0..{MAX_HARMONIC}"
        )
    try:
        f = float(f_max)
    except (TypeError, ValueError):
        f = float("nan")
    if isinstance(f_max, bool) or not (np.isfinite(f) and f > 0.0):
        raise InputError(
            f"f_max = {f_max!r} must be a positive finite frequency, Hz (the "
            "highest non-rotating frequency of variant FR's kept modes)"
        )
    return int(k_max), f


def check_variant(variant: str, contact: str, scenario: str = "") -> None:
    if variant not in VARIANTS:
        raise InputError(f"unknown variant {variant!r}: the time simulation has {VARIANTS}")
    if variant in FLEXIBLE_WHEELSETS and scenario not in FR_SCENARIOS:
        raise InputError(
            f"variant {variant!r} is not available in {scenario or 'this scenario'} "
            f"yet (flexible wheelsets: only {FR_SCENARIOS}); use variant='RR'"
        )
    if variant in RING_TRACK and scenario not in RF_SCENARIOS:
        raise InputError(
            f"variant {variant!r} is not available in {scenario or 'this scenario'} "
            f"yet (ring track: only {RF_SCENARIOS}); use variant='RR'"
        )
    contact_id(contact)


def coach_system(
    variant: str = "RR",
    coach: Coach | None = None,
    *,
    linear_conicity: float | None = None,
    speed_kmh: float | None = None,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    speed: float | None = None,
    geometry: str | None = None,
    follow_contact: bool = False,
    **rf: Any,
) -> System:
    """The assembled coach-track system; ``linear_conicity`` replaces the table by its
    equivalent linearisation (rolling radius linear in y, no flange).

    ``geometry`` is the contact geometry of the Hertz + Kalker and Hertz + FASTSIM contacts:
    'strip' (default: the strip potential over the whole interpenetration,
    :mod:`railvti.vehicle.strip`; exactly conservative, no jumps) or 'table' (one Hertz point
    per slot at the table's lowest gap: the fast option, whose contact-point jumps sustain
    spurious tread cycles). The BEM contact always reads the table. Default under
    ``linear_conicity``: 'table'.

    Variant 'FR' (flexible wheelsets, :func:`fr_system`) needs the speed, ``speed`` (m/s) or
    ``speed_kmh`` (its modal matrices depend on the spin), and takes the mode selection
    ``k_max``, ``f_max`` (Hz); the state is then the DOFs followed by the modal coordinates.
    Variant 'RF' (the ring track, :func:`rf_system`) needs the speed too and takes
    ``n_sleepers``, ``f_limit``, ``track_params`` and ``x_offset``; variant 'FF' (flexible
    wheelsets on the ring, :func:`ff_system`) takes the keys of both. Variants 'FR' and 'FF'
    take ``follow_contact`` (the rims' rows follow the contact point, :func:`fr_system`).
    """
    v = None
    if variant != "RR" and (speed is not None or speed_kmh is not None):
        v = _checks.speed_si(speed, speed_kmh)
    return system_and_layouts(
        variant,
        coach,
        v,
        linear_conicity=linear_conicity,
        k_max=k_max,
        f_max=f_max,
        geometry=geometry,
        follow_contact=follow_contact,
        **rf,
    )[0]


def system_and_layouts(
    variant: str,
    coach: Coach | None,
    speed: float | None,
    *,
    linear_conicity: float | None = None,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    geometry: str | None = None,
    follow_contact: bool = False,
    **rf: Any,
) -> tuple[System, list]:
    """:func:`coach_system` at ``speed`` (m/s; None for variant RR, which does not depend on
    it) and variant FR's and FF's layouts (the mode labels; [] for RR and RF)."""
    check_variant(variant, "hertz-kalker", "coach_system")
    if follow_contact and variant not in FLEXIBLE_WHEELSETS:
        raise InputError(
            f"follow_contact: a key of variants 'FR' and 'FF' (flexible wheelsets); "
            f"variant {variant!r} has rigid wheelsets"
        )
    geometry = _system_geometry(geometry, linear_conicity)
    if variant in RING_TRACK:
        if speed is None:
            raise InputError(
                f"variant {variant!r} needs the speed, speed (m/s) or speed_kmh (the "
                "contact points move along the ring at it)"
            )
        if linear_conicity is not None:
            raise InputError(f"variant {variant!r} has no linearised table (linear_conicity)")
        if variant == "FF":
            return ff_system(
                coach,
                speed=speed,
                k_max=k_max,
                f_max=f_max,
                geometry=geometry,
                follow_contact=follow_contact,
                **rf,
            )
        if (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
            no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
        return rf_system(coach, speed=speed, geometry=geometry, **rf), []
    if rf:
        raise InputError(
            f"{', '.join(sorted(rf))}: not a key of variant {variant!r} "
            f"(variants 'RF' and 'FF' take {RF_KEYS})"
        )
    if variant == "FR":
        if speed is None:
            raise InputError(
                "variant 'FR' needs the speed, speed (m/s) or speed_kmh (the modes depend on the spin)"
            )
        return fr_system(
            coach,
            speed=speed,
            k_max=k_max,
            f_max=f_max,
            linear_conicity=linear_conicity,
            geometry=geometry,
            follow_contact=follow_contact,
        )
    tab = wheel_table()
    if linear_conicity is not None:
        _linear_table_geometry(geometry)
        tab = linearised_table(tab, linear_conicity)
    return with_geometry(build_coach(coach or Coach(), tab), geometry), []


def _linear_table_geometry(geometry: str) -> None:
    if geometry != "table":
        raise InputError(
            "linear_conicity replaces the profiles by a cone: it has no strip geometry (geometry='table')"
        )


def fr_system(
    coach: Coach | None = None,
    *,
    speed_kmh: float | None = None,
    speed: float | None = None,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    linear_conicity: float | None = None,
    geometry: str | None = None,
    follow_contact: bool = False,
) -> tuple[System, list]:
    """Variant FR at one speed: the coach with four flexible wheelsets and their layouts.

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
    v = _checks.speed_si(speed, speed_kmh)
    k_max, f_max = check_fr_selection(k_max, f_max)
    geometry = _system_geometry(geometry, linear_conicity)
    tab = wheel_table()
    if linear_conicity is not None:
        _linear_table_geometry(geometry)
        tab = linearised_table(tab, linear_conicity)
    sy, lays = _fr_build(coach or Coach(), tab, v, k_max, f_max, follow_contact=follow_contact)
    return with_geometry(sy, geometry), lays


def _fr_build(
    coach: Coach,
    table: WheelTable,
    v: float,
    k_max: int,
    f_max: float,
    *,
    track: bool = True,
    follow_contact: bool = False,
) -> tuple[System, list]:
    """build_fr on the scenarios' cached FE wheelset (scaled by the coach's
    wheelset_stiffness_scale); with follow_contact, the residual's 5 mm table over the contact
    points made once per speed and selection (about 30 s)."""
    if not follow_contact:
        return build_fr(coach, table, v, wheelset=fr_wheelset(), k_max=k_max, f_max=f_max, track=track)
    ws, body = coach_body(coach, fr_wheelset(), v, k_max, f_max)
    key = ("residual_grid", float(v), k_max, float(f_max), coach["wheelset_stiffness_scale"])
    if key not in _PROFILES:
        _PROFILES[key] = residual_table(ws, body)
    return build_fr(
        coach,
        table,
        v,
        wheelset=ws,
        body=body,
        follow_contact=True,
        residual_grid=_PROFILES[key],
        track=track,
    )


def ring_track(n_sleepers: Any, track_params: dict | None):
    """The ring track of variant RF (cached per n_sleepers and parameters)."""
    n = _checks.positive_int("n_sleepers", n_sleepers, minimum=2)
    tp = dict(track_params or {})
    key = (n, tuple(sorted((k, repr(v)) for k, v in tp.items())))
    if key not in _RINGS:
        _RINGS.clear()  # one ring at a time: they are large
        _RINGS[key] = RingTrack(n, **tp)
    return _RINGS[key]


def rf_system(
    coach: Coach | None = None,
    *,
    speed_kmh: float | None = None,
    speed: float | None = None,
    n_sleepers: int = RF_N_SLEEPERS,
    f_limit: float | None = RF_F_LIMIT,
    track_params: dict | None = None,
    x_offset: float = 0.0,
    geometry: str | None = None,
    ring_residual: bool = True,
    ring_residual_hz: float | None = None,
    ring_residual_inertia: bool = False,
):
    """Variant RF at one speed: the coach's rigid wheelsets on the flexible ring track.

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
        "Variant RF"); runs with flange-only contact at 400 km/h need it off or massive today
        (a Newton failure with the massless coordinates, docs/vehicle.md "Variants RF and FF:
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
    v = _checks.speed_si(speed, speed_kmh)
    sy, _ = on_ring(
        "RF",
        coach or Coach(),
        wheel_table(RING_TABLE_Y_MAX),
        v,
        n_sleepers=n_sleepers,
        f_limit=f_limit,
        track_params=track_params,
        x_offset=x_offset,
        ring_residual=ring_residual,
        ring_residual_hz=ring_residual_hz,
        ring_residual_inertia=ring_residual_inertia,
    )
    return with_geometry(sy, _system_geometry(geometry))


def on_ring(
    variant: str,
    coach: Coach,
    table: WheelTable,
    v: float,
    *,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    n_sleepers: Any = RF_N_SLEEPERS,
    f_limit: float | None = RF_F_LIMIT,
    track_params: dict | None = None,
    x_offset: float = 0.0,
    ring_residual: bool = True,
    ring_residual_hz: float | None = None,
    ring_residual_inertia: bool = False,
    fr_base: tuple | None = None,
    follow_contact: bool = False,
) -> tuple[System, list]:
    """Variant RF or FF on ``table`` at v (m/s), without the speed bound of the scenarios (the
    linear method's bisection may pass it): the ring checked and built (cached), FR's
    wheelsets on rigid ground for FF (``fr_base``: that (system, layouts) already built at v),
    the ring's block appended. Returns (system, FR layouts or [])."""
    track = checked_ring(coach, n_sleepers, track_params)
    base, lays = None, []
    if variant == "FF" and fr_base is not None:
        base, lays = fr_base
    elif variant == "FF":
        base, lays = _fr_build(coach, table, v, k_max, f_max, track=False, follow_contact=follow_contact)
    sy = build_rf(
        coach,
        table,
        v,
        track,
        f_limit=f_limit,
        x_offset=x_offset,
        base=base,
        residual=bool(ring_residual),
        residual_hz=ring_residual_hz,
        residual_inertia=bool(ring_residual_inertia),
    )
    return sy, lays


def checked_ring(coach: Coach, n_sleepers: Any, track_params: dict | None):
    """The ring of n_sleepers bays, its length checked against the coach before it is built."""
    n = _checks.positive_int("n_sleepers", n_sleepers, minimum=2)
    spacing = dict(track_params or {}).get("sleeper_spacing", 0.6)
    check_ring_length(n, spacing, coach)
    return ring_track(n, track_params)


def ff_system(
    coach: Coach | None = None,
    *,
    speed_kmh: float | None = None,
    speed: float | None = None,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    n_sleepers: int = RF_N_SLEEPERS,
    f_limit: float | None = RF_F_LIMIT,
    track_params: dict | None = None,
    x_offset: float = 0.0,
    geometry: str | None = None,
    ring_residual: bool = True,
    ring_residual_hz: float | None = None,
    ring_residual_inertia: bool = False,
    follow_contact: bool = False,
) -> tuple[System, list]:
    """Variant FF at one speed: the coach's flexible rotating wheelsets on the ring track.

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
    v = _checks.speed_si(speed, speed_kmh)
    k_max, f_max = check_fr_selection(k_max, f_max)
    sy, lays = on_ring(
        "FF",
        coach or Coach(),
        wheel_table(RING_TABLE_Y_MAX),
        v,
        k_max=k_max,
        f_max=f_max,
        n_sleepers=n_sleepers,
        f_limit=f_limit,
        track_params=track_params,
        x_offset=x_offset,
        ring_residual=ring_residual,
        ring_residual_hz=ring_residual_hz,
        ring_residual_inertia=ring_residual_inertia,
        follow_contact=bool(follow_contact),
    )
    return with_geometry(sy, _system_geometry(geometry)), lays


def scenario_system(variant: str, coach: Coach | None, speed: float, kw: dict) -> tuple[System, list]:
    """The scenario's system at ``speed`` (m/s) and its FR layouts (:func:`system_and_layouts`):
    RR, or FR, RF, FF at this speed with their keys (the mode selection, the ring's) popped
    from kw."""
    geometry = kw.pop("geometry", None)
    follow = {"follow_contact": kw.pop("follow_contact")} if "follow_contact" in kw else {}
    if variant in RING_TRACK:
        rf = {k: kw.pop(k) for k in RF_KEYS if k in kw}
        if variant == "RF":
            no_fr_keys(kw)
        else:
            rf.update(k_max=kw.pop("k_max", FR_K_MAX), f_max=kw.pop("f_max", FR_F_MAX))
        return system_and_layouts(variant, coach, speed, geometry=geometry, **follow, **rf)
    extra = sorted(k for k in RF_KEYS if k in kw)
    if extra:
        raise InputError(
            f"{', '.join(extra)}: keys of variants 'RF' and 'FF' (the ring track); "
            f"variant {variant!r} has none"
        )
    if variant == "FR":
        return system_and_layouts(
            variant,
            coach,
            speed,
            k_max=kw.pop("k_max", FR_K_MAX),
            f_max=kw.pop("f_max", FR_F_MAX),
            geometry=geometry,
            **follow,
        )
    no_fr_keys(kw)
    return system_and_layouts(variant, coach, None, geometry=geometry, **follow)


def no_fr_keys(kw: dict) -> None:
    """InputError for variant FR's mode selection given to variant RR."""
    extra = sorted(k for k in ("k_max", "f_max") if k in kw)
    if extra:
        raise InputError(
            f"{', '.join(extra)}: the mode selection of variants 'FR' and 'FF'; "
            "variants 'RR' and 'RF' have rigid wheelsets (no modes)"
        )


def default_step(sy: System, exact: bool | None = None) -> float:
    """1 ms; with modal blocks stepped by the trapezoidal rule (``exact`` False) 1 ms divided
    so that h omega_max <= 2 (MODAL_STEP_LIMIT: every kept mode resolved without the step-size
    refusal of simulate). The exact modal step (``exact``, simulate(modal_step='exact')) keeps
    every mode's frequency at 1 ms. ``exact`` None: simulate's default for sy
    (:func:`railvti.vehicle.simulate.default_modal_step`; 'exact-flange' for FR, trapezoidal
    for the others)."""
    if exact is None:
        exact = exact_modal(sy)
    h = 1e-3
    if sy.modal is not None and not exact:
        h = 1e-3 / np.ceil(1e-3 * sy.modal.max_frequency() / 2.0)
    return h


def time_step(sy: System, h: float | None, exact: bool | None = None) -> float:
    """The time step of a run of sy: h checked against the kept modes
    (:func:`railvti.vehicle.simulate.check_modal_step`, before any work), or the default;
    ``exact``: the run steps its modal blocks exactly (simulate.exact_modal; None: simulate's
    default for sy, integrator 'hht' with alpha = 0)."""
    if exact is None:
        exact = exact_modal(sy)
    if h is None:
        return default_step(sy, exact)
    h = _checks.positive("h", h)
    check_modal_step(sy, h, exact)
    return h


def hunting_conicity() -> float:
    """The equivalent conicity at 3 mm of the profiles (computed once, ~0.5 s; kept in the
    disk cache, railvti._cache, for the next process: a sweep's worker needs it in its first
    task)."""
    if "conicity" not in _PROFILES:
        w, r = profiles()
        key = _cache.digest("conicity", w, r, 0.003)
        hit = _cache.load("conicity", key)
        if hit is not None and set(hit) == {"value"} and hit["value"].shape == ():
            _PROFILES["conicity"] = float(hit["value"])
        else:
            _PROFILES["conicity"] = equivalent_conicity(0.003)
            _cache.store("conicity", key, {"value": np.array(_PROFILES["conicity"])})
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


def run_output_dt(
    sy: System, v: float, h: float, output_dt: float | None, base: float, check: bool = True
) -> float:
    """The output interval of a run of sy at v (m/s) with step h: the given ``output_dt``
    (an AliasingWarning when it aliases a known excitation, unless ``check`` is False) or
    the scene's ``base`` shortened to resolve the excitations (railvti.vehicle.output)."""
    if output_dt is not None and not check:
        return _checks.positive("output_dt", output_dt)
    return _output.output_interval(output_dt, h, _excitations(sy, v), base)


def ring_keys(variant: str, ring: dict | None) -> dict:
    """The ring's keys of a sweep, checked: only RF_KEYS, and only for RF and FF."""
    ring = dict(ring or {})
    bad = sorted(k for k in ring if k not in RF_KEYS)
    if bad:
        raise InputError(
            f"{', '.join(bad)}: unknown keyword(s) (the ring track's keys of "
            f"variants 'RF' and 'FF' are {RF_KEYS})"
        )
    if ring and variant not in RING_TRACK:
        raise InputError(
            f"{', '.join(sorted(ring))}: keys of variants 'RF' and 'FF' (the ring "
            f"track); variant {variant!r} has none"
        )
    return ring
