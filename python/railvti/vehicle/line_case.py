"""Deck case type ``line``: the coach over a line, an irregular track with or without a curve,
at its line speed, with the standards' assessment of the run (issue 34).

Keys (SI; ``railvti cases line`` lists them with units and bounds): model ('RR', 'FR', 'RF',
'FF'; each with or without a curve), contact, speed (m/s; or speed_kmh), route_length (m: the
irregularity's extent from x = 0), irregularity (a standard spectrum of
railvti.track.IRREGULARITY_SPECTRA, 'file' to read irregularity_file, or 'none'),
irregularity_seed, irregularity_band (shortest and longest wavelength, m), curve_radius (m,
+ left, - right; 0: no curve), curve_cant (m), curve_transition (m, each clothoid),
curve_arc (m), curve_start (m), output_dt (s), max_duration (s).

Results: the run's history (as the vehicle case's), the irregularity's source, the curve, the
rails' inputs under the wheels (``track_input``), the position along the track ``x``, and the
assessment (railvti.assessment: ``assess_KEY`` rows with limits, sources and verdicts, and the
flag ``assessment_passed`` carrying the one-screen table). Plots: the line's inputs and the
wheel forces over the position.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..assessment import assess
from .._checks import KMH_PER_M_S, MAX_SPEED, from_kmh
from .._plotting import pyplot
from ..casetypes import Alias, CaseOutput, CaseType, Key, register, split_labels, validate
from ..track.curve import TrackCurve
from ..track.irregularity_file import read_csv
from ..track.irregularity_spectra import SPECTRA, generate
from ..track.irregularity import TrackIrregularity
from .contact_models import CONTACT_MODELS
from .cases import stored_scalar
from .line_running import line_run
from .systems import VARIANTS

__all__ = ["DEFAULTS", "KEYS", "run", "plot"]

DEFAULTS: dict[str, Any] = {
    "model": "RR",
    "contact": "hertz-fastsim",
    "speed": from_kmh(200.0),
    "route_length": 1000.0,
    "irregularity": "erri-b176-low",
    "irregularity_file": None,
    "irregularity_seed": 1,
    "irregularity_band": [3.0, 70.0],
    "curve_radius": 0.0,
    "curve_cant": 0.0,
    "curve_transition": 100.0,
    "curve_arc": 300.0,
    "curve_start": 400.0,
    "output_dt": None,
    "max_duration": 600.0,
}

KEYS: dict[str, Key] = {
    "model": Key("", "'RR', 'FR', 'RF' or 'FF' (each with or without a curve)", "str", choices=VARIANTS),
    "contact": Key("", "wheel-rail contact model", "str", choices=tuple(CONTACT_MODELS)),
    "speed": Key(
        "m/s",
        "line speed (or speed_kmh, km/h)",
        lo=0.0,
        hi=MAX_SPEED,
        lo_open=True,
        why="the fastest wheel-on-rail run was 575 km/h",
    ),
    "route_length": Key(
        "m", "length of the line from x = 0", lo=50.0, hi=20000.0, why="at most 20 km per case"
    ),
    "irregularity": Key(
        "",
        "standard spectrum of the irregularity, 'file' (irregularity_file) or 'none'",
        "str",
        choices=tuple(SPECTRA) + ("file", "none"),
    ),
    "irregularity_file": Key(
        "", "CSV file of a measured irregularity (irregularity = 'file')", "str", optional=True
    ),
    "irregularity_seed": Key("1", "seed of the generated irregularity", "int", 0, 2**31 - 1),
    "irregularity_band": Key(
        "m", "shortest and longest wavelength of the generated irregularity", "floats", lo=0.1, hi=1000.0
    ),
    "curve_radius": Key("m", "radius of the curve's arc, + left, - right (0: no curve)", lo=-1e5, hi=1e5),
    "curve_cant": Key("m", "cant of the arc", lo=0.0, hi=0.2, why="EN 13803's largest cant"),
    "curve_transition": Key("m", "length of each clothoid", lo=0.0, hi=1000.0),
    "curve_arc": Key("m", "length of the arc", lo=0.0, hi=20000.0),
    "curve_start": Key("m", "where the entry clothoid begins", lo=0.0, hi=20000.0),
    "output_dt": Key(
        "s",
        "interval of the stored history (default: 10 ms, shortened for the sleeper passing and hunting)",
        lo=0.0,
        hi=1.0,
        lo_open=True,
        optional=True,
    ),
    "max_duration": Key("s", "largest simulated time accepted", lo=0.0, hi=86400.0, lo_open=True),
}
ALIASES = {"speed_kmh": Alias("speed", deprecated=False, unit="km/h", divisor=KMH_PER_M_S)}


def check(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'line' case: the band, the file, the curve and the duration."""
    out = []
    band = params["irregularity_band"]
    if not isinstance(band, (list, tuple)) or len(band) != 2 or not band[0] < band[1]:
        out.append(f"irregularity_band = {band!r}: two wavelengths, shortest first (m)")
    if (params["irregularity"] == "file") != (params["irregularity_file"] is not None):
        out.append("irregularity_file is given exactly when irregularity = 'file'")
    r = params["curve_radius"]
    if r != 0.0:
        if abs(r) < 100.0:
            out.append(f"curve_radius = {r:g} m: |R| >= 100 m (0: no curve)")
        end = params["curve_start"] + 2 * params["curve_transition"] + params["curve_arc"]
        if end > params["route_length"]:
            out.append(f"the curve ends at {end:g} m, beyond route_length = {params['route_length']:g} m")
    duration = params["route_length"] / params["speed"]
    if duration > params["max_duration"]:
        out.append(f"the line takes {duration:g} s, above max_duration = {params['max_duration']:g} s")
    return out


def _text(res: Any, key: str) -> str:
    """A text scalar of a stored case ('' when absent)."""
    v = np.asarray(res[key])[()] if key in res else res.attrs.get(key, "")
    return v.decode() if isinstance(v, bytes) else str(v)


def _irregularity(params: dict[str, Any]) -> TrackIrregularity:
    """The case's irregularity over 0 .. route_length (zero channels for 'none')."""
    length = float(params["route_length"])
    kind = str(params["irregularity"])
    if kind == "file":
        return read_csv(Path(params["irregularity_file"]))
    if kind == "none":
        x = np.linspace(0.0, length, int(length / 0.25) + 1)
        z = np.zeros_like(x)
        return TrackIrregularity(x, z, z, z, z, source="none (perfect track)")
    lo, hi = (float(b) for b in params["irregularity_band"])
    return generate(kind, length, seed=int(params["irregularity_seed"]), band=(lo, hi))


def _curve(params: dict[str, Any]) -> TrackCurve | None:
    if params["curve_radius"] == 0.0:
        return None
    return TrackCurve(
        radius=float(params["curve_radius"]),
        cant=float(params["curve_cant"]),
        transition_in=float(params["curve_transition"]),
        arc_length=float(params["curve_arc"]),
        transition_out=float(params["curve_transition"]),
        start=float(params["curve_start"]),
    )


def run(params: dict[str, Any]) -> CaseOutput:
    """Run one line case (keys: the module docstring)."""
    params = validate("line", params)
    irr = _irregularity(params)
    curve = _curve(params)
    lr = line_run(
        speed=float(params["speed"]),
        irregularity=irr,
        curve=curve,
        variant=str(params["model"]),
        contact=str(params["contact"]),
        output_dt=params["output_dt"],
        progress=False,
    )
    r = lr.run
    data, scalars = r.case_data()
    data = dict(data)
    scalars = dict(scalars)
    data["x"] = (
        lr.position(),
        "m",
        {"axes": ["t"], "meaning": "the coach's reference (carbody centre) along the track"},
    )
    scalars["model"] = (str(params["model"]), "text")
    scalars["contact"] = (r.contact, "text")
    scalars["x_start"] = (lr.x_start, "m")
    scalars["speed"] = (r.speed, "m/s")
    if curve is not None:
        for k in ("radius", "cant", "transition_in", "arc_length", "start"):
            scalars[f"curve_{k}"] = (getattr(curve, k), "m")
        scalars["cant_deficiency"] = (curve.cant_deficiency(r.speed), "m")
    a = assess(r, coach=lr.coach)
    data.update(a.case_data())
    data["assessment_passed"] = (np.int64(a.passed), "1 (flag: 1 = no row fails)", {"table": a.table()})
    where = (
        f" into R {curve.radius:g} m (deficiency {1e3 * curve.cant_deficiency(r.speed):.0f} mm)"
        if curve
        else ""
    )
    summary = (
        f"line {r.speed * KMH_PER_M_S:.0f} km/h, {params['route_length']:g} m of {params['irregularity']}"
        f"{where}: assessment {'passed' if a.passed else 'FAILED'}; {r.wheels().line()}"
    )
    data, labels = split_labels(data)
    return CaseOutput(summary=summary, datasets=data, scalars=scalars, attrs=labels)


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """The line's inputs and the wheel forces over the position along the track."""
    res = group["results"] if "results" in group else group
    x = np.asarray(res["x"])
    q = np.asarray(res["wheel_Q"]) / 1e3
    y = np.asarray(res["wheel_Y"]) / 1e3
    plt = pyplot()
    fig, ax = plt.subplots(4, 1, figsize=(12, 11), sharex=True)
    if "track_input" in res:
        ti = np.asarray(res["track_input"])
        ax[0].plot(x, 1e3 * ti[:, 1, 0, 0], lw=0.8, label="rail height under wheelset 1, left")
        ax[0].plot(x, 1e3 * ti[:, 0, 0, 0], lw=0.8, label="rail lateral position, left")
    ax[0].set_ylabel("mm")
    ax[0].set_title("track input under the leading wheelset")
    for k, side in enumerate(("left", "right")):
        ax[1].plot(x, q[:, k, 0], lw=0.8, label=f"Q wheelset 1 {side}")
        ax[2].plot(x, y[:, k, 0], lw=0.8, label=f"Y wheelset 1 {side}")
    ax[1].set_ylabel("Q, kN")
    ax[2].set_ylabel("Y, kN")
    ax[3].plot(x, y.sum(axis=1)[:, 0], lw=0.8, label="sum Y wheelset 1")
    ax[3].plot(x, y.sum(axis=1)[:, 3], lw=0.8, label="sum Y wheelset 4")
    p0 = 2.0 * float(q[0].mean())  # the static axle load, kN (the run starts at rest on perfect track)
    for sign in (1, -1):
        ax[3].axhline(sign * (10.0 + p0 / 3.0), color="r", lw=0.8, ls="--")
    ax[3].plot([], [], "r--", lw=0.8, label=f"Prud'homme limit 10 kN + P0/3 = {10 + p0 / 3:.1f} kN")
    ax[3].set_ylabel("sum Y, kN")
    ax[3].set_xlabel("position of the carbody's centre along the track, m")

    start = stored_scalar(res, "curve_start")
    curved = bool(np.isfinite(start))
    for a in ax:
        if curved:  # the curve: clothoid, arc, clothoid
            end = (
                start + 2 * stored_scalar(res, "curve_transition_in") + stored_scalar(res, "curve_arc_length")
            )
            a.axvspan(start, end, color="0.9", zorder=0)
        a.legend(fontsize=8, loc="upper right")
        a.grid(alpha=0.3)
    if curved:
        ax[0].set_title(
            "track input under the leading wheelset "
            f"(grey: the curve, R {stored_scalar(res, 'curve_radius'):g} m)"
        )
    fig.suptitle(
        f"line: model {_text(res, 'model')}, {_text(res, 'contact')}, "
        f"{stored_scalar(res, 'speed') * KMH_PER_M_S:.0f} km/h, {_text(res, 'irregularity').split(';')[0]}"
    )
    fig.tight_layout()
    out = Path(outdir) / f"{stem}_line.png"
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return [out]


register(
    CaseType(
        name="line",
        defaults=DEFAULTS,
        run=run,
        plot=plot,
        keys=KEYS,
        check=check,
        aliases=ALIASES,
        summary="coach over a line: irregular track (spectrum or file) into a curve, with the assessment",
    )
)
