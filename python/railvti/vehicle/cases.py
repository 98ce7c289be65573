"""Deck case type ``vehicle``: the coach-track scenarios (centred running, hunting, critical
speed / bifurcation) with the contact model named in the deck; results record it.

Keys (SI units unless the name says km/h): scenario ('centred_running' | 'hunting' |
'critical_speed'), model (railvti.scenarios.MODELS: 'RR' rigid or 'FR' flexible wheelsets on
rigid track elements; 'RF' rigid and 'FF' flexible wheelsets on the flexible ring track;
every scenario), k_max and f_max (models FR and FF: the wheelsets' mode selection, highest
harmonic, highest frequency in Hz), n_sleepers, f_limit (Hz), x_offset (m) and the ring's
parameters prefixed 'track_' (railvti.track.DEFAULTS and NUMERICS, e.g.
track_pad_stiffness_vertical, track_f_max) for the ring track of models RF and FF, contact
('hertz-kalker' | 'hertz-fastsim' | 'bem'), speed (m/s; or speed_kmh, km/h), duration (s, at
most max_duration), max_duration (s), h (s; default 1 ms, model FR 1 ms divided so that
h omega_max <= 2), alpha (HHT, 0 = average acceleration), y0 (m, hunting disturbance),
output_dt (s; default: the scenario's, resolving the sleeper passing and hunting,
railvti.vehicle.output), speeds_kmh_min/max/step (critical_speed sweep, km/h), and any Coach parameter
prefixed 'coach_' (railvti.vehicle.DEFAULTS, e.g. coach_carbody_mass) to override the
Manchester benchmark coach. ``railvti cases vehicle`` lists them with units and bounds.

Model FR's results add the modal coordinates with their mode labels (``modal_q`` and
``mode_label``, ``mode_k``, ``mode_family``, ``mode_frequency``) and the rims' deformation at
the contact points (``rim_deformation``; ``rim_camber_change``, the rims' camber, rad;
``rim_rail_angle_change``, the rim-rail relative angle: camber minus the rail head's roll
under the wheel, rad, + when the inner edge rises). Model RF's add the ring's
modal coordinates with their labels (``modal_q``, ``mode_label``, ``mode_group``,
``mode_frequency``) and the rail's motion under each wheel (``rail_deflection``: the pose
y, z, roll of the element under the wheel; ``rail_crown_z``: the crown's vertical
displacement there). Model FF's add both: the wheelsets' as FR's, the ring's with the
prefix 'ring_' (``ring_modal_q``, ``ring_mode_label``, ...) beside ``rail_deflection``, and
``rail_head_roll`` (the rail head's roll under each wheel in the angle convention, rad).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from dataclasses import replace

from .._checks import KMH_PER_M_S, MAX_SPEED, MAX_SPEED_KMH, from_kmh, to_kmh
from ..casetypes import (
    Alias,
    CaseOutput,
    CaseType,
    Key,
    case_sink,
    history_bytes,
    register,
    split_labels,
    validate,
)
from ..errors import InputError
from ..track.cases import KEYS as TRACK_KEYS
from ..track.ring import DEFAULTS as TRACK_DEFAULTS
from ..track.ring import NUMERICS as TRACK_NUMERICS
from .bifurcation import AMPLITUDE_WINDOW, amplitude, bifurcation
from .linear_stability import DAMPER_STATES, linear_critical_speed
from .contact_models import CONTACT_MODELS, GEOMETRIES, parse_contact_model
from .flexible import mode_labels
from .flexible_points import rail_head_roll, rim_camber_change, rim_deformation
from .plots import plot_bifurcation, plot_history, plot_patch, plot_wheels
from .ring_coupling import check_ring_length
from .run_result import STAT_UNITS, WHEEL_UNITS
from .simulate import MODAL_STEP_LIMIT, check_modal_step
from .params import BOUNDS as COACH_BOUNDS
from .params import DEFAULTS as COACH_DEFAULTS
from .params import Coach
from . import output
from .running import centred_running, contact_patch, hunting
from .scenario_results import WHEEL_SIDES, kmh_label
from .systems import (
    FLEXIBLE_WHEELSETS,
    FR_F_MAX,
    FR_K_MAX,
    MODELS,
    RF_F_LIMIT,
    RF_N_SLEEPERS,
    RF_SCENARIOS,
    RING_TRACK,
    fr_system,
    hunting_conicity,
    resolve_geometry,
)
from .model import WHEEL_OUTPUTS

__all__ = ["DEFAULTS", "KEYS", "ALIASES", "NAN_MEANINGS", "check", "run", "plot"]

_SCENARIOS = ("centred_running", "hunting", "critical_speed")
#: The railvti.scenarios functions each deck scenario runs.
_RUNS = {
    "centred_running": ("centred_running",),
    "hunting": ("hunting",),
    "critical_speed": ("bifurcation", "linear_critical_speed"),
}
#: The models whose results a deck case stores (the model key's choices are scenarios.MODELS).
_DECK_MODELS = ("RR", "FR", "RF", "FF")
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
    "scenario": Key("", "what to run", "str", choices=_SCENARIOS),
    "model": Key(
        "",
        "'RR' rigid wheelsets on rigid track elements, 'FR' flexible rotating wheelsets, "
        "'RF' rigid wheelsets on the flexible ring track, 'FF' flexible wheelsets on the ring",
        "str",
        choices=MODELS,
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
    elif params["h"] is not None:
        problem = _fr_step_problem(params)
        if problem:
            out.append(problem)
    if params["model"] not in _DECK_MODELS:
        out.append(
            f"model {params['model']!r} runs from railvti.scenarios but not from a deck yet "
            f"(decks run {_DECK_MODELS})"
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
        _coach(params)
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


def _ring_selection(params: dict[str, Any]) -> dict[str, Any]:
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
    model = str(params["model"])
    given = _ring_keys(params)
    if model not in RING_TRACK:
        return (
            [
                f"{', '.join(given)}: keys of the ring track (model 'RF'); model {model!r} runs on "
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
            f"model {model!r} does not run scenario {params['scenario']!r} yet "
            f"(railvti.scenarios.{', '.join(missing)}); it runs {allowed}"
        )
    sel = _ring_selection(params)
    spacing = sel["track_params"].get("sleeper_spacing", TRACK_DEFAULTS["sleeper_spacing"])
    try:
        coach = _coach(params)
    except InputError:
        return out  # reported by check as a coach problem
    try:
        check_ring_length(sel["n_sleepers"], spacing, coach)
    except InputError as exc:
        out.append(f"n_sleepers = {sel['n_sleepers']}: {exc}")
    return out


def _fr_selection(params: dict[str, Any]) -> dict[str, Any]:
    """Model FR's k_max, f_max from the case (the scenarios' defaults where not given)."""
    return {
        "k_max": FR_K_MAX if params.get("k_max") is None else params["k_max"],
        "f_max": FR_F_MAX if params.get("f_max") is None else params["f_max"],
    }


def _fr_step_problem(params: dict[str, Any]) -> str | None:
    """Why the given h is too large for model FR's kept modes (None: it is not). Cheap when
    h 2 pi f_max <= 2 (no kept mode is above f_max); otherwise the FR system is built at the
    case's (highest) speed and its highest mode checked exactly (check_modal_step)."""
    sel = _fr_selection(params)
    scale = params.get("coach_wheelset_stiffness_scale") or 1.0
    if params["h"] * 2.0 * np.pi * sel["f_max"] * np.sqrt(scale) <= MODAL_STEP_LIMIT:
        return None
    speed = from_kmh(params["speeds_kmh_max"]) if params["scenario"] == "critical_speed" else params["speed"]
    try:
        coach = _coach(params)
    except InputError:
        return None  # reported by check as a coach problem
    try:
        sy, _ = fr_system(coach, speed=min(speed, MAX_SPEED), **sel)
        check_modal_step(sy, params["h"])
    except InputError as exc:
        return f"model FR: {exc}"
    return None


def _coach(params: dict[str, Any]) -> Coach:
    kw = {k[6:]: v for k, v in params.items() if k.startswith("coach_")}
    return Coach(**kw)


def _dof_unit(name: str, rate: bool) -> str:
    """'m' or 'rad' (per second with rate) of a state name such as 'ws1_y', 'bogie1_roll'."""
    last = name.rsplit("_", 1)[-1]
    if name.startswith("ring_res") and last == "r":
        last = "roll"  # model RF's residual coordinate of the element's roll
    if last in ("x", "y", "z"):
        unit = "m"
    elif last in ("roll", "pitch", "yaw", "beta"):
        unit = "rad"
    else:
        unit = "1"  # modal coordinates: mass-normalised
    return f"{unit}/s" if rate and unit != "1" else unit


def _history(res, data: dict, scalars: dict) -> None:
    nw = res.wheel.shape[-1]
    wheelsets = [f"ws{w + 1}" for w in range(nw)]
    names = list(res.dof_names)
    data["t"] = (res.t, "s", {"axes": ["t"]})
    data["q"] = (
        res.q,
        "m or rad (per column: column_units)",
        {"axes": ["t", "state"], "dof_names": names, "column_units": [_dof_unit(n, False) for n in names]},
    )
    data["v"] = (
        res.v,
        "m/s or rad/s (per column: column_units)",
        {"axes": ["t", "state"], "dof_names": names, "column_units": [_dof_unit(n, True) for n in names]},
    )
    data["y_ws1"] = (res.y_ws1, "m", {"axes": ["t"]})
    data["vy_ws1"] = (res.vy_ws1, "m/s", {"axes": ["t"]})
    per_wheel = {"axes": ["t", "wheel", "wheelset"], "wheel": WHEEL_SIDES, "wheelset": wheelsets}
    for i, name in enumerate(WHEEL_OUTPUTS):
        data[f"wheel_{name}"] = (res.wheel[:, i], WHEEL_UNITS.get(name, "1"), per_wheel)
    for k, v in res.stats.items():
        scalars[f"stat_{k}"] = (v, STAT_UNITS.get(k, "1"))
    ws = res.wheels()
    last = {"over": f"the last {ws.window:g} s"}
    data["ws_y"] = (
        np.stack([res.dof(f"ws{w + 1}_y") for w in range(nw)], 1),
        "m",
        {"axes": ["t", "wheelset"], "wheelset": wheelsets},
    )
    data["wheel_amplitude"] = (ws.amplitude, "m", {"axes": ["wheelset"], "wheelset": wheelsets, **last})
    per_wheel_max = {"axes": ["wheel", "wheelset"], "wheel": WHEEL_SIDES, "wheelset": wheelsets, **last}
    data["wheel_Q_max"] = (ws.Q_max, "N", per_wheel_max)
    data["wheel_Y_max"] = (ws.Y_max, "N", per_wheel_max)
    data["wheel_YQ_max"] = (ws.YQ_max, "1", per_wheel_max)
    scalars["nadal_limit"] = (ws.nadal, "1")
    scalars["flange_angle"] = (ws.flange_angle, "rad")
    scalars["friction"] = (ws.friction, "1")
    scalars["exceeds_nadal"] = (int(ws.exceeds_nadal), "1 (flag: 1 = a wheel above Nadal's limit)")
    return ws.line()


def _fr_history(res, system, layouts, data: dict, stop: int | None = None) -> None:
    """Model FR: the modal coordinates with their mode labels and the rims' deformation at
    the contact points (railvti.vehicle.flexible_points.rim_deformation, rim_camber_change,
    rail_head_roll on the ring, rim_rail_angle_change: the relative angle);
    ``stop``: the state's end of the wheelsets' coordinates (model FF: the ring's follow)."""
    n = system.n
    stop = system.n_state if stop is None else stop
    nm = stop - n
    labels = list(mode_labels(system, layouts))[:nm]
    k = np.full(nm, -1)
    fam = np.full(nm, "residual", dtype=object)
    freq = np.full(nm, np.nan)
    units = ["m"] * nm  # residual coordinates: point displacements, m
    for lay in layouts:
        i = slice(lay.modes.start - n, lay.modes.stop - n)
        k[i], fam[i], freq[i] = lay.k, lay.family, lay.freq_hz
        units[i] = ["kg^0.5 m"] * (i.stop - i.start)  # mass-normalised (M = I)
    mode = {"axes": ["mode"], "mode_label": labels}
    data["mode_label"] = (np.array(labels, dtype=object), "text", {"axes": ["mode"]})
    data["mode_k"] = (
        k,
        "1",
        {**mode, "meaning": "circumferential harmonic (-1: residual flexibility's massless coordinate)"},
    )
    data["mode_family"] = (
        np.array([str(f) for f in fam], dtype=object),
        "text",
        {**mode, "meaning": "'0' (k = 0), 'A' or 'B' (k > 0), 'residual'"},
    )
    data["mode_frequency"] = (
        freq,
        "Hz",
        {**mode, "meaning": "free-free non-rotating natural frequency (NaN: residual)"},
    )
    data["modal_q"] = (
        res.q[:, n:stop],
        "kg^0.5 m or m (per column: column_units)",
        {"axes": ["t", "mode"], "mode_label": labels, "column_units": units},
    )
    per = {
        "axes": ["t", "component", "wheel", "wheelset"],
        "component": ["dy", "dz", "drx"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(4)],
        "column_units": ["m", "m", "rad"],
        "meaning": "rim deformation at the contact points (taping line), track axes",
    }
    data["rim_deformation"] = (rim_deformation(system, res.q), "m, m, rad (per component)", per)
    per_w = {
        "axes": ["t", "wheel", "wheelset"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(4)],
    }
    inner = (
        "+: the inner edge, towards the track centre, rises; -drx on the left wheel, +drx "
        "on the right, drx about the vehicle's x, y positive to the left"
    )
    camber = rim_camber_change(system, res.q)
    roll = rail_head_roll(system, res.q, res.t)
    data["rim_camber_change"] = (
        camber,
        "rad",
        {**per_w, "meaning": "elastic camber of the rim at the contact point (" + inner + ")"},
    )
    if getattr(system, "ring", None) is not None:
        data["rail_head_roll"] = (
            roll,
            "rad",
            {
                **per_w,
                "meaning": "elastic roll of the rail head "
                "under the wheel from the ring's modes (" + inner + ")",
            },
        )
    data["rim_rail_angle_change"] = (
        camber - roll,
        "rad",
        {
            **per_w,
            "meaning": "change of the rim-rail relative angle: rim_camber_change minus the "
            "rail head's roll under the wheel (rail_head_roll; 0 on the rigid "
            "track of model FR) (" + inner + ")",
        },
    )


def _ring_history(res, system, data: dict, prefix: str = "") -> None:
    """Model RF: the ring's modal coordinates with their labels and the rail's motion under
    each wheel (RingSystem.rail_deflection; the crown's vertical displacement beside it);
    the mode datasets' names get ``prefix`` (model FF: 'ring_', beside the wheelsets')."""
    ring = system.ring
    n0 = system.n_state - ring.n_modes - ring.n_residual
    labels = list(system.state_names[n0:])
    mb = system.modal
    nm = ring.n_modes
    om = np.sqrt([float(mb.stiffness[i][0, 0]) for i in range(nm)])
    freq = np.concatenate([om / (2 * np.pi), np.full(ring.n_residual, np.nan)])
    zeta = np.concatenate(
        [[float(mb.damping[i][0, 0]) / (2 * o) for i, o in enumerate(om)], np.full(ring.n_residual, np.nan)]
    )
    group = np.array([int(n.split("_")[1][1:]) if n.startswith("ring_g") else -1 for n in labels])
    units = ["kg^0.5 m"] * nm + [("rad" if n.endswith("_r") else "m") for n in labels[nm:]]
    mode = {"axes": ["mode"], "mode_label": labels}
    data[prefix + "mode_label"] = (np.array(labels, dtype=object), "text", {"axes": ["mode"]})
    data[prefix + "mode_group"] = (
        group,
        "1",
        {
            **mode,
            "meaning": "cyclic group j of the ring mode (its "
            "sleeper-pattern wave number; -1: a residual "
            "flexibility coordinate)",
        },
    )
    data[prefix + "mode_frequency"] = (
        freq,
        "Hz",
        {**mode, "meaning": "natural frequency of the ring mode (NaN: residual)"},
    )
    data[prefix + "mode_damping_ratio"] = (
        zeta,
        "1",
        {**mode, "meaning": "modal damping ratio (NaN: residual)"},
    )
    data[prefix + "modal_q"] = (
        res.q[:, n0:],
        "kg^0.5 m, m or rad (per column: column_units)",
        {
            "axes": ["t", "mode"],
            "mode_label": labels,
            "column_units": units,
            "meaning": "ring modes (mass-normalised), then per wheel the residual "
            "flexibility's coordinates (y, z, roll of the element pose)",
        },
    )
    rail = system.rail_deflection(res.t, res.q)  # (nt, 3, 2, nw)
    nw = rail.shape[-1]
    per = {
        "axes": ["t", "component", "wheel", "wheelset"],
        "component": ["y", "z", "roll"],
        "wheel": WHEEL_SIDES,
        "wheelset": [f"ws{w + 1}" for w in range(nw)],
        "column_units": ["m", "m", "rad"],
        "meaning": "rail head's motion under each wheel: the pose (y, z, roll; vehicle frame, y "
        "to the left) of the track element under the wheel, from the ring's modes",
    }
    data["rail_deflection"] = (rail, "m, m, rad (per component)", per)
    half = 0.5 * ring.rail_distance
    crown = rail[:, 1] + np.array([half, -half])[:, None] * rail[:, 2]
    data["rail_crown_z"] = (
        crown,
        "m",
        {
            "axes": ["t", "wheel", "wheelset"],
            "wheel": WHEEL_SIDES,
            "wheelset": [f"ws{w + 1}" for w in range(nw)],
            "meaning": "vertical displacement of the rail crown under each wheel (+ up)",
        },
    )


def _modal_histories(res, sy, layouts: list, fr: dict, ring: dict, data: dict, scalars: dict) -> None:
    """The modal datasets of a run (model FR: the wheelsets'; RF: the ring's; FF: both, the
    ring's prefixed 'ring_') from the system ``sy`` the run used and its FR ``layouts``
    (nothing is rebuilt to label them)."""
    if fr:
        stop = sy.n_state - (sy.ring.n_modes + sy.ring.n_residual if ring else 0)
        _fr_history(res, sy, layouts, data, stop=stop)
    if ring:
        _ring_history(res, sy, data, prefix="ring_" if fr else "")
        scalars["n_ring_modes"] = (int(sy.ring.n_modes), "1")


def _stream_derived() -> dict:
    """The full-length datasets of :func:`_history` computed from each block of a streamed
    history (railvti.runner.stream), so that a streamed case stores what an in-memory one does."""

    def col(src: str, name: str):
        return lambda b, a: b[src][:, list(a["q"]["dof_names"]).index(name)]

    def ws_y(b, a):
        names = list(a["q"]["dof_names"])
        return b["q"][:, [names.index(f"ws{w + 1}_y") for w in range(b["wheel"].shape[-1])]]

    out = {"y_ws1": col("q", "ws1_y"), "vy_ws1": col("v", "ws1_y"), "ws_y": ws_y}
    out.update({f"wheel_{n}": (lambda b, a, i=i: b["wheel"][:, i]) for i, n in enumerate(WHEEL_OUTPUTS)})
    return out


def _patch(pt, data: dict, scalars: dict) -> None:
    """The leading wheelset's right contact patch (FASTSIM on the Hertz ellipse, or the BEM
    fields with contact='bem')."""
    for name, unit in (
        ("x", "m"),
        ("y", "m"),
        ("pressure", "Pa"),
        ("tx", "Pa"),
        ("ty", "Pa"),
        ("power_density", "W/m^2"),
    ):
        data[f"patch_{name}"] = (
            np.asarray(getattr(pt, name)),
            unit,
            {
                "axes": ["x (rolling)", "y (lateral, contact frame)"],
                "wheel": "right wheel of the leading wheelset",
            },
        )
    scalars["patch_power"] = (float(pt.power), "W")
    scalars["patch_a"] = (float(pt.a), "m")
    scalars["patch_b"] = (float(pt.b), "m")


def _estimated_output_dt(scen: str, speed: float) -> float:
    """The default output interval of a case on the rigid track (RR, FR), for the size of
    its history (whether to stream it): the scenario's, shortened for hunting at Klingel's
    frequency (railvti.vehicle.output; the run rounds it to its step)."""
    f = output.hunting(speed, hunting_conicity(), COACH_DEFAULTS["wheel_radius"][0])
    return output.default_interval([f], 1e-9, 0.01 if scen == "centred_running" else 0.002)


def run(params: dict[str, Any]) -> CaseOutput:
    """Run one vehicle scenario (keys: see the module docstring)."""

    params = validate("vehicle", params)
    speed = float(params["speed"])
    kmh = kmh_label(speed)  # the label: km/h as given, to 1e-9
    scen = str(params["scenario"])
    if scen not in _SCENARIOS:
        raise InputError(f"scenario must be one of {_SCENARIOS}, got {scen!r}")
    coach = _coach(params)
    model, contact = str(params["model"]), str(params["contact"])
    geometry = resolve_geometry(contact, params["geometry"])
    data: dict[str, tuple[np.ndarray, str]] = {}
    scalars: dict[str, tuple[Any, str]] = {
        "scenario": (scen, "text"),
        "model": (model, "text"),
        "contact": (contact, "text"),
        "geometry": (geometry, "text"),
    }
    fr = _fr_selection(params) if model in FLEXIBLE_WHEELSETS else {}
    if fr:
        scalars["k_max"] = (int(fr["k_max"]), "1")
        scalars["f_max"] = (float(fr["f_max"]), "Hz")
    ring = _ring_selection(params) if model in RING_TRACK else {}
    if ring:
        scalars["n_sleepers"] = (ring["n_sleepers"], "1")
        scalars["f_limit"] = (ring["f_limit"], "Hz")
        scalars["x_offset"] = (ring["x_offset"], "m")
    # a long history streams to the runner's file (railvti.runner.stream; docs/results.md); models FR
    # and RF keep their history in memory (their modal datasets are derived from the whole run)
    out_dt = params["output_dt"] or _estimated_output_dt(scen, params["speed"])
    stream = (
        case_sink(history_bytes(params["duration"], out_dt), store=("t", "q", "v"), derived=_stream_derived())
        if scen != "critical_speed" and not fr and not ring
        else None
    )
    if scen == "centred_running":
        c = centred_running(
            model=model,
            contact=contact,
            speed=speed,
            duration=params["duration"],
            h=params["h"],
            coach=coach,
            stream_to=stream,
            geometry=geometry,
            output_dt=params["output_dt"],
            **fr,
            **ring,
        )
        wl = _history(c.run, data, scalars)
        _modal_histories(c.run, c.system, c.layouts, fr, ring, data, scalars)
        final_data, final_scalars = c.case_data()
        data.update(final_data)
        scalars.update(final_scalars)
        if c.patch is not None:
            _patch(c.patch, data, scalars)
            scalars["patch_time"] = (float(c.run.t[-1]), "s")
        summary = (
            f"centred running {kmh:g} km/h ({contact}): Q within "
            f"{c.q_error:.2e} of the static load {c.static_wheel_load:.0f} N; {wl}"
        )
    elif scen == "hunting":
        r, sy, layouts = hunting(
            model=model,
            contact=contact,
            speed=speed,
            duration=params["duration"],
            y0=params["y0"],
            h=params["h"],
            alpha=params["alpha"],
            output_dt=params["output_dt"],
            coach=coach,
            stream_to=stream,
            geometry=geometry,
            return_system=True,
            **fr,
            **ring,
        )
        wl = _history(r, data, scalars)
        _modal_histories(r, sy, layouts, fr, ring, data, scalars)
        nright = r.wheel_output("N_tread")[:, 1, 0] + r.wheel_output("N_flange")[:, 1, 0]
        k = int(np.argmax(nright))
        if r.bem_patches is not None:
            k = -1  # BEM fields: the final state's
            pt = r.bem_patches.get((0, 1))
        else:
            pt = contact_patch(sy, r, k, wheel=1, wheelset=0)
        if pt is not None:
            _patch(pt, data, scalars)
            scalars["patch_time"] = (float(r.t[k]), "s")
        amp = amplitude(r)
        scalars["amplitude_last_second"] = (amp, "m")
        scalars["speed_kmh"] = (kmh, "km/h")
        window = (
            "the last second"
            if params["duration"] > AMPLITUDE_WINDOW
            else f"the whole {params['duration']:g} s run (shorter than the 1 s window)"
        )
        summary = (
            f"hunting {kmh:g} km/h ({contact}): leading wheelset amplitude "
            f"{amp * 1e3:.2f} mm over {window}, RTF {r.stats['real_time_factor']:.3f}; "
            f"{wl}"
        )
    else:
        sp = np.arange(
            float(params["speeds_kmh_min"]),
            float(params["speeds_kmh_max"]) + 1e-9,
            float(params["speeds_kmh_step"]),
        )
        b = bifurcation(
            sp,
            model,
            contact,
            duration=params["duration"],
            h=params["h"],
            coach=coach,
            progress=False,
            geometry=geometry,
            output_dt=params["output_dt"],
            **fr,
            **ring,
        )
        lin, freq = linear_critical_speed(model, coach, **fr, **ring)
        sweep_data, sweep_scalars = b.case_data(steps=bool(fr))
        data.update(sweep_data)
        scalars.update(sweep_scalars)
        scalars["critical_speed_linear"] = (lin, "km/h")
        scalars["hunting_frequency_linear"] = (freq, "Hz")
        scalars["linear_yaw_damper_state"] = (DAMPER_STATES["stuck"], "")
        summary = (
            f"critical speed ({contact}): {b.message}; flange-contact cycle from "
            f"{b.flange_kmh:.0f} km/h; linear {lin:.0f} km/h (yaw damper stuck)"
        )
    if stream is not None:
        data = stream.substitute(data)
    data, labels = split_labels(data)
    for name, meaning in NAN_MEANINGS.items():  # NaN as "none found", said in the file
        if name in scalars:
            labels.setdefault(name, {})["nan"] = meaning
    return CaseOutput(summary=summary, datasets=data, scalars=scalars, attrs=labels)


#: What NaN (or inf) means in the scalars of a critical_speed case: "none found", not a
#: failed computation (the ``nan`` attribute of each in the results file).
NAN_MEANINGS = {
    "critical_speed_nonlinear": "NaN: no sustained limit cycle found in the sweep: see no_decay_below_kmh "
    "(the cycle lived down to there) and no_cycle_up_to_kmh (none up to the top)",
    "no_decay_below_kmh": "NaN: the limit cycle died within the sweep (critical_speed_nonlinear holds it)",
    "no_cycle_up_to_kmh": "NaN: a limit cycle was sustained within the sweep",
    "flange_hunting_speed": "NaN: no speed of the upper branch had a flange-contact cycle",
    "critical_branch_amplitude": "NaN: no critical speed, so no cycle to measure",
    "critical_speed_linear": "inf: the centred running is stable up to the top of the search",
    "hunting_frequency_linear": "NaN: no unstable hunting mode up to the top of the search",
}


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Time histories and phase portrait (hunting / centred running) or the bifurcation diagram."""

    res = group["results"] if "results" in group else group
    outdir = Path(outdir)
    if "speeds_kmh" in res:
        return [
            plot_bifurcation(
                np.asarray(res["speeds_kmh"]),
                np.asarray(res["upper_amplitude"]),
                np.asarray(res["decay_amplitude"]),
                _scalar(res, "critical_speed_linear"),
                outdir / f"{stem}_bifurcation.png",
                title=_sweep_title(group, res),
                critical_kmh=_scalar(res, "critical_speed_nonlinear"),
            )
        ]
    title = _run_title(res)
    if str(group.attrs.get("status", "ok")).startswith("interrupted") and len(res["t"]):
        title += f"; INTERRUPTED at t = {float(res['t'][-1]):.3g} s"  # what the case kept
    paths = plot_history(
        np.asarray(res["t"]),
        np.asarray(res["y_ws1"]),
        np.asarray(res["vy_ws1"]),
        np.asarray(res["wheel_Q"]),
        np.asarray(res["wheel_Y"]),
        outdir,
        stem,
        title,
    )
    if "ws_y" in res:
        paths.append(
            plot_wheels(
                np.asarray(res["t"]),
                np.asarray(res["ws_y"]),
                np.asarray(res["wheel_Q"]),
                np.asarray(res["wheel_Y"]),
                _scalar(res, "nadal_limit"),
                outdir / f"{stem}_wheels.png",
                title,
            )
        )
    if "patch_pressure" in res:
        paths.append(
            plot_patch(
                *(np.asarray(res[f"patch_{k}"]) for k in ("x", "y", "pressure", "tx", "ty", "power_density")),
                outdir / f"{stem}_patch.png",
                f"leading wheelset, right wheel, t = {_scalar(res, 'patch_time'):.3g} s: {_run_title(res)}",
            )
        )
    return paths


register(
    CaseType(
        name="vehicle",
        defaults=DEFAULTS,
        run=run,
        plot=plot,
        keys=KEYS,
        check=check,
        aliases=ALIASES,
        summary="coach on track in time: centred running, hunting, critical speed",
    )
)


def _scalar(res: Any, key: str) -> float:
    """A scalar result stored as a dataset or an attribute; NaN when absent."""
    if key in res:
        return float(np.asarray(res[key]))
    return float(res.attrs.get(key, np.nan))


def _text(res: Any, key: str) -> str:
    """A text result, else the case's input of that name (an interrupted case stores no
    scenario, model...: its inputs say them), else ''."""
    if key not in res:
        inputs = res["inputs"] if "inputs" in res else None
        if inputs is None or key not in inputs:
            return ""
        res = inputs
    v = np.asarray(res[key]).item()
    return v.decode() if isinstance(v, bytes) else str(v)


def _sweep_title(group: Any, res: Any) -> str:
    """'NAME: critical speed, model RR, hertz-fastsim (table)' of a critical_speed result."""
    name = group.attrs.get("name", "")
    name = name.decode() if isinstance(name, bytes) else str(name)
    geometry = _text(res, "geometry")
    parts = [
        "critical speed",
        f"model {_text(res, 'model')}",
        _text(res, "contact") + (f" ({geometry})" if geometry else ""),
    ]
    return (f"{name}: " if name else "") + ", ".join(p for p in parts if p.strip())


def _run_title(res: Any) -> str:
    """'hunting, 420 km/h, model RR, hertz-fastsim' from a result group ('... on the strips'
    with the strip contact geometry)."""
    parts = [_text(res, "scenario")]
    speed = _scalar(res, "speed_kmh")
    if not np.isfinite(speed) and "inputs" in res and "speed" in res["inputs"]:
        try:  # the deck's speed, m/s (a case stores no speed_kmh)
            speed = to_kmh(float(np.asarray(res["inputs"]["speed"])))
        except (TypeError, ValueError):
            pass
    if np.isfinite(speed):
        parts.append(f"{speed:.0f} km/h")
    model, contact = _text(res, "model"), _text(res, "contact")
    geometry = _text(res, "geometry")
    parts += [
        f"model {model}" if model else "",
        f"{contact} on the strips" if geometry == "strip" else contact,
    ]
    return ", ".join(p for p in parts if p)
