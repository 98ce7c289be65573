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

from ..casetypes import REQUIRED, Alias, CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from .element import TrackElement
from .ring import DEFAULTS, NUMERICS, RingTrack

_COMMON: dict[str, Any] = {
    "n_sleepers": REQUIRED,
    **DEFAULTS,
    **{k: v for k, v in NUMERICS.items() if k != "f_max"},
}
#: The deck's mm alias of arc_step (the deck key and RingTrack's argument are in m).
_ALIASES = {"arc_step_mm": Alias("arc_step", 1e-3, deprecated=False, unit="mm")}


def _pos(unit: str, meaning: str, hi: float | None = None, zero: bool = False, why: str = "") -> Key:
    return Key(unit, meaning, lo=0.0, hi=hi, lo_open=not zero, why=why)


#: The plausibility bound of the pads' and the ballast's stiffness and damping.
_WHY_DECADES = "at most two decades above railvti.track.DEFAULTS (soft pads ~20 MN/m, stiff ~1 GN/m)"


def _decades(unit: str, meaning: str, key: str, zero: bool = False) -> Key:
    """A stiffness or damping of the track: > 0 (>= 0 with ``zero``), at most two decades
    above its default in railvti.track.DEFAULTS."""
    return _pos(unit, meaning, 1e2 * DEFAULTS[key], zero=zero, why=_WHY_DECADES)


#: Units, meanings and bounds of the track keys.
KEYS: dict[str, Key] = {
    "n_sleepers": Key(
        "1",
        "sleepers on the ring (ring length = n_sleepers x sleeper_spacing)",
        "int",
        8,
        1024,
        why="a ring of fewer than 8 bays has its own ring modes in the band and is no long track",
    ),
    "sleeper_spacing": _pos("m", "sleeper spacing", 2.0),
    "rail_young": _pos("Pa", "rail Young's modulus", 1e12),
    "rail_poisson": Key("1", "rail Poisson's ratio", lo=0.0, hi=0.5, hi_open=True),
    "rail_density": _pos("kg/m^3", "rail density", 3e4),
    "rail_loss_factor": _pos("1", "rail material loss factor", 1.0, zero=True),
    "rail_distance": _pos("m", "distance between the rail axes", 3.0),
    "cant": Key("1", "rail inclination, tan (1:40 = 0.025)", lo=-0.2, hi=0.2),
    "pad_stiffness_vertical": _decades(
        "N/m", "rail pad vertical stiffness per rail seat", "pad_stiffness_vertical"
    ),
    "pad_stiffness_lateral": _decades(
        "N/m", "rail pad lateral stiffness per rail seat", "pad_stiffness_lateral"
    ),
    "pad_stiffness_longitudinal": _decades(
        "N/m", "rail pad longitudinal stiffness per rail seat", "pad_stiffness_longitudinal"
    ),
    "pad_damping_vertical": _decades(
        "N s/m", "rail pad vertical damping per rail seat", "pad_damping_vertical", zero=True
    ),
    "pad_damping_lateral": _decades(
        "N s/m", "rail pad lateral damping per rail seat", "pad_damping_lateral", zero=True
    ),
    "pad_damping_longitudinal": _decades(
        "N s/m", "rail pad longitudinal damping per rail seat", "pad_damping_longitudinal", zero=True
    ),
    "pad_length": _pos("m", "rail pad length along the rail", 1.0),
    "sleeper_mass": _pos("kg", "mass of a whole sleeper", 5000.0),
    "sleeper_length": _pos("m", "sleeper length (roll inertia, ballast roll stiffness)", 5.0),
    "ballast_stiffness_vertical": _decades(
        "N/m", "ballast vertical stiffness per sleeper", "ballast_stiffness_vertical"
    ),
    "ballast_stiffness_lateral": _decades(
        "N/m", "ballast lateral stiffness per sleeper", "ballast_stiffness_lateral"
    ),
    "ballast_damping_vertical": _decades(
        "N s/m", "ballast vertical damping per sleeper", "ballast_damping_vertical", zero=True
    ),
    "ballast_damping_lateral": _decades(
        "N s/m", "ballast lateral damping per sleeper", "ballast_damping_lateral", zero=True
    ),
    "f_cut_factor": Key("1", "rail modes kept per wave number up to f_cut_factor x f_max", lo=1.0, hi=10.0),
    "kappa_max": _pos("rad/m", "highest rail wave number in the series", 1e4),
    "mesh_max_area": Key(
        "m^2",
        "largest triangle of the rail-section mesh",
        lo=1e-6,
        hi=1e-2,
        why="a finer mesh has over 10^4 triangles in a 77 cm^2 rail",
    ),
    "arc_step": Key(
        "m",
        "spacing of the section outline's points on arcs",
        lo=0.5e-3,
        hi=0.05,
        why="8 mm is 0.008 m; arc_step_mm takes mm",
    ),
    "n_samples": Key("1", "sample wave numbers of the rail's reduced basis", "int", 2, 1000),
    "f_min": Key("Hz", "lowest frequency of the receptances", lo=0.0, hi=1e5),
    "f_max": _pos("Hz", "highest frequency (receptances and modes)", 2e4),
    "n_freq": Key("1", "frequencies from f_min to f_max", "int", 2, 1_000_000),
    "position": Key(
        "", "where the element is fitted: 'midspan' or 'sleeper'", "str", choices=("midspan", "sleeper")
    ),
}


def check_receptance(p: dict[str, Any]) -> list[str]:
    """Consistency of a 'track_receptance' case: f_min < f_max."""
    if not p["f_min"] < p["f_max"]:
        return [f"f_min = {p['f_min']:g} must be < f_max = {p['f_max']:g} (Hz)"]
    return []


def _track(params: dict[str, Any], f_max: float) -> RingTrack:
    kw = {k: params[k] for k in _COMMON if k != "n_sleepers"}
    return RingTrack(params["n_sleepers"], f_max=f_max, **kw)


def run_receptance(params: dict[str, Any]) -> CaseOutput:
    """Receptances of a ring track.

    Keys: n_sleepers (-), every RingTrack parameter (SI units, see railvti.track.DEFAULTS;
    arc_step in m, arc_step_mm its mm alias),
    f_min, f_max (Hz), n_freq (-).
    """
    params = validate("track_receptance", params)
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
    scalars = {
        "n_modes_total": (tr.n_modes, "1"),
        "build_time": (sum(tr.build_time), "s"),
        "static_vertical_midspan": (tr.static_modal("vertical", "midspan"), "m/N"),
        "static_lateral_midspan": (tr.static_modal("lateral", "midspan"), "m/N"),
    }
    summary = (
        f"ring track n_sl={tr.n_sleepers}: {m.freq.size} modes <= {f_max:g} Hz, "
        f"static vertical {scalars['static_vertical_midspan'][0]:.3e} m/N"
    )
    return CaseOutput(
        summary=summary,
        datasets=data,
        scalars=scalars,
        attrs={"mode_freq": {"axes": ["mode"]}, "mode_damping_ratio": {"axes": ["mode"]}},
    )


def plot_receptance(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Log-magnitude receptance charts (vertical and lateral), like the paper's Figs 6-7."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = group["results"] if "results" in group else group
    f = np.asarray(res["freq"])
    name = group.attrs.get("name", "")
    name = name.decode() if isinstance(name, bytes) else str(name)
    inputs = group["inputs"] if "inputs" in group else {}
    ring = f", ring of {int(np.asarray(inputs['n_sleepers']))} sleepers" if "n_sleepers" in inputs else ""
    how = {"vertical": "in phase on both rails", "lateral": "opposite on the two rails"}
    paths = []
    for d in ("vertical", "lateral"):
        fig, ax = plt.subplots(figsize=(6.4, 3.6))
        for pos in ("midspan", "sleeper"):
            h = np.asarray(res[f"{d}_{pos}_re"]) + 1j * np.asarray(res[f"{d}_{pos}_im"])
            ax.semilogy(f, np.abs(h), label=pos)
        ax.set_xlabel("frequency, Hz")
        ax.set_ylabel("|receptance|, m/N")
        ax.set_title(f"{name}: {d} receptance at the rail head ({how[d]}){ring}", fontsize=9)
        ax.legend(title="force and response", fontsize=8, title_fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        p = Path(outdir) / f"{stem}_{d}.png"
        fig.tight_layout()
        fig.savefig(p, dpi=90)
        plt.close(fig)
        paths.append(p)
    return paths


def run_element(params: dict[str, Any]) -> CaseOutput:
    """Rigid track element fitted to a ring track (keys as track_receptance, plus position)."""
    params = validate("track_element", params)
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
    summary = "track element: k_z %.3g N/m, k_y %.3g N/m, m_z %.1f kg, f_z %.0f Hz" % (
        e.stiffness[1],
        e.stiffness[0],
        e.inertia[1],
        math.sqrt(e.stiffness[1] / e.inertia[1]) / (2 * math.pi),
    )
    return CaseOutput(summary=summary, datasets=data, scalars=scalars)


register(
    CaseType(
        name="track_receptance",
        defaults={**_COMMON, "f_min": 0.0, "f_max": 3000.0, "n_freq": 3000},
        run=run_receptance,
        plot=plot_receptance,
        keys=KEYS,
        check=check_receptance,
        aliases=_ALIASES,
        summary="ring track (2.5-D FE rails on discrete sleepers): rail-head receptances, modes",
    )
)
register(
    CaseType(
        name="track_element",
        defaults={**_COMMON, "position": "midspan"},
        run=run_element,
        keys=KEYS,
        aliases=_ALIASES,
        summary="rigid track element (mass, stiffness, damping per direction) fitted to a ring track",
    )
)

__all__ = ["KEYS", "check_receptance", "run_receptance", "plot_receptance", "run_element"]
