"""Centred running, the hunting test and a run over an irregular track on straight track
(railvti.scenarios), with the contact patch of a run."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _checks
from ..errors import InputError
from ..contact.fastsim import fastsim
from .assembly import System
from .flexible_points import rail_head_roll, rim_camber_change
from .params import Coach
from .scenario_results import CentredRunning
from .equilibrium import contact_state, lateral_disturbance, static_equilibrium
from .irregular_track import check_irregularity, fade_in, on_track, run_span
from ..track.irregularity import TrackIrregularity
from .model import WHEEL_OUTPUTS
from .model_choice import ModelChoice, auto_contact, auto_variant, flange_scene
from .run_result import SimulationResult
from .simulate import exact_modal, simulate
from dataclasses import replace
from .systems import (
    FLEXIBLE_WHEELSETS,
    RING_TRACK,
    check_variant,
    resolve_geometry,
    run_output_dt,
    scenario_system,
    time_step,
)

__all__ = ["centred_running", "contact_patch", "hunting", "irregular_track"]


def centred_running(
    speed_kmh: float | None = None,
    variant: str = "RR",
    contact: str = "hertz-kalker",
    *,
    speed: float | None = None,
    duration: float = 1.0,
    h: float | None = None,
    coach: Coach | None = None,
    **kw: Any,
) -> CentredRunning:
    """Centred running on straight ideal track: the steady state and Q, Y per wheel.

    Parameters
    ----------
    speed_kmh : float, optional
        Speed, km/h (> 0): the suffixed alias of ``speed``; default 200 km/h.
    variant, contact : str
        'RR', 'FR', 'RF', 'FF' or 'auto' (the cheapest measured variant within
        ``variant_tolerance`` on ``variant_quantities``, scene 'centred');
        'hertz-kalker', 'hertz-fastsim', 'bem' or 'auto' (the cheapest
        measured model within ``tolerance`` on ``quantities``, keywords of **kw:
        railvti.vehicle.model_choice, scene 'centred-ring').
    speed : float, optional
        Speed, m/s (give it or speed_kmh, not both).
    duration : float
        Simulated time after the static equilibrium, s.
    h : float, optional
        Time step, s (default 1 ms; the modal variants' 1 ms divided into as many parts as the
        highest kept mode needs, h omega_max <= 2, unless their modal blocks are stepped
        exactly: ``modal_step='exact'`` or ``'exact-flange'``, or simulate's default_modal_step:
        FR's).
    coach : Coach, optional
        Vehicle parameters (default: Manchester benchmark coach).
    **kw
        Passed to simulate; variant FR also takes k_max and f_max (Hz), the mode selection;
        variant RF n_sleepers, f_limit, track_params, x_offset (:func:`rf_system`).
        ``output_dt`` (s): the interval of the stored history. Default: 10 ms, shortened
        so that the known periodic excitations get 10 samples per period each
        (railvti.vehicle.output): the sleeper passing v / sleeper spacing on the ring track
        (RF, FF: 1 ms at 200 km/h on 0.6 m with the 0.5 ms step) and hunting; the elastic
        modes only when asked with a finer ``output_dt``. A given ``output_dt`` coarser
        than the Nyquist limit of one of them gives an AliasingWarning.
    """
    v = _checks.speed_si(speed, speed_kmh, 200.0)
    choice = vchoice = None
    if variant == "auto":
        variant, vchoice = auto_variant(kw, "centred")
    if contact == "auto":
        contact, choice = auto_contact(kw, "centred-ring")
    check_variant(variant, contact, "centred_running")
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy, layouts = scenario_system(variant, coach, v, kw)
    h = time_step(sy, h, _exact(sy, kw.get("alpha", 0.0), kw))
    kw["output_dt"] = run_output_dt(sy, v, h, kw.get("output_dt"), 0.01)
    # one BEM state for the equilibrium and the run (railvti.vehicle.equilibrium.contact_state)
    with contact_state(sy, contact, kw.pop("bem", None), kw.pop("bem_options", None)) as st:
        q0, v0, _ = static_equilibrium(sy, v, contact, bem=st, return_velocity=True)
        run = simulate(sy, v, duration, contact=contact, h=h, q0=q0, v0=v0, bem=st, **kw)
    run = replace(run, model_choice=choice, variant_choice=vchoice)
    if st is not None:
        patch = (run.bem_patches or {}).get((0, 1))
    else:
        patch = contact_patch(sy, run, -1, wheel=1, wheelset=0)
    rim = camber = roll = None
    if variant in FLEXIBLE_WHEELSETS:
        camber = rim_camber_change(sy, run.q[-1])
        roll = rail_head_roll(sy, run.q[-1], run.t[-1])
        rim = camber - roll
    rail = None
    if variant in RING_TRACK:  # simulate's, or the history's own when it had none
        rail = run.rail if run.rail is not None else sy.rail_deflection(run.t, run.q)
    return CentredRunning(
        Q=run.Q[-1],
        Y=run.Y[-1],
        static_wheel_load=sy.wheel_load,
        q_static=q0,
        run=run,
        speed=v,
        contact=contact,
        patch=patch,
        variant=variant,
        rim_angle=rim,
        rail=rail,
        rim_camber=camber,
        rail_roll=roll,
        system=sy,
        layouts=layouts,
    )


def contact_patch(
    system: System, run: SimulationResult, index: int = -1, *, wheel: int = 1, wheelset: int = 0, n: int = 40
):
    """FASTSIM fields (Hertz pressure) of one wheel's more loaded contact point at output
    ``index`` of a run: pressure, tractions, slip, friction power density."""
    w = run.wheel[index, :, wheel, wheelset]
    fn = max(w[WHEEL_OUTPUTS.index("N_tread")], w[WHEEL_OUTPUTS.index("N_flange")])
    if fn <= 0:
        return None
    col = WHEEL_OUTPUTS.index
    return fastsim(
        w[col("a")],
        w[col("b")],
        fn,
        system.table.material,
        system.friction,
        (w[col("xi")], w[col("eta")], w[col("spin")]),
        nx=n,
        ny=n,
        speed=run.speed,
        pressure="hertz",
    )


def hunting(
    speed_kmh: float | None = None,
    variant: str = "RR",
    contact: str = "hertz-kalker",
    *,
    speed: float | None = None,
    duration: float = 5.0,
    y0: float = 0.004,
    h: float | None = None,
    output_dt: float | None = None,
    alpha: float = 0.0,
    coach: Coach | None = None,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    return_system: bool = False,
    **kw: Any,
) -> SimulationResult | tuple[SimulationResult, System, list]:
    """Hunting test: the leading bogie's wheelsets shifted by y0, then released.

    Returns the SimulationResult (``t``, ``y_ws1``, ``vy_ws1``, ``q``, ``Q``, ``Y``, ...).
    ``q0``/``v0`` continue from a given state instead (speed sweeps); on the ring track (RF,
    FF) the ring's rows start at ``x_offset``, so a state carried from a run of duration T
    at speed v continues only with ``x_offset`` advanced by v T (modulo the ring's length:
    critical_search does this), not from 0. ``h`` defaults to 1 ms (the modal variants' 1 ms
    divided so that h omega_max <= 2 for the highest kept mode unless their modal blocks are
    stepped exactly, as centred_running); variant 'FR' also takes
    ``k_max`` and ``f_max`` (Hz). The speed is ``speed`` in m/s or its suffixed alias
    ``speed_kmh`` in km/h (exactly one).
    ``output_dt`` (s) defaults to 2 ms, shortened so that the known periodic excitations get
    10 samples per period each (railvti.vehicle.output: hunting, and the sleeper passing on
    the ring track, RF and FF); a given one that aliases either gives an AliasingWarning.
    ``return_system``: return (SimulationResult, the system it ran, variant FR's and FF's
    layouts with the mode labels or []) instead, so that nothing is rebuilt to label it.
    ``contact='auto'``: the cheapest measured model within ``tolerance`` (default 0.05) on
    ``quantities`` (keywords; railvti.vehicle.model_choice), the scene ('hunting-tread' or
    'hunting-flange') from a Hertz + Kalker pre-run of the same release. ``variant='auto'``:
    the cheapest measured variant within ``variant_tolerance`` (default 0.05) on
    ``variant_quantities`` (scene 'critical-speed': the four-variant study's folds).
    """
    v = _checks.speed_si(speed, speed_kmh)
    choice = vchoice = None
    if variant == "auto":
        variant, vchoice = auto_variant(kw, "critical-speed")
    if contact == "auto":
        contact, choice = _auto_hunting(v, duration, y0, coach, kw)
    check_variant(variant, contact, "hunting")
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy, layouts = scenario_system(variant, coach, v, kw)
    h = time_step(sy, h, _exact(sy, alpha, kw))
    output_dt = run_output_dt(sy, v, h, output_dt, 0.002)
    # one BEM state for the equilibrium and the run (railvti.vehicle.equilibrium.contact_state)
    with contact_state(sy, contact, kw.pop("bem", None), kw.pop("bem_options", None)) as st:
        if q0 is None:
            qs, _ = static_equilibrium(sy, v, contact, bem=st)
            q0 = lateral_disturbance(sy, qs, _checks.finite("y0", y0), wheelsets=(0, 1))
        run = simulate(
            sy,
            v,
            duration,
            contact=contact,
            h=h,
            output_dt=output_dt,
            alpha=alpha,
            q0=q0,
            v0=v0,
            bem=st,
            **kw,
        )
    run = replace(run, model_choice=choice, variant_choice=vchoice)
    return (run, sy, layouts) if return_system else run


def _auto_hunting(
    v: float, duration: float, y0: float, coach: Coach | None, kw: dict
) -> tuple[str, ModelChoice]:
    """contact='auto' of a hunting run: the scene's kind from a pre-run of the same release on
    variant RR with Hertz + Kalker on the table (RTF ~0.1): flange contact or tread only
    (:func:`railvti.vehicle.model_choice.flange_scene`), then the choice."""
    pre = hunting(
        speed=v,
        contact="hertz-kalker",
        duration=duration,
        y0=y0,
        coach=coach,
        geometry="table",
        progress=False,
    )
    load = (coach or Coach()).static_wheel_load
    return auto_contact(kw, flange_scene(float(pre.wheel_output("N_flange").max()), load))


def _exact(sy: System, alpha: float, kw: dict) -> bool:
    """Whether the run (simulate's keywords kw) steps sy's modal blocks exactly."""
    return exact_modal(sy, kw.get("integrator", "hht"), alpha, kw.get("modal_step"))


def irregular_track(
    speed_kmh: float | None = None,
    irregularity: TrackIrregularity | None = None,
    variant: str = "RR",
    contact: str = "hertz-kalker",
    *,
    speed: float | None = None,
    duration: float | None = None,
    x_start: float | None = None,
    h: float | None = None,
    output_dt: float | None = None,
    lead_in: float = 20.0,
    coach: Coach | None = None,
    return_system: bool = False,
    **kw: Any,
) -> SimulationResult | tuple[SimulationResult, System, list]:
    """The coach over an irregular straight track (docs/vehicle_irregularity.md): the static
    equilibrium at its start, the irregularity faded in ahead of the leading wheelset over
    ``lead_in``, then the run.

    Parameters
    ----------
    speed_kmh : float, optional
        Speed, km/h (> 0; or ``speed`` in m/s, exactly one).
    irregularity : TrackIrregularity
        The track (railvti.track: e.g. ``irregularity_spectra.generate`` or
        ``irregularity_file.read_csv``, or one made from arrays).
    variant, contact : str
        'RR', 'FR', 'RF' or 'FF'; 'hertz-kalker', 'hertz-fastsim' or 'bem'.
    duration : float, optional
        Simulated time, s; default: until the leading wheelset reaches the irregularity's end.
    x_start : float, optional
        Track position of the coach's origin at t = 0, m; default: the trailing wheelset at
        the irregularity's start.
    h, output_dt : float, optional
        Time step (the variant's default) and output interval (default 2 ms, shortened as
        in :func:`hunting`), s.
    lead_in : float
        The irregularity is zero up to the leading wheelset's start and faded in by a raised
        cosine over this length, m (:func:`~railvti.vehicle.irregular_track.fade_in`), so that
        the run starts from the static equilibrium on perfect track (0: no fade, the static
        equilibrium on the irregular track).
    coach : Coach, optional
    return_system : bool
        Return (SimulationResult, system, layouts) instead.
    **kw
        Passed to simulate, and the variants' keys (as :func:`centred_running`).

    Returns
    -------
    SimulationResult
        With ``irregularity`` (the source) and ``track_input`` (the rails under the wheels).
    """
    if irregularity is None:
        raise InputError("irregular_track needs an irregularity (a railvti.track.TrackIrregularity)")
    irr = check_irregularity(irregularity)
    v = _checks.speed_si(speed, speed_kmh)
    check_variant(variant, contact, "irregular_track")
    kw["geometry"] = resolve_geometry(contact, kw.get("geometry"))
    sy, layouts = scenario_system(variant, coach, v, kw)
    h = time_step(sy, h, _exact(sy, kw.get("alpha", 0.0), kw))
    output_dt = run_output_dt(sy, v, h, output_dt, 0.002)
    xw = np.asarray(sy.x_wheelsets, dtype=float)
    x0, duration = run_span(irr, xw, v, h, x_start, duration)
    if lead_in != 0.0:
        irr = fade_in(irr, x0 + float(xw.max()), lead_in)
    with contact_state(sy, contact, kw.pop("bem", None), kw.pop("bem_options", None)) as st:
        with on_track(sy, irr, v, x0):
            q0, v0, _ = static_equilibrium(sy, v, contact, bem=st, return_velocity=True)
        run = simulate(
            sy,
            v,
            duration,
            contact=contact,
            h=h,
            output_dt=output_dt,
            q0=q0,
            v0=v0,
            bem=st,
            irregularity=irr,
            x_start=x0,
            **kw,
        )
    return (run, sy, layouts) if return_system else run
