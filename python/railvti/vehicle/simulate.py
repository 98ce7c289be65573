"""Time integration of an assembled System (Fortran core): :func:`simulate`.

The System lives in the Fortran core behind a handle (``System.native``, a
:class:`~railvti.vehicle.model.VehicleModel`), sent once. :func:`simulate` checks the settings,
finds the start (the steady state of :func:`~railvti.vehicle.equilibrium.static_equilibrium`
unless given) and runs the Fortran time loop in chunks (:mod:`railvti.vehicle.time_loop`); the
result is a :class:`~railvti.vehicle.run_result.SimulationResult`. A run with the BEM contact
opens one BEM state for its equilibrium and its time loop.
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
import time
from dataclasses import replace
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np

from .. import _checks
from ..casetypes import STREAM_TAIL_SECONDS, HistorySink
from .._native import core
from .._status import check
from ..errors import ConvergenceError, InputError, RailvtiError
from ..track.curve import TrackCurve
from ..track.irregularity import TrackIrregularity
from .assembly import System
from .bem import BemOptions, BemState
from .contact_models import ContactModel, parse_contact_model
from .curving import attached_curve
from .equilibrium import call_settings, contact_state, static_equilibrium, wait_idle
from .irregular_track import check_coverage, check_irregularity, on_track, rail_inputs, source_of
from .model import CallSettings
from .params import Coach
from .ring_coupling import RingSystem
from .run_result import SimulationResult
from .time_loop import RunPlan, check_history_memory, integrate, plan_run, with_bem_fields

__all__ = [
    "MAXSUB",
    "MODAL_STEP_LIMIT",
    "INTEGRATORS",
    "simulate",
    "bem_threads",
    "check_modal_step",
    "default_modal_step",
    "system_variant",
    "EXACT_BY_DEFAULT",
    "EXACT_STEPS",
    "FLANGE_LEVEL",
    "exact_modal",
    "MODAL_STEPS",
    "SCHEME_EXACT",
    "consistent_massless",
]

#: Default deepest sub-step level of :func:`simulate`: a step whose Newton iterations fail is
#: retried as 2, 4, ... 2^MAXSUB sub-steps. A run that converges takes the same steps at any
#: depth it does not reach (the halving only goes deeper where the last level failed), so the
#: depth only turns failures into runs. 6 (h/64) stopped the BEM at 0.75 mm in the flange
#: impacts of hunting at 400 km/h (t = 1.26 s, with 20 or 50 iterations alike); 8 or 10 carry
#: it through (validation/vehicle_bem_speed_accuracy.py, docs/speed_accuracy.md).
MAXSUB = 10

#: Largest h * omega_max allowed with modal blocks (omega_max: the highest undamped natural
#: frequency kept, rad/s). The trapezoidal rule is stable for any step but shortens the discrete
#: frequency to 2 atan(omega h / 2) / h: at omega h = 2 the highest mode runs 21 % slow and has
#: pi steps per period. A step beyond this resolves none of that mode's dynamics: drop the mode
#: (keep its static part) or take a smaller step.
MODAL_STEP_LIMIT = 2.0

#: Time-stepping schemes of :func:`simulate` (``integrator``) and their core ids
#: (vehicle_newmark SCHEME_*): 'hht' Newmark / HHT-alpha (the default), 'energy' the
#: energy-conserving midpoint rule with the discrete gradient of the strip contact's potential
#: (docs/vehicle.md, "Energy-conserving integrator").
INTEGRATORS = {"hht": 0, "energy": 1}

#: Core id of the trapezoidal rule (alpha = 0) with the modal blocks that have mass stepped
#: exactly (vehicle_newmark SCHEME_EXACT, vehicle_modal_step; ``modal_step='exact'``).
SCHEME_EXACT = 2

#: How :func:`simulate` steps the modal blocks (``modal_step``): 'trapezoidal' with the rule
#: of the rigid DOFs, 'exact' (integrator 'hht' with alpha = 0) each block with
#: mass exactly for the point forces linear in time over the step (matrix exponential per
#: block and step size; docs/vehicle_integrator.md, "Exact modal step"); 'exact-moving' the
#: same with the ring track's modes (RF, FF) integrated over their moving rows at
#: :data:`RING_NODES` + 1 nodes a step (docs/vehicle_integrator.md, "The ring's moving rows");
#: 'exact-flange' the 'exact' step with a step that starts in flange contact taken as
#: 2^:data:`FLANGE_LEVEL` sub-steps (docs/vehicle_integrator.md, "Exact modal step: sub-steps in
#: flange contact"). The default: :func:`default_modal_step`.
MODAL_STEPS = ("exact", "exact-moving", "exact-flange", "trapezoidal")

#: The modal steps of :data:`MODAL_STEPS` that step the blocks exactly (vehicle_newmark SCHEME_EXACT).
EXACT_STEPS = ("exact", "exact-moving", "exact-flange")

#: Sub-step level of 'exact-flange' (core id SCHEME_EXACT + 2048 * FLANGE_LEVEL): a step that
#: starts with a wheel in flange contact (its flange point's normal force > 0) is taken as
#: 2^FLANGE_LEVEL sub-steps. The exact step is stable only while sqrt(k_c) h <= sqrt(12) for a
#: point coupling k_c per unit modal mass; FR's flange contact exceeds that at 1 ms and 0.5 ms
#: (flange cycle at 420 km/h: Q max 398 and 190 kN against 104.0 kN converged) and not at
#: 0.25 ms (104.1 kN). 3 (h/8 at 1 ms): 104.1 kN, and FR tread hunting's amplitude as close to
#: its converged value as the trapezoidal step at 0.5 ms (docs/speed_accuracy.md).
FLANGE_LEVEL = 3

#: Sub-intervals a step of 'exact-moving' divides the ring's moving rows into (core id
#: SCHEME_EXACT + 16 * RING_NODES, 1..64).
RING_NODES = 4

#: The variants (:func:`system_variant`) whose modal blocks take the exact modal step by
#: default ('exact-flange', at RR's 1 ms): FR (issue 33). A variant opts in by joining this tuple
#: (simulate, the scenarios' default step, the deck check and the cost estimate follow). FR,
#: measured against the trapezoidal step at 1/16 ms (validation/vehicle_fr_flange_step.py,
#: docs/speed_accuracy.md "FR at RR's 1 ms with sub-steps in flange contact"): the flange cycle
#: at 420 km/h's Q max 104.1 kN against 104.0 kN (the trapezoidal 0.5 ms step 105.9 kN; the
#: plain 'exact' step 398 kN), tread hunting's amplitude and Q max closer than the trapezoidal
#: 0.5 ms step's, at 1.7-1.8x RR's cost instead of 2.2-2.7x (a flange cycle costs 2x the old
#: default's: its flange steps in eighths). The ring track (RF, FF): its moving rows, not its
#: modes, set its step (at 1 ms RF hunting's amplitude is 1.8 % off its converged value;
#: docs/speed_accuracy.md).
EXACT_BY_DEFAULT: tuple[str, ...] = ("FR",)


def system_variant(system: System) -> str:
    """The variant of a system: 'RR' (no modal blocks), 'FR' (flexible wheelsets' rims,
    :class:`~railvti.vehicle.model.ModalCouplings`, on rigid track), 'RF' (the ring track,
    :class:`~railvti.vehicle.ring_coupling.RingSystem`), 'FF' (both), '' (other modal blocks:
    a system built by hand)."""
    if system.modal is None:
        return "RR"
    cp = system.modal.couplings
    rims = cp is not None and np.size(cp.rim_wheelsets) > 0
    if isinstance(system, RingSystem):
        return "FF" if rims else "RF"
    return "FR" if rims else ""


def default_modal_step(variant: str, integrator: str = "hht", alpha: float = 0.0) -> str:
    """The modal step a run takes when ``modal_step`` is not given (:data:`MODAL_STEPS`):
    'exact-flange' for the variants of :data:`EXACT_BY_DEFAULT` when the run is the
    trapezoidal rule's (integrator 'hht', alpha = 0), else 'trapezoidal'. ``variant``: 'RR',
    'FR', 'RF', 'FF' (:func:`system_variant`, a deck's model) or '' (a system built by hand).
    The one place of the choice: simulate, the scenarios' default step
    (:func:`railvti.vehicle.systems.default_step`), the deck check and the cost estimate."""
    exact = integrator == "hht" and alpha == 0.0 and variant in EXACT_BY_DEFAULT
    return "exact-flange" if exact else "trapezoidal"


def exact_modal(
    system: System, integrator: str = "hht", alpha: float = 0.0, modal_step: str | None = None
) -> bool:
    """Whether a run of ``system`` with these settings steps its modal blocks exactly
    (:data:`MODAL_STEPS`; ``modal_step`` None: :func:`default_modal_step` of the system's
    variant, :func:`system_variant`: 'exact-flange' for FR, 'trapezoidal' for the others).
    InputError for an unknown name or 'exact' with alpha /= 0 or the energy integrator.

    'exact' integrates each modal block with mass exactly over the step for the point forces
    linear in time (docs/vehicle_integrator.md, "Exact modal step"): no step-size limit from
    the modes themselves (a point coupling stiffer than (sqrt(12) / h)^2 per unit modal mass
    is not stable: Newmark's beta = 1/6 for it). 'exact-moving' also integrates the ring
    track's modes (RF, FF) over their rows at :data:`RING_NODES` + 1 nodes a step, the contact
    points moving within the step (docs/vehicle_integrator.md, "The ring's moving rows");
    without a ring it is 'exact'. 'exact-flange' is 'exact' with a step that starts in flange
    contact taken as 2^:data:`FLANGE_LEVEL` sub-steps (the flange's Hertz spring on the rims is a
    coupling beyond the exact step's bound at 1 ms; docs/vehicle_integrator.md)."""
    if modal_step is not None and modal_step not in MODAL_STEPS:
        raise InputError(f"unknown modal_step {modal_step!r}; one of {list(MODAL_STEPS)}")
    applies = integrator == "hht" and alpha == 0.0
    if modal_step in EXACT_STEPS and not applies:
        raise InputError(
            f"modal_step={modal_step!r} is the trapezoidal rule's (integrator 'hht', alpha = 0); "
            f"got integrator {integrator!r}, alpha {alpha}: take modal_step='trapezoidal'"
        )
    if modal_step is None:
        modal_step = default_modal_step(system_variant(system), integrator, alpha)
    return system.modal is not None and modal_step in EXACT_STEPS


def check_modal_step(system: System, h: float, exact: bool = False) -> None:
    """InputError when the step h is too large for the highest mode of the system's modal
    blocks stepped by the trapezoidal rule: h * omega_max > :data:`MODAL_STEP_LIMIT` (nothing
    to check without blocks, or with ``exact``: the exact modal step, :func:`exact_modal`,
    keeps each mode's frequency and damping at any step)."""
    if system.modal is None or exact:
        return
    wmax = system.modal.max_frequency()
    if h * wmax > MODAL_STEP_LIMIT:
        raise InputError(
            f"time step h = {h:.3g} s too large for the highest mode kept "
            f"({wmax / (2 * math.pi):.4g} Hz): h * omega_max = {h * wmax:.3g} > "
            f"{MODAL_STEP_LIMIT} (MODAL_STEP_LIMIT); take h <= {MODAL_STEP_LIMIT / wmax:.3g} s "
            "or drop the mode"
        )


# long: the public entry point, whose docstring documents every keyword of a run (its body is 30 lines)
def simulate(
    system: System,
    speed: float,
    duration: float,
    *,
    contact: str | ContactModel = "hertz-kalker",
    h: float = 1e-3,
    output_dt: float = 0.01,
    alpha: float = 0.0,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    tol: float | None = None,
    maxit: int = 20,
    maxsub: int = MAXSUB,
    qmax: float = 1.0,
    fastsim_n: int = 8,
    progress: bool | None = None,
    chunk: float | None = None,
    bem_options: BemOptions | None = None,
    bem: BemState | None = None,
    rtol: float | None = None,
    stream_to: HistorySink | None = None,
    stream_tail: float = STREAM_TAIL_SECONDS,
    integrator: str = "hht",
    threads: int | None = None,
    curve: TrackCurve | None = None,
    irregularity: TrackIrregularity | None = None,
    x_start: float = 0.0,
    coach: Coach | None = None,
    modal_step: str | None = None,
) -> SimulationResult:
    """Integrate the system in time (Newmark / HHT-alpha with Newton, all in Fortran).

    Parameters
    ----------
    system : System
    speed : float
        Forward speed v0, m/s (> 0).
    duration : float
        Simulated time, s.
    contact : str
        'hertz-kalker', 'hertz-fastsim' or 'bem' (BEM normal + steady rolling on a fixed
        0.75 mm grid per wheel and candidate point, warm-started; modified Newton with the
        Hertz + Kalker tangent).
    h, output_dt : float
        Time step and output interval (rounded to a multiple of h), s.
    alpha : float
        HHT-alpha in [-1/3, 0]; 0 is the average acceleration rule (no numerical damping).
    q0, v0 : ndarray, optional
        Initial state (default: the steady state of static_equilibrium, at rest but for the
        wheelsets' free-rolling spin rates; a q0 without v0 starts with v = 0). With modal
        blocks (``system.modal``) q0, v0 hold the DOFs followed by the modal coordinates
        (``system.state_names``); the step must then satisfy :func:`check_modal_step`.
    tol : float, optional
        Newton tolerance on the correction, m or rad (default 1e-9; 1e-8 with contact='bem',
        whose tangent is a calibrated cheap model: hunting at 300 km/h, 0.1 s, the leading
        wheelset's position changes by 2e-8 m and the BEM solves per step drop by 19 %). On
        the ring track (RF, FF) with the kept matrix a step also stops when the error left
        after its last correction, estimated from Newton's contraction, is below ``tol``
        (docs/speed_accuracy.md, "The ring's Newton stopping test").
    rtol : float, optional
        Newton tolerance on the residual, relative to the load scale: a step has converged
        when, at the predictor or after a full step, the next correction is below ``tol``
        (it is then added without a new force evaluation) AND the residual there,
        max |M a - (1 + alpha) F + alpha F_n| over all DOFs (N, or N m for rotations, i.e.
        N per metre of lever arm), is below ``rtol`` times the static wheel load
        (``system.wheel_load``). Default :data:`~railvti.vehicle.equilibrium.NEWTON_RTOL`.
    maxit : int
        Newton iterations per step.
    maxsub : int
        A step whose Newton iterations fail is retried with h/2, h/4, ... h/2^maxsub
        (contact closing or opening inside the step); 0 makes the step strictly fixed.
        Default :data:`MAXSUB` (10: h/1024).
    qmax : float
        Any |q| above this (m, rad) stops the run as diverged.
    fastsim_n : int
        FASTSIM strips and points per strip.
    progress : bool, optional
        Show a tqdm bar (default: when the run has more than 2000 steps).
    chunk : float, optional
        Largest simulated time per Fortran call with the bar, s (each call also lasts at
        most about :data:`~railvti.vehicle.time_loop.CHUNK_SECONDS` of wall time).
    bem_options : BemOptions, optional
        Grid and solver settings of contact='bem'.
    bem : BemState, optional
        An existing BEM state to use (and leave open, with its warm starts); by default a
        state is made for the run and freed at its end.
    stream_to : HistorySink, optional
        Hand the history (``t``, ``q``, ``v``, ``wheel``) to this sink
        (:class:`railvti.casetypes.HistorySink`) as the time loop's chunks finish, e.g.
        ``railvti.runner.stream.HistoryStream(path)``, resizable chunked HDF5 datasets in the
        group 'history' (the sink is left open for its owner), and keep in memory only the
        last ``stream_tail`` seconds: the
        returned SimulationResult (and an interruption's ``partial``) then holds that tail,
        and its ``streamed`` names the file and group. The streamed rows equal, to the bit,
        those of a run kept in memory. For long runs (``railvti run`` streams a case whose
        history exceeds :func:`railvti.runner.stream.stream_threshold`).
    stream_tail : float
        Simulated time kept in memory when streaming, s (default
        :data:`railvti.runner.stream.STREAM_TAIL_SECONDS`).
    integrator : str
        'hht' (default): Newmark / HHT-alpha. 'energy': the energy-conserving midpoint rule
        (alpha must be 0; the strip contact geometry, whose normal contact has a potential):
        the linear forces at the step's midpoint and the Gonzalez discrete gradient of the
        contact potential and the bump stops, so that an undamped frictionless run keeps its
        energy to the Newton tolerance (docs/vehicle.md, "Energy-conserving integrator").
        Each Newton iteration evaluates the contact three times (end, midpoint, frictionless
        midpoint).
    threads : int, optional
        contact='bem': threads that solve the patches of all wheels of a force evaluation
        concurrently (OpenMP; the results are the same to the bit with any number). Default:
        the environment variable ``RAILVTI_THREADS``, else all cores (``OMP_NUM_THREADS`` when
        set). Set on the BEM state (a given ``bem`` keeps it); 1 in a build without OpenMP;
        ``stats['bem_threads']`` says how many ran. Ignored by the other contact models.
    curve : TrackCurve, optional
        Run through this curve (plan and cant; :mod:`railvti.vehicle.curving`, variants RR
        and RF, integrator 'hht'): the vehicle's reference point (the carbody's centre) is at
        ``x_start`` + speed t along the track; the start state (unless given) is the steady
        state there. None: straight track.
    irregularity : TrackIrregularity, optional
        Run on this irregular track (docs/vehicle_irregularity.md): wheelset w at x_start +
        speed t + ``system.x_wheelsets[w]``, m, for the whole run (InputError otherwise); the
        static start (no q0) is found on it at t = 0. The result keeps its source and the rail
        inputs (``irregularity``, ``track_input``). Not with integrator='energy'.
    x_start : float
        The position along the track of the coach's reference point (the carbody's centre)
        at t = 0, m (with ``curve`` or ``irregularity``).
    coach : Coach, optional
        The coach the system was built from (its geometry places the bodies in the curve;
        default ``Coach()``).
    modal_step : str, optional
        'trapezoidal', 'exact', 'exact-flange' or 'exact-moving' (RF, FF): :func:`exact_modal`; None:
        :func:`default_modal_step` ('exact-flange' for FR, 'trapezoidal' for the others:
        :data:`EXACT_BY_DEFAULT`).

    Raises
    ------
    DivergenceError
        Newton did not converge, the state became non-finite or huge, or a wheelset left
        its contact table; the message names the time and the step.
    GridTooSmallError
        A BEM contact patch reached the edge of its grid.
    KeyboardInterrupt
        Ctrl-C (or SIGTERM under ``railvti run``) between two chunks of the time loop; its
        ``partial`` attribute holds the SimulationResult of the chunks completed (the
        numbers of an uninterrupted run up to ``stats['interrupted_at']``).
    InputError
        Bad settings, or a time history that would need more memory than the limit of
        :mod:`railvti.resources` (``RAILVTI_MAX_MEMORY``; 80 % of the available memory by
        default), said before the run starts.
    """
    spec = parse_contact_model(contact)
    with contact_state(system, spec, bem, bem_options) as bem:
        speed = _checks.positive("speed", speed)
        plan = plan_run(
            spec,
            duration,
            h,
            output_dt,
            alpha,
            tol,
            maxit,
            maxsub,
            qmax,
            progress,
            chunk,
            rtol,
            system.wheel_load,
        )
        plan = replace(plan, scheme=_scheme(integrator, plan.alpha, system, modal_step))
        check_modal_step(system, plan.h, plan.scheme % 16 == SCHEME_EXACT)
        if curve is not None and plan.scheme == INTEGRATORS["energy"]:
            raise InputError("curve: the curve's tables enter integrator 'hht' only, not 'energy'")
        run = functools.partial(
            _run_planned, system, speed, spec, bem, plan, q0, v0, fastsim_n, threads, stream_to, stream_tail
        )
        with attached_curve(system, curve, speed, x_start, plan.nsteps * plan.h, coach):
            if irregularity is None:
                return run()
            return _run_on_track(run, system, speed, plan, irregularity, x_start)


def _run_on_track(
    run: Callable[[], SimulationResult],
    system: System,
    speed: float,
    plan: RunPlan,
    irregularity: Any,
    x_start: float,
) -> SimulationResult:
    """``run()`` (:func:`simulate`'s planned run) on the irregular track, checked, with the
    irregularity's source and the rail inputs at the outputs in the result."""
    irr = check_irregularity(irregularity)
    x_start = _checks.finite("x_start", x_start)
    if plan.scheme == INTEGRATORS["energy"]:
        raise InputError(
            "integrator='energy' conserves the energy of an autonomous system: an irregular "
            "track is a time-dependent input; use integrator='hht'"
        )
    check_coverage(system, irr, speed, plan.nsteps * plan.h, x_start)
    wait_idle(system)  # a static solve interrupted earlier may still run on this model
    with on_track(system, irr, speed, x_start):
        res = run()
        inputs = rail_inputs(system, res.t)[:, :3]
    return replace(res, irregularity=source_of(irr, x_start), track_input=inputs)


def _run_planned(
    system: System,
    speed: float,
    spec: ContactModel,
    bem: BemState | None,
    plan: RunPlan,
    q0: np.ndarray | None,
    v0: np.ndarray | None,
    fastsim_n: int,
    threads: int | None,
    stream_to: HistorySink | None,
    stream_tail: float,
) -> SimulationResult:
    """:func:`simulate` once its run is planned (``speed`` checked, m/s): the remaining
    settings checked, the start state, the time loop (streamed or kept) and its result."""
    stream_tail = _checks.positive("stream_tail", stream_tail)
    if stream_to is None:
        check_history_memory(system, plan)
    cs = call_settings(speed, spec, _checks.positive_int("fastsim_n", fastsim_n), bem)
    nthreads = bem_threads(bem, threads) if spec.needs_bem else 1
    wait_idle(system)  # a static solve interrupted earlier may still run on this model
    q, v = _start_state(system, cs, spec, bem, q0, v0)
    if plan.scheme == INTEGRATORS["energy"]:
        q = consistent_massless(system, speed, q, v, spec, fastsim_n)
    cnt0 = bem.counts() if bem is not None else None
    wall0 = time.perf_counter()
    with _open_stream(stream_to) as stream:
        res = integrate(system, cs, plan, q, v, spec.name, stream, stream_tail)
    return _finish(res, system, plan, time.perf_counter() - wall0, bem, cnt0, nthreads)


def _finish(
    res: SimulationResult,
    system: System,
    plan: RunPlan,
    wall: float,
    bem: BemState | None,
    cnt0: dict | None,
    nthreads: int,
) -> SimulationResult:
    """The result of a completed time loop with its wall time, the rail under the wheels
    (variant RF) and the BEM's counters and fields."""
    res.stats.update({"wall_time": wall, "real_time_factor": wall / (plan.nsteps * plan.h)})
    if getattr(system, "ring", None) is not None and res.t.size:
        # variant RF: the rail under the wheels, after the timed loop (the RTF stays the loop's)
        res = replace(res, rail=system.rail_deflection(res.t, res.q))
    if bem is not None:
        res = with_bem_fields(res, system, bem, cnt0, plan.nsteps)
        res.stats["bem_threads"] = nthreads
    if not (np.isfinite(res.q).all() and np.isfinite(res.wheel).all()):
        raise RailvtiError("non-finite values in the output")  # defensive: never return NaN
    return res


def bem_threads(bem: BemState, threads: int | None = None) -> int:
    """Set the threads of a BEM state's patch loop (see :func:`simulate`, ``threads``).

    Parameters
    ----------
    bem : BemState
    threads : int, optional
        Threads (>= 1); None: ``RAILVTI_THREADS`` if set, else all cores.

    Returns
    -------
    int
        The number set: 1 in a build without OpenMP.
    """
    if threads is None:
        env = os.environ.get("RAILVTI_THREADS", "").strip()
        try:
            threads = _checks.positive_int("RAILVTI_THREADS", int(env)) if env else 0
        except ValueError:
            raise InputError(f"RAILVTI_THREADS must be a positive integer, got {env!r}") from None
    else:
        threads = _checks.positive_int("threads", threads)
    nset, info = core.vehicle_bem_threads_c(bem.handle, threads)
    check(info, "BEM contact state already freed")
    return int(nset)


def _scheme(integrator: str, alpha: float, system: System, modal_step: str | None = None) -> int:
    """The core id of ``integrator`` (:data:`INTEGRATORS`), or :data:`SCHEME_EXACT` (plus the
    moving rows' or the flange sub-steps' code) when the modal blocks step exactly
    (:func:`exact_modal`); InputError for an unknown name, or 'energy' with alpha /= 0 or
    without the strip geometry (the table contact has no potential whose discrete gradient
    could be taken)."""
    if modal_step is None:
        modal_step = default_modal_step(system_variant(system), integrator, alpha)
    if exact_modal(system, integrator, alpha, modal_step):
        if modal_step == "exact-flange":
            return SCHEME_EXACT + 2048 * FLANGE_LEVEL
        return SCHEME_EXACT + (16 * RING_NODES if modal_step == "exact-moving" else 0)
    if integrator not in INTEGRATORS:
        raise InputError(f"unknown integrator {integrator!r}; one of {sorted(INTEGRATORS)}")
    if integrator == "energy":
        if alpha != 0.0:
            raise InputError(f"integrator='energy' is the midpoint rule: alpha must be 0, got {alpha}")
        if system.strip is None:
            raise InputError(
                "integrator='energy' needs the strip contact geometry "
                "(geometry='strip'): the table contact has no potential"
            )
    return INTEGRATORS[integrator]


def consistent_massless(
    system: System,
    speed: float,
    q: np.ndarray,
    v: np.ndarray | None = None,
    contact: str | ContactModel = "hertz-kalker",
    fastsim_n: int = 8,
    tol: float = 1e-9,
    maxit: int = 8,
) -> np.ndarray:
    """The state q with its massless coordinates (the residual flexibility, ``modal.mass`` 0)
    solved from their algebraic equations F_r(q, v) = 0 at the others' values (a copy; q itself
    without massless coordinates). Newton with a forward-difference Jacobian over the massless
    coordinates until max |F_r| <= tol times the static wheel load.

    integrator='energy' starts from it: the midpoint rule holds a massless row at the step's
    midpoint, so an inconsistent start (e.g. a wheelset moved off its equilibrium, its rim
    loads changed) would stay as an undamped alternating error of those coordinates, which
    the endpoint contact (and the discrete gradient through it) would see at every step.

    Raises
    ------
    ConvergenceError
        The equations are not met after ``maxit`` iterations.
    """
    q = np.array(q, dtype=float)
    mb = system.modal
    if mb is None or not np.any(mb.mass == 0.0):
        return q
    v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
    cs = call_settings(speed, contact, fastsim_n, None)
    idx = system.n + np.flatnonzero(mb.mass == 0.0)

    def f_r(x: np.ndarray) -> np.ndarray:
        f, _, info = system.native.state_force(cs, x, v)
        check(info, "the massless coordinates' equations at the start")
        return f[idx]

    r = f_r(q)
    limit = tol * system.wheel_load
    for _ in range(maxit):
        if np.abs(r).max() <= limit:
            return q
        eps = 1e-10 * max(1.0, float(np.abs(q[idx]).max()) * 1e3)
        jac = np.empty((idx.size, idx.size))
        for j, i in enumerate(idx):
            x = q.copy()
            x[i] += eps
            jac[:, j] = (f_r(x) - r) / eps
        q[idx] -= np.linalg.solve(jac, r)
        r = f_r(q)
    if np.abs(r).max() <= limit:
        return q
    raise ConvergenceError(
        f"the massless coordinates' equations at the start: max |F| "
        f"{np.abs(r).max():.3g} N after {maxit} Newton iterations",
        iterations=maxit,
        residual=float(np.abs(r).max()),
    )


def _start_state(
    system: System,
    cs: CallSettings,
    contact: ContactModel,
    bem: BemState | None,
    q0: np.ndarray | None,
    v0: np.ndarray | None,
) -> tuple[np.ndarray, np.ndarray]:
    """The initial (q, v): given, or the steady state of static_equilibrium."""
    if q0 is None:
        q0, vs, _ = static_equilibrium(
            system, cs.speed, contact, fastsim_n=cs.fastsim_n, bem=bem, return_velocity=True
        )
        if v0 is None:
            v0 = vs
    n = system.n_state
    q = np.array(_checks.finite_array("q0", q0, shape=(n,)), dtype=float)
    v = np.zeros(n) if v0 is None else np.array(_checks.finite_array("v0", v0, shape=(n,)), dtype=float)
    return q, v


@contextlib.contextmanager
def _open_stream(stream_to: Any) -> Iterator[HistorySink | None]:
    """The sink of ``stream_to``: None or the given sink (left open for its owner)."""
    if stream_to is not None and not isinstance(stream_to, HistorySink):
        hint = (
            " (a path: pass railvti.runner.stream.HistoryStream(path) and close it after the run)"
            if isinstance(stream_to, (str, Path))
            else ""
        )
        raise InputError(
            "stream_to must be a history sink (railvti.casetypes.HistorySink), got "
            f"{type(stream_to).__name__}{hint}"
        )
    yield stream_to
