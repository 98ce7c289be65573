"""Deck case type of viscoelastic steady rolling: ``type = 'viscoelastic_rolling'``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..casetypes import REQUIRED, CaseOutput, CaseType, Key, register, validate
from ..material import Material
from .grid import Grid
from .viscoelastic import (
    ViscoelasticMaterial,
    solve_viscoelastic,
    solve_viscoelastic_line,
)
from .viscoelastic_rolling import solve_viscoelastic_rolling
from .._plotting import save_figure

_DEFAULTS = {
    "geometry": "line",
    "radius": REQUIRED,  # m
    "radius_y": None,  # m, 'point' only; default: radius
    "fn": REQUIRED,  # N/m ('line') or N ('point')
    "speed": REQUIRED,  # m/s
    "shear_modulus": REQUIRED,  # Pa, G0
    "shear_modulus_relaxed": REQUIRED,  # Pa, Ginf
    "relaxation_time": REQUIRED,  # s
    "poisson": 0.4,
    "body2": "rigid",
    "body2_shear_modulus": None,  # Pa ('elastic')
    "body2_poisson": None,
    "n": 400,
    "n_per_semiaxis": 16,
    "tol": 1e-10,
    "max_iter": 200,
    "mu": None,  # 'point': with mu, the tangential problem too
    "xi": 0.0,
    "eta": 0.0,
    "phi": 0.0,  # 1/m
}

KEYS: dict[str, Key] = {
    "geometry": Key(
        "",
        "'line': a cylinder (plane strain, fn per length); 'point': a body of radii radius, radius_y",
        "str",
        choices=("line", "point"),
    ),
    "radius": Key("m", "combined rolling radius R (gap x^2 / (2 R))", lo=0.0, hi=10.0, lo_open=True),
    "radius_y": Key("m", "combined lateral radius ('point')", lo=0.0, hi=1e3, lo_open=True, optional=True),
    "fn": Key(
        "N/m or N", "load per unit length ('line') or normal force ('point')", lo=0.0, hi=1e9, lo_open=True
    ),
    "speed": Key("m/s", "rolling speed", lo=0.0, hi=1e3),
    "shear_modulus": Key(
        "Pa", "instantaneous (glassy) shear modulus G0 of body 1", lo=0.0, hi=1e12, lo_open=True
    ),
    "shear_modulus_relaxed": Key(
        "Pa", "long-term (relaxed) shear modulus Ginf of body 1, <= G0", lo=0.0, hi=1e12, lo_open=True
    ),
    "relaxation_time": Key("s", "relaxation time of body 1's G(t)", lo=0.0, hi=1e9, lo_open=True),
    "poisson": Key("1", "Poisson's ratio of body 1", lo=-1.0, hi=0.5, lo_open=True, hi_open=True),
    "body2": Key(
        "",
        "body 2: 'rigid', 'elastic' (body2_shear_modulus, body2_poisson) or 'same' as body 1",
        "str",
        choices=("rigid", "elastic", "same"),
    ),
    "body2_shear_modulus": Key(
        "Pa", "shear modulus of an elastic body 2", lo=0.0, hi=1e12, lo_open=True, optional=True
    ),
    "body2_poisson": Key(
        "1",
        "Poisson's ratio of an elastic body 2",
        lo=-1.0,
        hi=0.5,
        lo_open=True,
        hi_open=True,
        optional=True,
    ),
    "n": Key("1", "strips of the line contact's grid", "int", 8, 4000, why="a dense LU of 4000 strips"),
    "n_per_semiaxis": Key("1", "elements per relaxed Hertz semi-axis ('point')", "int", 4, 64),
    "tol": Key("1", "interpenetration allowed outside the contact, relative", lo=0.0, hi=0.1, lo_open=True),
    "max_iter": Key("1", "active-set iteration limit", "int", 1, 10000),
    "mu": Key(
        "1",
        "friction coefficient: with it a 'point' case solves the tangential problem too",
        lo=0.0,
        hi=1.0,
        lo_open=True,
        optional=True,
    ),
    "xi": Key("1", "longitudinal creepage (with mu)", lo=-1.0, hi=1.0),
    "eta": Key("1", "lateral creepage (with mu)", lo=-1.0, hi=1.0),
    "phi": Key("1/m", "spin creepage (with mu)", lo=-100.0, hi=100.0),
}


def check(p: dict[str, Any]) -> list[str]:
    """Consistency: Ginf <= G0; an elastic body 2 has its modulus and ratio."""
    out = []
    if p["shear_modulus_relaxed"] > p["shear_modulus"]:
        out.append(
            f"shear_modulus_relaxed = {p['shear_modulus_relaxed']:g} Pa must not exceed "
            f"shear_modulus = {p['shear_modulus']:g} Pa (a standard linear solid relaxes)"
        )
    if str(p["body2"]).lower() == "elastic" and (
        p["body2_shear_modulus"] is None or p["body2_poisson"] is None
    ):
        out.append("body2 = 'elastic' needs body2_shear_modulus (Pa) and body2_poisson")
    if p["mu"] is not None and str(p["geometry"]).lower() != "point":
        out.append("mu (the tangential problem) needs geometry = 'point'")
    if p["mu"] is not None and not p["speed"] > 0:
        out.append("mu (the tangential problem) needs speed > 0 (m/s)")
    return out


def _bodies(p: dict[str, Any]):
    body1 = ViscoelasticMaterial(
        shear_modulus=p["shear_modulus"],
        shear_modulus_relaxed=p["shear_modulus_relaxed"],
        relaxation_time=p["relaxation_time"],
        poisson=p["poisson"],
    )
    kind = str(p["body2"]).lower()
    if kind == "same":
        return body1, body1
    if kind == "elastic":
        return body1, Material(shear_modulus=p["body2_shear_modulus"], poisson=p["body2_poisson"])
    return body1, None


def run(params: dict[str, Any]) -> CaseOutput:
    """Viscoelastic steady rolling: ``geometry`` 'line' (a cylinder of combined radius
    ``radius`` (m) under ``fn`` N/m) or 'point' (radii ``radius``, ``radius_y``, force ``fn``
    N), rolling ``speed`` (m/s); body 1 a standard linear solid (``shear_modulus``,
    ``shear_modulus_relaxed`` in Pa, ``relaxation_time`` in s, ``poisson``), body 2 rigid,
    elastic or the same."""
    p = validate("viscoelastic_rolling", params)
    body1, body2 = _bodies(p)
    if str(p["geometry"]).lower() == "line":
        return _run_line(p, body1, body2)
    return _run_point(p, body1, body2)


def _run_line(p, body1, body2) -> CaseOutput:
    r = solve_viscoelastic_line(
        p["radius"], p["fn"], p["speed"], body1, body2, n=p["n"], tol=p["tol"], max_iter=p["max_iter"]
    )
    a = r.hertz_half_width_relaxed
    return CaseOutput(
        summary=(
            f"line: contact [{r.x_trailing / a:.4f}, {r.x_leading / a:.4f}] a_inf, centroid e = "
            f"{r.centroid * 1e6:.4g} um, mu_R = {r.resistance_coefficient:.4g}, "
            f"pmax = {r.pmax / 1e6:.4g} MPa, {r.iterations} active-set it"
        ),
        datasets={"x": (r.x, "m"), "pressure": (r.pressure, "Pa"), "displacement": (r.displacement, "m")},
        scalars={
            "fn": (r.fn, "N/m"),
            "approach": (r.approach, "m"),
            "x_trailing": (r.x_trailing, "m"),
            "x_leading": (r.x_leading, "m"),
            "centroid": (r.centroid, "m"),
            "moment": (r.moment, "N m/m"),
            "resistance_coefficient": (r.resistance_coefficient, "1"),
            "pmax": (r.pmax, "Pa"),
            "hertz_half_width_instant": (r.hertz_half_width_instant, "m"),
            "hertz_half_width_relaxed": (r.hertz_half_width_relaxed, "m"),
            "iterations": (r.iterations, "1"),
            "residual": (r.residual, "1"),
        },
    )


def _run_point(p, body1, body2) -> CaseOutput:
    rx = p["radius"]
    ry = rx if p["radius_y"] is None else p["radius_y"]
    # the grid from the relaxed Hertz circle of the mean radius (1.4 of it each side)
    jinf = sum(b.compliance_relaxed if isinstance(b, ViscoelasticMaterial) else 0.0 for b in (body1, body2))
    if isinstance(body2, Material):
        jinf += (1.0 - body2.poisson) / (2.0 * body2.shear_modulus)
    rm = np.sqrt(rx * ry)
    a = (3.0 * p["fn"] * rm * jinf / 4.0) ** (1.0 / 3.0)
    ax, ay = a * (rx / rm) ** 0.5, a * (ry / rm) ** 0.5
    grid = Grid.covering(ax, ay, n_per_semiaxis=p["n_per_semiaxis"], margin=1.4)
    x, y = grid.mesh()
    gap = np.asfortranarray(x * x / (2.0 * rx) + y * y / (2.0 * ry))
    if p["mu"] is not None:
        return _run_tangential(p, grid, gap, body1, body2)
    r = solve_viscoelastic(gap, grid, p["fn"], p["speed"], body1, body2, tol=p["tol"], max_iter=p["max_iter"])
    return CaseOutput(
        summary=(
            f"point: centroid e = {r.centroid * 1e6:.4g} um, mu_R = {r.resistance_coefficient:.4g}, "
            f"pmax = {r.pmax / 1e6:.4g} MPa, area = {r.area * 1e6:.4g} mm^2, {r.iterations} active-set it"
        ),
        datasets={"x": (grid.x, "m"), "y": (grid.y, "m"), "pressure": (r.pressure, "Pa")},
        scalars={
            "fn": (r.fn, "N"),
            "approach": (r.approach, "m"),
            "area": (r.area, "m^2"),
            "centroid": (r.centroid, "m"),
            "resistance_force": (r.resistance_force, "N"),
            "resistance_coefficient": (r.resistance_coefficient, "1"),
            "pmax": (r.pmax, "Pa"),
            "iterations": (r.iterations, "1"),
            "fft_products": (r.fft_products, "1"),
            "residual": (r.residual, "1"),
        },
    )


def _run_tangential(p, grid, gap, body1, body2) -> CaseOutput:
    t = solve_viscoelastic_rolling(
        gap, grid, p["fn"], p["speed"], (p["xi"], p["eta"], p["phi"]), p["mu"], body1, body2
    )
    r = t.normal
    return CaseOutput(
        summary=(
            f"point rolling: Fx = {t.fx:.4g} N, Fy = {t.fy:.4g} N, |F|/(mu Fn) = "
            f"{np.hypot(t.fx, t.fy) / (p['mu'] * r.fn):.4f}, mu_R = {r.resistance_coefficient:.4g}, "
            f"{t.iterations} sweeps"
        ),
        datasets={
            "x": (grid.x, "m"),
            "y": (grid.y, "m"),
            "pressure": (r.pressure, "Pa"),
            "tx": (t.tx, "Pa"),
            "ty": (t.ty, "Pa"),
            "status": (t.status, "0 exterior, 1 adhesion, 2 slip"),
        },
        scalars={
            "fn": (r.fn, "N"),
            "fx": (t.fx, "N"),
            "fy": (t.fy, "N"),
            "mz": (t.mz, "N m"),
            "centroid": (r.centroid, "m"),
            "resistance_force": (r.resistance_force, "N"),
            "resistance_coefficient": (r.resistance_coefficient, "1"),
            "iterations": (t.iterations, "1"),
            "residual": (t.residual, "1"),
        },
    )


def plot(group: Any, outdir: Path, stem: str) -> list[Path]:
    """The pressure along x (line) or along the grid's centre line (point)."""
    import matplotlib.pyplot as plt

    x = group["x"][()] * 1e3
    p = group["pressure"][()] / 1e6
    where = "pressure (MPa)"
    if p.ndim == 2:
        p = p[:, p.shape[1] // 2]
        where = "pressure on the centre line (MPa)"
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    ax.plot(x, p)
    ax.set_xlabel("x, rolling direction (mm); leading edge at the right")
    ax.set_ylabel(where)
    ax.set_title(f"{group.attrs['name']}: viscoelastic steady rolling")
    return save_figure(fig, outdir / f"{stem}_pressure.png")


register(
    CaseType(
        name="viscoelastic_rolling",
        defaults=_DEFAULTS,
        run=run,
        plot=plot,
        keys=KEYS,
        check=check,
        summary="steady rolling on a viscoelastic (standard linear solid) body: pressure shift, resistance",
    )
)

__all__ = ["KEYS", "check", "run", "plot"]
