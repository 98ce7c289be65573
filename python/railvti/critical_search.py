"""Nonlinear critical speed by path-following down from a large limit cycle (issue 30 item 5).

Two numbers, named:

* the **fold** (:attr:`PathCriticalSpeed.fold`): the lowest speed at which a limit cycle
  exists, found by following the large cycle down in speed with the whole state carried
  (continuation) and, where it dies, bisecting between the last speed with a cycle and the
  first without, every bisection run restarting from the last living state, until the
  bracket is no wider than ``resolution``;
* the **decay boundary** (:attr:`PathCriticalSpeed.decay_boundary`): the lowest speed at
  which a small disturbance ``y_small`` of centred running grows rather than decays (a
  linear-stability-like boundary), found by the same walk down and bisection, each run
  independent (from the static state at its speed).

The criteria (:func:`cycle_verdict`, :func:`growth_rate`, in :mod:`railvti.envelope_criteria`)
judge the amplitude *envelope* (half the peak-to-peak lateral displacement of the leading
wheelset in consecutive windows of ``window`` s) rather than one amplitude against one
threshold:

* a run carries a **living cycle** when the envelope's fitted growth rate over the second
  half of the run, d ln A / dt, is above ``-rate_tol`` (settled or growing), its last
  window is above the floor ``threshold`` and, for a run carried in on the cycle, above
  ``collapse`` (0.5) times its first window (the followed branch is kept, not a slowly
  decaying remnant); a run whose envelope still falls faster is continued
  (``max_extensions`` times by ``duration``) before it is declared dead; below the floor it
  is dead at once. The floor only separates a cycle from the rest of a decay; the trend
  decides near the fold.
* a small disturbance **grows** when its envelope's last window exceeds its first (the
  release from ``y_small``): no threshold at all (:func:`growth_rate` > 0).

Examples
--------
>>> from railvti.critical_search import nonlinear_critical_speed
>>> c = nonlinear_critical_speed("RR", speed_top_kmh=420, resolution_kmh=2.5)
>>> c.fold_kmh, c.decay_boundary_kmh, c.message
"""

from __future__ import annotations

import contextlib
import logging
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator

import numpy as np

from . import _checks
from ._threads import serial_blas
from .envelope_criteria import cycle_verdict, envelope, growth_rate
from .errors import ConvergenceError, GridTooSmallError, InputError
from .vehicle.bem import BemState
from .vehicle.bifurcation import point_systems
from .vehicle.params import Coach
from .vehicle.equilibrium import contact_state, lateral_disturbance, static_equilibrium
from .vehicle.simulate import simulate
from .vehicle.systems import (
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    check_fr_selection,
    check_variant,
    resolve_geometry,
    ring_keys,
    run_output_dt,
)

__all__ = [
    "envelope",
    "growth_rate",
    "cycle_verdict",
    "Bracket",
    "bracket_down",
    "PathCriticalSpeed",
    "RUN_FAILURES",
    "nonlinear_critical_speed",
    "RESOLUTION_KMH",
    "STEP_KMH",
    "TOP_KMH",
    "FLOOR_KMH",
]

log = logging.getLogger(__name__)

#: Default fold bracket width and coarse walk step, km/h (the keywords ``resolution`` and
#: ``step`` take them in m/s).
RESOLUTION_KMH, STEP_KMH = 2.5, 20.0
#: Default top speed and floor of the walk, km/h.
TOP_KMH, FLOOR_KMH = 420.0, 150.0


# --------------------------------------------------------------------------------------------
# The bracketing
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Bracket:
    """A walk down in speed and its bisection (:func:`bracket_down`).

    Attributes
    ----------
    lo : float
        The highest speed tested where the test failed below ``hi`` (NaN: it never failed
        down to the floor), same unit as the speeds given.
    hi : float
        The lowest speed where the test passed (NaN: it failed at the top already).
    visited : list of (speed, passed, record)
        Every test in order (the walk, then the bisection).
    failure : str
        '' or why the search stopped early: a test whose record has ``failed`` (a run that
        could not be completed) ends the walk (lo NaN: unknown) or the bisection (the
        bracket as it stood).
    """

    lo: float
    hi: float
    visited: list = field(default_factory=list)
    failure: str = ""


def bracket_down(
    test: Callable[[float, Any], tuple[bool, Any, Any]],
    top: float,
    step: float,
    floor: float,
    resolution: float,
    state: Any = None,
) -> Bracket:
    """Walk down from ``top`` by ``step`` while ``test`` passes, then bisect between the last
    pass and the first failure until they are at most ``resolution`` apart.

    ``test(speed, state) -> (passed, state_after, record)``. The walk carries the state of
    each pass to the next speed (continuation); every bisection test starts from the state
    of the current upper bracket end (the last living state), and a pass moves that end and
    its state down. The walk stops at the last speed not below ``floor``.

    Returns
    -------
    Bracket
    """
    visited: list = []
    s = float(top)
    hi = lo = float("nan")
    while s >= floor - 1e-9:
        ok, after, rec = test(s, state)
        visited.append((s, bool(ok), rec))
        if isinstance(rec, dict) and rec.get("failed"):
            return Bracket(
                lo=float("nan"), hi=hi, visited=visited, failure=f"the run at {s:g} failed: {rec['failed']}"
            )
        if not ok:
            lo = s
            break
        hi, state = s, after
        s = s - step
    if math.isnan(hi) or math.isnan(lo):
        return Bracket(lo=lo, hi=hi, visited=visited)
    while hi - lo > resolution + 1e-9:
        mid = 0.5 * (hi + lo)
        ok, after, rec = test(mid, state)
        visited.append((mid, bool(ok), rec))
        if isinstance(rec, dict) and rec.get("failed"):
            return Bracket(
                lo=lo, hi=hi, visited=visited, failure=f"the run at {mid:g} failed: {rec['failed']}"
            )
        if ok:
            hi, state = mid, after
        else:
            lo = mid
    return Bracket(lo=lo, hi=hi, visited=visited)


# --------------------------------------------------------------------------------------------
# The result
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PathCriticalSpeed:
    """The fold and the decay boundary of :func:`nonlinear_critical_speed`.

    Speeds are in m/s (fields); their km/h twins are the ``*_kmh`` properties.

    Attributes
    ----------
    fold : float
        The lowest speed with a limit cycle (the upper end of ``fold_bracket``), m/s; NaN
        when the cycle died at the top or lived down to the floor (see ``message``).
    fold_bracket : tuple of float
        (highest speed without, lowest speed with a cycle), m/s; width <= the resolution.
    decay_boundary : float
        The lowest speed at which the small disturbance grows (upper end of
        ``decay_bracket``), m/s; NaN when none was found.
    decay_bracket : tuple of float
        (highest speed where it decays, lowest where it grows), m/s.
    path_speeds, path_amplitudes, path_rates : ndarray
        The upper branch's runs in order (walk, then bisection): speed (m/s), the envelope's
        last window (m), its growth rate over the run's second half (1/s).
    path_alive : ndarray of bool
    path_durations : ndarray
        Simulated time of each run (s): ``duration`` times (1 + extensions).
    decay_speeds, decay_amplitudes, decay_rates : ndarray
        The decay tests in order: speed (m/s), last window (m), fitted growth rate (1/s).
    fold_amplitude : float
        The cycle's amplitude at the fold, m.
    fold_branch : str
        'flange cycle' (flange force above 1 % of the static wheel load in the last window
        of the fold's run), 'tread cycle' or 'none'.
    variant : str
    method : str
        The criteria and settings in words.
    settings : dict
        The settings (SI).
    failure : str
        '' or the run that could not be completed (a time integration that stopped, a BEM
        patch at its grid's edge) and where: the search stopped there, keeping what it had
        (``fold_bracket`` then as it stood; NaN where unknown).
    """

    fold: float
    fold_bracket: tuple
    decay_boundary: float
    decay_bracket: tuple
    path_speeds: np.ndarray
    path_amplitudes: np.ndarray
    path_rates: np.ndarray
    path_alive: np.ndarray
    path_durations: np.ndarray
    decay_speeds: np.ndarray
    decay_amplitudes: np.ndarray
    decay_rates: np.ndarray
    fold_amplitude: float = float("nan")
    fold_branch: str = "none"
    variant: str = "RR"
    method: str = ""
    settings: dict = field(default_factory=dict)
    failure: str = ""

    @property
    def fold_kmh(self) -> float:
        """The fold, km/h."""
        return _checks.to_kmh(self.fold)

    @property
    def decay_boundary_kmh(self) -> float:
        """The decay boundary, km/h."""
        return _checks.to_kmh(self.decay_boundary)

    @property
    def fold_bracket_kmh(self) -> tuple[float, float]:
        """The fold bracket, km/h."""
        return (_checks.to_kmh(self.fold_bracket[0]), _checks.to_kmh(self.fold_bracket[1]))

    @property
    def decay_bracket_kmh(self) -> tuple[float, float]:
        """The decay bracket, km/h."""
        return (_checks.to_kmh(self.decay_bracket[0]), _checks.to_kmh(self.decay_bracket[1]))

    @property
    def message(self) -> str:
        """One line: both numbers with their brackets, or why one is missing."""
        top = _checks.to_kmh(self.settings.get("speed_top", float("nan")))
        bottom = _checks.to_kmh(self.settings.get("speed_floor", float("nan")))
        lo, hi = self.fold_bracket_kmh
        if math.isnan(hi) and self.failure.startswith("fold"):
            f = f"fold unknown (no verdict at the top speed {top:.1f} km/h)"
        elif math.isnan(hi):
            f = f"no limit cycle at the top speed {top:.1f} km/h"
        elif math.isnan(lo):
            f = f"fold below {hi:.1f} km/h (the cycle lives down to the floor {bottom:.1f})"
        else:
            f = (
                f"fold (lowest speed with a limit cycle) {self.fold_kmh:.1f} km/h "
                f"[{lo:.1f}, {hi:.1f}], {self.fold_branch} {self.fold_amplitude * 1e3:.2f} mm"
            )
        lo, hi = self.decay_bracket_kmh
        if not self.settings.get("decay", True):
            d = "decay boundary not computed"
        elif math.isnan(hi):
            d = f"a small disturbance decays at the top speed {top:.1f} km/h"
        elif math.isnan(lo):
            d = f"decay boundary below {hi:.1f} km/h (grows down to the floor)"
        else:
            d = f"decay boundary {self.decay_boundary_kmh:.1f} km/h [{lo:.1f}, {hi:.1f}]"
        if self.failure:
            return f"{self.variant}: {f}; {d}; stopped early: {self.failure}"
        return f"{self.variant}: {f}; {d}"


# --------------------------------------------------------------------------------------------
# The runs
# --------------------------------------------------------------------------------------------

#: What stops one run of a search without stopping the search's finished results: a time
#: integration that could not go on (Newton, a wheelset at the table's end), a BEM patch at
#: its grid's edge.
RUN_FAILURES = (ConvergenceError, GridTooSmallError)


def _failed(speed: float, err: Exception) -> tuple[bool, None, dict]:
    """A test's result for a run that failed at speed (m/s): not passed, the reason recorded."""
    log.warning("run at %.2f km/h failed: %s", _checks.to_kmh(speed), err)
    nan = float("nan")
    return False, None, dict(amplitude=nan, rate=nan, duration=nan, flange=nan, failed=str(err).split(";")[0])


class _Runs:
    """The simulations of one search: the systems at each speed (scenarios' sweep systems:
    RR's one system, FR, RF, FF built per speed), a run continued in ``segments`` calls."""

    def __init__(
        self,
        variant: str,
        contact: str,
        coach: Coach | None,
        h: float | None,
        k_max: int,
        f_max: float,
        geometry: str,
        ring: dict,
        output_dt: float | None,
        segments: int,
    ) -> None:
        self.contact, self.output_dt, self.segments = contact, output_dt, segments
        self.systems = point_systems(variant, coach, contact, h, k_max, f_max, geometry, ring)
        self.bem: BemState | None = None

    @contextlib.contextmanager
    def point(self, speed: float) -> Iterator[None]:
        """One BEM state (with contact='bem') for a search point's static solves and all its
        run segments, closed at the point's end; nothing for the other contact models."""
        with contact_state(self.systems.at(speed)[0], self.contact) as st:
            self.bem = st
            try:
                yield
            finally:
                self.bem = None

    def static(self, speed: float, travel: float = 0.0) -> np.ndarray:
        """The static state at speed (m/s), the contact points ``travel`` along the ring."""
        sy = self.systems.upper_at(speed, travel)[0]
        return static_equilibrium(sy, speed, self.contact, bem=self.bem)[0]

    def run(
        self, speed: float, q: np.ndarray, v: np.ndarray | None, duration: float, travel: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float, float]:
        """``duration`` s at speed (m/s) from (q, v), in ``segments`` continued calls.

        Returns (t, y_ws1, q_end, v_end, travel_end, max flange force of the leading bogie
        over the last 0.5 s)."""
        vv = speed
        _, _, hs = self.systems.at(speed)
        ts, ys, fl = [], [], []
        t0 = 0.0
        part = duration / self.segments
        for _ in range(self.segments):
            sy = self.systems.upper_at(speed, travel)[0]
            r = simulate(
                sy,
                vv,
                part,
                contact=self.contact,
                h=hs,
                q0=q,
                v0=v,
                output_dt=run_output_dt(sy, vv, hs, self.output_dt, 0.002, check=False),
                progress=False,
                bem=self.bem,
            )
            ts.append(r.t + t0)
            ys.append(r.y_ws1)
            fl.append(r.wheel_output("N_flange")[:, :, :2].max(axis=(1, 2)))
            t0 += float(r.t[-1])
            travel += vv * float(r.t[-1])
            q, v = r.q[-1], r.v[-1]
        t, f = np.concatenate(ts), np.concatenate(fl)
        return t, np.concatenate(ys), q, v, travel, float(f[t >= t[-1] - 0.5].max())


def _speed_arg(name: str, si: Any, kmh: Any, default_kmh: float) -> float:
    """A speed-like keyword in m/s from exactly one of ``name`` (m/s) and ``name_kmh``."""
    if si is not None and kmh is not None:
        raise InputError(f"give {name} once: {name} (m/s) or {name}_kmh (km/h), not both")
    if si is not None:
        return _checks.positive(name, si)
    return _checks.from_kmh(_checks.positive(f"{name}_kmh", default_kmh if kmh is None else kmh))


def nonlinear_critical_speed(
    variant: str = "RR",
    contact: str = "hertz-kalker",
    *,
    speed_top: float | None = None,
    speed_top_kmh: float | None = None,
    speed_floor: float | None = None,
    speed_floor_kmh: float | None = None,
    step: float | None = None,
    step_kmh: float | None = None,
    resolution: float | None = None,
    resolution_kmh: float | None = None,
    duration: float = 4.0,
    y_large: float = 0.006,
    y_small: float = 0.0005,
    threshold: float = 0.25e-3,
    rate_tol: float = 0.05,
    collapse: float = 0.5,
    window: float = 0.5,
    max_extensions: int = 2,
    h: float | None = None,
    segments: int = 1,
    output_dt: float | None = None,
    decay: bool = True,
    progress: bool = False,
    coach: Coach | None = None,
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    geometry: str | None = None,
    **ring: Any,
) -> PathCriticalSpeed:
    """The fold (lowest speed with a limit cycle) and the decay boundary, by path-following.

    The upper branch: the static state at the top speed with the leading bogie's wheelsets
    shifted by ``y_large``, ``duration`` s; then down by ``step`` with the whole state carried
    (continuation); where the cycle dies (:func:`cycle_verdict`), bisection between the last
    speed with a cycle and the first without, each run from the last living state, down to a
    bracket of ``resolution``. The decay boundary: the same walk and bisection with
    independent runs from ``y_small`` (grows: :func:`growth_rate` > 0). See the module's
    docstring for the criteria.

    Parameters
    ----------
    variant : str
        'RR', 'FR', 'RF' or 'FF' (FR, RF, FF built at each speed, as in
        :func:`railvti.scenarios.bifurcation`).
    contact : str
        'hertz-kalker' (default), 'hertz-fastsim' or 'bem'.
    speed_top, speed_top_kmh : float, optional
        Top speed, m/s or km/h (one of them; default 420 km/h).
    speed_floor, speed_floor_kmh : float, optional
        The walk's lowest speed, m/s or km/h (default 150 km/h); below the top.
    step, step_kmh : float, optional
        The walk's coarse step, m/s or km/h (default 20 km/h).
    resolution, resolution_kmh : float, optional
        The brackets' final width, m/s or km/h (default 2.5 km/h); at most the step.
    duration : float
        Simulated time per speed, s (a run still dying above the floor is continued up to
        ``max_extensions`` times by ``duration``).
    y_large, y_small : float
        The upper branch's initial shift and the decay test's disturbance, m.
    threshold : float
        The living cycle's floor, m (the envelope's last window).
    rate_tol : float
        The settled envelope's tolerance, 1/s (alive: growth rate >= -rate_tol).
    collapse : float
        A run carried in on the cycle is dead when its last window falls below this fraction
        of its first (it has left the followed branch), in (0, 1).
    window : float
        Envelope window, s.
    max_extensions : int
        How often a still-dying run is continued before it is declared dead.
    h : float, optional
        Time step, s (default: 1 ms, divided for the flexible wheelsets' modes).
    segments : int
        Each run as this many continued :func:`simulate` calls (chunking check; 1: one call).
    output_dt : float, optional
        Output interval, s (default 2 ms or finer, as the sweeps).
    decay : bool
        Also the decay boundary (default True).
    progress : bool
        A tqdm bar over the runs (their number is not known beforehand); every run is also
        logged at INFO level (``railvti.critical_search``).
    coach, k_max, f_max, geometry, **ring
        As :func:`railvti.scenarios.bifurcation`.

    Returns
    -------
    PathCriticalSpeed

    Raises
    ------
    InputError
        A bad key (named), before any run.
    """
    top = _speed_arg("speed_top", speed_top, speed_top_kmh, TOP_KMH)
    bottom = _speed_arg("speed_floor", speed_floor, speed_floor_kmh, FLOOR_KMH)
    dstep = _speed_arg("step", step, step_kmh, STEP_KMH)
    res = _speed_arg("resolution", resolution, resolution_kmh, RESOLUTION_KMH)
    cfg = _checked_search(
        top,
        bottom,
        dstep,
        res,
        duration=duration,
        y_large=y_large,
        y_small=y_small,
        threshold=threshold,
        rate_tol=rate_tol,
        collapse=collapse,
        window=window,
        max_extensions=max_extensions,
        segments=segments,
        h=h,
    )
    _check_variant_keys(variant, contact, k_max, f_max)
    if variant in FLEXIBLE_WHEELSETS:
        k_max, f_max = check_fr_selection(k_max, f_max)
    ring = ring_keys(variant, ring)
    geometry = resolve_geometry(contact, geometry)
    runs = _Runs(variant, contact, coach, h, k_max, f_max, geometry, ring, output_dt, cfg["segments"])
    fb, db = _search(runs, cfg, top, dstep, bottom, res, decay, progress)
    settings = _search_settings(
        cfg, top, bottom, dstep, res, runs.systems.at(top)[2], contact, geometry, decay
    )
    return _path_result(fb, db, runs, variant, settings)


def _search(
    runs: _Runs, cfg: dict, top: float, dstep: float, bottom: float, res: float, decay: bool, progress: bool
) -> tuple[Bracket, Bracket]:
    """The fold's bracket and (``decay``) the decay boundary's, speeds in m/s; a tqdm bar
    over the runs with ``progress``."""
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(desc="critical speed (runs)", leave=False)
    try:
        with serial_blas():
            fb = bracket_down(_upper_test(runs, cfg, bar), top, dstep, bottom, res)
            db = (
                bracket_down(_decay_test(runs, cfg, bar), top, dstep, bottom, res)
                if decay
                else Bracket(float("nan"), float("nan"), [])
            )
    finally:
        if bar is not None:
            bar.close()
    return fb, db


def _search_settings(
    cfg: dict,
    top: float,
    bottom: float,
    dstep: float,
    res: float,
    h: float,
    contact: str,
    geometry: str,
    decay: bool,
) -> dict:
    """The settings of a search as :attr:`PathCriticalSpeed.settings` records them (SI; ``h``
    the time step at the top speed)."""
    return dict(
        speed_top=top,
        speed_floor=bottom,
        step=dstep,
        resolution=res,
        duration=cfg["duration"],
        y_large=cfg["y_large"],
        y_small=cfg["y_small"],
        threshold=cfg["threshold"],
        rate_tol=cfg["rate_tol"],
        collapse=cfg["collapse"],
        window=cfg["window"],
        max_extensions=cfg["max_extensions"],
        h=h,
        segments=cfg["segments"],
        contact=contact,
        geometry=geometry,
        decay=bool(decay),
    )


def _checked_search(
    top: float,
    bottom: float,
    dstep: float,
    res: float,
    *,
    duration: Any,
    y_large: Any,
    y_small: Any,
    threshold: Any,
    rate_tol: Any,
    collapse: Any,
    window: Any,
    max_extensions: Any,
    segments: Any,
    h: Any,
) -> dict:
    """The search's settings checked (speeds in m/s), as a dict; InputError naming a bad one."""
    if not 0.0 < top <= _checks.MAX_SPEED:
        raise InputError(
            f"speed_top_kmh = {_checks.to_kmh(top):g} km/h must be in (0, "
            f"{_checks.MAX_SPEED_KMH:g}] km/h (the fastest wheel-on-rail run was "
            "575 km/h)"
        )
    if bottom >= top:
        raise InputError(
            f"speed_top = {_checks.to_kmh(top):g} km/h must lie above speed_floor = "
            f"{_checks.to_kmh(bottom):g} km/h"
        )
    if res > dstep:
        raise InputError(
            f"resolution = {_checks.to_kmh(res):g} km/h must not exceed step = {_checks.to_kmh(dstep):g} km/h"
        )
    cfg = dict(
        duration=_checks.positive("duration", duration),
        y_large=_checks.positive("y_large", y_large),
        y_small=_checks.positive("y_small", y_small),
        threshold=_checks.positive("threshold", threshold),
        rate_tol=_checks.positive("rate_tol", rate_tol),
        collapse=_checks.positive("collapse", collapse),
    )
    if cfg["collapse"] >= 1.0:
        raise InputError(
            f"collapse = {cfg['collapse']:g} must lie in (0, 1): the fraction of the "
            f"carried cycle's amplitude below which it has died"
        )
    cfg["window"] = _checks.positive("window", window)
    if 2.0 * cfg["window"] > cfg["duration"]:
        raise InputError(
            f"window = {cfg['window']:g} s: the run (duration = "
            f"{cfg['duration']:g} s) must hold at least two windows"
        )
    cfg["max_extensions"] = _checks.positive_int("max_extensions", max_extensions, minimum=0)
    cfg["segments"] = _checks.positive_int("segments", segments)
    if h is not None:
        _checks.positive("h", h)
    return cfg


def _check_variant_keys(variant: str, contact: str, k_max: Any, f_max: Any) -> None:
    """The variant and contact, and no mode selection for the rigid wheelsets."""
    check_variant(variant, contact, "bifurcation")
    if variant not in FLEXIBLE_WHEELSETS and (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
        raise InputError("k_max, f_max: the mode selection of variants 'FR' and 'FF'")


def _upper_test(runs: _Runs, cfg: dict, bar: Any) -> Callable:
    """The fold's test for :func:`bracket_down`: is a limit cycle alive at speed (m/s), the
    state carried in from the last living run (the top: the static state shifted by
    y_large)? A run still dying is continued up to max_extensions times. One BEM state
    for the point's static solves and runs (:meth:`_Runs.point`)."""

    def upper(s: float, state: Any) -> tuple[bool, Any, dict]:
        try:
            with runs.point(s):
                ok, state, rec = _upper_point(runs, cfg, s, state)
        except RUN_FAILURES as e:
            return _failed(s, e)
        kmh = _checks.to_kmh(s)
        log.info(
            "path %.2f km/h: %s, %.3f mm, rate %.3f 1/s, %.1f s",
            kmh,
            rec["verdict"],
            rec["amplitude"] * 1e3,
            rec["rate"],
            rec["duration"],
        )
        if bar is not None:
            bar.set_postfix_str(f"fold search {kmh:.2f} km/h {rec['verdict']}")
            bar.update()
        del rec["verdict"]
        return ok, state, rec

    return upper


def _upper_point(runs: _Runs, cfg: dict, s: float, state: Any) -> tuple[bool, Any, dict]:
    """The runs of :func:`_upper_test` at speed s (m/s) from ``state`` (None at the top).
    Returns (alive, the carried state, the record with its verdict)."""
    crit = dict(threshold=cfg["threshold"], rate_tol=cfg["rate_tol"], window=cfg["window"])
    duration = cfg["duration"]
    if state is None:  # the top: a large shift of the static state
        sy = runs.systems.at(s)[0]
        q = lateral_disturbance(sy, runs.static(s), cfg["y_large"])
        state = (q, np.zeros(sy.n_state), s, 0.0)
    q, v, s_from, travel = state
    carried = s_from != s or travel > 0.0
    if s_from != s:
        q, v, _ = runs.systems.carry(q, v, s_from, s, lambda: runs.static(s, travel))
    t, y, q, v, travel, fl = runs.run(s, q, v, duration, travel)
    cut = cfg["collapse"] if carried else None
    verdict, amp, rate = cycle_verdict(t, y, collapse=cut, **crit)
    n_ext = 0
    while verdict == "decaying" and n_ext < cfg["max_extensions"]:
        t2, y2, q, v, travel, fl = runs.run(s, q, v, duration, travel)
        t, y = np.concatenate([t, t2 + t[-1]]), np.concatenate([y, y2])
        verdict, amp, rate = cycle_verdict(t, y, collapse=cut, **crit)
        n_ext += 1
    rec = dict(amplitude=amp, rate=rate, duration=float(t[-1]), flange=fl, verdict=verdict)
    return verdict == "alive", (q, v, s, travel), rec


def _decay_test(runs: _Runs, cfg: dict, bar: Any) -> Callable:
    """The decay boundary's test for :func:`bracket_down`: does a small disturbance y_small
    of the static state at speed (m/s) grow (an independent run)?"""
    window = cfg["window"]

    def grows(s: float, state: Any) -> tuple[bool, Any, dict]:
        sy = runs.systems.at(s)[0]
        try:
            with runs.point(s):  # one BEM state for the point's static solve and run
                q = lateral_disturbance(sy, runs.static(s), cfg["y_small"])
                t, y, *_ = runs.run(s, q, None, cfg["duration"], 0.0)
        except RUN_FAILURES as e:
            return _failed(s, e)
        rate = growth_rate(t, y, window)
        amp = float(envelope(t, y, window)[1][-1])
        kmh = _checks.to_kmh(s)
        log.info("decay %.2f km/h: rate %.4f 1/s, %.4f mm", kmh, rate, amp * 1e3)
        if bar is not None:
            bar.set_postfix_str(f"decay test {kmh:.2f} km/h {'grows' if rate > 0 else 'decays'}")
            bar.update()
        return rate > 0.0, None, dict(amplitude=amp, rate=rate)

    return grows


def _path_result(fb: Bracket, db: Bracket, runs: _Runs, variant: str, settings: dict) -> PathCriticalSpeed:
    """The PathCriticalSpeed of the fold's and the decay boundary's brackets (m/s)."""
    amp_f, branch = float("nan"), "none"
    if not (math.isnan(fb.hi) or math.isnan(fb.lo)):
        rec = next(r for s, ok, r in fb.visited if ok and s == fb.hi)
        amp_f = rec["amplitude"]
        wheel_load = runs.systems.at(fb.hi)[0].wheel_load
        branch = "flange cycle" if rec["flange"] > 0.01 * wheel_load else "tread cycle"
    st, kmh = settings, _checks.to_kmh
    method = (
        f"fold: continuation down from {st['y_large'] * 1e3:g} mm at "
        f"{kmh(st['speed_top']):g} km/h in {kmh(st['step']):g} km/h steps, bisection "
        f"from the last living state to {kmh(st['resolution']):g} km/h; alive = "
        f"envelope ({st['window']:g} s windows) growth rate over the run's second half "
        f">= -{st['rate_tol']:g} 1/s, last window >= {st['threshold'] * 1e3:g} mm and >= "
        f"{st['collapse']:g} x the first when carried ({st['duration']:g} s per run, up "
        f"to {st['max_extensions']} extensions); decay boundary: independent runs from "
        f"{st['y_small'] * 1e3:g} mm, grows = last envelope window above the first"
    )
    pv, dv = fb.visited, db.visited
    failure = "; ".join(f"{name}: {b.failure}" for name, b in (("fold", fb), ("decay", db)) if b.failure)
    return PathCriticalSpeed(
        fold=fb.hi if not math.isnan(fb.lo) else float("nan"),
        fold_bracket=(fb.lo, fb.hi),
        decay_boundary=db.hi if not math.isnan(db.lo) else float("nan"),
        decay_bracket=(db.lo, db.hi),
        path_speeds=np.array([s for s, _, _ in pv], dtype=float),
        path_amplitudes=np.array([r["amplitude"] for _, _, r in pv]),
        path_rates=np.array([r["rate"] for _, _, r in pv]),
        path_alive=np.array([ok for _, ok, _ in pv], dtype=bool),
        path_durations=np.array([r["duration"] for _, _, r in pv]),
        decay_speeds=np.array([s for s, _, _ in dv], dtype=float),
        decay_amplitudes=np.array([r["amplitude"] for _, _, r in dv]),
        decay_rates=np.array([r["rate"] for _, _, r in dv]),
        fold_amplitude=amp_f,
        fold_branch=branch,
        variant=variant,
        method=method,
        settings=settings,
        failure=failure,
    )
