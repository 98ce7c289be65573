"""The time loop of :func:`railvti.vehicle.simulate`: its checked plan, the chunked calls of the
Fortran loop (``vehicle_run_c``), the gathered (or streamed) output and the errors of a failed
step.

The whole time loop runs in Fortran; Python calls it in chunks of about :data:`CHUNK_SECONDS`
of wall time (whole output intervals: the numbers are those of one call) to update a progress
bar (simulated time and real-time factor) and to let Ctrl-C / SIGTERM stop a run between chunks.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .. import _checks
from ..casetypes import STREAM_TAIL_SECONDS, HistorySink
from .._status import Status, check, error
from .._threads import serial_blas
from ..errors import DivergenceError, InputError
from ..resources import check_memory
from .assembly import System
from .bem import BemState
from .contact_models import ContactModel
from .equilibrium import BEM_EDGE_HINT, NEWTON_RTOL
from .model import WHEEL_OUTPUTS, CallSettings, RunCarry
from .run_result import WHEEL_UNITS, SimulationResult, flange_angle

__all__ = [
    "CHUNK_SECONDS",
    "MIN_STEP",
    "RunPlan",
    "plan_run",
    "check_history_memory",
    "integrate",
    "with_bem_fields",
]

#: Smallest time step of a simulation, s (below it the step's increments are round-off).
MIN_STEP = 1e-6

#: Wall time of one call of the Fortran time loop, s: Python runs the loop in calls of about
#: this length (whole output intervals), so Ctrl-C or SIGTERM stops a run within about it.
CHUNK_SECONDS = 0.2


@dataclass(frozen=True)
class RunPlan:
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


def plan_run(
    contact: ContactModel,
    duration: float,
    h: float,
    output_dt: float,
    alpha: float,
    tol: float | None,
    maxit: int,
    maxsub: int,
    qmax: float,
    progress: bool | None,
    chunk: float | None,
    rtol: float | None = None,
    load_scale: float = 1.0,
) -> RunPlan:
    """Check the integration settings and derive the step counts and chunk size (``tol``
    None: the contact model's default)."""
    if tol is None:
        tol = contact.newton_tol
    tol = _checks.positive("tol", tol)
    rtol = _checks.positive("rtol", NEWTON_RTOL if rtol is None else rtol)
    duration = _checks.positive("duration", duration)
    h = _checks.positive("h", h)
    if h < MIN_STEP:
        raise InputError(
            f"h = {h:g} s is below {MIN_STEP:g} s: the Newton tolerance on the step's "
            "increments is then round-off (the stiffest kept mode, 20 kHz, needs 16 us)"
        )
    alpha = _checks.finite("alpha", alpha)
    if not -1.0 / 3.0 - 1e-12 <= alpha <= 0.0:
        raise InputError(f"alpha must lie in [-1/3, 0], got {alpha}")
    if isinstance(maxsub, bool) or not isinstance(maxsub, (int, np.integer)) or not 0 <= maxsub <= 20:
        raise InputError(
            f"maxsub must be an integer in [0, 20] (sub-steps down to h/2^maxsub), got {maxsub!r}"
        )
    nevery = max(1, int(round(_checks.positive("output_dt", output_dt) / h)))
    nsteps = int(math.ceil(duration / h - 1e-9))
    nevery = min(nevery, nsteps)
    if progress is None:
        progress = nsteps > 2000
    per_chunk = nsteps if not progress else max(nevery, int(round((chunk or 0.25) / h)) // nevery * nevery)
    return RunPlan(
        h=h,
        nsteps=nsteps,
        nevery=nevery,
        alpha=alpha,
        tol=tol,
        maxit=maxit,
        maxsub=maxsub,
        qmax=qmax,
        rtol=rtol,
        load_scale=float(load_scale),
        per_chunk=per_chunk,
        progress=bool(progress),
    )


def integrate(
    system: System,
    cs: CallSettings,
    plan: RunPlan,
    q: np.ndarray,
    v: np.ndarray,
    contact: str,
    stream: HistorySink | None = None,
    tail: float = STREAM_TAIL_SECONDS,
) -> SimulationResult:
    """Run the Fortran time loop from (q, v), with a = M^-1 F(q, v), in chunks (for the
    progress bar) and gather the output (or stream it, keeping the last ``tail`` seconds).
    Raises the exception of a failed step."""
    model = system.native
    if system.modal is None:
        f, _, _, _, info = model.force(cs, q, v)
        check(info, "the initial state (q0, v0)")
        a = np.linalg.solve(system.m, f)
    else:  # M = I on the modal coordinates
        f, _, info = model.state_force(cs, q, v)
        check(info, "the initial state (q0, v0)")
        # massless coordinates carry no acceleration at the start; from then on the time
        # loop's own (BDF2) rates travel from chunk to chunk, so the chunking (sized by wall
        # time) cannot change the result
        fm = np.where(system.modal.mass == 0.0, 0.0, f[system.n :])
        a = np.concatenate([np.linalg.solve(system.m, f[: system.n]), fm])
    t = np.zeros((), dtype=float)
    out = _Output(plan.h, plan.load_scale, stream, tail)
    if stream is not None:
        for name, attrs in _stream_attrs(system).items():
            stream.attrs.setdefault(name, attrs)
    bar = _progress_bar(plan)
    wall0 = time.perf_counter()
    with serial_blas():  # small dense solves: a threaded BLAS only spins
        try:
            done = 0
            size = min(plan.per_chunk, plan.nevery * max(1, 16 // plan.nevery))
            carry = RunCarry.fresh(q.size, model.n_wheelsets)  # F(q, v) from call to call
            while done < plan.nsteps:
                ns = min(size, plan.nsteps - done)
                tc = time.perf_counter()
                nout = max(1, ns // plan.nevery)
                tout, qout, vout, wout, st, info, tfail = model.run(
                    cs,
                    plan.h,
                    ns,
                    plan.nevery,
                    plan.alpha,
                    plan.tol,
                    plan.maxit,
                    plan.maxsub,
                    plan.qmax,
                    plan.rtol * plan.load_scale,
                    t,
                    q,
                    v,
                    a,
                    nout,
                    scheme=plan.scheme,
                    carry=carry,
                )
                wall_call = time.perf_counter() - tc  # the Fortran call alone (not the writing)
                out.add(tout, qout, vout, wout, st, ns // plan.nevery if info == Status.OK else None)
                if info != Status.OK:
                    raise _run_error(
                        info,
                        float(tfail),
                        plan,
                        system,
                        out.result(system, cs.speed, contact, {"failed_at": float(tfail)}),
                        int(out.stats[0]),
                    )
                done += ns
                size = _next_chunk(ns, wall_call, plan)
                if bar is not None:
                    bar.update(min(round(ns * plan.h, 6), max(bar.total - bar.n, 0.0)))
                    rtf = (time.perf_counter() - wall0) / max(done * plan.h, 1e-12)
                    bar.set_postfix_str(f"RTF {rtf:.2f}")
        except KeyboardInterrupt as exc:  # Ctrl-C or the runner's SIGTERM: keep what is done
            if out.t and sum(len(x) for x in out.t):
                exc.partial = out.result(
                    system, cs.speed, contact, dict(out.named_stats(), interrupted_at=float(out.t[-1][-1]))
                )
            raise
        finally:
            if bar is not None:
                bar.close()
    return out.result(
        system, cs.speed, contact, dict(out.named_stats(), newton_rtol=plan.rtol, newton_tol=plan.tol)
    )


def check_history_memory(system: System, plan: RunPlan) -> None:
    """InputError before a run whose time history would not fit the memory limit
    (:mod:`railvti.resources`): q and v of every state and the 12 x 2 wheel outputs of every
    wheelset per output time, gathered in chunks and then joined (about 2 copies)."""
    nout = plan.nsteps // plan.nevery
    per_output = 8 * (2 * system.n_state + len(WHEEL_OUTPUTS) * 2 * system.iws.shape[1] + 1)
    check_memory(
        f"the time history ({nout} outputs of {per_output} bytes)",
        2.0 * nout * per_output,
        "shorten the duration, raise output_dt, or stream the history to a file "
        "(stream_to=HistoryStream(PATH), railvti.runner.stream)",
    )


def _next_chunk(ns: int, wall: float, plan: RunPlan) -> int:
    """Steps of the next Fortran call: about :data:`CHUNK_SECONDS` of wall time at the pace
    of the last call, a multiple of the output interval (so that the outputs, and every
    number, are those of one call), at most ``plan.per_chunk``."""
    per_step = max(wall, 1e-6) / ns
    k = max(1, int(CHUNK_SECONDS / per_step) // plan.nevery)
    return min(plan.per_chunk, k * plan.nevery)


def _progress_bar(plan: RunPlan):
    """A tqdm bar over the simulated time, or None."""
    if not plan.progress:
        return None
    from tqdm import tqdm

    return tqdm(
        total=round(plan.nsteps * plan.h, 6),
        unit="s sim",
        leave=False,
        bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s sim [{elapsed}, {postfix}]",
    )


def _stream_attrs(system: System) -> dict[str, dict[str, Any]]:
    """Units and labels of the streamed t, q, v and wheel (as railvti.runner.result_objects.save)."""
    names = list(system.state_names)
    nw = system.iws.shape[1]
    return {
        "t": {"units": "s", "axes": ["t"]},
        "q": {"units": "m or rad (per dof_names)", "axes": ["t", "state"], "dof_names": names},
        "v": {"units": "m/s or rad/s (per dof_names)", "axes": ["t", "state"], "dof_names": names},
        "wheel": {
            "units": "per quantity: see quantity_units",
            "axes": ["t", "quantity", "wheel", "wheelset"],
            "quantities": list(WHEEL_OUTPUTS),
            "quantity_units": [WHEEL_UNITS.get(n, "1") for n in WHEEL_OUTPUTS],
            "wheel": ["left", "right"],
            "wheelset": [f"ws{w + 1}" for w in range(nw)],
        },
    }


class _Output:
    """The outputs and statistics of the chunks of one run, gathered (or streamed: appended
    to a HistoryStream, only the chunks of the last ``tail`` seconds kept)."""

    def __init__(
        self,
        h: float,
        load_scale: float = 1.0,
        stream: HistorySink | None = None,
        tail: float = STREAM_TAIL_SECONDS,
    ) -> None:
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
        block = {
            "t": tout[:k],
            "q": qout[:, :k].T,
            "v": vout[:, :k].T,
            "wheel": np.moveaxis(wout[..., :k], -1, 0),
        }
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
        if st[3] > 0:  # the chunk accepted steps: its last residual/correction are the last
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
        return {
            "newton_iterations": int(s[0]),
            "tangents": int(s[1]),
            "max_error_estimate": float(s[2]),
            "steps": int(s[3]),
            "substepped_steps": int(s[4]),
            "smallest_step": float(s[5]),
            "newton_residual": float(s[6] / self.load_scale),
            "newton_residual_max": float(s[7] / self.load_scale),
            "newton_correction": float(s[8]),
            "newton_correction_max": float(s[9]),
            "load_scale": float(self.load_scale),
        }

    def result(self, system: System, speed: float, contact: str, stats: dict) -> SimulationResult:
        """The SimulationResult of what was gathered."""
        return SimulationResult(
            t=np.concatenate(self.t),
            q=np.concatenate(self.q),
            v=np.concatenate(self.v),
            wheel=np.concatenate(self.w),
            dof_names=system.state_names,
            speed=speed,
            contact=contact,
            h=self.h,
            stats=stats,
            friction=float(system.friction),
            flange_angle=flange_angle(system.table),
            streamed=self.stream.where if self.stream is not None else "",
        )


def _run_error(
    info: int, tfail: float, plan: RunPlan, system: System, partial: SimulationResult, iterations: int
) -> Exception:
    """The exception of a failed time step: the time, the step and what went wrong."""
    step = int(round(tfail / plan.h))
    if info == Status.GRID_EDGE:
        return error(info, f"time integration stopped at t = {tfail:.5f} s (step {step}): {BEM_EDGE_HINT}")
    if info == Status.NOT_CONVERGED:
        why = (
            f"Newton's method did not converge in {plan.maxit} iterations, even with the "
            f"step cut to h/{2**plan.maxsub}"
        )
    elif info == Status.OUTSIDE_TABLE:
        why = (
            f"a wheelset left the contact table (|y| > {system.table.y[-1] * 1e3:.0f} mm: "
            "flange climb or a diverging solution)"
        )
    elif info == Status.MOTION_TOO_LARGE:
        why = "the state became non-finite or exceeded qmax"
    elif info == Status.CONTACT_NOT_CONVERGED:
        why = "a BEM contact solver (normal or steady rolling) did not converge"
    else:
        return error(info, f"time integration stopped at t = {tfail:.5f} s (step {step})")
    hint = (
        "try a smaller time step"
        if plan.h > 10 * MIN_STEP
        else f"a smaller time step will not help (h is {plan.h / MIN_STEP:.3g} x the smallest, "
        f"{MIN_STEP:g} s): check the case's stiffnesses, masses and speed"
    )
    return error(
        info,
        f"time integration stopped at t = {tfail:.5f} s (step {step}, h = {plan.h:g} s): {why}; {hint}",
        exc=DivergenceError,
        iterations=iterations,
        result=partial,
    )


def with_bem_fields(
    res: SimulationResult, system: System, bem: BemState, cnt0: dict, nsteps: int
) -> SimulationResult:
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
