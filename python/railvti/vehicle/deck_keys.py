"""The keys of deck case type ``vehicle`` (railvti.vehicle.cases): their defaults, units,
meanings and bounds, the alias speed_kmh, the case's consistency checks, and the selections of
railvti.scenarios (coach, model FR's modes, the ring track) a case's keys make."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from .._checks import KMH_PER_M_S, MAX_SPEED, MAX_SPEED_KMH, from_kmh
from ..casetypes import Alias, Key
from ..errors import InputError
from ..track.cases import KEYS as TRACK_KEYS
from ..track.ring import DEFAULTS as TRACK_DEFAULTS
from ..track.ring import NUMERICS as TRACK_NUMERICS
from .bifurcation import AMPLITUDE_WINDOW
from .contact_models import CONTACT_MODELS, GEOMETRIES, parse_contact_model
from .params import BOUNDS as COACH_BOUNDS
from .params import DEFAULTS as COACH_DEFAULTS
from .params import Coach
from .ring_coupling import check_ring_length
from .simulate import MODAL_STEP_LIMIT, check_modal_step, default_modal_step
from .systems import (
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    VARIANTS,
    RF_F_LIMIT,
    RF_N_SLEEPERS,
    RF_SCENARIOS,
    RING_TRACK,
    fr_system,
)

__all__ = [
    "SCENARIOS",
    "DEFAULTS",
    "KEYS",
    "ALIASES",
    "check",
    "coach_from",
    "fr_selection",
    "ring_selection",
]

SCENARIOS = ("centred_running", "hunting", "critical_speed")
#: The railvti.scenarios functions each deck scenario runs.
_RUNS = {
    "centred_running": ("centred_running",),
    "hunting": ("hunting",),
    "critical_speed": ("bifurcation", "linear_critical"),
}
#: The models whose results a deck case stores (the model key's choices are scenarios.MODELS).
_DECK_VARIANTS = ("RR", "FR", "RF", "FF")
#: The ring track's parameters in a deck: 'track_' + a RingTrack parameter (physics, numerics).
_TRACK_PARAMS = tuple(TRACK_DEFAULTS) + tuple(TRACK_NUMERICS)

DEFAULTS: dict[str, Any] = {
    "scenario": "hunting",
    "model": "RR",
    "contact": "hertz-kalker",
    "geometry": None,
    "speed": from_kmh(300.0),
    "duration": 3.0,
    "max_duration": 600.0,
    "h": None,
    "k_max": None,
    "f_max": None,
    "alpha": 0.0,
    "y0": 0.004,
    "output_dt": None,
    "speeds_kmh_min": 160.0,
    "speeds_kmh_max": 440.0,
    "speeds_kmh_step": 20.0,
    "n_sleepers": None,
    "f_limit": None,
    "x_offset": None,
    **{f"track_{k}": None for k in _TRACK_PARAMS},
    **{f"coach_{k}": v[0] for k, v in COACH_DEFAULTS.items()},
}


_WHY_SPEED = "the fastest wheel-on-rail run was 575 km/h"
#: Units, meanings and bounds of the keys of 'vehicle'.
KEYS: dict[str, Key] = {
    "scenario": Key("", "what to run", "str", choices=SCENARIOS),
    "model": Key(
        "",
        "'RR' rigid wheelsets on rigid track elements, 'FR' flexible rotating wheelsets, "
        "'RF' rigid wheelsets on the flexible ring track, 'FF' flexible wheelsets on the ring",
        "str",
        choices=VARIANTS,
    ),
    "k_max": Key(
        "1",
        "models FR and FF: highest circumferential harmonic of the kept wheelset modes (default 2)",
        "int",
        0,
        30,
        optional=True,
        why="the wheelset model's harmonics (as the wheelset deck)",
    ),
    "f_max": Key(
        "Hz",
        "models FR and FF: highest non-rotating frequency of the kept modes (default 800 Hz)",
        lo=0.0,
        hi=2e4,
        lo_open=True,
        optional=True,
        why="each kept mode needs h omega <= 2: 20 kHz asks for 16 us steps",
    ),
    "contact": Key("", "wheel-rail contact model", "str", choices=tuple(CONTACT_MODELS)),
    "geometry": Key(
        "",
        "contact geometry of hertz-kalker / hertz-fastsim: 'strip' (default: strip "
        "potential over the whole interpenetration, conservative, no jumps) or 'table' "
        "(one Hertz point per slot: faster, its point jumps sustain spurious tread "
        "cycles); contact = 'bem' reads the table",
        "str",
        choices=GEOMETRIES,
        optional=True,
    ),
    "speed": Key(
        "m/s", "vehicle speed (or speed_kmh, km/h)", lo=0.0, hi=MAX_SPEED, lo_open=True, why=_WHY_SPEED
    ),
    "duration": Key(
        "s",
        "simulated time (per speed in critical_speed: more than the amplitude window of "
        f"{AMPLITUDE_WINDOW:g} s; at most max_duration)",
        lo=1e-3,
        why="at least one default time step of 1 ms",
    ),
    "max_duration": Key(
        "s",
        "largest duration accepted (raise it for longer runs)",
        lo=0.0,
        hi=86400.0,
        lo_open=True,
        why="a day of simulated time is about 86 GB of history",
    ),
    "h": Key(
        "s",
        "time step (default 1 ms; model FR: 1 ms divided so that h omega_max <= 2)",
        lo=1e-6,
        hi=0.01,
        optional=True,
        why="below 1 us the step's increments are round-off; above 10 ms the wheelset's modes are missed",
    ),
    "alpha": Key("1", "HHT alpha (0: average acceleration)", lo=-1.0 / 3.0, hi=0.0),
    "y0": Key(
        "m",
        "lateral disturbance of the leading bogie's wheelsets (hunting)",
        lo=-0.01,
        hi=0.01,
        why="beyond 10 mm the wheelset is in flange contact",
    ),
    "output_dt": Key(
        "s",
        "interval of the stored history and of the runs of critical_speed (default: 10 ms "
        "centred running, 2 ms hunting and sweeps, shortened to 10 samples per period of "
        "the sleeper passing (RF, FF) and of hunting; a value that aliases them warns)",
        lo=0.0,
        hi=1.0,
        lo_open=True,
        optional=True,
    ),
    "speeds_kmh_min": Key(
        "km/h",
        "first speed of the critical_speed sweep",
        lo=0.0,
        hi=MAX_SPEED_KMH,
        lo_open=True,
        why=_WHY_SPEED,
    ),
    "speeds_kmh_max": Key(
        "km/h",
        "last speed of the critical_speed sweep",
        lo=0.0,
        hi=MAX_SPEED_KMH,
        lo_open=True,
        why=_WHY_SPEED,
    ),
    "speeds_kmh_step": Key(
        "km/h", "speed step of the critical_speed sweep", lo=0.0, hi=MAX_SPEED_KMH, lo_open=True
    ),
    "n_sleepers": Key(
        "1",
        f"models RF and FF: sleepers on the ring track (default {RF_N_SLEEPERS}; the paper's 128); "
        "the ring must hold the wheelsets' span plus two bays",
        "int",
        8,
        1024,
        optional=True,
        why="as the track_receptance deck's n_sleepers",
    ),
    "f_limit": Key(
        "Hz",
        f"models RF and FF: kept ring modes up to this frequency (default {RF_F_LIMIT:g} Hz), the "
        "rest as residual flexibility",
        lo=0.0,
        hi=2e4,
        lo_open=True,
        optional=True,
        why="each kept mode needs h omega <= 2: 20 kHz asks for 16 us steps",
    ),
    "x_offset": Key(
        "m",
        "models RF and FF: the coach centre's position along the ring at t = 0 (default 0: above a sleeper)",
        lo=-1e3,
        hi=1e3,
        optional=True,
    ),
    **{
        f"track_{k}": replace(
            TRACK_KEYS[k],
            optional=True,
            meaning=f"models RF and FF: ring track {TRACK_KEYS[k].meaning} "
            f"(default {v:g}, railvti.track.{'DEFAULTS' if k in TRACK_DEFAULTS else 'NUMERICS'})",
        )
        for k, v in {**TRACK_DEFAULTS, **TRACK_NUMERICS}.items()
    },
    **{
        f"coach_{k}": Key(
            v[1],
            f"coach {k.replace('_', ' ')} (default {v[0]:g}: {v[2].split(' (')[0]})",
            lo=COACH_BOUNDS[k][0],
            hi=COACH_BOUNDS[k][1],
            lo_open=k == "friction",
            why=COACH_BOUNDS[k][2],
        )
        for k, v in COACH_DEFAULTS.items()
    },
}
#: speed_kmh: the speed in km/h (not deprecated: its suffix names the unit).
ALIASES = {"speed_kmh": Alias("speed", deprecated=False, unit="km/h", divisor=KMH_PER_M_S)}


def check(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'vehicle' case: duration, sweep and coach."""
    out = []
    if params["duration"] > params["max_duration"]:
        out.append(
            f"duration = {params['duration']:g} s exceeds max_duration = {params['max_duration']:g} s "
            "(about 1 MB of history per simulated second; raise max_duration to run longer)"
        )
    try:  # the contact model's geometries (its spec: railvti.vehicle.contact_models)
        parse_contact_model(params["contact"]).resolve_geometry(params["geometry"])
    except InputError as exc:
        out.append(str(exc))
    if params["h"] is not None and params["h"] > params["duration"]:
        out.append(f"h = {params['h']:g} s must be <= duration = {params['duration']:g} s")
    if params["output_dt"] is not None and params["output_dt"] > params["duration"]:
        out.append(
            f"output_dt = {params['output_dt']:g} s must be <= duration = {params['duration']:g} s "
            "(the history would hold the start only)"
        )
    if params["scenario"] == "critical_speed" and params["duration"] <= AMPLITUDE_WINDOW:
        out.append(
            f"duration = {params['duration']:g} s must be > {AMPLITUDE_WINDOW:g} s for scenario "
            f"'critical_speed': each speed's amplitude is measured over the last "
            f"{AMPLITUDE_WINDOW:g} s of its run (the amplitude window), which must lie inside "
            "the run after its start"
        )
    if params["model"] not in FLEXIBLE_WHEELSETS:
        given = [k for k in ("k_max", "f_max") if params.get(k) is not None]
        if given:
            out.append(
                f"{', '.join(given)}: the mode selection of models FR and FF; model "
                f"{params['model']!r} has rigid wheelsets"
            )
    elif params["h"] is not None and _trapezoidal_modal_step(params):
        problem = _fr_step_problem(params)
        if problem:
            out.append(problem)
    if params["model"] not in _DECK_VARIANTS:
        out.append(
            f"model {params['model']!r} runs from railvti.scenarios but not from a deck yet "
            f"(decks run {_DECK_VARIANTS})"
        )
    else:
        out += _ring_problems(params)
    if params["scenario"] == "critical_speed":
        lo, hi, step = (params[f"speeds_kmh_{k}"] for k in ("min", "max", "step"))
        if lo >= hi:
            out.append(f"speeds_kmh_min = {lo:g} must be < speeds_kmh_max = {hi:g} (km/h)")
        elif (hi - lo) / step > 200:
            out.append(
                f"speeds_kmh_step = {step:g} km/h gives {int((hi - lo) / step) + 1} speeds; at most 201"
            )
    try:
        coach_from(params)
    except InputError as exc:
        out.append(f"coach: {exc}")
    return out


def _ring_keys(params: dict[str, Any]) -> list[str]:
    """The keys of the ring track given in a case (not left at None)."""
    return [
        k
        for k in ("n_sleepers", "f_limit", "x_offset", *(f"track_{t}" for t in _TRACK_PARAMS))
        if params.get(k) is not None
    ]


def ring_selection(params: dict[str, Any]) -> dict[str, Any]:
    """The ring keys of railvti.scenarios (n_sleepers, f_limit, x_offset, track_params) from
    a case, the scenarios' defaults where not given."""
    tp = {t: params[f"track_{t}"] for t in _TRACK_PARAMS if params.get(f"track_{t}") is not None}
    return {
        "n_sleepers": RF_N_SLEEPERS if params.get("n_sleepers") is None else int(params["n_sleepers"]),
        "f_limit": RF_F_LIMIT if params.get("f_limit") is None else float(params["f_limit"]),
        "x_offset": 0.0 if params.get("x_offset") is None else float(params["x_offset"]),
        "track_params": tp,
    }


def _ring_problems(params: dict[str, Any]) -> list[str]:
    """Model RF's keys: only with a model on the ring, a scenario it runs, a ring that holds
    the coach (checked before any ring is built) and track parameters RingTrack takes."""
    variant = str(params["model"])
    given = _ring_keys(params)
    if variant not in RING_TRACK:
        return (
            [
                f"{', '.join(given)}: keys of the ring track (model 'RF'); model {variant!r} runs on "
                "rigid track elements"
            ]
            if given
            else []
        )
    out = []
    allowed = RF_SCENARIOS
    missing = [f for f in _RUNS.get(str(params["scenario"]), ()) if allowed is not None and f not in allowed]
    if missing:
        out.append(
            f"model {variant!r} does not run scenario {params['scenario']!r} yet "
            f"(railvti.scenarios.{', '.join(missing)}); it runs {allowed}"
        )
    sel = ring_selection(params)
    spacing = sel["track_params"].get("sleeper_spacing", TRACK_DEFAULTS["sleeper_spacing"])
    try:
        coach = coach_from(params)
    except InputError:
        return out  # reported by check as a coach problem
    try:
        check_ring_length(sel["n_sleepers"], spacing, coach)
    except InputError as exc:
        out.append(f"n_sleepers = {sel['n_sleepers']}: {exc}")
    return out


def fr_selection(params: dict[str, Any]) -> dict[str, Any]:
    """Model FR's k_max, f_max from the case (the scenarios' defaults where not given)."""
    return {
        "k_max": FR_K_MAX if params.get("k_max") is None else params["k_max"],
        "f_max": FR_F_MAX if params.get("f_max") is None else params["f_max"],
    }


def _trapezoidal_modal_step(params: dict[str, Any]) -> bool:
    """Whether the case's modal blocks take the trapezoidal step (simulate's default for the
    model and alpha, simulate.default_modal_step; the exact step has no step limit)."""
    return default_modal_step(params["model"], alpha=params["alpha"]) == "trapezoidal"


def _fr_step_problem(params: dict[str, Any]) -> str | None:
    """Why the given h is too large for model FR's kept modes (None: it is not). Cheap when
    h 2 pi f_max <= 2 (no kept mode is above f_max); otherwise the FR system is built at the
    case's (highest) speed and its highest mode checked exactly (check_modal_step)."""
    sel = fr_selection(params)
    scale = params.get("coach_wheelset_stiffness_scale") or 1.0
    if params["h"] * 2.0 * np.pi * sel["f_max"] * np.sqrt(scale) <= MODAL_STEP_LIMIT:
        return None
    speed = from_kmh(params["speeds_kmh_max"]) if params["scenario"] == "critical_speed" else params["speed"]
    try:
        coach = coach_from(params)
    except InputError:
        return None  # reported by check as a coach problem
    try:
        sy, _ = fr_system(coach, speed=min(speed, MAX_SPEED), **sel)
        check_modal_step(sy, params["h"])
    except InputError as exc:
        return f"model FR: {exc}"
    return None


def coach_from(params: dict[str, Any]) -> Coach:
    """The Coach of a case: the defaults with its 'coach_' keys."""
    kw = {k[6:]: v for k, v in params.items() if k.startswith("coach_")}
    return Coach(**kw)
