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

Hunting and centred running also store the run's assessment (railvti.assessment, docs/
assessment.md): datasets ``assess_KEY`` with units and the labels limit, limit_source,
verdict, and the flag ``assessment_passed`` with the text table as its label ``table``.

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

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from .._checks import to_kmh
from ..assessment import assess
from ..casetypes import CaseOutput, CaseType, case_sink, history_bytes, register, split_labels, validate
from ..errors import InputError
from .bifurcation import AMPLITUDE_WINDOW, amplitude, bifurcation
from .linear_stability import DAMPER_STATES, linear_critical
from .plots import plot_bifurcation, plot_history, plot_patch, plot_wheels
from .params import DEFAULTS as COACH_DEFAULTS
from . import output
from .running import centred_running, contact_patch, hunting
from .scenario_results import kmh_label
from .systems import FLEXIBLE_WHEELSETS, RING_TRACK, hunting_conicity, resolve_geometry
from .deck_datasets import modal_datasets, patch_datasets, stream_derived
from .deck_keys import ALIASES, DEFAULTS, KEYS, SCENARIOS, check, coach_from, fr_selection, ring_selection

__all__ = ["DEFAULTS", "KEYS", "ALIASES", "NAN_MEANINGS", "check", "run", "plot", "stored_scalar"]


def _add(part: tuple[dict, dict], data: dict, scalars: dict) -> None:
    """Add a result's part of the results file, (datasets, scalars), to the case's."""
    data.update(part[0])
    scalars.update(part[1])


def _add_assessment(run: Any, coach: Any, data: dict, scalars: dict, stream: Any = None) -> None:
    """The run's assessment (railvti.assessment.assess: EN 14363, EN 12299, Sperling) as
    datasets ``assess_KEY`` (value, unit; labels: limit, limit_source, verdict, ...) and the
    flag ``assessment_passed`` carrying the text table as its label ``table``. A streamed
    run is assessed from its sink's whole history (the bodies' velocities and the wheel
    forces only), so it stores what the run kept in memory stores. A run the assessment
    cannot take (too few output times) says why in the scalar ``assessment``: the case
    itself stands."""
    try:
        a = assess(_assessed_history(run, stream), coach=coach)
    except InputError as exc:
        scalars["assessment"] = (f"not evaluated: {exc}", "text")
        return
    data.update(a.case_data())
    data["assessment_passed"] = (np.int64(a.passed), "1 (flag: 1 = no row fails)", {"table": a.table()})


def _assessed_history(run: Any, stream: Any) -> Any:
    """``run`` itself, or for a streamed run the history the assessment reads, from the sink:
    t, the carbody's and bogie frames' q and v, the wheel forces Q and Y."""
    if not run.streamed:
        return run
    if stream is None:
        raise InputError(f"the history was streamed to {run.streamed} and its sink is gone")
    cols = [i for i, n in enumerate(run.dof_names) if n.startswith(("carbody_", "bogie"))]
    wheel = np.stack([stream.read("wheel_Q"), stream.read("wheel_Y")], axis=1)  # Q, Y: rows 0, 1
    return replace(
        run,
        t=stream.read("t"),
        q=stream.read("q", cols),
        v=stream.read("v", cols),
        wheel=wheel,
        dof_names=tuple(run.dof_names[i] for i in cols),
        streamed="",
    )


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
    if scen not in SCENARIOS:
        raise InputError(f"scenario must be one of {SCENARIOS}, got {scen!r}")
    coach = coach_from(params)
    variant, contact = str(params["model"]), str(params["contact"])
    geometry = resolve_geometry(contact, params["geometry"])
    data: dict[str, tuple[np.ndarray, str]] = {}
    scalars: dict[str, tuple[Any, str]] = {
        "scenario": (scen, "text"),
        "model": (variant, "text"),
        "contact": (contact, "text"),
        "geometry": (geometry, "text"),
    }
    fr = fr_selection(params) if variant in FLEXIBLE_WHEELSETS else {}
    if fr:
        scalars["k_max"] = (int(fr["k_max"]), "1")
        scalars["f_max"] = (float(fr["f_max"]), "Hz")
    ring = ring_selection(params) if variant in RING_TRACK else {}
    if ring:
        scalars["n_sleepers"] = (ring["n_sleepers"], "1")
        scalars["f_limit"] = (ring["f_limit"], "Hz")
        scalars["x_offset"] = (ring["x_offset"], "m")
    # a long history streams to the runner's file (railvti.runner.stream; docs/results.md); models FR
    # and RF keep their history in memory (their modal datasets are derived from the whole run)
    out_dt = params["output_dt"] or _estimated_output_dt(scen, params["speed"])
    stream = (
        case_sink(history_bytes(params["duration"], out_dt), store=("t", "q", "v"), derived=stream_derived())
        if scen != "critical_speed" and not fr and not ring
        else None
    )
    if scen == "centred_running":
        c = centred_running(
            variant=variant,
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
        _add(c.run.case_data(), data, scalars)
        _add_assessment(c.run, coach, data, scalars, stream)
        wl = c.run.wheels().line()
        modal_datasets(c.run, c.system, c.layouts, fr, ring, data, scalars)
        _add(c.case_data(), data, scalars)
        if c.patch is not None:
            patch_datasets(c.patch, data, scalars)
            scalars["patch_time"] = (float(c.run.t[-1]), "s")
        summary = (
            f"centred running {kmh:g} km/h ({contact}): Q within "
            f"{c.q_error:.2e} of the static load {c.static_wheel_load:.0f} N; {wl}"
        )
    elif scen == "hunting":
        r, sy, layouts = hunting(
            variant=variant,
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
        _add(r.case_data(), data, scalars)
        _add_assessment(r, coach, data, scalars, stream)
        wl = r.wheels().line()
        modal_datasets(r, sy, layouts, fr, ring, data, scalars)
        nright = r.wheel_output("N_tread")[:, 1, 0] + r.wheel_output("N_flange")[:, 1, 0]
        k = int(np.argmax(nright))
        if r.bem_patches is not None:
            k = -1  # BEM fields: the final state's
            pt = r.bem_patches.get((0, 1))
        else:
            pt = contact_patch(sy, r, k, wheel=1, wheelset=0)
        if pt is not None:
            patch_datasets(pt, data, scalars)
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
            variant,
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
        lin_si, freq = linear_critical(variant, coach, **fr, **ring)
        lin = to_kmh(lin_si)  # the results file's unit for this scalar
        _add(b.case_data(steps=bool(fr)), data, scalars)
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
                stored_scalar(res, "critical_speed_linear"),
                outdir / f"{stem}_bifurcation.png",
                title=_sweep_title(group, res),
                critical_kmh=stored_scalar(res, "critical_speed_nonlinear"),
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
                stored_scalar(res, "nadal_limit"),
                outdir / f"{stem}_wheels.png",
                title,
            )
        )
    if "patch_pressure" in res:
        paths.append(
            plot_patch(
                *(np.asarray(res[f"patch_{k}"]) for k in ("x", "y", "pressure", "tx", "ty", "power_density")),
                outdir / f"{stem}_patch.png",
                f"leading wheelset, right wheel, t = {stored_scalar(res, 'patch_time'):.3g} s: "
                f"{_run_title(res)}",
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


def stored_scalar(res: Any, key: str) -> float:
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
    speed = stored_scalar(res, "speed_kmh")
    if not np.isfinite(speed) and "inputs" in res and "speed" in res["inputs"]:
        try:  # the deck's speed, m/s (a case stores no speed_kmh)
            speed = to_kmh(float(np.asarray(res["inputs"]["speed"])))
        except (TypeError, ValueError):
            pass
    if np.isfinite(speed):
        parts.append(f"{speed:.0f} km/h")
    variant, contact = _text(res, "model"), _text(res, "contact")
    geometry = _text(res, "geometry")
    parts += [
        f"model {variant}" if variant else "",
        f"{contact} on the strips" if geometry == "strip" else contact,
    ]
    return ", ".join(p for p in parts if p)
