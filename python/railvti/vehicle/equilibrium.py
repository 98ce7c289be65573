"""The steady state of an assembled System and the linearisation about a state.

:func:`static_equilibrium` solves F(q, v) = 0 for centred running (one Fortran Newton call in a
worker thread that Ctrl-C / SIGTERM can leave), :func:`lateral_disturbance` shifts wheelsets
off it, and :func:`force_and_tangent` / :func:`eigenvalues` linearise about a state. A run with
the BEM contact uses one BEM state throughout (:func:`contact_state`).
"""

from __future__ import annotations

import contextlib
import logging
import math
from typing import Iterator

import numpy as np

from .. import _checks, _interrupt
from .._native import core
from .._status import Status, check
from ..errors import ConvergenceError, InputError
from .assembly import System
from .bem import BemOptions, BemState
from .contact_models import HERTZ_KALKER, ContactModel, parse_contact_model
from .model import CallSettings

__all__ = [
    "NEWTON_RTOL",
    "bem_state",
    "contact_state",
    "call_settings",
    "static_equilibrium",
    "lateral_disturbance",
    "force_and_tangent",
    "eigenvalues",
]

log = logging.getLogger(__name__)

#: Default Newton residual tolerance of :func:`~railvti.vehicle.simulate.simulate`, relative to
#: the static wheel load: max |r| (N, or N m per metre of lever arm) over all DOFs <=
#: NEWTON_RTOL * wheel load (66 N for the default coach). Hunting runs at 300-420 km/h reach at
#: most 2e-4 (Hertz + Kalker / FASTSIM, tol 1e-9) and 5e-4 (BEM, tol 1e-8): the bound catches a
#: modified Newton that stalls with a small correction but a large error, without moving those
#: runs.
NEWTON_RTOL = 1e-3

#: What a BEM patch at its grid's edge asks of the user.
BEM_EDGE_HINT = "a BEM contact patch reached the edge of its grid (enlarge BemOptions nx/ny or load_factor)"


def call_settings(
    speed: float, contact: str | ContactModel, fastsim_n: int, bem: BemState | None
) -> CallSettings:
    """The per-call values of the shims; InputError for an unknown contact model, or for the
    BEM contact without a BEM state."""
    spec = parse_contact_model(contact)
    if not spec.needs_bem:
        return CallSettings(speed, spec.fortran_id, fastsim_n, 0)
    if bem is None or not bem.handle:
        raise InputError(f"contact={spec.name!r} needs a BEM contact state")
    return CallSettings(speed, spec.fortran_id, fastsim_n, bem.handle)


def bem_state(system: System, options: BemOptions | None = None) -> BemState:
    """A BEM contact state for ``system`` (close it, or use it as a context manager)."""
    return BemState(system.table, system.wheel_load, system.iws.shape[1], options)


@contextlib.contextmanager
def contact_state(
    system: System,
    contact: str | ContactModel,
    bem: BemState | None = None,
    options: BemOptions | None = None,
) -> Iterator[BemState | None]:
    """The BEM state of a run: ``bem`` when given (left open), else for a model that needs
    one a new state made with ``options`` and closed at the end, else None. Open it once
    around a run's equilibrium and time loop: one BEM state per run.

    Raises
    ------
    InputError
        An unknown contact model.
    """
    spec = parse_contact_model(contact)
    if bem is not None or not spec.needs_bem:
        yield bem
        return
    with bem_state(system, options) as st:
        yield st


def static_equilibrium(
    system: System,
    speed: float,
    contact: str | ContactModel = "hertz-kalker",
    *,
    q0: np.ndarray | None = None,
    tol: float = 1e-11,
    maxit: int = 60,
    fastsim_n: int = 8,
    bem: BemState | None = None,
    bem_options: BemOptions | None = None,
    return_velocity: bool = False,
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
    spec = parse_contact_model(contact)
    with contact_state(system, spec, bem, bem_options) as st:
        return _equilibrium(system, speed, spec, st, q0, tol, maxit, fastsim_n, return_velocity)


def _equilibrium(
    system: System,
    speed: float,
    spec: ContactModel,
    bem: BemState | None,
    q0: np.ndarray | None,
    tol: float,
    maxit: int,
    fastsim_n: int,
    return_velocity: bool,
) -> tuple[np.ndarray, ...]:
    """:func:`static_equilibrium` with the run's BEM state (or None) open."""
    cs = call_settings(speed, spec, fastsim_n, bem)
    if bem is None:
        return _equilibrium_solves(system, speed, spec, cs, bem, q0, tol, maxit, fastsim_n, return_velocity)
    band = bem.update_band
    bem.set_update_band(0.0)  # the equilibrium solves every patch (no linear updates)
    try:
        return _equilibrium_solves(system, speed, spec, cs, bem, q0, tol, maxit, fastsim_n, return_velocity)
    finally:
        if bem.handle:
            bem.set_update_band(band)


def _equilibrium_solves(
    system: System,
    speed: float,
    spec: ContactModel,
    cs: CallSettings,
    bem: BemState | None,
    q0: np.ndarray | None,
    tol: float,
    maxit: int,
    fastsim_n: int,
    return_velocity: bool,
) -> tuple[np.ndarray, ...]:
    """:func:`_equilibrium`'s Newton solves (the BEM state, if any, without linear updates)."""
    if q0 is None:  # modal coordinates (if any) start undeformed
        q = np.concatenate([_initial_guess(system), np.zeros(system.n_state - system.n)])
    else:
        q = np.array(_checks.finite_array("q0", q0, shape=(system.n_state,)), dtype=float)
    q_start = q.copy()
    limit = NEWTON_RTOL * system.wheel_load  # forces balanced: an equilibrium, not a stall
    if bem is not None and q0 is None:
        # the BEM's Newton (every patch solved) from Hertz + Kalker's equilibrium: FF with
        # the BEM 4 iterations instead of 7 from the start guess (issue 33); the equilibrium
        # moves by the BEM's tolerance (1.1e-8 m, forces balanced to 0.05-0.08 N either way)
        kalker = call_settings(speed, HERTZ_KALKER, fastsim_n, None)
        if _static_call(system, kalker, None, q, tol, maxit)[-1] != Status.OK:
            q[:] = q_start
    v, f, wout, iters, resid, info = _static_call(system, cs, bem, q, tol, maxit)
    stalled = info == Status.NOT_CONVERGED or (info == Status.OK and not float(np.max(np.abs(f))) <= limit)
    if stalled and spec.static_restart:
        # FASTSIM's and the BEM's Newton (with Hertz + Kalker's tangent) can stall far from
        # equilibrium (discretised creep forces; seen on the ring track from the undeformed
        # start: FF with the BEM stopped with 447 N unbalanced): start again from Hertz +
        # Kalker's equilibrium, where it converges in a few iterations
        log.debug("static equilibrium: %s's Newton stalled; restarting from Kalker's", spec.name)
        q = q_start
        _static_call(system, call_settings(speed, HERTZ_KALKER, fastsim_n, None), None, q, tol, maxit)
        v, f, wout, iters, resid, info = _static_call(system, cs, bem, q, tol, maxit)
    fmax = float(np.max(np.abs(f)))
    if info == Status.NOT_CONVERGED and resid <= 100.0 * tol and fmax <= limit:
        # the correction stalls at round-off a little above tol (RF's critical_speed stopped
        # at 1.87e-11 against 1e-11) with the forces balanced: that is the equilibrium
        log.debug(
            "static equilibrium: correction %.3g stalled above tol %.3g, forces balanced (%.3g N): accepted",
            resid,
            tol,
            fmax,
        )
        info = Status.OK
    context = "static equilibrium"
    if info == Status.OUTSIDE_TABLE:
        context = "static equilibrium: a wheelset left its contact table"
    elif info == Status.GRID_EDGE:
        context = f"static equilibrium: {BEM_EDGE_HINT}"
    elif info in (Status.NOT_CONVERGED, Status.SINGULAR):
        context = f"static equilibrium not found after {iters} Newton iterations, last correction {resid:.3g}"
    check(info, context, iterations=int(iters), residual=float(resid))
    # the Newton correction can end small because the line search cut it: the state is an
    # equilibrium only if the forces balance too (NEWTON_RTOL of the wheel load, as a step)
    if not fmax <= limit:
        raise ConvergenceError(
            f"static equilibrium not found: the Newton correction stopped at "
            f"{resid:.3g} with an unbalanced force of {fmax:.3g} N (N m) "
            f"(limit {limit:.3g}); try another q0",
            iterations=int(iters),
            residual=fmax,
        )
    log.debug("static equilibrium: %d iterations, unbalanced force %.3g", iters, fmax)
    return (q, v, wout) if return_velocity else (q, wout)


#: Handles of the vehicle models a static solve still uses in a worker thread.
_busy_models: set[int] = set()


def wait_idle(system: System) -> None:
    """Wait until no interrupted static solve still runs on ``system``'s Fortran model."""
    _interrupt.wait_while(lambda: system.native.handle in _busy_models)


def _static_call(
    system: System, cs: CallSettings, bem: BemState | None, q: np.ndarray, tol: float, maxit: int
) -> tuple:
    """``system.native.static(cs, q, tol, maxit)`` (one Fortran call, ~3-5 s with the BEM)
    in a worker thread, the shim releasing the GIL (``!f2py threadsafe``), while the main
    thread waits for signals (:func:`railvti._interrupt.call_in_worker`): Ctrl-C / SIGTERM
    raise here within ~0.05 s. The Newton iteration cannot be stopped from outside: an
    interrupted call runs on to its end in the background. Meanwhile its model is kept (a
    later call on it waits; it is not freed at exit) and its BEM state, mid-solve, is
    abandoned: ``bem.handle`` becomes 0 (closing it does nothing) and the worker frees it
    when the call ends."""
    native = system.native
    wait_idle(system)
    handle = native.handle
    abandoned: list[int] = []

    def on_abandon() -> None:
        native._free.atexit = False  # not freed at exit under the running call
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
    return _interrupt.call_in_worker(
        native.static, cs, q, tol, maxit, on_abandon=on_abandon, on_end=on_end, name="railvti-static"
    )


def _rigid_only(system: System, what: str) -> None:
    """InputError for a System with modal blocks where only rigid models are handled yet."""
    if system.modal is not None:
        raise InputError(f"{what} does not handle modal blocks yet")


def _initial_guess(system: System) -> np.ndarray:
    q = np.zeros(system.n)
    t = system.table
    i0 = int(np.argmin(np.abs(t.y)))
    g0, dl, kh = t.data[0, 0, i0], t.data[2, 0, i0], t.data[6, 0, i0]
    k = np.diag(system.k)
    if not kh > 0.0:  # a table without contact (build_rigid_system): start at zero
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


def lateral_disturbance(
    system: System, q: np.ndarray, y0: float, wheelsets: tuple[int, ...] = (0, 1)
) -> np.ndarray:
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


def force_and_tangent(
    system: System,
    q: np.ndarray,
    v: np.ndarray,
    speed: float,
    contact: str | ContactModel = "hertz-kalker",
    fastsim_n: int = 8,
    *,
    bem: BemState | None = None,
):
    """F(q, v), the per-wheel outputs, dF/dq and dF/dv (contact by forward differences).
    With the BEM contact the state ``bem`` is used (and left warm), or a temporary one.

    Raises
    ------
    DivergenceError
        The state is outside the contact table.
    """
    spec = parse_contact_model(contact)
    with contact_state(system, spec, bem) as st:
        return _force_and_tangent(system, q, v, speed, spec, fastsim_n, st)


def _force_and_tangent(
    system: System,
    q: np.ndarray,
    v: np.ndarray,
    speed: float,
    contact: str | ContactModel,
    fastsim_n: int,
    bem: BemState | None,
):
    _rigid_only(system, "force_and_tangent")
    cs = call_settings(_checks.positive("speed", speed), contact, fastsim_n, bem)
    q = _checks.finite_array("q", q, shape=(system.n,))
    v = _checks.finite_array("v", v, shape=(system.n,))
    f, wout, jq, jv, info = system.native.force(cs, q, v)
    check(info, "force and tangent at the given state")
    return f, wout, jq, jv


def eigenvalues(
    system: System,
    speed: float,
    q: np.ndarray | None = None,
    contact: str | ContactModel = "hertz-kalker",
    v: np.ndarray | None = None,
) -> np.ndarray:
    """Eigenvalues (1/s) of the system linearised about (q, v) (default: the steady state of
    static_equilibrium, with its spin rates). Each wheelset's spin angle beta, free (no
    stiffness), adds a zero eigenvalue. The BEM contact: one BEM state for the equilibrium
    and the linearisation."""
    spec = parse_contact_model(contact)
    with contact_state(system, spec) as st:
        if q is None:
            q, v, _ = static_equilibrium(system, speed, spec, bem=st, return_velocity=True)
        if v is None:
            v = np.zeros(system.n)
        _, _, jq, jv = force_and_tangent(system, q, v, speed, spec, bem=st)
    n = system.n
    minv = np.linalg.inv(system.m)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = minv @ jq
    a[n:, n:] = minv @ jv
    return np.linalg.eigvals(a)
