"""Deck case type ``type = 'subsurface'``: the stresses below a solved contact patch.

The normal problem of a 'hertz' gap under ``fn`` is solved on the grid; the tangential
tractions are none, full sliding (``traction = 'sliding'``: mu p along +x on the body) or
those of steady rolling (``traction = 'rolling'``: creepages, speed; the rail or wheel
side by ``body``). The stresses are computed on the element centres at ``nz`` depths from
``z_min`` to ``z_max`` (m, > 0 into the body) and written to HDF5 (docs/contact_subsurface.md).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from .._checks import MAX_FRICTION
from ..casetypes import REQUIRED, CaseOutput, CaseType, Key, register, validate
from ..material import Material
from .cases import KEYS, _COMMON, check_normal, make_gap
from .hertz import hertz
from .normal import solve_normal
from .rolling import solve_rolling
from .subsurface import COMPONENTS, subsurface_stress, subsurface_stress_fields
from .._plotting import save_figure

_DEFAULTS = {k: v for k, v in _COMMON.items() if k != "gap"}
_DEFAULTS.update(
    {
        "gap": "hertz",
        "fn": REQUIRED,
        "approach": None,
        "traction": "none",
        "mu": 0.3,
        "xi": 0.0,
        "eta": 0.0,
        "phi": 0.0,
        "speed": 10.0,
        "body": "rail",
        "z_min": REQUIRED,
        "z_max": REQUIRED,
        "nz": 30,
        "stress_method": "auto",
    }
)

_KEYS = dict(
    KEYS,
    gap=Key("", "undeformed gap: 'hertz' (gap_a x^2 + gap_b y^2)", "str", choices=("hertz",)),
    traction=Key(
        "",
        "tangential traction: 'none', 'sliding' (mu p along +x on the body) or 'rolling' (steady rolling)",
        "str",
        choices=("none", "sliding", "rolling"),
    ),
    mu=Key("1", "friction coefficient of 'sliding' and 'rolling'", lo=0.0, hi=MAX_FRICTION),
    body=Key(
        "",
        "body whose stresses are computed ('rolling'): 'rail' or 'wheel'",
        "str",
        choices=("rail", "wheel"),
    ),
    z_min=Key(
        "m",
        "shallowest depth of the subsurface grid (> 0: inside the half-space, positive into the body)",
        lo=0.0,
        hi=0.1,
        lo_open=True,
        why="the half-space is z > 0; 0.1 m is far below any wheel-rail patch",
    ),
    z_max=Key("m", "deepest depth of the subsurface grid", lo=0.0, hi=0.1, lo_open=True),
    nz=Key("1", "depths of the subsurface grid (z_min to z_max, evenly spaced)", "int", 1, 2000),
    stress_method=Key(
        "",
        "subsurface summation: 'auto', 'fft' (per-depth convolution) or 'direct'",
        "str",
        choices=("auto", "fft", "direct"),
    ),
)


def check_subsurface(p: dict[str, Any]) -> list[str]:
    """Consistency of a 'subsurface' case: the normal case's checks and z_min <= z_max."""
    out = check_normal(p)
    if p["z_min"] is not None and p["z_max"] is not None and p["z_max"] < p["z_min"]:
        out.append(f"z_max = {p['z_max']:g} m must be >= z_min = {p['z_min']:g} m")
    if p["traction"] == "rolling" and p["mu"] <= 0:
        out.append("traction = 'rolling' needs mu > 0")
    return out


def run_subsurface(params: dict[str, Any]) -> CaseOutput:
    """Subsurface stresses (Pa) below the contact of a 'hertz' gap under ``fn`` (N), with
    depths ``z_min``..``z_max`` (m) in ``nz`` steps."""
    params = validate("subsurface", params)
    grid, gap, material = make_gap(params)
    z = np.linspace(params["z_min"], params["z_max"], params["nz"])
    t0 = time.perf_counter()
    kind = str(params["traction"]).lower()
    if kind == "rolling":
        res = solve_rolling(
            gap,
            grid,
            material,
            params["mu"],
            params["fn"],
            (params["xi"], params["eta"], params["phi"]),
            params["speed"],
        )
    else:
        res = solve_normal(gap, grid, material, fn=params["fn"], method=params["method"], tol=params["tol"])
    t1 = time.perf_counter()
    if kind == "sliding":
        q = params["mu"] * res.pressure
        r = subsurface_stress_fields(
            grid, res.pressure, q, poisson=material.poisson, z=z, method=params["stress_method"], body="given"
        )
    else:
        r = subsurface_stress(res, material, z, body=params["body"], method=params["stress_method"])
    t2 = time.perf_counter()
    return _output(params, grid, res, r, material, t1 - t0, t2 - t1)


def _output(params, grid, res, r, material: Material, t_contact: float, t_stress: float) -> CaseOutput:
    h = hertz(params["gap_a"], params["gap_b"], res.fn, material)
    (xv, yv, zv), (xt, yt, zt) = r.max_von_mises_at, r.max_tresca_at
    data = {
        "x": (grid.x, "m"),
        "y": (grid.y, "m"),
        "z": (r.z, "m"),
        "pressure": (res.pressure, "Pa"),
        "stress": (r.stress, "Pa, tension positive; last axis " + " ".join(COMPONENTS)),
        "principal": (r.principal, "Pa, s1 >= s2 >= s3"),
        "von_mises": (r.von_mises, "Pa"),
        "tresca": (r.tresca, "Pa (s1 - s3)"),
    }
    out = CaseOutput(
        summary=(
            f"max von Mises {r.max_von_mises / 1e6:.4g} MPa = {r.max_von_mises / h.p0:.4f} p0 at "
            f"x = {xv * 1e3:.3g} mm, z = {zv * 1e3:.3g} mm = {zv / h.a:.3f} a; max Tresca "
            f"{r.max_tresca / 1e6:.4g} MPa; {grid.nx}x{grid.ny} elements x {r.z.size} depths, "
            f"stresses {t_stress:.2f} s ({r.method}), contact {t_contact:.2f} s"
        ),
        datasets=data,
        scalars={
            "fn": (res.fn, "N"),
            "pmax": (float(res.pressure.max()), "Pa"),
            "max_von_mises": (r.max_von_mises, "Pa"),
            "max_von_mises_x": (xv, "m"),
            "max_von_mises_y": (yv, "m"),
            "max_von_mises_z": (zv, "m"),
            "max_tresca": (r.max_tresca, "Pa"),
            "max_tresca_x": (xt, "m"),
            "max_tresca_y": (yt, "m"),
            "max_tresca_z": (zt, "m"),
            "hertz_a": (h.a, "m"),
            "hertz_b": (h.b, "m"),
            "hertz_p0": (h.p0, "Pa"),
            "stress_method": (r.method, ""),
            "stress_seconds": (t_stress, "s"),
        },
        attrs={
            "stress": {"axes": ["x", "y", "z", "component"]},
            "principal": {"axes": ["x", "y", "z", "principal"]},
            "von_mises": {"axes": ["x", "y", "z"]},
            "tresca": {"axes": ["x", "y", "z"]},
        },
    )
    return out


def plot_subsurface(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Von Mises stress in the x-z plane through its maximum, and its largest value per depth."""
    import matplotlib.pyplot as plt

    x = group["x"][()] * 1e3
    z = group["z"][()] * 1e3
    vm = group["von_mises"][()] / 1e6
    j = int(np.unravel_index(int(np.argmax(vm)), vm.shape)[1])
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10.0, 4.2), gridspec_kw={"width_ratios": [2, 1]})
    cs = ax.contourf(x, z, vm[:, j, :].T, levels=20, cmap="viridis")
    ax.invert_yaxis()
    fig.colorbar(cs, ax=ax, label="von Mises stress (MPa)")
    ax.set_xlabel("x, rolling direction (mm)")
    ax.set_ylabel("depth z (mm)")
    ax.set_title(f"{group.attrs['name']}: y = {group['y'][()][j] * 1e3:.3g} mm")
    ax2.plot(vm.max(axis=(0, 1)), z)
    ax2.invert_yaxis()
    ax2.set_xlabel("largest von Mises at the depth (MPa)")
    ax2.set_ylabel("depth z (mm)")
    ax2.grid(True, alpha=0.3)
    return save_figure(fig, outdir / f"{stem}_subsurface.png")


register(
    CaseType(
        name="subsurface",
        defaults=_DEFAULTS,
        run=run_subsurface,
        plot=plot_subsurface,
        keys={k: v for k, v in _KEYS.items() if k in _DEFAULTS},
        check=check_subsurface,
        summary="subsurface stresses (von Mises, Tresca, principal) below a normal, sliding or rolling patch",
    )
)

__all__ = ["check_subsurface", "run_subsurface", "plot_subsurface"]
