"""Deck case type ``type = 'transient'``: shift (Cattaneo-Mindlin), transient rolling from
rest, and rolling under a time-varying normal load (``kind``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ..casetypes import REQUIRED, CaseOutput, CaseType, Key, register, validate
from .cases import KEYS, _COMMON, check_normal, make_gap
from .hertz import hertz
from .rolling import solve_rolling
from .transient import TransientResult, shift_problem, solve_transient
from .._plotting import save_figure

_KINDS = ("shift", "rolling", "load")

_KEYS = dict(
    KEYS,
    kind=Key(
        "",
        "'shift' (pressed, then a tangential force in steps), 'rolling' (from rest at constant "
        "creepage) or 'load' (rolling under fn (1 + fn_amplitude sin(2 pi frequency t)))",
        "str",
        choices=_KINDS,
    ),
    fx=Key("N", "tangential force reached at the end of a shift ('shift')", lo=-1e7, hi=1e7),
    fy=Key("N", "lateral force reached at the end of a shift ('shift')", lo=-1e7, hi=1e7),
    steps=Key("1", "load increments of a shift ('shift')", "int", 1, 10000),
    speed=Key("m/s", "rolling speed ('rolling', 'load')", lo=0.0, hi=KEYS["speed"].hi, lo_open=True),
    distance=Key("m", "distance rolled ('rolling', 'load')", lo=0.0, hi=100.0, lo_open=True),
    dt=Key(
        "s",
        "time step (default dx / speed); speed dt must be a whole number of elements dx, "
        "shorter than the patch",
        lo=0.0,
        hi=10.0,
        lo_open=True,
        optional=True,
    ),
    theta=Key(
        "1", "weight of the second-order slip (1/3: the steady solver's stencil; 0: Kalker's)", lo=0.0, hi=1.0
    ),
    fn_amplitude=Key("1", "relative amplitude of the normal load ('load')", lo=0.0, hi=0.9),
    frequency=Key(
        "Hz", "frequency of the normal load ('load'); 0: a step of fn_amplitude at step_at", lo=0.0, hi=1e5
    ),
    step_at=Key("m", "distance rolled when the load steps ('load' with frequency = 0)", lo=0.0, hi=100.0),
    quasi_steady=Key(
        "",
        "also solve steady rolling at each step ('load'; one solve per step); fx_max_difference is taken "
        "after three patch lengths",
        "flag",
    ),
)

_DEFAULTS = {k: v for k, v in _COMMON.items() if k not in ("method", "max_iter")}
_DEFAULTS.update(
    {
        "tol": 1e-7,
        "gap_a": REQUIRED,
        "gap_b": REQUIRED,
        "kind": REQUIRED,
        "fn": REQUIRED,
        "mu": REQUIRED,
        "fx": 0.0,
        "fy": 0.0,
        "steps": 1,
        "xi": 0.0,
        "eta": 0.0,
        "phi": 0.0,
        "speed": 30.0,
        "distance": None,
        "dt": None,
        "theta": 1.0 / 3.0,
        "fn_amplitude": 0.1,
        "frequency": 92.6,
        "step_at": 0.0,
        "quasi_steady": 0,
    }
)
_KEYS["distance"] = Key(
    "m", "distance rolled ('rolling', 'load')", lo=0.0, hi=100.0, lo_open=True, optional=True
)


def check_transient(p: dict[str, Any]) -> list[str]:
    """Consistency of a 'transient' case: the normal keys, the force of a shift below mu fn,
    a distance for rolling."""
    out = check_normal({**p, "approach": None})
    kind = str(p["kind"]).lower()
    if kind == "shift" and math.hypot(p["fx"], p["fy"]) >= p["mu"] * p["fn"]:
        out.append(
            f"fx, fy: the shift force {math.hypot(p['fx'], p['fy']):g} N must stay below mu fn = "
            f"{p['mu'] * p['fn']:g} N (full sliding leaves the shift undetermined)"
        )
    if kind in ("rolling", "load") and p["distance"] is None:
        out.append(f"kind = '{kind}' needs distance (m)")
    return out


def _normal_force(params: dict[str, Any], time: np.ndarray, dist: np.ndarray) -> np.ndarray:
    fn, amp = params["fn"], params["fn_amplitude"]
    if str(params["kind"]).lower() != "load":
        return np.full(time.size, fn)
    if params["frequency"] > 0:
        return fn * (1.0 + amp * np.sin(2.0 * np.pi * params["frequency"] * time))
    return np.where(dist >= params["step_at"], fn * (1.0 + amp), fn)


def _rolling_run(params: dict[str, Any], grid, gap, material) -> tuple[TransientResult, np.ndarray | None]:
    speed = params["speed"]
    dt = params["dt"] if params["dt"] is not None else grid.dx / speed
    steps = max(1, int(round(params["distance"] / (speed * dt))))
    time = dt * np.arange(1, steps + 1)
    fn = _normal_force(params, time, speed * time)
    creep = (params["xi"], params["eta"], params["phi"])
    r = solve_transient(
        grid,
        material,
        params["mu"],
        fn,
        steps,
        dt,
        gap=gap,
        speed=speed,
        creepage=creep,
        theta=params["theta"],
        tol=params["tol"],
    )
    quasi = None
    if str(params["kind"]).lower() == "load" and params["quasi_steady"]:
        quasi = np.array([solve_rolling(gap, grid, material, params["mu"], f, creep, speed).fx for f in fn])
    return r, quasi


def run_transient(params: dict[str, Any]) -> CaseOutput:
    """Transient or shift contact (``kind``): see the keys of ``railvti cases transient``."""
    params = validate("transient", params)
    grid, gap, material = make_gap(params)
    kind = str(params["kind"]).lower()
    quasi = None
    if kind == "shift":
        r = shift_problem(
            gap,
            grid,
            material,
            params["mu"],
            params["fn"],
            (params["fx"], params["fy"]),
            steps=params["steps"],
            tol=params["tol"],
        )
    else:
        r, quasi = _rolling_run(params, grid, gap, material)
    snap = r.last
    total = r.shift_total
    datasets = {
        "time": (r.time, "s"),
        "distance": (r.distance, "m"),
        "fn_history": (r.fn, "N"),
        "fx_history": (r.fx, "N"),
        "fy_history": (r.fy, "N"),
        "shift_x": (total[:, 0], "m"),
        "shift_y": (total[:, 1], "m"),
        "n_slip": (r.n_slip, "1"),
        "iterations": (r.iterations, "1"),
        "x": (grid.x, "m"),
        "y": (grid.y, "m"),
        "pressure": (snap.pressure, "Pa"),
        "tx": (snap.tx, "Pa"),
        "ty": (snap.ty, "Pa"),
        "status": (snap.status, "0 exterior, 1 adhesion, 2 slip"),
    }
    scalars: dict[str, tuple[Any, str]] = {
        "kind": (kind, ""),
        "fx": (float(r.fx[-1]), "N"),
        "fy": (float(r.fy[-1]), "N"),
        "fn": (float(r.fn[-1]), "N"),
        "shift_x_total": (float(total[-1, 0]), "m"),
        "shift_y_total": (float(total[-1, 1]), "m"),
        "n_slip_final": (int(r.n_slip[-1]), "1"),
        "steps": (int(r.time.size), "1"),
    }
    summary = f"{kind}: {r.time.size} steps, Fx = {r.fx[-1]:.5g} N, Fy = {r.fy[-1]:.5g} N"
    if kind == "shift":
        summary += _shift_theory(params, material, r, scalars)
    else:
        summary += _rolling_summary(params, grid, gap, material, r, quasi, datasets, scalars)
    return CaseOutput(summary=summary, datasets=datasets, scalars=scalars)


def _shift_theory(params, material, r: TransientResult, scalars) -> str:
    """Cattaneo-Mindlin (Johnson 1985, eqs 7.38 and 7.42) beside a circular Hertz shift."""
    if params["gap_a"] != params["gap_b"] or str(params["gap"]).lower() != "hertz" or params["fy"] != 0.0:
        return ""
    h = hertz(params["gap_a"], params["gap_b"], params["fn"], material)
    ratio = abs(params["fx"]) / (params["mu"] * params["fn"])
    c_th = h.a * (1.0 - ratio) ** (1.0 / 3.0)
    d_th = (
        3.0
        * params["mu"]
        * params["fn"]
        * (2.0 - material.poisson)
        / (8.0 * material.shear_modulus * h.a)
        * (1.0 - (1.0 - ratio) ** (2.0 / 3.0))
    )
    c = math.sqrt(r.last.adhesion.sum() * r.grid.element_area / math.pi)
    d = abs(float(r.shift_total[-1, 0]))
    scalars.update(
        {
            "hertz_a": (h.a, "m"),
            "stick_radius": (c, "m"),
            "stick_radius_theory": (c_th, "m"),
            "shift_theory": (d_th, "m"),
        }
    )
    return (
        f", stick radius {c / h.a:.4f} a (Cattaneo {c_th / h.a:.4f} a), shift {d * 1e6:.4g} um "
        f"(Mindlin {d_th * 1e6:.4g} um, {100 * (d / d_th - 1):+.2f} %)"
    )


def _rolling_summary(params, grid, gap, material, r, quasi, datasets, scalars) -> str:
    steady = solve_rolling(
        gap,
        grid,
        material,
        params["mu"],
        params["fn"],
        (params["xi"], params["eta"], params["phi"]),
        params["speed"],
    )
    d99 = r.distance_to_fraction(0.99, steady.fx) if abs(steady.fx) > 0 else math.nan
    scalars.update({"steady_fx": (steady.fx, "N"), "steady_fy": (steady.fy, "N"), "distance_99": (d99, "m")})
    text = f", steady Fx = {steady.fx:.5g} N, 99 % after {d99 * 1e3:.4g} mm"
    if quasi is not None:
        # after three contact lengths (the start from rest has then settled to ~1 %)
        rows = np.nonzero((r.last.pressure > 0.0).any(axis=1))[0]
        length = (rows[-1] - rows[0] + 1) * grid.dx if rows.size else 0.0
        late = r.distance >= 3.0 * length
        if not late.any():
            late[:] = True
        datasets["fx_quasi_steady"] = (quasi, "N")
        diff = float(np.abs(r.fx - quasi)[late].max())
        scalars["fx_max_difference"] = (diff, "N")
        text += f", max |Fx - quasi-steady| = {diff:.4g} N after {3e3 * length:.3g} mm"
    return text


def plot_transient(group: Any, outdir: Path, stem: str) -> list[str | Path]:
    """Force history and the final traction profile along x at the centre line."""
    import matplotlib.pyplot as plt

    kind = group["kind"][()] if "kind" in group else b""
    kind = kind.decode() if isinstance(kind, bytes) else str(kind)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    dist = group["distance"][()]
    xs = dist * 1e3 if dist.max() > 0 else np.arange(1, dist.size + 1)
    ax1.plot(xs, group["fx_history"][()] / 1e3, label="Fx")
    ax1.plot(xs, group["fy_history"][()] / 1e3, label="Fy")
    if "steady_fx" in group:
        ax1.axhline(float(group["steady_fx"][()]) / 1e3, color="grey", ls=":", lw=1.0, label="Fx steady")
    if "fx_quasi_steady" in group:
        ax1.plot(xs, group["fx_quasi_steady"][()] / 1e3, "--", label="Fx quasi-steady")
    ax1.set_xlabel("distance rolled (mm)" if dist.max() > 0 else "load step")
    ax1.set_ylabel("force (kN)")
    ax1.legend()
    x = group["x"][()] * 1e3
    j = group["y"][()].size // 2
    ax2.plot(x, group["tx"][()][:, j] / 1e6, label="tx")
    ax2.plot(x, group["ty"][()][:, j] / 1e6, label="ty")
    ax2.axhline(0.0, color="k", lw=0.5)
    ax2.set_xlabel("x (mm)")
    ax2.set_ylabel("traction at the centre line (MPa)")
    ax2.legend()
    fig.suptitle(f"{group.attrs['name']}: transient contact, kind '{kind}' (last step's tractions)")
    return save_figure(fig, outdir / f"{stem}_transient.png")


register(
    CaseType(
        name="transient",
        defaults=_DEFAULTS,
        run=run_transient,
        plot=plot_transient,
        keys=_KEYS,
        check=check_transient,
        summary="transient and shift contact: Cattaneo-Mindlin shift, rolling from rest, varying normal load",
    )
)

__all__ = ["check_transient", "run_transient", "plot_transient"]
