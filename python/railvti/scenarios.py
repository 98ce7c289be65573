"""Vehicle-track scenarios on straight track: centred running, hunting, critical speed.

Variant 'RR': rigid wheelsets on the rigid track element (one per wheelset). Variant 'FR'
(every scenario): the same with flexible rotating wheelsets (railvti.vehicle.flexible:
free-free elastic modes coupled through the rims and journals, docs/vehicle_integrator.md
"Flexible wheelsets (FR)"); its modal matrices depend on the spin, so it is built at each
speed (:func:`fr_system`) with the mode selection ``k_max``, ``f_max``. Variant 'RF': rigid
wheelsets on the flexible ring track (railvti.vehicle.ring_coupling, docs/vehicle.md "Model
RF"), built per speed (:func:`rf_system`) with ``n_sleepers``, ``f_limit``,
``track_params``, ``x_offset``, ``ring_residual``. Variant 'FF': the
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

The scenarios live by topic in railvti.vehicle: the systems and their caches
(:mod:`railvti.vehicle.systems`), centred running and hunting
(:mod:`railvti.vehicle.running`), the bifurcation sweep (:mod:`railvti.vehicle.bifurcation`),
the linear critical speed (:mod:`railvti.vehicle.linear_stability`) and the results
(:mod:`railvti.vehicle.scenario_results`); this module is their public face and
:func:`critical_speed` joins the two methods.
"""

from __future__ import annotations

from typing import Any

from . import _checks
from .errors import InputError
from .vehicle.bifurcation import (
    AMPLITUDE_WINDOW,
    SweepSystems,
    amplitude,
    bifurcation,
    bifurcation_point,
    bifurcation_upper,
)
from .vehicle.linear_stability import (
    BAY_OFFSETS,
    DAMPER_STATES,
    RING_ROWS,
    linear_critical,
    linear_critical_speed_kmh,
)
from .vehicle.params import Coach
from .vehicle.curve_running import CurveRun, SteadyCurving, curving
from .vehicle.line_running import LineRun, line_run
from .vehicle.running import centred_running, contact_patch, hunting, irregular_track
from .vehicle.scenario_results import Bifurcation, CentredRunning, CriticalSpeed
from .vehicle.systems import (
    DEFAULT_GEOMETRY,
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    GEOMETRIES,
    MAX_HARMONIC,
    VARIANTS,
    RF_F_LIMIT,
    RF_N_SLEEPERS,
    RF_SCENARIOS,
    RING_TABLE_Y_MAX,
    RING_TRACK,
    check_fr_selection,
    check_variant,
    coach_system,
    equivalent_conicity,
    ff_system,
    fr_system,
    hunting_conicity,
    resolve_geometry,
    rf_system,
    wheel_table,
)

__all__ = [
    # scenarios
    "centred_running",
    "hunting",
    "curving",
    "line_run",
    "irregular_track",
    "bifurcation",
    "critical_speed",
    "linear_critical_speed_kmh",
    "linear_critical",
    "contact_patch",
    "amplitude",
    "bifurcation_upper",
    "bifurcation_point",
    # results
    "CentredRunning",
    "Bifurcation",
    "CriticalSpeed",
    "CurveRun",
    "LineRun",
    "SteadyCurving",
    # systems
    "coach_system",
    "fr_system",
    "rf_system",
    "ff_system",
    "wheel_table",
    "equivalent_conicity",
    "hunting_conicity",
    "resolve_geometry",
    "check_fr_selection",
    "SweepSystems",
    # settings
    "VARIANTS",
    "FLEXIBLE_WHEELSETS",
    "RING_TRACK",
    "RF_SCENARIOS",
    "FR_K_MAX",
    "FR_F_MAX",
    "MAX_HARMONIC",
    "RF_N_SLEEPERS",
    "RF_F_LIMIT",
    "RING_TABLE_Y_MAX",
    "GEOMETRIES",
    "DEFAULT_GEOMETRY",
    "AMPLITUDE_WINDOW",
    "DAMPER_STATES",
    "RING_ROWS",
    "BAY_OFFSETS",
]


def critical_speed(
    variant: str = "RR",
    contact: str = "hertz-kalker",
    method: str = "nonlinear",
    *,
    coach: Coach | None = None,
    **kw: Any,
) -> CriticalSpeed:
    """Critical speed (:class:`CriticalSpeed`; ``.kmh`` or ``float()`` for the value in km/h).

    method 'linear': :func:`linear_critical_speed_kmh` (eigenvalues; contact model irrelevant;
    ``damper='stuck'`` or ``'sliding'`` for the dry-friction yaw damper, reported in
    ``damper_state``). method 'nonlinear': :func:`bifurcation` (lowest speed with a
    sustained limit cycle; the sweep is extended downward until the cycle dies, otherwise
    ``kmh`` is NaN and ``no_decay_below_kmh`` says down to where it was searched; ``branch``
    names the tread or flange cycle that defines it; its speeds in m/s as ``speeds`` or in
    km/h as ``speeds_kmh``). Variant 'FR' takes ``k_max`` and ``f_max`` (Hz) in both methods
    and is built at every speed. ``.speed`` is the result in m/s.
    """
    check_variant(variant, contact, "critical_speed")
    if method == "linear":
        damper = kw.get("damper", "stuck")
        lin = {k: kw.pop(k) for k in ("v_lo_kmh", "v_hi_kmh", "tol_kmh") if k in kw}
        si = {k[:-4]: _checks.from_kmh(v) for k, v in lin.items()}
        v, f = linear_critical(variant, coach, **si, **kw)
        return CriticalSpeed(
            speed=v,
            method="linear",
            branch="linear (equivalent conicity)",
            damper_state=DAMPER_STATES.get(damper, damper),
            frequency_hz=f,
            variant=variant,
        )
    if method == "nonlinear":
        b = bifurcation(variant=variant, contact=contact, coach=coach, **kw)
        return CriticalSpeed(
            speed=b.critical,
            method="nonlinear",
            branch=b.branch,
            damper_state="as simulated (stick-slip, torque T tanh(rate / w0))",
            no_decay_below=b.no_decay_below,
            bifurcation=b,
            variant=variant,
        )
    raise InputError(f"method must be 'linear' or 'nonlinear', got {method!r}")
