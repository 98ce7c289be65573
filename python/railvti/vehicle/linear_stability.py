"""The linear critical speed (railvti.scenarios): eigenvalues of the coach linearised about
centred running at the equivalent conicity, bisected in speed; on the ring track the
sleeper-bay average of the frozen contact rows."""

from __future__ import annotations

import logging
from typing import Any

import numpy as np

from .. import _checks
from ..errors import InputError
from .flexible import build_fr
from .flexible_linear import eigenvalues as fr_eigenvalues
from .params import Coach
from .equilibrium import eigenvalues
from .systems import (
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    RF_N_SLEEPERS,
    RING_TRACK,
    check_fr_selection,
    check_variant,
    checked_ring,
    coach_system,
    equivalent_conicity,
    fr_wheelset,
    no_fr_keys,
    on_ring,
    ring_keys,
    wheel_table,
)
from .table import WheelTable, linearised_table

__all__ = [
    "RING_ROWS",
    "BAY_OFFSETS",
    "DAMPER_STATES",
    "V_LO",
    "V_HI",
    "TOL",
    "linear_critical_speed_kmh",
    "linear_critical",
    "hunting_mode",
    "bay_rates",
    "frozen_crossings",
]

log = logging.getLogger(__name__)


#: The linear method's treatment of the ring's contact rows (:func:`linear_critical`).
RING_ROWS = ("bay_average", "frozen")
#: Contact-point positions across one sleeper bay in the bay average.
BAY_OFFSETS = 8
#: The bisection's default bracket and tolerance, m/s (50 to 800 km/h, to 0.5 km/h).
V_LO, V_HI, TOL = _checks.from_kmh(50.0), _checks.from_kmh(800.0), _checks.from_kmh(0.5)
#: The dry-friction yaw damper's states of the linear method.
DAMPER_STATES = {
    "stuck": (
        "stuck: friction torque T tanh(rate / w0) linearised at rest, a viscous slope "
        "T / w0 (1.5e7 N m s/rad for the defaults), practically locked"
    ),
    "sliding": (
        "sliding: the friction torque saturated at +-T, no incremental stiffness or "
        "damping (yaw_friction_torque set to 0 in the linearisation)"
    ),
}


def linear_critical_speed_kmh(
    variant: str = "RR",
    coach: Coach | None = None,
    *,
    conicity: float | None = None,
    amplitude_m: float = 0.003,
    v_lo_kmh: float = 50.0,
    v_hi_kmh: float = 800.0,
    tol_kmh: float = 0.5,
    damper: str = "stuck",
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    ring_rows: str = "bay_average",
    n_offsets: int = BAY_OFFSETS,
    **ring: Any,
) -> tuple[float, float]:
    """:func:`linear_critical` in km/h: the linear critical speed (km/h) and the hunting
    frequency there (Hz), bisected between ``v_lo_kmh`` and ``v_hi_kmh`` to ``tol_kmh``
    (km/h). The method, its keys and its errors: :func:`linear_critical`."""
    speed, freq = linear_critical(
        variant,
        coach,
        conicity=conicity,
        amplitude_m=amplitude_m,
        v_lo=_checks.from_kmh(v_lo_kmh),
        v_hi=_checks.from_kmh(v_hi_kmh),
        tol=_checks.from_kmh(tol_kmh),
        damper=damper,
        k_max=k_max,
        f_max=f_max,
        ring_rows=ring_rows,
        n_offsets=n_offsets,
        **ring,
    )
    return _checks.to_kmh(speed), freq


def linear_critical(
    variant: str = "RR",
    coach: Coach | None = None,
    *,
    conicity: float | None = None,
    amplitude_m: float = 0.003,
    v_lo: float = V_LO,
    v_hi: float = V_HI,
    tol: float = TOL,
    damper: str = "stuck",
    k_max: int = FR_K_MAX,
    f_max: float = FR_F_MAX,
    ring_rows: str = "bay_average",
    n_offsets: int = BAY_OFFSETS,
    **ring: Any,
) -> tuple[float, float]:
    """Linear critical speed (m/s; inf when stable up to ``v_hi``) and the hunting frequency
    there (Hz), bisected between ``v_lo`` and ``v_hi`` (m/s) to ``tol`` (m/s).
    :func:`linear_critical_speed_kmh` is the same in km/h (and :func:`railvti.scenarios.
    critical_speed` with ``method='linear'`` gives both).

    Eigenvalues of the system linearised about centred running with the contact table
    replaced by its equivalent linearisation at the EN 15302 equivalent conicity for the
    amplitude ``amplitude_m`` (Kalker's linear creep). The dry-friction yaw damper enters in
    the state ``damper`` (:data:`DAMPER_STATES`): 'stuck' (default; its tangent at rest, a
    steep viscous slope) or 'sliding' (its torque saturated: no incremental contribution).
    Bisection on the largest real part of the oscillatory eigenvalues below 20 Hz.

    Variant 'FR' (mode selection ``k_max``, ``f_max``): the flexible DOFs are in the
    linearisation (:func:`railvti.vehicle.flexible_linear.eigenvalues`: elastic and residual
    coordinates, about FR's own steady state); its modes depend on the spin, so the system is
    rebuilt at every speed of the bisection. The wheelsets' elastic modes lie above 70 Hz,
    outside the 20 Hz band searched: they change the hunting eigenvalue, not the band.

    Variants 'RF' and 'FF' (the ring's keys ``**ring``, :func:`rf_system`): the ring's kept
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
    k_max, f_max, ring, n_offsets = _checked_settings(
        variant, damper, ring_rows, n_offsets, k_max, f_max, ring
    )
    coach = coach or Coach()
    if damper == "sliding":
        coach = coach.with_(yaw_friction_torque=0.0)
    lam = conicity if conicity is not None else equivalent_conicity(amplitude_m)
    growth = _HuntingGrowth(
        variant,
        coach,
        lam,
        k_max,
        f_max,
        ring,
        bay=variant in RING_TRACK and ring_rows == "bay_average",
        n_offsets=n_offsets,
    )
    speed, freq = _bisect(growth, float(v_lo), float(v_hi), tol)
    if growth.bay and np.isfinite(speed) and speed != float(v_lo):
        per = frozen_crossings(growth.frozen)
        log.info(
            "%s linear critical speed, bay average over %d offsets: %.1f km/h; frozen "
            "rows per offset: %.1f .. %.1f km/h (%s)",
            variant,
            n_offsets,
            _checks.to_kmh(speed),
            _checks.to_kmh(np.nanmin(per)),
            _checks.to_kmh(np.nanmax(per)),
            ", ".join(f"{_checks.to_kmh(v):.1f}" for v in per),
        )
    return speed, freq


def _checked_settings(
    variant: str, damper: str, ring_rows: str, n_offsets: Any, k_max: Any, f_max: Any, ring: dict
) -> tuple[int, float, dict, int]:
    """The linear method's settings checked: (k_max, f_max, the ring's keys, n_offsets)."""
    if damper not in DAMPER_STATES:
        raise InputError(f"damper must be one of {sorted(DAMPER_STATES)}, got {damper!r}")
    if ring_rows not in RING_ROWS:
        raise InputError(f"ring_rows must be one of {RING_ROWS}, got {ring_rows!r}")
    n_offsets = _checks.positive_int("n_offsets", n_offsets)
    check_variant(variant, "hertz-kalker", "linear_critical")
    if variant in FLEXIBLE_WHEELSETS:
        k_max, f_max = check_fr_selection(k_max, f_max)
    elif (k_max, f_max) != (FR_K_MAX, FR_F_MAX):
        no_fr_keys({"k_max": k_max} if k_max != FR_K_MAX else {"f_max": f_max})
    return k_max, f_max, ring_keys(variant, ring), n_offsets


class _HuntingGrowth:
    """The hunting mode's growth rate (1/s) and frequency (Hz) at a speed (m/s), cached per
    speed: the system linearised at the equivalent conicity ``lam``; on the ring track with
    ``bay`` the mean over the frozen contact rows across one bay (``frozen``: speed -> the
    growth rate per offset)."""

    def __init__(
        self,
        variant: str,
        coach: Coach,
        lam: float,
        k_max: int,
        f_max: float,
        ring: dict,
        *,
        bay: bool,
        n_offsets: int,
    ) -> None:
        self.variant, self.coach, self.lam = variant, coach, lam
        self.k_max, self.f_max, self.ring = k_max, f_max, ring
        self.bay, self.n_offsets = bay, n_offsets
        self.frozen: dict[float, np.ndarray] = {}
        self._seen: dict[float, tuple[float, float]] = {}
        self._rr = coach_system(variant, coach, linear_conicity=lam) if variant == "RR" else None

    def spectrum(self, v: float) -> np.ndarray:
        """The eigenvalues of the linearised system at v (m/s)."""
        if self._rr is not None:
            return eigenvalues(self._rr, v)
        # built directly: the bisection's bracket may pass the scenarios' 600 km/h bound
        tab = linearised_table(wheel_table(), self.lam)
        if self.variant in RING_TRACK:
            sf = on_ring(self.variant, self.coach, tab, v, k_max=self.k_max, f_max=self.f_max, **self.ring)[0]
        else:
            sf = build_fr(self.coach, tab, v, wheelset=fr_wheelset(), k_max=self.k_max, f_max=self.f_max)[0]
        return fr_eigenvalues(sf, v)

    def __call__(self, v: float) -> tuple[float, float]:
        if v in self._seen:
            return self._seen[v]
        if self.bay:
            tab = linearised_table(wheel_table(), self.lam)
            rates, freqs = bay_rates(
                self.variant,
                self.coach,
                tab,
                v,
                self.n_offsets,
                k_max=self.k_max,
                f_max=self.f_max,
                ring=self.ring,
            )
            self.frozen[v] = rates
            self._seen[v] = float(np.mean(rates)), float(np.mean(freqs))
        else:
            self._seen[v] = hunting_mode(self.spectrum(v))
        return self._seen[v]


def _bisect(growth: Any, lo: float, hi: float, tol: float) -> tuple[float, float]:
    """Bisection of the growth rate's sign change between lo and hi to tol: (the speed, the
    frequency at the bracket's upper end); (lo, its frequency) when it grows at lo already,
    (inf, NaN) when it decays at hi."""
    if growth(lo)[0] > 0:
        return lo, growth(lo)[1]
    if growth(hi)[0] < 0:
        return float("inf"), float("nan")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if growth(mid)[0] > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi), growth(hi)[1]


def hunting_mode(ev: np.ndarray) -> tuple[float, float]:
    """Growth rate (1/s) and frequency (Hz) of the least damped oscillatory eigenvalue in the
    hunting band (0.1 rad/s < |imag| < 20 Hz)."""
    osc = ev[(np.abs(ev.imag) > 0.1) & (np.abs(ev.imag) < 2 * np.pi * 20)]
    i = int(np.argmax(osc.real))
    return float(osc[i].real), float(abs(osc[i].imag) / (2 * np.pi))


def bay_rates(
    variant: str,
    coach: Coach,
    table: WheelTable,
    v: float,
    n_offsets: int,
    *,
    k_max: int,
    f_max: float,
    ring: dict,
) -> tuple[np.ndarray, np.ndarray]:
    """Variant RF or FF at v (m/s): the hunting growth rate (1/s) and frequency (Hz) with the
    contact rows frozen at each of n_offsets positions across one sleeper bay
    (:func:`linear_critical`)."""
    ring = dict(ring)
    x0 = float(ring.pop("x_offset", 0.0))
    spacing = checked_ring(coach, ring.get("n_sleepers", RF_N_SLEEPERS), ring.get("track_params")).params[
        "sleeper_spacing"
    ]
    base = None
    if variant == "FF":  # the wheelsets do not depend on the ring's rows: built once per speed
        base = build_fr(coach, table, v, wheelset=fr_wheelset(), k_max=k_max, f_max=f_max, track=False)
    out = []
    for k in range(n_offsets):
        sy = on_ring(
            variant,
            coach,
            table,
            v,
            k_max=k_max,
            f_max=f_max,
            fr_base=base,
            x_offset=x0 + k * spacing / n_offsets,
            **ring,
        )[0]
        out.append(hunting_mode(fr_eigenvalues(sy, v)))
    rates, freqs = np.array(out).T
    return rates, freqs


def frozen_crossings(samples: dict[float, np.ndarray]) -> np.ndarray:
    """Per offset: the lowest speed (m/s, as the samples' keys) where its frozen growth rate
    turns positive, linearly interpolated between the sampled speeds (NaN: no sign change
    sampled)."""
    speeds = np.array(sorted(samples))
    g = np.array([samples[v] for v in speeds])
    out = np.full(g.shape[1], np.nan)
    for k in range(g.shape[1]):
        up = np.nonzero((g[:-1, k] <= 0) & (g[1:, k] > 0))[0]
        if up.size:
            i = up[0]
            out[k] = speeds[i] + (speeds[i + 1] - speeds[i]) * -g[i, k] / (g[i + 1, k] - g[i, k])
    return out
