"""Deck case type ``wheelset``: modes per harmonic and the FRF of the rotating
wheelset in its bogie at several speeds."""
from __future__ import annotations

from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from ..casetypes import CaseOutput, CaseType, register
from ..errors import InputError
from .geometry import WheelsetGeometry
from .model import PrimarySuspension, Wheelset

_GEOMETRY_DEFAULTS = {f.name: f.default for f in fields(WheelsetGeometry)}

DEFAULTS: dict[str, Any] = {
    "k_max": 6,                 # highest harmonic
    "f_max": 3000.0,            # Hz, highest mode frequency
    "support": "free",          # modes table: 'free' or 'suspension'
    "speeds_kmh": [0.0, 200.0, 300.0],
    "f_lo": 20.0,               # FRF band, Hz
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


def run(params: dict[str, Any]) -> CaseOutput:
    """Run a wheelset case (lengths m, stiffness N/m, frequencies Hz, speeds km/h)."""
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
        h[i] = ws.frf(freqs, v / 3.6, input=params["input"], output=params["output"],
                      k_max=params["k_max"], f_max=params["f_max"],
                      damping_ratio=params["damping_ratio"])
    first = {k: table.first(k) for k in (0, 1, 2) if k <= params["k_max"] and np.any(table.k == k)}
    summary = "wheelset: " + ", ".join(f"first k={k} {f:.1f} Hz" for k, f in first.items())
    return CaseOutput(
        summary=summary,
        datasets={"mode_k": (table.k, "1"), "mode_freq": (table.freq_hz, "Hz"),
                  "frf_freq": (freqs, "Hz"), "speeds": (speeds, "km/h"),
                  "frf_real": (h.real, "m/N"), "frf_imag": (h.imag, "m/N")},
        scalars={f"first_k{k}": (f, "Hz") for k, f in first.items()},
        attrs={"mode_k": {"axes": ["mode"]}, "mode_freq": {"axes": ["mode"]},
               "frf_freq": {"axes": ["frf_freq"]}, "speeds": {"axes": ["speed"]},
               "frf_real": {"axes": ["speeds", "frf_freq"]}, "frf_imag": {"axes": ["speeds", "frf_freq"]}})


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """FRF magnitude at each speed."""
    from .plots import plot_frf
    res = group["results"] if "results" in group else group
    f = res["frf_freq"][()]
    h = res["frf_real"][()] + 1j * res["frf_imag"][()]
    curves = {f"{v:.0f} km/h": h[i] for i, v in enumerate(res["speeds"][()])}
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    return [plot_frf(outdir / f"{stem}_frf.png", f, curves, "wheelset in bogie: contact-point receptance")]


register(CaseType(name="wheelset", defaults=DEFAULTS, run=run, plot=plot))
