"""Deck case type ``type = 'dissimilar_rolling'``: steady rolling of a wheel and a rail of
different materials (railvti.contact.dissimilar; docs/contact_dissimilar.md)."""

from __future__ import annotations

from typing import Any


from ..casetypes import REQUIRED, CaseOutput, CaseType, Key, register, validate
from ..errors import InputError
from .cases import KEYS, rolling_datasets
from .dissimilar import BodyPair, solve_dissimilar_rolling
from .grid import Grid
from .hertz import hertz_gap
from .plots_rolling import plot_rolling

_SHEAR = dict(lo=1e6, hi=1e12, why="steel is 82e9 Pa, aluminium 26e9 Pa, polyamide about 1e9 Pa")
_POISSON = dict(lo=-1.0, hi=0.5, lo_open=True, hi_open=True)

#: Keys of 'dissimilar_rolling': the rolling case's grid, gap, load and kinematics, and each
#: body's material.
KEYS_DISSIMILAR: dict[str, Key] = {
    **{k: KEYS[k] for k in ("nx", "ny", "dx", "dy", "x0", "y0", "fn", "mu", "xi", "eta", "phi", "speed")},
    "gap_a": Key("1/m", "gap curvature along x, 1/(2 R_x)", lo=0.0, hi=1e4, lo_open=True),
    "gap_b": Key("1/m", "gap curvature along y, 1/(2 R_y); 0: a cylinder (plane strain)", lo=0.0, hi=1e4),
    "wheel_shear_modulus": Key(
        "Pa", "shear modulus G1 of the wheel (body 1, carries the tractions)", **_SHEAR
    ),
    "wheel_poisson": Key("1", "Poisson's ratio nu1 of the wheel", **_POISSON),
    "rail_shear_modulus": Key("Pa", "shear modulus G2 of the rail (body 2)", **_SHEAR),
    "rail_poisson": Key("1", "Poisson's ratio nu2 of the rail", **_POISSON),
    "free_rolling": Key("", "1: solve xi for Fx = 0 (xi ignored)", "flag"),
    "method": Key("", "tangential solver: 'fftgs' or 'gs'", "str", choices=("fftgs", "gs")),
    "tol": Key("1", "relative residual of the tangential solves", lo=0.0, hi=0.1, lo_open=True),
    "outer_tol": Key(
        "1",
        "largest change of p, t (over p_max, mu p_max) of the outer iteration",
        lo=0.0,
        hi=0.1,
        lo_open=True,
    ),
    "max_outer": Key("1", "outer (Panagiotopoulos) iteration limit", "int", 1, 1000),
}

_DEFAULTS: dict[str, Any] = {
    "nx": REQUIRED,
    "ny": REQUIRED,
    "dx": REQUIRED,
    "dy": REQUIRED,
    "x0": None,
    "y0": None,
    "gap_a": REQUIRED,
    "gap_b": REQUIRED,
    "fn": REQUIRED,
    "mu": REQUIRED,
    "xi": 0.0,
    "eta": 0.0,
    "phi": 0.0,
    "speed": REQUIRED,
    "wheel_shear_modulus": 82.0e9,
    "wheel_poisson": 0.28,
    "rail_shear_modulus": 82.0e9,
    "rail_poisson": 0.28,
    "free_rolling": 0,
    "method": "fftgs",
    "tol": 1e-7,
    "outer_tol": 1e-6,
    "max_outer": 30,
}


def run_dissimilar_rolling(params: dict[str, Any]) -> CaseOutput:
    """Steady rolling of a dissimilar pair: normal force ``fn`` (N), friction ``mu``, creepages
    ``xi``, ``eta`` (1), spin ``phi`` (1/m), ``speed`` (m/s), gap ``gap_a x^2 + gap_b y^2`` (1/m),
    the wheel's and the rail's shear modulus (Pa) and Poisson's ratio."""
    params = validate("dissimilar_rolling", params)
    pair = BodyPair.from_constants(
        params["wheel_shear_modulus"],
        params["wheel_poisson"],
        params["rail_shear_modulus"],
        params["rail_poisson"],
    )
    grid = Grid(params["nx"], params["ny"], params["dx"], params["dy"], params["x0"], params["y0"])
    gap = hertz_gap(grid, params["gap_a"], params["gap_b"])
    if params["gap_b"] == 0.0:
        if grid.ny < 4:
            raise InputError(
                "gap_b = 0 (plane strain) needs ny >= 4: the first and last rows stay out of contact"
            )
        gap[:, [0, -1]] = 1.0  # a strip: the outer rows out of contact
    res = solve_dissimilar_rolling(
        gap,
        grid,
        pair,
        params["mu"],
        params["fn"],
        (params["xi"], params["eta"], params["phi"]),
        params["speed"],
        free_rolling=bool(params["free_rolling"]),
        method=params["method"],
        tol=params["tol"],
        outer_tol=params["outer_tol"],
        max_outer=params["max_outer"],
    )
    r = res.rolling
    n_slip = int(r.slip.sum())
    return CaseOutput(
        summary=(
            f"beta = {pair.beta:.4f}, K = {pair.difference_parameter:.4f}, xi = {res.creepage[0]:.5g}, "
            f"Fx = {r.fx / 1e3:.4g} kN, Fy = {r.fy / 1e3:.4g} kN, pmax = {r.pmax / 1e6:.4g} MPa, "
            f"slip {n_slip}/{r.n_contact} elements, {res.outer_iterations} outer iterations"
        ),
        datasets=rolling_datasets(r, gap, grid),
        scalars={
            "fn": (r.fn, "N"),
            "fx": (r.fx, "N"),
            "fy": (r.fy, "N"),
            "mz": (r.mz, "N m"),
            "power": (r.power, "W"),
            "xi": (res.creepage[0], "1"),
            "pmax": (r.pmax, "Pa"),
            "n_contact": (r.n_contact, "1"),
            "n_slip": (n_slip, "1"),
            "beta": (pair.beta, "1"),
            "difference_parameter": (pair.difference_parameter, "1"),
            "combined_shear_modulus": (pair.shear_modulus, "Pa"),
            "combined_poisson": (pair.poisson, "1"),
            "outer_iterations": (res.outer_iterations, "1"),
            "outer_change": (res.outer_change, "1"),
        },
    )


register(
    CaseType(
        name="dissimilar_rolling",
        defaults=_DEFAULTS,
        run=run_dissimilar_rolling,
        plot=plot_rolling,
        keys=KEYS_DISSIMILAR,
        summary="steady rolling of a wheel and a rail of different materials (normal-tangential coupling)",
    )
)

__all__ = ["KEYS_DISSIMILAR", "run_dissimilar_rolling"]
