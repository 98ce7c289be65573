"""railvti's friction laws against CONTACT's own reference outputs (an independent code).

CONTACT (E.A.H. Vollebregt, Vtech CMCC, Apache-2.0) ships example inputs with their outputs;
the forces used here are transcribed in tests/data/contact_friction_contact_ref.csv (source
files and commit named in its header):

* ``tractcurv`` (the Eurosprinter test case after Polach 2005 / Vollebregt 2014): Hertz
  contact A1 = 0.8e-3 /mm with a/b = 0.5 (IPOTCN -2: Hertzian geometry given by the curvature
  A1 and the ratio a/b, FN prescribed, a 48 x 44 grid over SCALE = 1.1 times the semi-axes),
  FN = 106.7 kN, V = 10 m/s, G = 82 GPa, nu = 0.28.
  Series 1: BEM steady rolling, Coulomb mu = 0.33 -> railvti's ``solve_tangential`` on the
  same grid and pressure. Series 3: original FASTSIM, mu = 0.33 -> ``fastsim_friction`` with a
  constant law. Series 4: CONTACT's modified FASTSIM with the exponential law L=4 (FKIN
  0.1368, FEXP1 0.2232, SABSH1 990 mm/s, i.e. mu = FKIN + FEXP1 2^(-s / SABSH1), which is
  railvti's ``exponential`` law with mu_static 0.36, mu_kinetic 0.1368, v_h 0.99 m/s) and a
  slope reduction K_EFF(creepage) printed per case -> ``fastsim_friction`` with
  ``slope_reduction = K_EFF`` (railvti divides all flexibilities by it), the same with no
  reduction, and the BEM with the same law. Series 2 needs CONTACT's interfacial layer,
  which railvti does not have: not compared.
* ``veldep_fric`` case 1: 2-D steady rolling (92 elements of 0.1 mm, one 200 mm wide row),
  wheel R 460 mm on a flat rail, FN 622 kN, V 45 m/s, creepage -0.1 %, exponential law
  FKIN 0.18, FEXP1 0.12, SABSH1 100 mm/s -> railvti's BEM with the same row between two
  empty rows (railvti needs ny >= 2 and no contact on the lateral grid edges). Its transient
  cases (time steps from other initial states) are not compared.

Prints, per case, CONTACT's |Fx| / (mu_static Fn), railvti's and the difference, railvti's
time per case on this machine (best of 3) and the load, and draws
validation/figures/contact_friction_contact_ref.png.

Run: ``PYTHONPATH=_site python validation/contact_friction_contact_ref.py``
"""

from __future__ import annotations

import csv
import os
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from railvti.contact import Grid, hertz, hertz_gap, solve_normal, solve_tangential
from railvti.contact.friction import FrictionLaw, fastsim_friction, solve_tangential_friction
from railvti.material import Material

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "contact_friction_contact_ref.csv"
FIG = Path(__file__).resolve().parent / "figures" / "contact_friction_contact_ref.png"

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN_T = 106700.0  # N, tractcurv
V_T = 10.0  # m/s
A1 = 0.8  # 1/m (0.8e-3 /mm)
MU_C = 0.33
LAW4 = FrictionLaw("exponential", 0.36, 0.1368, 0.990)  # FKIN + FEXP1, FKIN, SABSH1 (m/s)
FN_V = 622216.0  # N, veldep_fric
V_V = 45.0  # m/s
LAW_V = FrictionLaw("exponential", 0.30, 0.18, 0.100)


def load_reference(path: Path = DATA) -> list[dict]:
    """The reference rows (comment lines skipped), numbers as floats."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for r in rows:
        r["series"] = int(r["series"])
        r["case"] = int(r["case"])
        r["xi"] = float(r["xi"])
        r["k_eff"] = float(r["k_eff"]) if r["k_eff"] else None
        r["fx_fstat_fn"] = float(r["fx_fstat_fn"])
    return rows


def tractcurv_setup():
    """CONTACT's IPOTCN -2 geometry: B from a/b = 0.5, the 48 x 44 grid over 1.1 x the semi-axes."""

    def ratio(b_curv: float) -> float:
        h = hertz(A1, b_curv, FN_T, MAT)
        return h.a / h.b - 0.5

    b_curv = brentq(ratio, 0.05, 0.8, xtol=1e-14)
    h = hertz(A1, b_curv, FN_T, MAT)
    grid = Grid(48, 44, 2.2 * h.a / 48, 2.2 * h.b / 44)
    normal = solve_normal(hertz_gap(grid, A1, b_curv), grid, MAT, fn=FN_T)
    return h, grid, normal


def veldep_setup():
    """CONTACT's 92 x 1 row (dx 0.1 mm, dy 200 mm) between two empty rows, circular wheel R 460 mm."""
    grid = Grid(92, 3, 0.1e-3, 0.2, x0=-4.6e-3, y0=-0.2)
    x, _ = grid.mesh()
    gap = np.asfortranarray(0.46 - np.sqrt(0.46**2 - x * x))
    gap[:, 0] = 1.0
    gap[:, 2] = 1.0
    return grid, solve_normal(gap, grid, MAT, fn=FN_V)


def railvti_value(row: dict, setup_t, setup_v, variant: str = "as_mapped") -> float:
    """railvti's |Fx| / (mu_static Fn) for one reference row.

    variant: 'as_mapped' (series 4: slope_reduction = K_EFF), 'no_reduction' (series 4 with
    slope_reduction = 1) or 'bem' (series 4's law on the BEM).
    """
    h, grid, normal = setup_t
    s, xi = row["series"], row["xi"]
    if s == 1:
        r = solve_tangential(normal.pressure, grid, MAT, MU_C, (xi, 0.0, 0.0), V_T)
        return abs(r.fx) / (MU_C * FN_T)
    if s == 3:
        fx = fastsim_friction(h.a, h.b, MAT, FrictionLaw.constant(MU_C), FN_T, (xi, 0, 0), V_T, nx=48, ny=44)[
            0
        ]
        return abs(fx[0]) / (MU_C * FN_T)
    if s == 4 and variant == "bem":
        r = solve_tangential_friction(normal.pressure, grid, MAT, LAW4, (xi, 0.0, 0.0), V_T)
        return abs(r.fx) / (0.36 * FN_T)
    if s == 4:
        k = row["k_eff"] if variant == "as_mapped" else 1.0
        fx = fastsim_friction(h.a, h.b, MAT, LAW4, FN_T, (xi, 0, 0), V_T, slope_reduction=k, nx=48, ny=44)[0]
        return abs(fx[0]) / (0.36 * FN_T)
    grid_v, normal_v = setup_v
    r = solve_tangential_friction(normal_v.pressure, grid_v, MAT, LAW_V, (xi, 0.0, 0.0), V_V)
    return abs(r.fx) / (0.30 * FN_V)


def _timed(fn, reps: int = 3) -> tuple[float, float]:
    best = np.inf
    for _ in range(reps):
        t = time.perf_counter()
        value = fn()
        best = min(best, time.perf_counter() - t)
    return value, best


def main() -> None:
    rows = load_reference()
    setup_t, setup_v = tractcurv_setup(), veldep_setup()
    print(f"load before: {os.getloadavg()[0]:.2f} (2 shared cores)")
    print("| source | series | case | xi | CONTACT | railvti | diff | railvti ms/case |")
    print("|---|---|---|---|---|---|---|---|")
    results = []
    for row in rows:
        variants = ("as_mapped", "no_reduction", "bem") if row["series"] == 4 else ("as_mapped",)
        for var in variants:
            value, sec = _timed(lambda: railvti_value(row, setup_t, setup_v, var))
            diff = value - row["fx_fstat_fn"]
            label = {"as_mapped": "", "no_reduction": " (k=1)", "bem": " (BEM)"}[var]
            results.append((row, var, value))
            print(
                f"| {row['source']} | {row['series']}{label} | {row['case']} | {row['xi']:g} | "
                f"{row['fx_fstat_fn']:.4f} | {value:.4f} | {diff:+.4f} | {sec * 1e3:.2f} |"
            )
    print(f"load after: {os.getloadavg()[0]:.2f}")
    _plot(results)


def _plot(results) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    styles = {
        (1, "as_mapped"): ("C0", "o", "BEM, Coulomb 0.33 (series 1)"),
        (3, "as_mapped"): ("C1", "s", "FASTSIM, Coulomb 0.33 (series 3)"),
        (4, "as_mapped"): ("C2", "^", "FASTSIM, falling, slope K_EFF (series 4)"),
        (4, "no_reduction"): ("C3", "v", "FASTSIM, falling, no slope reduction"),
        (4, "bem"): ("C4", "D", "BEM, falling friction"),
    }
    for (series, var), (color, marker, label) in styles.items():
        sel = [(r["xi"], r["fx_fstat_fn"], v) for r, vv, v in results if r["series"] == series and vv == var]
        if not sel:
            continue
        xs, ref, val = (np.array(t) for t in zip(*sel))
        ax.semilogx(xs * 100, val, color=color, marker=marker, ls="-", lw=1, ms=5, label=f"railvti: {label}")
        if var == "as_mapped":
            ax.semilogx(
                xs * 100,
                ref,
                color=color,
                marker=marker,
                ls="none",
                ms=10,
                mfc="none",
                label=f"CONTACT ({series})",
            )
    ax.set_xlabel("longitudinal creepage xi, %")
    ax.set_ylabel("|Fx| / (mu_static Fn)")
    ax.set_title("tractcurv (Eurosprinter, 48 x 44): railvti (lines) vs CONTACT ref_out (open markers)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    FIG.parent.mkdir(exist_ok=True)
    fig.savefig(FIG, dpi=120)
    print(f"wrote {FIG.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
