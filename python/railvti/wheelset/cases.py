"""Deck case type ``wheelset``: modes per harmonic and the FRF of the rotating
wheelset in its bogie at several speeds."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from .._checks import MAX_SPEED_KMH, from_kmh
from ..casetypes import CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from .geometry import WheelsetGeometry
from .model import PrimarySuspension, Wheelset
from .plots import plot_frf

_GEOMETRY_DEFAULTS = {f.name: f.default for f in fields(WheelsetGeometry)}

DEFAULTS: dict[str, Any] = {
    "k_max": 6,  # highest harmonic
    "f_max": 3000.0,  # Hz, highest mode frequency
    "support": "free",  # modes table: 'free' or 'suspension'
    "speeds_kmh": [0.0, 200.0, 300.0],
    "f_lo": 20.0,  # FRF band, Hz
    "f_hi": 1000.0,
    "n_freq": 800,
    "input": "lateral",
    "output": "lateral",
    "damping_ratio": 0.005,
    "k_longitudinal": PrimarySuspension.longitudinal,
    "k_lateral": PrimarySuspension.lateral,
    "k_vertical": PrimarySuspension.vertical,
    **_GEOMETRY_DEFAULTS,
}


_GEOMETRY_MEANING = {
    "wheel_radius": "nominal rolling radius at the taping line",
    "back_to_back": "distance between the flange backs",
    "rim_width": "axial width of the rim",
    "rim_depth": "radial depth of the rim below the rolling radius",
    "flange_height": "flange height above the rolling radius",
    "flange_width": "flange width at the rim face",
    "web_thickness_hub": "web thickness at the hub",
    "web_thickness_rim": "web thickness at the rim",
    "web_steps": "straight segments of the web's taper",
    "web_offset": "web centre from the rim centre (+ outward)",
    "hub_radius": "hub outer radius",
    "hub_width": "hub axial width",
    "hub_offset": "hub centre from the rim centre",
    "seat_radius": "axle radius at the wheel seats",
    "body_radius": "axle body radius",
    "collar_radius": "axle radius at the collars",
    "journal_radius": "journal radius",
    "journal_spacing": "distance between the journal centres",
    "journal_length": "journal length",
    "contact_offset": "taping line from the inner rim face",
    "young": "steel Young's modulus",
    "poisson": "steel Poisson's ratio",
    "density": "steel density",
    "mesh_size": "element edge in the wheels",
    "axle_mesh_size": "element edge in the axle",
}
_GEOMETRY_UNIT = {"web_steps": "1", "young": "Pa", "poisson": "1", "density": "kg/m^3"}
#: Upper plausibility bounds of the geometry keys (m unless _GEOMETRY_UNIT says; the two
#: offsets within +-this); the rest (web_steps, poisson, mesh sizes) are set in KEYS.
_GEOMETRY_HI = {
    "wheel_radius": 0.8,
    "back_to_back": 1.65,
    "rim_width": 0.3,
    "rim_depth": 0.3,
    "flange_height": 0.1,
    "flange_width": 0.1,
    "web_thickness_hub": 0.2,
    "web_thickness_rim": 0.2,
    "web_offset": 0.2,
    "hub_radius": 0.8,
    "hub_width": 0.5,
    "hub_offset": 0.2,
    "seat_radius": 0.8,
    "body_radius": 0.8,
    "collar_radius": 0.8,
    "journal_radius": 0.8,
    "journal_spacing": 3.0,
    "journal_length": 0.5,
    "contact_offset": 0.3,
    "young": 1e12,
    "density": 3e4,
}
_GEOMETRY_WHY = {
    "wheel_radius": "wheel diameters up to 1.6 m",
    "back_to_back": "narrow 1000 mm to Iberian 1668 mm gauge",
    "journal_spacing": "axleboxes about 2 m apart on a standard-gauge wheelset",
    "young": "steels are about 2.1e11 Pa",
    "density": "steels are about 7850 kg/m^3",
}
#: Units, meanings and bounds of the keys of 'wheelset'.
KEYS: dict[str, Key] = {
    "k_max": Key("1", "highest circumferential harmonic", "int", 0, 30),
    "f_max": Key("Hz", "highest mode frequency", lo=0.0, hi=2e4, lo_open=True),
    "support": Key(
        "", "modes table: 'free' or on the primary 'suspension'", "str", choices=("free", "suspension")
    ),
    "speeds_kmh": Key(
        "km/h",
        "speeds of the FRF (one or more)",
        "floats",
        0.0,
        MAX_SPEED_KMH,
        why="the fastest wheel-on-rail run was 575 km/h",
    ),
    "f_lo": Key("Hz", "lowest FRF frequency", lo=0.0, hi=2e4),
    "f_hi": Key("Hz", "highest FRF frequency", lo=0.0, hi=2e4, lo_open=True),
    "n_freq": Key("1", "FRF frequencies", "int", 2, 1_000_000),
    "input": Key(
        "", "force direction at the contact point", "str", choices=("lateral", "vertical", "longitudinal")
    ),
    "output": Key(
        "",
        "displacement direction at the contact point",
        "str",
        choices=("lateral", "vertical", "longitudinal"),
    ),
    "damping_ratio": Key("1", "modal damping ratio", lo=0.0, hi=1.0, hi_open=True),
    **{
        f"k_{d}": Key(
            "N/m",
            f"primary suspension stiffness, {d}",
            lo=0.0,
            hi=1e2 * getattr(PrimarySuspension, d),
            why="at most two decades above railvti.wheelset.PrimarySuspension's value",
        )
        for d in ("longitudinal", "lateral", "vertical")
    },
    **{
        k: Key(
            _GEOMETRY_UNIT.get(k, "m"),
            _GEOMETRY_MEANING.get(k, k),
            "int" if k == "web_steps" else "float",
            lo=-_GEOMETRY_HI[k] if k in ("web_offset", "hub_offset") else 0.0,
            hi=_GEOMETRY_HI[k],
            lo_open=k != "web_steps",
            why=_GEOMETRY_WHY.get(k, "a railway wheelset's dimensions"),
        )
        for k in _GEOMETRY_DEFAULTS
        if k in _GEOMETRY_HI
    },
    "web_steps": Key("1", _GEOMETRY_MEANING["web_steps"], "int", 1, 100),
    "poisson": Key("1", _GEOMETRY_MEANING["poisson"], lo=0.0, hi=0.5, hi_open=True),
    "mesh_size": Key(
        "m",
        _GEOMETRY_MEANING["mesh_size"],
        lo=0.002,
        hi=0.2,
        why="a finer mesh has hundreds of thousands of elements",
    ),
    "axle_mesh_size": Key(
        "m",
        _GEOMETRY_MEANING["axle_mesh_size"],
        lo=0.002,
        hi=0.5,
        why="a finer mesh has hundreds of thousands of elements",
    ),
}


def check(params: dict[str, Any]) -> list[str]:
    """Consistency of a 'wheelset' case: the band, and the geometry (WheelsetGeometry's checks)."""
    out = []
    if not params["f_lo"] < params["f_hi"]:
        out.append(f"f_lo = {params['f_lo']:g} must be < f_hi = {params['f_hi']:g} (Hz)")
    try:
        WheelsetGeometry(**{k: params[k] for k in _GEOMETRY_DEFAULTS})
    except InputError as exc:
        out.append(f"wheelset geometry: {exc}")
    return out


def run(params: dict[str, Any]) -> CaseOutput:
    """Run a wheelset case (lengths m, stiffness N/m, frequencies Hz, speeds km/h)."""
    params = validate("wheelset", params)
    geo = WheelsetGeometry(**{k: params[k] for k in _GEOMETRY_DEFAULTS})
    susp = PrimarySuspension(params["k_longitudinal"], params["k_lateral"], params["k_vertical"])
    ws = Wheelset(geo, suspension=susp)
    table = ws.modes(params["k_max"], params["f_max"], support=params["support"])
    speeds = np.atleast_1d(np.asarray(params["speeds_kmh"], dtype=float))
    if np.any(~np.isfinite(speeds)) or np.any(speeds < 0):
        raise InputError("speeds_kmh must be finite and >= 0")
    if not 0.0 <= params["f_lo"] < params["f_hi"]:
        raise InputError("need 0 <= f_lo < f_hi")
    freqs = np.linspace(params["f_lo"], params["f_hi"], int(params["n_freq"]))
    h = np.empty((speeds.size, freqs.size), dtype=complex)
    for i, v in enumerate(speeds):
        h[i] = ws.frf(
            freqs,
            from_kmh(v),
            input=params["input"],
            output=params["output"],
            k_max=params["k_max"],
            f_max=params["f_max"],
            damping_ratio=params["damping_ratio"],
        )
    first = {k: table.first(k) for k in (0, 1, 2) if k <= params["k_max"] and np.any(table.k == k)}
    summary = "wheelset: " + ", ".join(f"first k={k} {f:.1f} Hz" for k, f in first.items())
    return CaseOutput(
        summary=summary,
        datasets={
            "mode_k": (table.k, "1"),
            "mode_freq": (table.freq_hz, "Hz"),
            "frf_freq": (freqs, "Hz"),
            "speeds": (speeds, "km/h"),
            "frf_real": (h.real, "m/N"),
            "frf_imag": (h.imag, "m/N"),
        },
        scalars={f"first_k{k}": (f, "Hz") for k, f in first.items()},
        attrs={
            "mode_k": {"axes": ["mode"]},
            "mode_freq": {"axes": ["mode"]},
            "frf_freq": {"axes": ["frf_freq"]},
            "speeds": {"axes": ["speed"]},
            "frf_real": {"axes": ["speeds", "frf_freq"]},
            "frf_imag": {"axes": ["speeds", "frf_freq"]},
        },
    )


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """FRF magnitude at each speed."""
    res = group["results"] if "results" in group else group
    f = res["frf_freq"][()]
    h = res["frf_real"][()] + 1j * res["frf_imag"][()]
    curves = {f"{v:.0f} km/h": h[i] for i, v in enumerate(res["speeds"][()])}
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    return [plot_frf(outdir / f"{stem}_frf.png", f, curves, "wheelset in bogie: contact-point receptance")]


register(
    CaseType(
        name="wheelset",
        defaults=DEFAULTS,
        run=run,
        plot=plot,
        keys=KEYS,
        check=check,
        summary="flexible rotating wheelset (axisymmetric FE): modes per harmonic and FRF",
    )
)

__all__ = ["DEFAULTS", "KEYS", "check", "run", "plot"]
