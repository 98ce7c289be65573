"""The bifurcation diagram of the scenarios (railvti.scenarios): a downward speed sweep with
continuation of the upper (limit-cycle) branch and decay tests, serial or on a Dask client,
and the systems of a sweep built per speed (:class:`SweepSystems`)."""

from __future__ import annotations

import contextlib
import logging
import warnings
from typing import Any, Sequence

import numpy as np

from .. import _checks
from .._cluster import check_client, client_from
from .._threads import serial_blas
from ..errors import InputError
from .assembly import System
from .flexible import mode_labels
from .params import Coach
from .scenario_results import Bifurcation
from .equilibrium import contact_state, lateral_disturbance, static_equilibrium
from .run_result import SimulationResult
from .simulate import simulate
from .systems import (
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    RING_TRACK,
    check_fr_selection,
    check_variant,
    coach_system,
    ff_system,
    fr_system,
    no_fr_keys,
    resolve_geometry,
    rf_system,
    ring_keys,
    run_output_dt,
    time_step,
)

__all__ = [
    "AMPLITUDE_WINDOW",
    "amplitude",
    "SweepSystems",
    "bifurcation",
    "bifurcation_upper",
    "point_systems",
    "bifurcation_point",
]

log = logging.getLogger(__name__)

#: The window of :func:`amplitude` (s): a run's amplitude is that of its last second.
AMPLITUDE_WINDOW = 1.0


def amplitude(res: SimulationResult, window: float = AMPLITUDE_WINDOW) -> float:
    """Half the peak-to-peak leading wheelset lateral displacement over the last window, m."""
    k = res.t >= res.t[-1] - window
    return 0.5 * float(np.ptp(res.y_ws1[k]))


def _sweep_speeds(speeds_kmh: Sequence[float] | None, speeds: Sequence[float] | None) -> np.ndarray:
    """The sweep's speeds in m/s, descending, from exactly one of ``speeds`` (m/s) and
    ``speeds_kmh`` (its suffixed alias), or the default 200..460 km/h by 20."""
    if speeds is not None and speeds_kmh is not None:
        raise InputError("give the sweep's speeds once: speeds (m/s) or speeds_kmh (km/h), not both")
    if speeds is not None:
        v = np.atleast_1d(_checks.finite_array("speeds", speeds))
        if v.size < 2 or np.any(~np.isfinite(v)) or np.any(v <= 0) or np.any(v > _checks.MAX_SPEED):
            raise InputError(
                f"speeds must hold at least two speeds in (0, "
                f"{_checks.MAX_SPEED:.4g}] m/s, got {np.asarray(speeds).tolist()}"
            )
        sp = v
    else:
        sp = _checks.finite_array(
            "speeds_kmh", speeds_kmh if speeds_kmh is not None else np.arange(200.0, 461.0, 20.0)
        )
        if sp.ndim != 1 or sp.size < 2 or np.any(sp <= 0):
            raise InputError("speeds_kmh must hold at least two speeds > 0")
        for s_kmh in sp:
            _checks.speed_kmh("speeds_kmh", s_kmh)
        sp = _checks.from_kmh(sp)
    return np.sort(sp)[::-1]


def _floor(v_min_kmh: float | None, v_min: float | None) -> float:
    """The sweep extension's floor, m/s, from exactly one of v_min (m/s) and v_min_kmh."""
    if v_min is not None and v_min_kmh is not None:
        raise InputError("give the sweep's floor once: v_min (m/s) or v_min_kmh (km/h), not both")
    if v_min is not None:
        return _checks.positive("v_min", v_min)
    return _checks.from_kmh(_checks.positive("v_min_kmh", 20.0 if v_min_kmh is None else v_min_kmh))


#: The sweep's step when it holds one speed, m/s (10 km/h).
DEFAULT_STEP = _checks.from_kmh(10.0)
#: The slack of the extension's floor, m/s.
_FLOOR_SLACK = 1e-9


class SweepSystems:
    """The systems of a speed sweep: RR's one system, or variants FR, RF, FF built per speed
    (cached by speed; the wheelsets' modes depend on the spin, the ring's rows move at the
    speed) with their step and static states. ``ring``: the ring's keys (RF_KEYS)."""

    def __init__(
        self,
        variant: str,
        coach: Coach | None,
        contact: str,
        h: float | None,
        k_max: int,
        f_max: float,
        geometry: str | None = None,
        ring: dict | None = None,
    ) -> None:
        self.variant, self.coach, self.contact, self.h = variant, coach, contact, h
        self.k_max, self.f_max = k_max, f_max
        self.geometry = resolve_geometry(contact, geometry)
        self.ring = dict(ring or {})
        self._cache: dict[float, tuple] = {}
        self._rr = coach_system(variant, coach, geometry=geometry) if variant == "RR" else None
        self.steps: dict[float, float] = {}

    def at(self, speed: float) -> tuple[System, list, float]:
        """(system, FR layouts or [], step h) at speed (m/s)."""
        if self._rr is not None:
            return self._rr, [], 1e-3 if self.h is None else self.h
        key = float(speed)
        if key not in self._cache:
            if len(self._cache) >= 4 and self.variant in RING_TRACK:
                self._cache.pop(next(iter(self._cache)))  # ring systems are large
            self._cache[key] = self._build(key, self.ring)
            self.steps[key] = self._cache[key][2]
        return self._cache[key]

    def _build(self, key: float, ring: dict) -> tuple:
        if self.variant == "FR":
            sy, lay = fr_system(
                self.coach, speed=key, k_max=self.k_max, f_max=self.f_max, geometry=self.geometry
            )
        elif self.variant == "FF":
            sy, lay = ff_system(
                self.coach, speed=key, k_max=self.k_max, f_max=self.f_max, geometry=self.geometry, **ring
            )
        else:
            sy, lay = rf_system(self.coach, speed=key, geometry=self.geometry, **ring), []
        return sy, lay, time_step(sy, self.h)

    def upper_at(self, speed: float, travel: float) -> tuple[System, list, float]:
        """The system of the upper branch's run at speed (m/s): ``at(speed)``, except on the ring
        track, where its contact points start ``travel`` (m, the distance run along the ring
        by the branch so far) beyond x_offset, so that a ring state carried from the previous
        run belongs to them (the ring repeats: travel is taken modulo its length)."""
        base = self.at(speed)
        if self.variant not in RING_TRACK or travel == 0.0:
            return base
        ring = dict(self.ring)
        length = float(base[0].ring.length)
        ring["x_offset"] = (float(ring.get("x_offset", 0.0)) + travel) % length
        return self._build(float(speed), ring)

    def carry(
        self, q: np.ndarray, v: np.ndarray, s_from: float, s_to: float, static_to: Any
    ) -> tuple[np.ndarray, np.ndarray, bool]:
        """Map a state (q, v) of the system at s_from onto the system at s_to (m/s).

        The rigid DOFs carry over. Variant FR's modal coordinates (elastic and residual) carry
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
            self.variant not in FLEXIBLE_WHEELSETS or mode_labels(a, la) == mode_labels(b, lb)
        )
        if same and self.variant not in RING_TRACK:
            return q, v, False
        qs = static_to()
        qn, vn = np.array(qs, dtype=float), np.zeros(b.n_state)
        if same:
            # everything carries over: the upper branch's next run starts its contact points
            # where the previous run's ended (upper_at), so the ring's state belongs to them
            return q, v, False
        qn[:n], vn[:n] = q[:n], v[:n]
        return qn, vn, True


def _sweep_setup(
    sp: np.ndarray,
    variant: str,
    contact: str,
    coach: Coach | None,
    h: float | None,
    k_max: int,
    f_max: float,
    geometry: str,
    ring: dict | None = None,
    output_dt: float | None = None,
) -> tuple[float, SweepSystems]:
    """A bifurcation sweep's smallest step (m/s) and systems at the speeds ``sp`` (m/s,
    descending), every input checked and the step checked against the first speed's system
    before any run (serial continuation and independent points alike)."""
    step = float(np.min(-np.diff(sp)[np.diff(sp) < 0])) if np.any(np.diff(sp) < 0) else DEFAULT_STEP
    check_variant(variant, contact, "bifurcation")
    if variant in FLEXIBLE_WHEELSETS:
        k_max, f_max = check_fr_selection(k_max, f_max)
    elif (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
        no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
    ring = ring_keys(variant, ring)
    geometry = resolve_geometry(contact, geometry)
    systems = point_systems(variant, coach, contact, h, k_max, f_max, geometry, ring)
    sy, _, hs = systems.at(sp[0])
    if output_dt is not None:  # the top speed's excitations are the highest
        run_output_dt(sy, sp[0], hs, output_dt, 0.002)
    return step, systems


def _point_keys(
    systems: SweepSystems,
    variant: str,
    contact: str,
    coach: Coach | None,
    h: float | None,
    duration: float,
    output_dt: float | None,
) -> dict:
    """The keyword arguments of :func:`bifurcation_point` for a sweep over ``systems`` (the
    checked mode selection, geometry and ring keys taken from them)."""
    return dict(
        variant=variant,
        contact=contact,
        coach=coach,
        h=h,
        k_max=systems.k_max,
        f_max=systems.f_max,
        duration=duration,
        geometry=systems.geometry,
        ring=systems.ring,
        output_dt=output_dt,
    )


def bifurcation(
    speeds_kmh: Sequence[float] | None = None,
    variant: str = "RR",
    contact: str = "hertz-kalker",
    *,
    speeds: Sequence[float] | None = None,
    duration: float = 4.0,
    y_large: float = 0.006,
    y_small: float = 0.0005,
    threshold: float = 0.5e-3,
    h: float | None = None,
    flange_amplitude: float = 5e-3,
    v_min_kmh: float | None = None,
    v_min: float | None = None,
    coach: Coach | None = None,
    progress: bool = True,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    client: Any = None,
    independent: bool = False,
    geometry: str | None = None,
    output_dt: float | None = None,
    **ring: Any,
) -> Bifurcation:
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
    variant, contact : str
        'RR', 'FR', 'RF' or 'FF'; the contact model.
    speeds : sequence of float, optional
        The speeds, m/s (at least two).
    duration : float
        Simulated time per speed and branch, s.
    y_large, y_small, threshold, flange_amplitude : float
        Disturbances, the living-cycle threshold and the flange-hunting amplitude, m.
    h : float, optional
        Time step, s: default 1 ms (RR) or, variant FR, 1 ms divided so that h omega_max <= 2 at
        each speed; a given h is checked against the kept modes at every speed.
    v_min_kmh, v_min : float, optional
        The floor of the downward extension, km/h or m/s (one of them; default 20 km/h).
    coach : Coach, optional
    progress : bool
        Progress bar.
    k_max, f_max : int, float
        Variant FR's mode selection (harmonics, Hz). Variant FR is built at each speed; the
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
        Variants 'RF' and 'FF': the ring track's keys ``n_sleepers``, ``f_limit``,
        ``track_params``, ``x_offset`` (:func:`rf_system`). The ring is built once and its
        rows per speed. The upper branch carries the whole state down, the ring's
        coordinates too: each of its runs starts the contact points where the previous run
        left them (x_offset plus the distance run so far, modulo the ring's length), so the
        carried rail deflection lies under the wheels. The decay runs start at x_offset.
    """
    if client is not None:
        check_client(client)  # an unreachable address: InputError before any work
    sp = _sweep_speeds(speeds_kmh, speeds)
    floor = _floor(v_min_kmh, v_min)
    kw = dict(
        duration=duration,
        y_large=y_large,
        y_small=y_small,
        threshold=threshold,
        h=h,
        v_min=floor,
        coach=coach,
        k_max=k_max,
        f_max=f_max,
        geometry=geometry,
        ring=ring,
        output_dt=output_dt,
    )
    if independent:
        return _bifurcation_independent(
            sp, variant, contact, client=client, flange_amplitude=flange_amplitude, progress=progress, **kw
        )
    up, decay, systems = _bifurcation_continuation(
        sp, variant, contact, client=client, progress=progress, **kw
    )
    systems.steps.update(up["steps"])
    return _bifurcation_result(
        sp,
        up["speeds"],
        up["upper"],
        up["flange"],
        decay,
        up["alive"],
        threshold,
        flange_amplitude,
        systems,
        variant,
        up["restarts"],
    )


def _bifurcation_continuation(
    sp: np.ndarray,
    variant: str,
    contact: str,
    *,
    duration: float,
    y_large: float,
    y_small: float,
    threshold: float,
    h: float | None,
    v_min: float,
    coach: Coach | None,
    k_max: int,
    f_max: float,
    client: Any,
    geometry: str | None = None,
    ring: dict | None = None,
    output_dt: float | None = None,
    progress: bool = False,
) -> tuple[dict, list[float], SweepSystems]:
    """The runs of :func:`bifurcation`'s continuation sweep (speeds ``sp`` and the floor
    ``v_min`` in m/s), serial or on a Dask client: the upper branch's dict
    (:func:`bifurcation_upper`), the decay tests' amplitudes and the sweep's systems."""
    step, systems = _sweep_setup(sp, variant, contact, coach, h, k_max, f_max, geometry, ring, output_dt)
    point = _point_keys(systems, variant, contact, coach, h, duration, output_dt)
    chain = dict(point, y_large=y_large, threshold=threshold, step=step, v_min=v_min)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=2 * sp.size, desc="bifurcation", leave=False)
    decay: list[float] = []
    if client is None:

        def decay_at(s: float) -> None:  # after the upper run at s, as one loop
            if bar is not None:
                bar.total = max(bar.total, bar.n + 2)  # an extension below the sweep
                bar.update()
            decay.append(bifurcation_point(s, y_small, **point)[0])
            if bar is not None:
                bar.update()

        up = bifurcation_upper(list(sp), each=decay_at, **chain)
    else:
        up, decay = _bifurcation_on_client(client, sp, y_small, point, chain, bar)
    if bar is not None:
        bar.close()
    return up, decay, systems


def bifurcation_upper(
    speeds: Sequence[float],
    *,
    y_large: float,
    threshold: float,
    step: float,
    v_min: float,
    variant: str,
    contact: str,
    coach: Coach | None,
    h: float | None,
    k_max: int,
    f_max: float,
    duration: float,
    geometry: str | None = None,
    ring: dict | None = None,
    output_dt: float | None = None,
    each: Any = None,
) -> dict:
    """The upper branch of a :func:`bifurcation` sweep, one sequential chain (one task on a
    Dask client): from the static state at the first (highest) speed shifted by ``y_large``
    (m), ``duration`` s at each speed, each speed starting from the state carried down from
    the speed above, until the cycle dies (amplitude <= threshold); while it lives at the
    bottom, the sweep is extended by ``step`` down to ``v_min`` (speeds in m/s).

    ``each(speed)``, when given, is called after each speed's run (the serial sweep runs the
    decay test there). Returns a dict: 'speeds' (m/s, the sweep's and the extension's),
    'upper' (amplitude, m; 0 below the speed where the cycle died), 'flange' (max flange
    normal force on the leading bogie over the last second, N), 'alive' (at the last speed),
    'restarts' (m/s, :class:`Bifurcation` ``details``) and 'steps' (m/s -> h, s).
    """
    systems = point_systems(variant, coach, contact, h, k_max, f_max, geometry, ring)
    speeds_out: list[float] = []
    upper: list[float] = []
    flange: list[float] = []
    restarts: list[float] = []
    q = v = None
    alive = True
    todo = [float(s) for s in speeds]
    prev = None
    travel = 0.0  # distance run along the ring by the upper branch, m
    with serial_blas():  # one BLAS thread, in the caller as in a worker: the same bits
        while todo:
            s = todo.pop(0)
            systems.at(s)  # the point's system and step (details' 'h' lists every speed)
            up, fl = 0.0, 0.0
            if alive:
                r, q, v, restarted = _upper_run(
                    systems, s, prev, q, v, travel, contact, y_large, duration, output_dt
                )
                if restarted:
                    restarts.append(float(s))
                travel += s * float(r.t[-1])
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
            if not todo and alive and s - step >= v_min - _FLOOR_SLACK:
                todo.append(s - step)  # the cycle has not died: extend the sweep downward
    return {
        "speeds": speeds_out,
        "upper": upper,
        "flange": flange,
        "alive": alive,
        "restarts": restarts,
        "steps": {k: systems.steps[k] for k in systems.steps},
    }


def _upper_run(
    systems: Any,
    s: float,
    prev: float | None,
    q: np.ndarray | None,
    v: np.ndarray | None,
    travel: float,
    contact: str,
    y_large: float,
    duration: float,
    output_dt: float | None,
) -> tuple[Any, np.ndarray, np.ndarray, bool]:
    """One speed (m/s) of the upper branch: the state carried in from ``prev`` (or, at the
    top, the static state shifted by ``y_large``), then ``duration`` s. One BEM state for
    the point's static solves and run. Returns (result, q, v, restarted)."""
    sy, _, hs = systems.at(s)
    su = systems.upper_at(s, travel)[0]
    restarted = False
    with contact_state(sy, contact) as st:
        if q is None:
            q = lateral_disturbance(sy, static_equilibrium(sy, s, contact, bem=st)[0], y_large)
            v = np.zeros(sy.n_state)
        if prev is not None:
            q, v, restarted = systems.carry(
                q, v, prev, s, lambda: static_equilibrium(su, s, contact, bem=st)[0]
            )
        r = simulate(
            su,
            s,
            duration,
            contact=contact,
            h=hs,
            q0=q,
            v0=v,
            output_dt=run_output_dt(su, s, hs, output_dt, 0.002, check=False),
            progress=False,
            bem=st,
        )
    return r, q, v, restarted


def _bifurcation_on_client(
    client: Any, sp: np.ndarray, y_small: float, point: dict, chain: dict, bar: Any
) -> tuple[dict, list[float]]:
    """The continuation sweep on a Dask client: the upper branch as one task
    (:func:`bifurcation_upper`), the decay tests (independent by nature) as one task per
    speed beside it; the same runs as the serial sweep, so the same numbers."""
    from distributed import as_completed

    with client_from(client) as c:
        fut_up = c.submit(bifurcation_upper, list(map(float, sp)), pure=False, **chain)
        fut_decay = c.map(bifurcation_point, list(map(float, sp)), [y_small] * sp.size, pure=False, **point)
        pending = as_completed([fut_up, *fut_decay])
        up = None
        for f in pending:
            if f is fut_up:
                up = f.result()
                extra = up["speeds"][sp.size :]
                if extra:  # the sweep was extended downward
                    more = c.map(bifurcation_point, extra, [y_small] * len(extra), pure=False, **point)
                    fut_decay += more
                    pending.update(more)
                    if bar is not None:
                        bar.total += 2 * len(extra)
            if bar is not None:
                bar.update(len(up["speeds"]) if f is fut_up else 1)
        decay = [f.result()[0] for f in fut_decay]
    return up, decay


def _bifurcation_result(
    sp: np.ndarray,
    speeds_out: list,
    upper: list,
    flange: list,
    decay: list,
    alive: bool,
    threshold: float,
    flange_amplitude: float,
    systems: Any,
    variant: str,
    restarts: list,
) -> Bifurcation:
    """The Bifurcation of a finished sweep (its critical speed, branch and messages)."""
    spa, upa, fla = np.array(speeds_out), np.array(upper), np.array(flange)
    on = upa > threshold
    crit = float(spa[on].min()) if on.any() else float("nan")
    no_decay = no_cycle = float("nan")
    branch, amp_b, fl_b = "none", float("nan"), float("nan")
    if on.any() and alive:
        no_decay = float(spa.min())
        crit = float("nan")
        msg = (
            f"bifurcation: below {_checks.to_kmh(no_decay):.0f} km/h: no decay found (the "
            f"cycle is sustained at every speed swept; lower v_min_kmh to search further)"
        )
        log.warning(msg)
        warnings.warn(msg, RuntimeWarning, stacklevel=3)
    elif not on.any():
        no_cycle = float(spa.max())
        log.warning("bifurcation: no sustained cycle up to %.0f km/h", _checks.to_kmh(no_cycle))
    wheel_load = systems.at(sp[0])[0].wheel_load
    if np.isfinite(crit):
        k = int(np.argmin(np.where(on, spa, np.inf)))
        amp_b, fl_b = float(upa[k]), float(fla[k])
        branch = "flange cycle" if fl_b > 0.01 * wheel_load else "tread cycle"
    fl = upa > flange_amplitude
    order = np.argsort(spa)
    details: dict[str, Any] = {"flange_force": fla[order]}
    if variant != "RR":
        details["h"] = np.array([systems.steps[float(x)] for x in spa[order]])
        details["modal_restarts"] = np.array(sorted(restarts))
    return Bifurcation(
        speeds=spa[order],
        upper=upa[order],
        decay=np.array(decay)[order],
        critical=crit,
        threshold=threshold,
        flange=float(spa[fl].min()) if fl.any() else float("nan"),
        details=details,
        branch=branch,
        branch_amplitude=amp_b,
        branch_flange_force=fl_b,
        extended=np.sort(spa[spa < sp.min()]),
        no_decay_below=no_decay,
        no_cycle_up_to=no_cycle,
        variant=variant,
    )


#: The sweep systems of bifurcation runs in this process (a worker keeps its own).
_POINT_SYSTEMS: dict[str, "SweepSystems"] = {}


def point_systems(
    variant: str,
    coach: Coach | None,
    contact: str,
    h: float | None,
    k_max: int,
    f_max: float,
    geometry: str | None,
    ring: dict | None,
) -> SweepSystems:
    """The sweep systems of these settings in this process: one set at a time, shared by a
    sweep's upper branch and its decay runs (each run starts from its own state)."""
    geometry = resolve_geometry(contact, geometry)
    key = repr((variant, coach, contact, h, k_max, f_max, geometry, sorted((ring or {}).items())))
    if key not in _POINT_SYSTEMS:
        _POINT_SYSTEMS.clear()
        _POINT_SYSTEMS[key] = SweepSystems(variant, coach, contact, h, k_max, f_max, geometry, ring)
    return _POINT_SYSTEMS[key]


def bifurcation_point(
    speed: float,
    y: float,
    *,
    variant: str,
    contact: str,
    coach: Coach | None,
    h: float | None,
    k_max: int,
    f_max: float,
    duration: float,
    geometry: str | None = None,
    ring: dict | None = None,
    output_dt: float | None = None,
) -> tuple[float, float, float]:
    """One run of an independent bifurcation sweep (a task): from the static state at
    ``speed`` (m/s) with the leading bogie's wheelsets shifted by ``y`` (m), ``duration`` s.

    Returns
    -------
    amplitude : float
        Leading wheelset's amplitude over the last second, m (:func:`amplitude`).
    flange_force : float
        Max flange normal force on the leading bogie's wheels over the last second, N.
    h : float
        The time step used, s.
    """
    sy, _, hs = point_systems(variant, coach, contact, h, k_max, f_max, geometry, ring).at(speed)
    vv = speed
    # one BLAS thread, in the caller as in a worker: the same bits; one BEM state for the
    # point's equilibrium and run
    with serial_blas(), contact_state(sy, contact) as st:
        q0 = lateral_disturbance(sy, static_equilibrium(sy, vv, contact, bem=st)[0], y)
        r = simulate(
            sy,
            vv,
            duration,
            contact=contact,
            h=hs,
            q0=q0,
            output_dt=run_output_dt(sy, vv, hs, output_dt, 0.002, check=False),
            progress=False,
            bem=st,
        )
    last = r.t >= r.t[-1] - 1.0
    return amplitude(r), float(r.wheel_output("N_flange")[last][:, :, :2].max()), hs


def _bifurcation_independent(
    sp: np.ndarray,
    variant: str,
    contact: str,
    *,
    duration: float,
    y_large: float,
    y_small: float,
    threshold: float,
    h: float | None,
    flange_amplitude: float,
    v_min: float,
    coach: Coach | None,
    k_max: int,
    f_max: float,
    client: Any,
    geometry: str | None = None,
    ring: dict | None = None,
    output_dt: float | None = None,
    progress: bool = False,
) -> Bifurcation:
    """:func:`bifurcation` with every speed independent, serial or on a Dask client (speeds
    ``sp`` and the floor ``v_min`` in m/s)."""
    step, systems = _sweep_setup(sp, variant, contact, coach, h, k_max, f_max, geometry, ring, output_dt)
    kw = _point_keys(systems, variant, contact, coach, h, duration, output_dt)
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
        while out[-2][0] > threshold and speeds_out[-1] - step >= v_min - _FLOOR_SLACK:
            speeds_out.append(speeds_out[-1] - step)  # alive at the bottom: extend downward
            out += runs(speeds_out[-1:])
    upper, flange = [o[0] for o in out[0::2]], [o[1] for o in out[0::2]]
    decay = [o[0] for o in out[1::2]]
    if variant != "RR":
        systems.steps.update({float(s): o[2] for s, o in zip(speeds_out, out[0::2])})
    return _bifurcation_result(
        sp,
        speeds_out,
        upper,
        flange,
        decay,
        upper[-1] > threshold,
        threshold,
        flange_amplitude,
        systems,
        variant,
        [],
    )
