"""Deck case types of the contact area: ``type = 'normal'`` and ``type = 'rolling'``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .._checks import MAX_FRICTION, MAX_SPEED
from .._roots import brent_root
from ..casetypes import REQUIRED, CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from ..material import Material
from .grid import Grid
from .hertz import hertz, hertz_gap
from .normal import solve_normal
from .plots_rolling import plot_rolling
from .friction import FrictionLaw, solve_tangential_friction
from .rolling import RollingResult, solve_rolling
from .._plotting import save_figure

_COMMON = {
    "shear_modulus": 82.0e9,  # Pa
    "poisson": 0.28,
    "nx": REQUIRED,
    "ny": REQUIRED,
    "dx": REQUIRED,
    "dy": REQUIRED,  # m
    "x0": None,
    "y0": None,  # m, centre of element [0, 0]; default: grid centred
    "gap": "hertz",  # 'hertz' or 'two_bumps'
    "gap_a": REQUIRED,
    "gap_b": REQUIRED,  # 1/m: gap = gap_a x^2 + gap_b y^2
    "bump_separation": 0.0,  # m, lateral distance between the two bumps' centres
    "bump_height": 0.0,  # m, how much higher the second bump starts
    "method": "cg",
    "tol": 1e-8,
    "max_iter": None,
}


_WHY_GRID = "a larger grid needs more than ~1 GB for its influence spectra"
#: Units, meanings and bounds of the keys of 'normal' and 'rolling'.
KEYS: dict[str, Key] = {
    "shear_modulus": Key(
        "Pa",
        "shear modulus G of wheel and rail (quasi-identical bodies)",
        lo=1e6,
        hi=1e12,
        why="steel is 82e9 Pa",
    ),
    "poisson": Key("1", "Poisson's ratio of wheel and rail", lo=-1.0, hi=0.5, lo_open=True, hi_open=True),
    "nx": Key("1", "elements of the grid along x (rolling direction)", "int", 2, 2048, why=_WHY_GRID),
    "ny": Key("1", "elements of the grid along y (lateral)", "int", 2, 2048, why=_WHY_GRID),
    "dx": Key(
        "m",
        "element length along x",
        lo=0.0,
        hi=0.01,
        lo_open=True,
        why="an element above 10 mm is coarser than any wheel-rail contact",
    ),
    "dy": Key(
        "m",
        "element length along y",
        lo=0.0,
        hi=0.01,
        lo_open=True,
        why="an element above 10 mm is coarser than any wheel-rail contact",
    ),
    "x0": Key(
        "m", "x of the centre of element [0, 0] (default: grid centred)", lo=-1.0, hi=1.0, optional=True
    ),
    "y0": Key(
        "m", "y of the centre of element [0, 0] (default: grid centred)", lo=-1.0, hi=1.0, optional=True
    ),
    "gap": Key(
        "",
        "undeformed gap: 'hertz' (gap_a x^2 + gap_b y^2) or 'two_bumps'",
        "str",
        choices=("hertz", "two_bumps"),
    ),
    "gap_a": Key(
        "1/m",
        "gap curvature along x, 1/(2 R_x)",
        lo=0.0,
        hi=1e4,
        lo_open=True,
        why="a radius below 50 um is no wheel or rail",
        optional=True,
    ),
    "gap_b": Key(
        "1/m",
        "gap curvature along y, 1/(2 R_y)",
        lo=0.0,
        hi=1e4,
        lo_open=True,
        why="a radius below 50 um is no wheel or rail",
        optional=True,
    ),
    "bump_separation": Key(
        "m", "lateral distance between the two bumps' centres ('two_bumps')", lo=0.0, hi=1.0
    ),
    "bump_height": Key("m", "how much higher the second bump starts ('two_bumps')", lo=-0.01, hi=0.01),
    "method": Key(
        "",
        "normal solver: 'cg' (preconditioned CG), 'pk' (plain CG) or 'gs' (Gauss-Seidel)",
        "str",
        choices=("cg", "pk", "gs"),
    ),
    "tol": Key("1", "relative residual at which the solver stops", lo=0.0, hi=0.1, lo_open=True),
    "max_iter": Key("1", "iteration limit (default: the solver's)", "int", 1, 1e7, optional=True),
    "fn": Key(
        "N",
        "normal force (or give approach)",
        lo=0.0,
        hi=1e7,
        lo_open=True,
        optional=True,
        why="10 MN is fifty times the wheel load of a 40 t heavy-haul axle",
    ),
    "approach": Key("m", "approach of the bodies (or give fn)", lo=0.0, hi=0.01, lo_open=True, optional=True),
    "semi_a": Key(
        "m", "Hertz semi-axis along x (instead of gap_a, gap_b)", lo=0.0, hi=0.05, lo_open=True, optional=True
    ),
    "semi_b": Key(
        "m", "Hertz semi-axis along y (instead of gap_a, gap_b)", lo=0.0, hi=0.05, lo_open=True, optional=True
    ),
    "mu": Key(
        "1",
        "Coulomb friction coefficient (static = kinetic)",
        lo=0.0,
        hi=MAX_FRICTION,
        lo_open=True,
        why="dry steel on steel is about 0.3-0.6; 0 has no tangential problem",
    ),
    "xi": Key("1", "longitudinal creepage", lo=-1.0, hi=1.0),
    "eta": Key("1", "lateral creepage", lo=-1.0, hi=1.0),
    "phi": Key(
        "1/m", "spin creepage", lo=-100.0, hi=100.0, why="sin(contact angle) / radius stays below ~5 1/m"
    ),
    "speed": Key("m/s", "rolling speed", lo=0.0, hi=MAX_SPEED, lo_open=True, why="600 km/h"),
    "normal_method": Key(
        "", "normal solver of the rolling case: 'cg', 'pk' or 'gs'", "str", choices=("cg", "pk", "gs")
    ),
}
_KEYS_ROLLING = dict(
    KEYS,
    method=Key(
        "", "tangential solver: 'fftgs' (FFT-refreshed Gauss-Seidel) or 'gs'", "str", choices=("fftgs", "gs")
    ),
    # friction laws (docs/contact_friction.md): mu is then the static coefficient (Polach's mu0)
    friction_law=Key(
        "",
        "friction law; mu is its static coefficient (default: constant mu)",
        "str",
        choices=("coulomb", "linear", "rational", "exponential", "polach"),
        optional=True,
    ),
    mu_kinetic=Key(
        "1", "kinetic coefficient of the friction law (<= mu)", lo=0.0, hi=MAX_FRICTION, optional=True
    ),
    friction_halving_speed_m_s=Key(
        "m/s", "slip velocity at which mu - mu_kinetic is halved", lo=0.0, hi=1e3, lo_open=True, optional=True
    ),
    polach_a=Key(
        "1", "Polach's A = mu_infinity / mu (friction_law = 'polach')", lo=0.0, hi=1.0, optional=True
    ),
    friction_decay_s_m=Key(
        "s/m", "Polach's B, decay of mu with the slip velocity", lo=0.0, hi=1e3, lo_open=True, optional=True
    ),
    friction_root_rule=Key(
        "",
        "which of several element solutions: 'continuous' (with the iterate) or 'smallest' slip",
        "str",
        choices=("continuous", "smallest"),
    ),
)
_FRICTION_KEYS = ("mu_kinetic", "friction_halving_speed_m_s", "polach_a", "friction_decay_s_m")


def friction_law_of(p: dict[str, Any]) -> FrictionLaw | None:
    """The friction law of a rolling case's keys (None: today's constant ``mu``); raises
    InputError naming the key when the coefficients are inconsistent."""
    if p.get("friction_law") is None:
        given = [k for k in _FRICTION_KEYS if p.get(k) is not None]
        if given:
            raise InputError(
                f"{given[0]} needs friction_law (one of coulomb, linear, rational, exponential, polach)"
            )
        return None
    keys = {"friction_law": str(p["friction_law"]).lower(), "mu_static": p["mu"]}
    keys.update({k: p[k] for k in _FRICTION_KEYS if p.get(k) is not None})
    keys["friction_root_rule"] = str(p.get("friction_root_rule") or "continuous").lower()
    return FrictionLaw.from_keys(keys)


def _check_gap(p: dict[str, Any]) -> list[str]:
    out = []
    if str(p["gap"]).lower() == "two_bumps":
        if not p["bump_separation"] > 0:
            out.append("gap = 'two_bumps' needs bump_separation > 0 (m)")
        if p["gap_a"] is None or p["gap_b"] is None:
            out.append("gap = 'two_bumps' needs gap_a and gap_b (1/m)")
            return out
    return out


#: Fewest elements the Hertz patch of a 'hertz' gap must span along x and along y: below it
#: the force sits on one or two elements and the pressure is not resolved (fn = 1e-9 N on a
#: 0.2 mm grid gave pmax 6e-9 MPa against Hertz's 0.026).
MIN_PATCH_ELEMENTS = 2


def _resolution(p: dict[str, Any]) -> list[str]:
    """The Hertz patch of a 'hertz' gap under a prescribed fn against the grid's elements."""
    if str(p["gap"]).lower() != "hertz" or p.get("fn") is None:
        return []
    if p.get("semi_a") is not None and p.get("semi_b") is not None:
        a, b, what = p["semi_a"], p["semi_b"], "semi_a, semi_b"
    elif p["gap_a"] is not None and p["gap_b"] is not None:
        material = Material(shear_modulus=p["shear_modulus"], poisson=p["poisson"])
        h = hertz(p["gap_a"], p["gap_b"], p["fn"], material)
        a, b, what = h.a, h.b, f"fn = {p['fn']:g} N with gap_a = {p['gap_a']:g}, gap_b = {p['gap_b']:g} 1/m"
    else:
        return []
    ex, ey = 2.0 * a / p["dx"], 2.0 * b / p["dy"]
    if min(ex, ey) < MIN_PATCH_ELEMENTS:
        return [
            f"the Hertz patch of {what} ({2 * a * 1e3:.3g} x {2 * b * 1e3:.3g} mm) spans {ex:.3g} x "
            f"{ey:.3g} elements of dx = {p['dx']:g} m, dy = {p['dy']:g} m: at least "
            f"{MIN_PATCH_ELEMENTS} along x and y resolve its pressure; make dx, dy smaller"
        ]
    return []


def check_normal(p: dict[str, Any]) -> list[str]:
    """Consistency of a 'normal' case: fn or approach (one), the gap's keys, the Hertz patch
    against the grid."""
    out = _check_gap(p)
    if p["gap_a"] is None or p["gap_b"] is None:
        out.append("give the gap curvatures gap_a and gap_b (1/m)")
    if (p["fn"] is None) == (p["approach"] is None):
        out.append("give exactly one of fn (N) and approach (m)")
    return out or _resolution(p)


def check_rolling(p: dict[str, Any]) -> list[str]:
    """Consistency of a 'rolling' case: curvatures or semi-axes (not both), the gap's keys."""
    out = _check_gap(p)
    curv = [p["gap_a"] is not None, p["gap_b"] is not None]
    semi = [p.get("semi_a") is not None, p.get("semi_b") is not None]
    if any(curv) and any(semi):
        out.append(
            "give the gap curvatures gap_a, gap_b (1/m) or the Hertz semi-axes semi_a, semi_b (m), not both"
        )
    elif not all(curv) and not all(semi):
        out.append("give both gap curvatures gap_a, gap_b (1/m) or both semi-axes semi_a, semi_b (m)")
    if any(semi) and str(p["gap"]).lower() != "hertz":
        out.append("semi_a, semi_b describe a 'hertz' gap only")
    try:
        friction_law_of(p)
    except InputError as exc:
        out.append(str(exc))
    if all(semi):
        ratio = max(p["semi_a"], p["semi_b"]) / min(p["semi_a"], p["semi_b"])
        if ratio > MAX_SEMI_RATIO:
            out.append(
                f"semi_a = {p['semi_a']:g} m and semi_b = {p['semi_b']:g} m: their ratio {ratio:.3g} "
                f"must be <= {MAX_SEMI_RATIO:g} (wheel-rail Hertz ellipses have a/b of about 0.1-10; "
                "beyond 1000 no gap curvatures give the ellipse)"
            )
    return out or _resolution(p)


#: Largest ratio of the Hertz semi-axes semi_a, semi_b of a rolling case.
MAX_SEMI_RATIO = 1000.0


def make_gap(params: dict[str, Any]) -> tuple[Grid, np.ndarray, Material]:
    """Grid, undeformed gap and material of a contact case's parameters."""
    material = Material(shear_modulus=params["shear_modulus"], poisson=params["poisson"])
    grid = Grid(params["nx"], params["ny"], params["dx"], params["dy"], params["x0"], params["y0"])
    kind = str(params["gap"]).lower()
    A, B = params["gap_a"], params["gap_b"]
    if kind == "hertz":
        gap = hertz_gap(grid, A, B)
    elif kind == "two_bumps":
        s = float(params["bump_separation"])
        if s <= 0:
            raise InputError("gap = 'two_bumps' needs bump_separation > 0 (m)")
        x, y = grid.mesh()
        gap = np.minimum(
            A * x**2 + B * (y - s / 2) ** 2, A * x**2 + B * (y + s / 2) ** 2 + float(params["bump_height"])
        )
    else:
        raise InputError(f"gap must be 'hertz' or 'two_bumps', got {params['gap']!r}")
    return grid, np.asfortranarray(gap), material


def run_normal(params: dict[str, Any]) -> CaseOutput:
    """Normal contact on a grid; force ``fn`` (N) or ``approach`` (m) prescribed."""
    params = validate("normal", params)
    grid, gap, material = make_gap(params)
    r = solve_normal(
        gap,
        grid,
        material,
        fn=params["fn"],
        approach=params["approach"],
        method=params["method"],
        tol=params["tol"],
        max_iter=params["max_iter"],
    )
    out = CaseOutput(
        summary=(
            f"Fn = {r.fn / 1e3:.4g} kN, approach = {r.approach * 1e6:.4g} um, "
            f"pmax = {r.pmax / 1e6:.4g} MPa, area = {r.area * 1e6:.4g} mm^2 "
            f"({r.n_contact} elements), {r.method} {r.iterations} it, residual {r.residual:.1e}"
        ),
        datasets={"pressure": (r.pressure, "Pa"), "gap": (gap, "m"), "x": (grid.x, "m"), "y": (grid.y, "m")},
        scalars={
            "fn": (r.fn, "N"),
            "approach": (r.approach, "m"),
            "pmax": (r.pmax, "Pa"),
            "area": (r.area, "m^2"),
            "n_contact": (r.n_contact, "1"),
            "iterations": (r.iterations, "1"),
            "residual": (r.residual, "1"),
            "method": (r.method, ""),
        },
    )
    if str(params["gap"]).lower() == "hertz":
        h = hertz(params["gap_a"], params["gap_b"], r.fn, material)
        out.scalars.update(
            {
                "hertz_a": (h.a, "m"),
                "hertz_b": (h.b, "m"),
                "hertz_p0": (h.p0, "Pa"),
                "hertz_approach": (h.approach, "m"),
            }
        )
        out.summary += f"; Hertz pmax {h.p0 / 1e6:.4g} MPa"
    return out


def plot_pressure(group: Any, outdir: Path, stem: str) -> list[Path]:
    """Pressure map with the contact-area outline."""
    import matplotlib.pyplot as plt

    x = group["x"][()] * 1e3
    y = group["y"][()] * 1e3
    p = group["pressure"][()] / 1e6
    fig, ax = plt.subplots(figsize=(6.0, 4.8))
    dx, dy = x[1] - x[0], y[1] - y[0]
    im = ax.imshow(
        p.T,
        origin="lower",
        cmap="viridis",
        aspect="equal",
        extent=(x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2),
    )
    if (p > 0).any() and (p <= 0).any():
        ax.contour(x, y, (p > 0).T.astype(float), levels=[0.5], colors="w", linewidths=1.0)
    fig.colorbar(im, ax=ax, label="pressure (MPa)")
    ax.set_xlabel("x, rolling direction (mm)")
    ax.set_ylabel("y, lateral (mm)")
    ax.set_title(f"{group.attrs['name']}: Fn = {group['fn'][()] / 1e3:.3g} kN, pmax = {p.max():.0f} MPa")
    return save_figure(fig, outdir / f"{stem}_pressure.png")


register(
    CaseType(
        name="normal",
        defaults={**_COMMON, "fn": None, "approach": None},
        run=run_normal,
        plot=plot_pressure,
        keys=KEYS,
        check=check_normal,
        summary="normal contact of two elastic bodies on a grid (BEM), force or approach given",
    )
)


def _gap_from_semiaxes(a: float, b: float, fn: float, material: Material) -> tuple[float, float]:
    """Gap coefficients (A, B) whose Hertz contact under fn has the semi-axes a (x), b (y)."""
    a = float(a)
    b = float(b)
    if not (a > 0 and b > 0):
        raise InputError(f"semi_a and semi_b must be > 0 (m), got {a}, {b}")
    A = 1.0
    if abs(a / b - 1.0) < 1e-12:
        lb = 0.0
    else:

        def f(x: float) -> float:
            h = hertz(A, A * np.exp(x), fn, material)
            return float(np.log(h.a / h.b) - np.log(a / b))

        lb = brent_root(f, -14.0, 14.0, xtol=1e-12)
    h = hertz(A, A * np.exp(lb), fn, material)
    scale = (h.a / a) ** 3  # a ~ A^(-1/3) at a fixed ratio B/A
    return A * scale, A * np.exp(lb) * scale


def rolling_datasets(r: RollingResult, gap: np.ndarray, grid: Grid) -> dict[str, tuple[Any, str]]:
    """The grid fields every steady-rolling case type stores (HDF5 name -> (array, unit))."""
    return {
        "pressure": (r.pressure, "Pa"),
        "gap": (gap, "m"),
        "x": (grid.x, "m"),
        "y": (grid.y, "m"),
        "tx": (r.tx, "Pa"),
        "ty": (r.ty, "Pa"),
        "status": (r.status, "0 exterior, 1 adhesion, 2 slip"),
        "slip": (r.slip.astype(np.uint8), "1 = slip"),
        "slip_velocity": (r.slip_velocity, "m/s"),
        "power_density": (r.power_density, "W/m^2"),
    }


def run_rolling(params: dict[str, Any]) -> CaseOutput:
    """Steady rolling: normal force ``fn`` (N), friction ``mu``, creepages ``xi``, ``eta`` (1),
    spin ``phi`` (1/m), rolling ``speed`` (m/s). The gap is 'hertz' (``gap_a``, ``gap_b`` in 1/m,
    or the Hertz semi-axes ``semi_a``, ``semi_b`` in m) or 'two_bumps'."""
    params = validate("rolling", params)
    params = dict(params)
    material = Material(shear_modulus=params["shear_modulus"], poisson=params["poisson"])
    if params["gap_a"] is None or params["gap_b"] is None:
        if params["semi_a"] is None or params["semi_b"] is None:
            raise InputError("give the gap curvatures gap_a, gap_b (1/m) or the semi-axes semi_a, semi_b (m)")
        params["gap_a"], params["gap_b"] = _gap_from_semiaxes(
            params["semi_a"], params["semi_b"], params["fn"], material
        )
    grid, gap, material = make_gap(params)
    law = friction_law_of(params)
    creep = (params["xi"], params["eta"], params["phi"])
    n_multiple = 0
    if law is None:
        r = solve_rolling(
            gap,
            grid,
            material,
            params["mu"],
            params["fn"],
            creep,
            params["speed"],
            method=params["method"],
            tol=params["tol"],
            max_iter=params["max_iter"],
            normal_method=params["normal_method"],
        )
    else:
        normal = solve_normal(gap, grid, material, fn=params["fn"], method=params["normal_method"])
        rf = solve_tangential_friction(
            normal.pressure, grid, material, law, creep, params["speed"], method=params["method"],
            tol=params["tol"], max_iter=params["max_iter"],
        )  # fmt: skip
        r, n_multiple = rf.rolling, rf.n_multiple
    n_slip = int(r.slip.sum())
    out = CaseOutput(
        summary=(
            f"Fx = {r.fx / 1e3:.4g} kN, Fy = {r.fy / 1e3:.4g} kN, Mz = {r.mz:.4g} N m, "
            f"|F|/(mu Fn) = {np.hypot(r.fx, r.fy) / (r.mu * r.fn):.4f}, power = {r.power:.4g} W, "
            f"slip {n_slip}/{r.n_contact} elements, {r.method} {r.iterations} sweeps, "
            f"residual {r.residual:.1e}"
        ),
        datasets={
            **rolling_datasets(r, gap, grid),
            "slip_velocity_x": (r.slip_velocity_x, "m/s"),
            "slip_velocity_y": (r.slip_velocity_y, "m/s"),
        },
        scalars={
            "fn": (r.fn, "N"),
            "approach": (r.approach, "m"),
            "fx": (r.fx, "N"),
            "fy": (r.fy, "N"),
            "mz": (r.mz, "N m"),
            "power": (r.power, "W"),
            "pmax": (r.pmax, "Pa"),
            "area": (r.area, "m^2"),
            "n_contact": (r.n_contact, "1"),
            "n_slip": (n_slip, "1"),
            "iterations": (r.iterations, "1"),
            "residual": (r.residual, "1"),
            "method": (r.method, ""),
        },
    )
    if law is not None:
        out.scalars["n_multiple"] = (n_multiple, "elements with several solutions")
        out.summary += f", {law.law} friction law" + (
            f", {n_multiple} elements with several solutions" if n_multiple else ""
        )
    return out


_ROLLING = {k: v for k, v in _COMMON.items() if k not in ("method", "tol", "max_iter")}
_ROLLING.update(
    {
        "gap_a": None,
        "gap_b": None,
        "semi_a": None,
        "semi_b": None,
        "fn": REQUIRED,
        "mu": REQUIRED,
        "xi": 0.0,
        "eta": 0.0,
        "phi": 0.0,
        "speed": REQUIRED,
        "method": "fftgs",
        "tol": 1e-7,
        "max_iter": None,
        "normal_method": "cg",
        "friction_law": None,
        "mu_kinetic": None,
        "friction_halving_speed_m_s": None,
        "polach_a": None,
        "friction_decay_s_m": None,
        "friction_root_rule": "continuous",
    }
)
register(
    CaseType(
        name="rolling",
        defaults=_ROLLING,
        run=run_rolling,
        plot=plot_rolling,
        keys=_KEYS_ROLLING,
        check=check_rolling,
        summary="steady rolling contact: tractions, slip and creep forces",
    )
)

__all__ = [
    "KEYS",
    "MIN_PATCH_ELEMENTS",
    "check_normal",
    "check_rolling",
    "friction_law_of",
    "MAX_SEMI_RATIO",
    "make_gap",
    "run_normal",
    "plot_pressure",
    "rolling_datasets",
    "run_rolling",
]
