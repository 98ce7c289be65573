"""Deck case types of the track area.

``track_receptance``: the ring track's rail-head receptances (vertical in phase, lateral
opposite; mid-span and above a sleeper) and its modal summary.
``track_element``: the rigid track element fitted to a ring track.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..casetypes import REQUIRED, CaseOutput, CaseType, register
from ..errors import InputError
from .element import TrackElement
from .ring import DEFAULTS, NUMERICS, RingTrack

_COMMON: dict[str, Any] = {"n_sleepers": REQUIRED, **DEFAULTS,
                           **{k: v for k, v in NUMERICS.items() if k != "f_max"}}


def _track(params: dict[str, Any], f_max: float) -> RingTrack:
    kw = {k: params[k] for k in _COMMON if k != "n_sleepers"}
    return RingTrack(params["n_sleepers"], f_max=f_max, **kw)


def run_receptance(params: dict[str, Any]) -> CaseOutput:
    """Receptances of a ring track.

    Keys: n_sleepers (-), every RingTrack parameter (SI units, see railvti.track.DEFAULTS),
    f_min, f_max (Hz), n_freq (-).
    """
    f_max = float(params["f_max"])
    n_freq = int(params["n_freq"])
    if n_freq < 2:
        raise InputError(f"n_freq must be >= 2, got {n_freq}")
    tr = _track(params, f_max)
    f = np.linspace(float(params["f_min"]), f_max, n_freq)
    data: dict[str, tuple[np.ndarray, str]] = {"freq": (f, "Hz")}
    for d in ("vertical", "lateral"):
        for pos in ("midspan", "sleeper"):
            h = tr.receptance(f, d, pos)
            data[f"{d}_{pos}_re"] = (h.real, "m/N")
            data[f"{d}_{pos}_im"] = (h.imag, "m/N")
    m = tr.modes(f_max)
    data["mode_freq"] = (m.freq, "Hz")
    data["mode_damping_ratio"] = (m.damping_ratio, "1")
    scalars = {"n_modes_total": (tr.n_modes, "1"), "build_time": (sum(tr.build_time), "s"),
               "static_vertical_midspan": (tr.static_modal("vertical", "midspan"), "m/N"),
               "static_lateral_midspan": (tr.static_modal("lateral", "midspan"), "m/N")}
    summary = (f"ring track n_sl={tr.n_sleepers}: {m.freq.size} modes <= {f_max:g} Hz, "
               f"static vertical {scalars['static_vertical_midspan'][0]:.3e} m/N")
    return CaseOutput(summary=summary, datasets=data, scalars=scalars,
                      attrs={"mode_freq": {"axes": ["mode"]}, "mode_damping_ratio": {"axes": ["mode"]}})


def plot_receptance(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Log-magnitude receptance charts (vertical and lateral), like the paper's Figs 6-7."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = group["results"] if "results" in group else group
    f = np.asarray(res["freq"])
    paths = []
    for d in ("vertical", "lateral"):
        fig, ax = plt.subplots(figsize=(6.4, 3.6))
        for pos in ("midspan", "sleeper"):
            h = np.asarray(res[f"{d}_{pos}_re"]) + 1j * np.asarray(res[f"{d}_{pos}_im"])
            ax.semilogy(f, np.abs(h), label=pos)
        ax.set_xlabel("frequency, Hz")
        ax.set_ylabel("|receptance|, m/N")
        ax.set_title(f"{d} receptance")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        p = Path(outdir) / f"{stem}_{d}.png"
        fig.tight_layout()
        fig.savefig(p, dpi=90)
        plt.close(fig)
        paths.append(p)
    return paths


def run_element(params: dict[str, Any]) -> CaseOutput:
    """Rigid track element fitted to a ring track (keys as track_receptance, plus position)."""
    tr = _track(params, 1000.0)
    e = TrackElement.from_ring(tr, position=str(params["position"]))
    names = ("y", "z", "roll")
    scalars: dict[str, tuple[float, str]] = {}
    for i, n in enumerate(names):
        scalars[f"inertia_{n}"] = (e.inertia[i], "kg m^2" if n == "roll" else "kg")
        scalars[f"stiffness_{n}"] = (e.stiffness[i], "N m/rad" if n == "roll" else "N/m")
        scalars[f"damping_{n}"] = (e.damping[i], "N m s/rad" if n == "roll" else "N s/m")
    f = np.linspace(1.0, 400.0, 400)
    data = {"freq": (f, "Hz")}
    for d in ("vertical", "lateral_inphase", "vertical_opposite"):
        data[f"{d}_ring_abs"] = (np.abs(tr.receptance(f, d, str(params["position"]))), "m/N")
        data[f"{d}_element_abs"] = (np.abs(e.receptance(f, d)), "m/N")
    summary = ("track element: k_z %.3g N/m, k_y %.3g N/m, m_z %.1f kg, f_z %.0f Hz"
               % (e.stiffness[1], e.stiffness[0], e.inertia[1],
                  math.sqrt(e.stiffness[1] / e.inertia[1]) / (2 * math.pi)))
    return CaseOutput(summary=summary, datasets=data, scalars=scalars)


register(CaseType(name="track_receptance",
                  defaults={**_COMMON, "f_min": 0.0, "f_max": 3000.0, "n_freq": 3000},
                  run=run_receptance, plot=plot_receptance))
register(CaseType(name="track_element",
                  defaults={**_COMMON, "position": "midspan"},
                  run=run_element))
