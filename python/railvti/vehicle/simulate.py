"""Static equilibrium, time integration and linearisation of an assembled System (Fortran core).

The System lives in the Fortran core behind a handle (``System.native``, a
:class:`~railvti.vehicle.model.VehicleModel`), sent once. The whole time loop runs in Fortran
(``vehicle_run_c``); Python calls it in chunks of about :data:`CHUNK_SECONDS` of wall time (whole
output intervals: the numbers are those of one call) to update a progress bar (simulated time and
real-time factor) and to let Ctrl-C / SIGTERM stop a run between chunks.
"""
from __future__ import annotations

import contextlib
import logging
import math
import os
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar, Iterator

import numpy as np

from .. import _checks, _interrupt
from ..casetypes import STREAM_TAIL_SECONDS, HistorySink
from .._native import core
from .._status import Status, check, error
from .._threads import serial_blas
from ..errors import ConvergenceError, DivergenceError, InputError, RailvtiError
from ..resources import check_memory
from .analytic import nadal_limit
from .assembly import System
from .bem import BemOptions, BemState
from .model import CONTACT_MODELS, NWO, WHEEL_OUTPUTS, CallSettings, RunCarry  # noqa: F401 (NWO re-exported)

log = logging.getLogger(__name__)

#: Units of the per-wheel outputs (:data:`WHEEL_OUTPUTS`).
WHEEL_UNITS = {"Q": "N", "Y": "N", "Fx": "N", "N_tread": "N", "N_flange": "N", "spin": "1/m",
               "energy": "J", "contact_angle": "rad", "a": "m", "b": "m"}
#: Units of SimulationResult.stats (stored as stat_NAME).
STAT_UNITS = {"newton_iterations": "1", "tangents": "1", "max_error_estimate": "m", "steps": "1",
              "substepped_steps": "1", "smallest_step": "s",
              "newton_residual": "1 (relative to stat_load_scale)",
              "newton_residual_max": "1 (relative to stat_load_scale)",
              "newton_correction": "m or rad", "newton_correction_max": "m or rad",
              "load_scale": "N", "newton_tol": "m or rad", "newton_rtol": "1", "wall_time": "s",
              "real_time_factor": "1 (wall time / simulated time)", "failed_at": "s",
              "interrupted_at": "s",
              "bem_grid": "1, 1, m (nx, ny, dx)"}

#: Default Newton residual tolerance of :func:`simulate`, relative to the static wheel load:
#: max |r| (N, or N m per metre of lever arm) over all DOFs <= NEWTON_RTOL * wheel load
#: (66 N for the default coach). Hunting runs at 300-420 km/h reach at most 2e-4 (Hertz +
#: Kalker / FASTSIM, tol 1e-9) and 5e-4 (BEM, tol 1e-8): the bound catches a modified Newton
#: that stalls with a small correction but a large error, without moving those runs.
NEWTON_RTOL = 1e-3

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
#: Smallest time step of a simulation, s (below it the step's increments are round-off).
MIN_STEP = 1e-6

#: Time-stepping schemes of :func:`simulate` (``integrator``) and their core ids
#: (vehicle_newmark SCHEME_*): 'hht' Newmark / HHT-alpha (the default), 'energy' the
#: energy-conserving midpoint rule with the discrete gradient of the strip contact's potential
#: (docs/vehicle.md, "Energy-conserving integrator").
INTEGRATORS = {"hht": 0, "energy": 1}

#: Wall time of one call of the Fortran time loop, s: Python runs the loop in calls of about
#: this length (whole output intervals), so Ctrl-C or SIGTERM stops a run within about it.
CHUNK_SECONDS = 0.2

#: What a BEM patch at its grid's edge asks of the user.
_BEM_EDGE_HINT = ("a BEM contact patch reached the edge of its grid (enlarge BemOptions nx/ny or "
                  "load_factor)")


def contact_id(contact: str) -> int:
    """Fortran id of a contact model name; InputError for an unknown one."""
    if contact not in CONTACT_MODELS:
        raise InputError(f"unknown contact model {contact!r}; one of {sorted(CONTACT_MODELS)}")
    return CONTACT_MODELS[contact]


def _settings(speed: float, contact: str, fastsim_n: int, bem: BemState | None) -> CallSettings:
    """The per-call values of the shims; InputError for contact='bem' without a BEM state."""
    cid = contact_id(contact)
    if contact != "bem":
        return CallSettings(speed, cid, fastsim_n, 0)
    if bem is None or not bem.handle:
        raise InputError("contact='bem' needs a BEM contact state")
    return CallSettings(speed, cid, fastsim_n, bem.handle)


def bem_state(system: System, options: BemOptions | None = None) -> BemState:
    """A BEM contact state for ``system`` (close it, or use it as a context manager)."""
    return BemState(system.table, system.wheel_load, system.iws.shape[1], options)


@dataclass(frozen=True)
class SimulationResult:
    """Time histories of one run.

    Attributes
    ----------
    t : ndarray (nt,)
        Output times, s.
    q, v : ndarray (nt, n)
        Displacements (m, rad) and velocities of every DOF (``dof_names``).
    wheel : ndarray (nt, 12, 2, nw)
        Per output time, quantity :data:`WHEEL_OUTPUTS`, wheel (0 left, 1 right), wheelset:
        Q vertical and Y lateral (track y, + left) force of the rail on the wheel (N), the
        longitudinal creep force, the tread and flange normal forces, creepages, spin, Hertz
        energy, contact angle and semi-axes of the more loaded point.
    speed : float
        Forward speed, m/s.
    contact : str
        Contact model.
    stats : dict
        Newton iterations, tangent evaluations, max local error estimate (m), steps, wall
        time (s), real-time factor (wall / simulated); Newton's convergence:
        ``newton_residual`` / ``newton_residual_max`` (max |r| over the DOFs after the last
        iteration of the last accepted step / the largest over all accepted steps, relative to
        ``load_scale``, the static wheel load in N; rotations' residuals in N m are divided by
        the same N, i.e. per metre of lever arm), ``newton_correction`` /
        ``newton_correction_max`` (the last correction max |dq|, m or rad, likewise), and the
        tolerances ``newton_tol`` (correction) and ``newton_rtol`` (residual, relative); with contact='bem' also the BEM
        counters (:data:`railvti.vehicle.bem.COUNTERS`, prefixed ``bem_``) and
        ``bem_solves_per_step`` (normal + rolling solve pairs per time step, all wheels).
    bem_patches : dict or None
        contact='bem': the final BEM fields (:class:`railvti.vehicle.bem.BemPatch`) of the
        loaded candidate point of every wheel, keyed (wheelset, wheel), both 0-based.
    friction : float
        Wheel-rail friction coefficient of the run.
    flange_angle : float
        Flange angle of the wheel profile, rad (:func:`flange_angle`: the largest contact
        angle of the table's flange point on the flange side), for Nadal's limit.
    streamed : str
        '' for a history kept in memory; for a run streamed to HDF5 (``stream_to``), the
        'FILE::GROUP' holding the whole history: ``t``, ``q``, ``v`` and ``wheel`` here
        then hold only its last ``stream_tail`` seconds.
    rail : ndarray (nt, 3, 2, nw) or None
        Model RF (a system on the ring track): the rail head's motion under each wheel at the
        outputs, the pose (y m, z m, roll rad; vehicle frame) of the element under wheel
        [., ., wheel, wheelset] (``RingSystem.rail_deflection``, after a completed run); None
        on rigid track. The ring's modal coordinates are the last columns of ``q``, named in
        ``dof_names``.

    Per wheel: :meth:`wheels` (amplitude per wheelset, Q, Y, Y/Q against Nadal's limit, the
    worst wheel) and :attr:`nadal`.
    """

    #: The units this class gives its fields where its docstring does not end in one
    #: (railvti.runner.results.save reads them here: the result owns its file layout's units).
    FIELD_UNITS: ClassVar[dict[str, Any]] = {
        "t": "s", "q": "m or rad (per dof_names)", "v": "m/s or rad/s (per dof_names)",
        "wheel": "per quantity: see the quantities and quantity_units attributes",
        "speed": "m/s", "h": "s", "friction": "1", "flange_angle": "rad",
        "rail": "m, m, rad (per component: y, z, roll of the element under each wheel)",
        "stats": STAT_UNITS}
    #: Units of the per-wheel outputs and of the statistics (for the runner's records).
    WHEEL_UNITS: ClassVar[dict[str, str]] = WHEEL_UNITS
    STAT_UNITS: ClassVar[dict[str, str]] = STAT_UNITS

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    wheel: np.ndarray
    dof_names: tuple
    speed: float
    contact: str
    h: float
    stats: dict = field(default_factory=dict)
    bem_patches: dict | None = None
    friction: float = float("nan")
    flange_angle: float = float("nan")
    streamed: str = ""
    rail: np.ndarray | None = None

    def _save_attrs(self) -> dict:
        """Labels written beside the arrays by :func:`railvti.runner.results.save`."""
        nw = self.wheel.shape[-1]
        return {"q": {"axes": ["t", "state"], "dof_names": list(self.dof_names)},
                "v": {"axes": ["t", "state"], "dof_names": list(self.dof_names)},
                "t": {"axes": ["t"]},
                "wheel": {"axes": ["t", "quantity", "wheel", "wheelset"],
                          "quantities": list(WHEEL_OUTPUTS),
                          "quantity_units": [WHEEL_UNITS.get(n, "1") for n in WHEEL_OUTPUTS],
                          "wheel": ["left", "right"],
                          "wheelset": [f"ws{w + 1}" for w in range(nw)]},
                **({"rail": {"axes": ["t", "component", "wheel", "wheelset"],
                             "component": ["y", "z", "roll"], "column_units": ["m", "m", "rad"],
                             "wheel": ["left", "right"],
                             "wheelset": [f"ws{w + 1}" for w in range(nw)]}}
                   if self.rail is not None else {})}

    @property
    def nadal(self) -> float:
        """Nadal's limit Y/Q for this run's flange angle and friction."""
        return nadal_limit(self.flange_angle, self.friction)

    @property
    def y_over_q(self) -> np.ndarray:
        """(nt, 2, nw) flange-climb ratio of every wheel: the lateral force of the rail on the
        wheel towards the track centre (-Y on the left wheel, +Y on the right) over Q; 0
        where Q < 1 % of the largest Q of the run (wheel lifted)."""
        q = self.Q
        yout = self.Y * np.array([-1.0, 1.0])[None, :, None]
        ok = q > 0.01 * max(float(q.max()), 1e-30)
        return np.where(ok, yout / np.where(ok, q, 1.0), 0.0)

    def wheels(self, window: float = 1.0) -> "WheelSummary":
        """Per wheelset and wheel over the last ``window`` seconds: lateral amplitude, max Q,
        max |Y|, max Y/Q against Nadal's limit, and the worst wheel."""
        return WheelSummary.of(self, window)

    def dof(self, name: str) -> np.ndarray:
        """Time history of one DOF by name (e.g. 'ws1_y')."""
        if name not in self.dof_names:
            raise InputError(f"unknown DOF {name!r}")
        return self.q[:, self.dof_names.index(name)]

    def wheel_output(self, name: str) -> np.ndarray:
        """(nt, 2, nw) history of one per-wheel output."""
        if name not in WHEEL_OUTPUTS:
            raise InputError(f"unknown wheel output {name!r}; one of {WHEEL_OUTPUTS}")
        return self.wheel[:, WHEEL_OUTPUTS.index(name)]

    @property
    def y_ws1(self) -> np.ndarray:
        """Leading wheelset's lateral displacement, m."""
        return self.dof("ws1_y")

    @property
    def vy_ws1(self) -> np.ndarray:
        """Leading wheelset's lateral velocity, m/s."""
        return self.v[:, self.dof_names.index("ws1_y")]

    @property
    def Q(self) -> np.ndarray:
        """Vertical wheel forces (nt, 2, nw), N."""
        return self.wheel_output("Q")

    @property
    def Y(self) -> np.ndarray:
        """Lateral wheel forces (nt, 2, nw), N (track y, + left)."""
        return self.wheel_output("Y")


def flange_angle(table) -> float:
    """The flange angle of a contact table's wheel profile, rad: the largest contact angle of
    the flange-side candidate point (slot 1) over y >= 0 (70.0 deg for S1002 on UIC60 1:40,
    reached at y = 7 mm; beyond it the contact climbs towards the flange tip)."""
    d = table.at("delta", 1)
    return float(np.max(d[table.y >= 0.0]))


_SIDE = ("left", "right")


@dataclass(frozen=True)
class WheelSummary:
    """All eight wheels of a run over its last window (arrays (2, nw): wheel 0 left / 1 right,
    wheelset 0-based; amplitude (nw,)).

    Attributes
    ----------
    amplitude : ndarray (nw,)
        Half the peak-to-peak lateral displacement of each wheelset, m.
    Q_max, Y_max : ndarray (2, nw)
        Largest vertical force and largest |Y| (lateral, track y), N.
    YQ_max : ndarray (2, nw)
        Largest flange-climb ratio (:attr:`SimulationResult.y_over_q`).
    nadal : float
        Nadal's limit for ``flange_angle`` (rad) and ``friction``.
    worst_yq, worst_q : tuple (wheel, wheelset)
        The wheel with the largest Y/Q relative to Nadal's limit and the one with the
        largest Q.
    """

    window: float
    amplitude: np.ndarray
    Q_max: np.ndarray
    Y_max: np.ndarray
    YQ_max: np.ndarray
    nadal: float
    flange_angle: float
    friction: float
    worst_yq: tuple
    worst_q: tuple

    @classmethod
    def of(cls, res: "SimulationResult", window: float = 1.0) -> "WheelSummary":
        """The summary of ``res`` over its last ``window`` seconds."""
        k = res.t >= res.t[-1] - _checks.positive("window", window)
        nw = res.wheel.shape[-1]
        amp = np.array([0.5 * float(np.ptp(res.dof(f"ws{w + 1}_y")[k])) for w in range(nw)])
        q = res.Q[k].max(axis=0)
        y = np.abs(res.Y[k]).max(axis=0)
        yq = res.y_over_q[k].max(axis=0)
        wy = np.unravel_index(int(np.argmax(yq)), yq.shape)
        wq = np.unravel_index(int(np.argmax(q)), q.shape)
        return cls(window=float(window), amplitude=amp, Q_max=q, Y_max=y, YQ_max=yq,
                   nadal=res.nadal, flange_angle=res.flange_angle, friction=res.friction,
                   worst_yq=(int(wy[0]), int(wy[1])), worst_q=(int(wq[0]), int(wq[1])))

    @property
    def exceeds_nadal(self) -> bool:
        """Any wheel above Nadal's limit."""
        return bool(np.any(self.YQ_max > self.nadal))

    def line(self) -> str:
        """One line naming the worst wheel (largest Y/Q against Nadal, largest Q)."""
        s, w = self.worst_yq
        sq, wq = self.worst_q
        yq = self.YQ_max[s, w]
        flag = "ABOVE" if yq > self.nadal else "below"
        return (f"worst wheel: wheelset {w + 1} {_SIDE[s]} Y/Q {yq:.2f} ({flag} Nadal "
                f"{self.nadal:.2f}: {math.degrees(self.flange_angle):.1f} deg, mu "
                f"{self.friction:g}); largest Q {self.Q_max[sq, wq] / 1e3:.0f} kN at wheelset "
                f"{wq + 1} {_SIDE[sq]}; amplitudes "
                + "/".join(f"{a * 1e3:.1f}" for a in self.amplitude) + " mm")


def static_equilibrium(system: System, speed: float, contact: str = "hertz-kalker", *,
                       q0: np.ndarray | None = None, tol: float = 1e-11, maxit: int = 60,
                       fastsim_n: int = 8, bem: BemState | None = None,
                       bem_options: BemOptions | None = None, return_velocity: bool = False
                       ) -> tuple[np.ndarray, ...]:
    """Steady state of centred running on straight track: F(q, v) = 0 with v = 0 except the
    wheelsets' spin rates betadot (free rolling: the unknowns in place of the spin angles).

    Returns (q, wheel outputs (12, 2, nw)), or (q, v, wheel outputs) with
    ``return_velocity`` (v: zero but the spin rates, rad/s). The start puts each wheelset at the Hertz
    approach of the static load and each track element at its static deflection. With
    contact='bem' the BEM state ``bem`` is used (and left warm), or a temporary one made
    with ``bem_options``; the Newton tangent is then that of Hertz + Kalker.
    With modal blocks (``system.modal``) q, v run over the whole state (the DOFs, then the
    modal coordinates, which start undeformed): Newton with the modal rows condensed onto the
    attachment points (static stiffness K_m: elastic modes only).

    Raises
    ------
    DivergenceError
        A wheelset left its contact table.
    GridTooSmallError
        A BEM contact patch reached the edge of its grid.
    ConvergenceError
        Newton's method did not converge (or met a singular tangent).
    """
    speed = _checks.positive("speed", speed)
    if contact == "bem" and bem is None:
        with bem_state(system, bem_options) as tmp:
            return static_equilibrium(system, speed, contact, q0=q0, tol=tol, maxit=maxit,
                                      fastsim_n=fastsim_n, bem=tmp,
                                      return_velocity=return_velocity)
    cs = _settings(speed, contact, fastsim_n, bem)
    if q0 is None:      # modal coordinates (if any) start undeformed
        q = np.concatenate([_initial_guess(system), np.zeros(system.n_state - system.n)])
    else:
        q = np.array(_checks.finite_array("q0", q0, shape=(system.n_state,)), dtype=float)
    q_start = q.copy()
    limit = NEWTON_RTOL * system.wheel_load     # forces balanced: an equilibrium, not a stall
    v, f, wout, iters, resid, info = _static_call(system, cs, bem, q, tol, maxit)
    stalled = info == Status.NOT_CONVERGED or (
        info == Status.OK and not float(np.max(np.abs(f))) <= limit)
    if stalled and contact in ("hertz-fastsim", "bem"):
        # FASTSIM's and the BEM's Newton (with Hertz + Kalker's tangent) can stall far from
        # equilibrium (discretised creep forces; seen on the ring track from the undeformed
        # start: FF with the BEM stopped with 447 N unbalanced): start again from Hertz +
        # Kalker's equilibrium, where it converges in a few iterations
        log.debug("static equilibrium: %s's Newton stalled; restarting from Kalker's", contact)
        q = q_start
        _static_call(system, _settings(speed, "hertz-kalker", fastsim_n, None), None, q, tol,
                     maxit)
        v, f, wout, iters, resid, info = _static_call(system, cs, bem, q, tol, maxit)
    fmax = float(np.max(np.abs(f)))
    if info == Status.NOT_CONVERGED and resid <= 100.0 * tol and fmax <= limit:
        # the correction stalls at round-off a little above tol (RF's critical_speed stopped
        # at 1.87e-11 against 1e-11) with the forces balanced: that is the equilibrium
        log.debug("static equilibrium: correction %.3g stalled above tol %.3g, forces balanced "
                  "(%.3g N): accepted", resid, tol, fmax)
        info = Status.OK
    context = "static equilibrium"
    if info == Status.OUTSIDE_TABLE:
        context = "static equilibrium: a wheelset left its contact table"
    elif info == Status.GRID_EDGE:
        context = f"static equilibrium: {_BEM_EDGE_HINT}"
    elif info in (Status.NOT_CONVERGED, Status.SINGULAR):
        context = (f"static equilibrium not found after {iters} Newton iterations, last "
                   f"correction {resid:.3g}")
    check(info, context, iterations=int(iters), residual=float(resid))
    # the Newton correction can end small because the line search cut it: the state is an
    # equilibrium only if the forces balance too (NEWTON_RTOL of the wheel load, as a step)
    if not fmax <= limit:
        raise ConvergenceError(f"static equilibrium not found: the Newton correction stopped at "
                               f"{resid:.3g} with an unbalanced force of {fmax:.3g} N (N m) "
                               f"(limit {limit:.3g}); try another q0",
                               iterations=int(iters), residual=fmax)
    log.debug("static equilibrium: %d iterations, unbalanced force %.3g", iters, fmax)
    return (q, v, wout) if return_velocity else (q, wout)


#: Handles of the vehicle models a static solve still uses in a worker thread.
_busy_models: set[int] = set()


def _wait_idle(system: System) -> None:
    """Wait until no interrupted static solve still runs on ``system``'s Fortran model."""
    _interrupt.wait_while(lambda: system.native.handle in _busy_models)


def _static_call(system: System, cs: CallSettings, bem: BemState | None, q: np.ndarray,
                 tol: float, maxit: int) -> tuple:
    """``system.native.static(cs, q, tol, maxit)`` (one Fortran call, ~3-5 s with the BEM)
    in a worker thread, the shim releasing the GIL (``!f2py threadsafe``), while the main
    thread waits for signals (:func:`railvti._interrupt.call_in_worker`): Ctrl-C / SIGTERM
    raise here within ~0.05 s. The Newton iteration cannot be stopped from outside: an
    interrupted call runs on to its end in the background. Meanwhile its model is kept (a
    later call on it waits; it is not freed at exit) and its BEM state, mid-solve, is
    abandoned: ``bem.handle`` becomes 0 (closing it does nothing) and the worker frees it
    when the call ends."""
    native = system.native
    _wait_idle(system)
    handle = native.handle
    abandoned: list[int] = []

    def on_abandon() -> None:
        native._free.atexit = False          # not freed at exit under the running call
        if bem is not None and bem.handle:
            # the rest of the call on one thread: the exit then competes with one compute
            # thread, not all (0.5 s quicker on 2 loaded cores)
            core.vehicle_bem_threads_c(bem.handle, 1)
            abandoned.append(bem.handle)
            bem.handle = 0

    def on_end() -> None:
        for h in abandoned:
            core.vehicle_bem_free_c(h)
        native._free.atexit = True
        _busy_models.discard(handle)
    _busy_models.add(handle)
    return _interrupt.call_in_worker(native.static, cs, q, tol, maxit, on_abandon=on_abandon,
                                     on_end=on_end, name="railvti-static")


def _rigid_only(system: System, what: str) -> None:
    """InputError for a System with modal blocks where only rigid models are handled yet."""
    if system.modal is not None:
        raise InputError(f"{what} does not handle modal blocks yet")


def check_modal_step(system: System, h: float) -> None:
    """InputError when the step h is too large for the highest mode of the system's modal
    blocks: h * omega_max > :data:`MODAL_STEP_LIMIT` (nothing to check without blocks)."""
    if system.modal is None:
        return
    wmax = system.modal.max_frequency()
    if h * wmax > MODAL_STEP_LIMIT:
        raise InputError(
            f"time step h = {h:.3g} s too large for the highest mode kept "
            f"({wmax / (2 * math.pi):.4g} Hz): h * omega_max = {h * wmax:.3g} > "
            f"{MODAL_STEP_LIMIT} (MODAL_STEP_LIMIT); take h <= {MODAL_STEP_LIMIT / wmax:.3g} s "
            "or drop the mode")


def _initial_guess(system: System) -> np.ndarray:
    q = np.zeros(system.n)
    t = system.table
    i0 = int(np.argmin(np.abs(t.y)))
    g0, dl, kh = t.data[0, 0, i0], t.data[2, 0, i0], t.data[6, 0, i0]
    k = np.diag(system.k)
    if not kh > 0.0:        # a table without contact (build_rigid_system): start at zero
        return q
    for w in range(system.iws.shape[1]):
        # wheel load from the preload on this wheelset
        load = -0.5 * system.f0[system.iws[1, w] - 1]
        dn = (load / (kh * math.cos(dl))) ** (2.0 / 3.0)
        zt = 0.0
        jt = system.itr[1, w] - 1
        if jt >= 0:
            zt = -2.0 * load / k[jt]
            q[jt] = zt
        q[system.iws[1, w] - 1] = zt - g0 - dn / math.cos(dl)
    return q


@dataclass(frozen=True)
class _Plan:
    """The checked integration settings of one simulate call."""

    h: float
    nsteps: int
    nevery: int
    alpha: float
    tol: float
    maxit: int
    maxsub: int
    qmax: float
    rtol: float
    load_scale: float
    per_chunk: int
    progress: bool
    scheme: int = 0


def simulate(system: System, speed: float, duration: float, *, contact: str = "hertz-kalker",
             h: float = 1e-3, output_dt: float = 0.01, alpha: float = 0.0,
             q0: np.ndarray | None = None, v0: np.ndarray | None = None, tol: float | None = None,
             maxit: int = 20, maxsub: int = MAXSUB, qmax: float = 1.0, fastsim_n: int = 8,
             progress: bool | None = None, chunk: float | None = None,
             bem_options: BemOptions | None = None, bem: BemState | None = None,
             rtol: float | None = None, stream_to: HistorySink | None = None,
             stream_tail: float = STREAM_TAIL_SECONDS, integrator: str = "hht",
             threads: int | None = None) -> SimulationResult:
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
    h : float
        Time step, s.
    output_dt : float
        Output interval, s (rounded to a multiple of h).
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
        wheelset's position changes by 2e-8 m and the BEM solves per step drop by 19 %).
    rtol : float, optional
        Newton tolerance on the residual, relative to the load scale: a step has converged
        when, at the predictor or after a full step, the next correction is below ``tol``
        (it is then added without a new force evaluation) AND the residual there,
        max |M a - (1 + alpha) F + alpha F_n| over all DOFs (N, or N m for rotations, i.e.
        N per metre of lever arm), is below ``rtol`` times the static wheel load
        (``system.wheel_load``). Default :data:`NEWTON_RTOL`.
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
        most about :data:`CHUNK_SECONDS` of wall time).
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
    if contact_id(contact) == CONTACT_MODELS["bem"] and bem is None:
        with bem_state(system, bem_options) as st:
            return simulate(system, speed, duration, contact=contact, h=h, output_dt=output_dt,
                            alpha=alpha, q0=q0, v0=v0, tol=tol, maxit=maxit, maxsub=maxsub,
                            qmax=qmax, fastsim_n=fastsim_n, progress=progress, chunk=chunk, bem=st,
                            rtol=rtol, stream_to=stream_to, stream_tail=stream_tail,
                            integrator=integrator, threads=threads)
    speed = _checks.positive("speed", speed)
    plan = _plan(contact, duration, h, output_dt, alpha, tol, maxit, maxsub, qmax, progress, chunk,
                 rtol, system.wheel_load)
    plan = replace(plan, scheme=_scheme(integrator, plan.alpha, system))
    check_modal_step(system, plan.h)
    stream_tail = _checks.positive("stream_tail", stream_tail)
    if stream_to is None:
        _check_history_memory(system, plan)
    cs = _settings(speed, contact, _checks.positive_int("fastsim_n", fastsim_n), bem)
    nthreads = bem_threads(bem, threads) if contact_id(contact) == CONTACT_MODELS["bem"] else 1
    _wait_idle(system)      # a static solve interrupted earlier may still run on this model
    q, v = _start_state(system, cs, contact, bem, q0, v0)
    if plan.scheme == INTEGRATORS["energy"]:
        q = consistent_massless(system, speed, q, v, contact, fastsim_n)
    cnt0 = bem.counts() if bem is not None else None
    wall0 = time.perf_counter()
    with _open_stream(stream_to) as stream:
        res = _integrate(system, cs, plan, q, v, contact, stream, stream_tail)
    wall = time.perf_counter() - wall0
    res.stats.update({"wall_time": wall, "real_time_factor": wall / (plan.nsteps * plan.h)})
    if getattr(system, "ring", None) is not None and res.t.size:
        # model RF: the rail under the wheels, after the timed loop (the RTF stays the loop's)
        res = replace(res, rail=system.rail_deflection(res.t, res.q))
    if bem is not None:
        res = _with_bem_fields(res, system, bem, cnt0, plan.nsteps)
        res.stats["bem_threads"] = nthreads
    if not (np.isfinite(res.q).all() and np.isfinite(res.wheel).all()):
        raise RailvtiError("non-finite values in the output")   # defensive: never return NaN
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


def _scheme(integrator: str, alpha: float, system: System) -> int:
    """The core id of ``integrator`` (:data:`INTEGRATORS`); InputError for an unknown name, or
    'energy' with alpha /= 0 or without the strip geometry (the table contact has no
    potential whose discrete gradient could be taken)."""
    if integrator not in INTEGRATORS:
        raise InputError(f"unknown integrator {integrator!r}; one of {sorted(INTEGRATORS)}")
    if integrator == "energy":
        if alpha != 0.0:
            raise InputError(f"integrator='energy' is the midpoint rule: alpha must be 0, got {alpha}")
        if system.strip is None:
            raise InputError("integrator='energy' needs the strip contact geometry "
                             "(geometry='strip'): the table contact has no potential")
    return INTEGRATORS[integrator]


def consistent_massless(system: System, speed: float, q: np.ndarray, v: np.ndarray | None = None,
                        contact: str = "hertz-kalker", fastsim_n: int = 8, tol: float = 1e-9,
                        maxit: int = 8) -> np.ndarray:
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
    cs = _settings(speed, contact, fastsim_n, None)
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
    raise ConvergenceError(f"the massless coordinates' equations at the start: max |F| "
                           f"{np.abs(r).max():.3g} N after {maxit} Newton iterations",
                           iterations=maxit, residual=float(np.abs(r).max()))


def _plan(contact: str, duration: float, h: float, output_dt: float, alpha: float,
          tol: float | None, maxit: int, maxsub: int, qmax: float, progress: bool | None,
          chunk: float | None, rtol: float | None = None, load_scale: float = 1.0) -> _Plan:
    """Check the integration settings and derive the step counts and chunk size."""
    if tol is None:
        tol = 1e-8 if contact == "bem" else 1e-9
    tol = _checks.positive("tol", tol)
    rtol = _checks.positive("rtol", NEWTON_RTOL if rtol is None else rtol)
    duration = _checks.positive("duration", duration)
    h = _checks.positive("h", h)
    if h < MIN_STEP:
        raise InputError(f"h = {h:g} s is below {MIN_STEP:g} s: the Newton tolerance on the step's "
                         "increments is then round-off (the stiffest kept mode, 20 kHz, needs 16 us)")
    alpha = _checks.finite("alpha", alpha)
    if not -1.0 / 3.0 - 1e-12 <= alpha <= 0.0:
        raise InputError(f"alpha must lie in [-1/3, 0], got {alpha}")
    if isinstance(maxsub, bool) or not isinstance(maxsub, (int, np.integer)) or not 0 <= maxsub <= 20:
        raise InputError(f"maxsub must be an integer in [0, 20] (sub-steps down to h/2^maxsub), "
                         f"got {maxsub!r}")
    nevery = max(1, int(round(_checks.positive("output_dt", output_dt) / h)))
    nsteps = int(math.ceil(duration / h - 1e-9))
    nevery = min(nevery, nsteps)
    if progress is None:
        progress = nsteps > 2000
    per_chunk = (nsteps if not progress
                 else max(nevery, int(round((chunk or 0.25) / h)) // nevery * nevery))
    return _Plan(h=h, nsteps=nsteps, nevery=nevery, alpha=alpha, tol=tol, maxit=maxit,
                 maxsub=maxsub, qmax=qmax, rtol=rtol, load_scale=float(load_scale),
                 per_chunk=per_chunk, progress=bool(progress))


def _start_state(system: System, cs: CallSettings, contact: str, bem: BemState | None,
                 q0: np.ndarray | None, v0: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The initial (q, v): given, or the steady state of static_equilibrium."""
    if q0 is None:
        q0, vs, _ = static_equilibrium(system, cs.speed, contact, fastsim_n=cs.fastsim_n,
                                       bem=bem, return_velocity=True)
        if v0 is None:
            v0 = vs
    n = system.n_state
    q = np.array(_checks.finite_array("q0", q0, shape=(n,)), dtype=float)
    v = (np.zeros(n) if v0 is None
         else np.array(_checks.finite_array("v0", v0, shape=(n,)), dtype=float))
    return q, v


@contextlib.contextmanager
def _open_stream(stream_to: Any) -> Iterator[HistorySink | None]:
    """The sink of ``stream_to``: None or the given sink (left open for its owner)."""
    if stream_to is not None and not isinstance(stream_to, HistorySink):
        hint = (" (a path: pass railvti.runner.stream.HistoryStream(path) and close it after the run)"
                if isinstance(stream_to, (str, Path)) else "")
        raise InputError("stream_to must be a history sink (railvti.casetypes.HistorySink), got "
                         f"{type(stream_to).__name__}{hint}")
    yield stream_to


def _integrate(system: System, cs: CallSettings, plan: _Plan, q: np.ndarray, v: np.ndarray,
               contact: str, stream: HistorySink | None = None,
               tail: float = STREAM_TAIL_SECONDS) -> SimulationResult:
    """Run the Fortran time loop from (q, v), with a = M^-1 F(q, v), in chunks (for the
    progress bar) and gather the output (or stream it, keeping the last ``tail`` seconds).
    Raises the exception of a failed step."""
    model = system.native
    if system.modal is None:
        f, _, _, _, info = model.force(cs, q, v)
        check(info, "the initial state (q0, v0)")
        a = np.linalg.solve(system.m, f)
    else:           # M = I on the modal coordinates
        f, _, info = model.state_force(cs, q, v)
        check(info, "the initial state (q0, v0)")
        # massless coordinates carry no acceleration at the start; from then on the time
        # loop's own (BDF2) rates travel from chunk to chunk, so the chunking (sized by wall
        # time) cannot change the result
        fm = np.where(system.modal.mass == 0.0, 0.0, f[system.n:])
        a = np.concatenate([np.linalg.solve(system.m, f[:system.n]), fm])
    t = np.zeros((), dtype=float)
    out = _Output(plan.h, plan.load_scale, stream, tail)
    if stream is not None:
        for name, attrs in _stream_attrs(system).items():
            stream.attrs.setdefault(name, attrs)
    bar = _progress_bar(plan)
    wall0 = time.perf_counter()
    with serial_blas():         # small dense solves: a threaded BLAS only spins
        try:
            done = 0
            size = min(plan.per_chunk, plan.nevery * max(1, 16 // plan.nevery))
            carry = RunCarry.fresh(q.size, model.n_wheelsets)     # F(q, v) from call to call
            while done < plan.nsteps:
                ns = min(size, plan.nsteps - done)
                tc = time.perf_counter()
                nout = max(1, ns // plan.nevery)
                tout, qout, vout, wout, st, info, tfail = model.run(
                    cs, plan.h, ns, plan.nevery, plan.alpha, plan.tol, plan.maxit, plan.maxsub,
                    plan.qmax, plan.rtol * plan.load_scale, t, q, v, a, nout, scheme=plan.scheme,
                    carry=carry)
                wall_call = time.perf_counter() - tc    # the Fortran call alone (not the writing)
                out.add(tout, qout, vout, wout, st, ns // plan.nevery if info == Status.OK else None)
                if info != Status.OK:
                    raise _run_error(info, float(tfail), plan, system,
                                     out.result(system, cs.speed, contact, {"failed_at": float(tfail)}),
                                     int(out.stats[0]))
                done += ns
                size = _next_chunk(ns, wall_call, plan)
                if bar is not None:
                    bar.update(min(round(ns * plan.h, 6), max(bar.total - bar.n, 0.0)))
                    bar.set_postfix_str(f"RTF {(time.perf_counter() - wall0) / max(done * plan.h, 1e-12):.2f}")
        except KeyboardInterrupt as exc:       # Ctrl-C or the runner's SIGTERM: keep what is done
            if out.t and sum(len(x) for x in out.t):
                exc.partial = out.result(system, cs.speed, contact,
                                         dict(out.named_stats(), interrupted_at=float(out.t[-1][-1])))
            raise
        finally:
            if bar is not None:
                bar.close()
    return out.result(system, cs.speed, contact, dict(out.named_stats(), newton_rtol=plan.rtol,
                                                      newton_tol=plan.tol))


def _check_history_memory(system: System, plan: _Plan) -> None:
    """InputError before a run whose time history would not fit the memory limit
    (:mod:`railvti.resources`): q and v of every state and the 12 x 2 wheel outputs of every
    wheelset per output time, gathered in chunks and then joined (about 2 copies)."""
    nout = plan.nsteps // plan.nevery
    per_output = 8 * (2 * system.n_state + len(WHEEL_OUTPUTS) * 2 * system.iws.shape[1] + 1)
    check_memory(f"the time history ({nout} outputs of {per_output} bytes)", 2.0 * nout * per_output,
                 "shorten the duration, raise output_dt, or stream the history to a file "
                 "(stream_to=HistoryStream(PATH), railvti.runner.stream)")


def _next_chunk(ns: int, wall: float, plan: _Plan) -> int:
    """Steps of the next Fortran call: about :data:`CHUNK_SECONDS` of wall time at the pace
    of the last call, a multiple of the output interval (so that the outputs, and every
    number, are those of one call), at most ``plan.per_chunk``."""
    per_step = max(wall, 1e-6) / ns
    k = max(1, int(CHUNK_SECONDS / per_step) // plan.nevery)
    return min(plan.per_chunk, k * plan.nevery)


def _progress_bar(plan: _Plan):
    """A tqdm bar over the simulated time, or None."""
    if not plan.progress:
        return None
    from tqdm import tqdm
    return tqdm(total=round(plan.nsteps * plan.h, 6), unit="s sim", leave=False,
                bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s sim [{elapsed}, {postfix}]")


def _stream_attrs(system: System) -> dict[str, dict[str, Any]]:
    """Units and labels of the streamed t, q, v and wheel (as railvti.runner.results.save)."""
    names = list(system.state_names)
    nw = system.iws.shape[1]
    return {"t": {"units": "s", "axes": ["t"]},
            "q": {"units": "m or rad (per dof_names)", "axes": ["t", "state"], "dof_names": names},
            "v": {"units": "m/s or rad/s (per dof_names)", "axes": ["t", "state"], "dof_names": names},
            "wheel": {"units": "per quantity: see quantity_units",
                      "axes": ["t", "quantity", "wheel", "wheelset"],
                      "quantities": list(WHEEL_OUTPUTS),
                      "quantity_units": [WHEEL_UNITS.get(n, "1") for n in WHEEL_OUTPUTS],
                      "wheel": ["left", "right"], "wheelset": [f"ws{w + 1}" for w in range(nw)]}}


class _Output:
    """The outputs and statistics of the chunks of one run, gathered (or streamed: appended
    to a HistoryStream, only the chunks of the last ``tail`` seconds kept)."""

    def __init__(self, h: float, load_scale: float = 1.0, stream: HistorySink | None = None,
                 tail: float = STREAM_TAIL_SECONDS) -> None:
        self.h = h
        self.load_scale = load_scale
        self.stream = stream
        self.tail = tail
        self.t: list[np.ndarray] = []
        self.q: list[np.ndarray] = []
        self.v: list[np.ndarray] = []
        self.w: list[np.ndarray] = []
        self.stats = np.zeros(10)
        self.stats[5] = h

    def add(self, tout, qout, vout, wout, st, k: int | None) -> None:
        """Append one chunk's first k outputs (None: those written before a failure)."""
        if k is None:
            k = int(np.count_nonzero(tout > 0))
        block = {"t": tout[:k], "q": qout[:, :k].T, "v": vout[:, :k].T,
                 "wheel": np.moveaxis(wout[..., :k], -1, 0)}
        if self.stream is not None:
            self.stream.append(block)
        self.t.append(block["t"])
        self.q.append(block["q"])
        self.v.append(block["v"])
        self.w.append(block["wheel"])
        if self.stream is not None:
            self._drop_before(self.t[-1][-1] - self.tail if k else -math.inf)
        self.stats[[0, 1, 3, 4]] += st[[0, 1, 3, 4]]
        self.stats[2] = max(self.stats[2], st[2])
        self.stats[5] = min(self.stats[5], st[5])
        if st[3] > 0:      # the chunk accepted steps: its last residual/correction are the last
            self.stats[[6, 8]] = st[[6, 8]]
        self.stats[[7, 9]] = np.maximum(self.stats[[7, 9]], st[[7, 9]])

    def _drop_before(self, t0: float) -> None:
        """Forget the oldest chunks while the next one still starts at or before t0 (they are
        in the stream)."""
        while len(self.t) > 1 and (not len(self.t[1]) or self.t[1][0] <= t0):
            for lst in (self.t, self.q, self.v, self.w):
                del lst[0]

    def named_stats(self) -> dict:
        """The run statistics of SimulationResult.stats (without the wall time)."""
        s = self.stats
        return {"newton_iterations": int(s[0]), "tangents": int(s[1]),
                "max_error_estimate": float(s[2]), "steps": int(s[3]),
                "substepped_steps": int(s[4]), "smallest_step": float(s[5]),
                "newton_residual": float(s[6] / self.load_scale),
                "newton_residual_max": float(s[7] / self.load_scale),
                "newton_correction": float(s[8]), "newton_correction_max": float(s[9]),
                "load_scale": float(self.load_scale)}

    def result(self, system: System, speed: float, contact: str, stats: dict) -> SimulationResult:
        """The SimulationResult of what was gathered."""
        return SimulationResult(
            t=np.concatenate(self.t), q=np.concatenate(self.q), v=np.concatenate(self.v),
            wheel=np.concatenate(self.w), dof_names=system.state_names, speed=speed,
            contact=contact, h=self.h, stats=stats, friction=float(system.friction),
            flange_angle=flange_angle(system.table),
            streamed=self.stream.where if self.stream is not None else "")


def _run_error(info: int, tfail: float, plan: _Plan, system: System,
               partial: SimulationResult, iterations: int) -> Exception:
    """The exception of a failed time step: the time, the step and what went wrong."""
    step = int(round(tfail / plan.h))
    if info == Status.GRID_EDGE:
        return error(info, f"time integration stopped at t = {tfail:.5f} s (step {step}): "
                           f"{_BEM_EDGE_HINT}")
    if info == Status.NOT_CONVERGED:
        why = (f"Newton's method did not converge in {plan.maxit} iterations, even with the "
               f"step cut to h/{2 ** plan.maxsub}")
    elif info == Status.OUTSIDE_TABLE:
        why = (f"a wheelset left the contact table (|y| > {system.table.y[-1] * 1e3:.0f} mm: "
               "flange climb or a diverging solution)")
    elif info == Status.MOTION_TOO_LARGE:
        why = "the state became non-finite or exceeded qmax"
    elif info == Status.CONTACT_NOT_CONVERGED:
        why = "a BEM contact solver (normal or steady rolling) did not converge"
    else:
        return error(info, f"time integration stopped at t = {tfail:.5f} s (step {step})")
    hint = ("try a smaller time step" if plan.h > 10 * MIN_STEP else
            f"a smaller time step will not help (h is {plan.h / MIN_STEP:.3g} x the smallest, "
            f"{MIN_STEP:g} s): check the case's stiffnesses, masses and speed")
    return error(info, f"time integration stopped at t = {tfail:.5f} s (step {step}, "
                       f"h = {plan.h:g} s): {why}; {hint}",
                 exc=DivergenceError, iterations=iterations, result=partial)


def _with_bem_fields(res: SimulationResult, system: System, bem: BemState, cnt0: dict,
                     nsteps: int) -> SimulationResult:
    """The result with the BEM counters of the run and the final BEM patches."""
    cnt = {k: (v if k.startswith("max") else v - cnt0[k]) for k, v in bem.counts().items()}
    stats = dict(res.stats)
    stats.update({f"bem_{k}": v for k, v in cnt.items()})
    stats["bem_solves_per_step"] = cnt["normal_solves"] / max(nsteps, 1)
    stats["bem_grid"] = (bem.grid.nx, bem.grid.ny, bem.grid.dx)
    patches = {}
    for w in range(system.iws.shape[1]):
        for side in (0, 1):
            n_pt = [res.wheel[-1, WHEEL_OUTPUTS.index(n), side, w] for n in ("N_tread", "N_flange")]
            pt = bem.patch(w, side, int(np.argmax(n_pt)), res.speed)
            if pt is not None:
                patches[(w, side)] = pt
    return replace(res, stats=stats, bem_patches=patches)


def lateral_disturbance(system: System, q: np.ndarray, y0: float,
                        wheelsets: tuple[int, ...] = (0, 1)) -> np.ndarray:
    """A copy of q with the given wheelsets (0-based) shifted laterally by y0 (m), their height
    and roll corrected by the table so that the wheels keep their static approach."""
    y0 = _checks.finite("y0", y0)
    t = system.table
    out = np.array(q, dtype=float)
    for w in wheelsets:
        iy, iz, ir = (system.iws[k, w] - 1 for k in range(3))
        yr = q[iy] - (q[system.itr[0, w] - 1] if system.itr[0, w] > 0 else 0.0)
        if abs(yr + y0) > t.y[-1]:
            raise InputError(f"|y0| too large for the contact table (+-{t.y[-1] * 1e3:.0f} mm)")
        def gaps(y):
            gl = np.interp(y, t.y, t.gap_min)
            gr = np.interp(-y, t.y, t.gap_min)
            l = 0.5 * (np.interp(y, t.y, t.l_carrying) + np.interp(-y, t.y, t.l_carrying))
            return gl, gr, l
        gl0, gr0, l0 = gaps(yr)
        gl1, gr1, l1 = gaps(yr + y0)
        out[iy] += y0
        out[iz] -= 0.5 * ((gl1 + gr1) - (gl0 + gr0))
        out[ir] -= 0.5 * ((gl1 - gr1) / l1 - (gl0 - gr0) / l0)
    return out


def force_and_tangent(system: System, q: np.ndarray, v: np.ndarray, speed: float,
                      contact: str = "hertz-kalker", fastsim_n: int = 8):
    """F(q, v), the per-wheel outputs, dF/dq and dF/dv (contact by forward differences).

    Raises
    ------
    DivergenceError
        The state is outside the contact table.
    """
    if contact_id(contact) == CONTACT_MODELS["bem"]:
        with bem_state(system) as st:
            return _force_and_tangent(system, q, v, speed, contact, fastsim_n, st)
    return _force_and_tangent(system, q, v, speed, contact, fastsim_n, None)


def _force_and_tangent(system, q, v, speed, contact, fastsim_n, bem):
    _rigid_only(system, "force_and_tangent")
    cs = _settings(_checks.positive("speed", speed), contact, fastsim_n, bem)
    q = _checks.finite_array("q", q, shape=(system.n,))
    v = _checks.finite_array("v", v, shape=(system.n,))
    f, wout, jq, jv, info = system.native.force(cs, q, v)
    check(info, "force and tangent at the given state")
    return f, wout, jq, jv


def eigenvalues(system: System, speed: float, q: np.ndarray | None = None,
                contact: str = "hertz-kalker", v: np.ndarray | None = None) -> np.ndarray:
    """Eigenvalues (1/s) of the system linearised about (q, v) (default: the steady state of
    static_equilibrium, with its spin rates). Each wheelset's spin angle beta, free (no
    stiffness), adds a zero eigenvalue."""
    if q is None:
        q, v, _ = static_equilibrium(system, speed, contact, return_velocity=True)
    if v is None:
        v = np.zeros(system.n)
    _, _, jq, jv = force_and_tangent(system, q, v, speed, contact)
    n = system.n
    minv = np.linalg.inv(system.m)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = minv @ jq
    a[n:, n:] = minv @ jv
    return np.linalg.eigvals(a)
