"""Kalker's linear theory from the steady rolling BEM solver (issue 3, validation b).

Tiny creepages with a large friction coefficient (full adhesion) on Hertzian
patches with a/b in {0.2, 0.5, 1, 2, 5}, Hertz's pressure prescribed at the
element centres (so the contact area is the exact ellipse, digitised, and the
tangential solver alone is tested; with the BEM pressure the digitised area
of the normal solution adds +-1 % that does not vanish smoothly); the creep
coefficients
    C11 = -Fx / (G a b xi),  C22 = -Fy / (G a b eta),  C23 = -Fy / (G (a b)^1.5 phi)
are compared with Kalker (1990), Table E.3, nu = 0.25
(python/railvti/data/kalker_table_e3.csv). Each case is solved on two grids
(n and 2n elements on the shorter semi-axis) and extrapolated to zero element
size assuming first-order convergence (Richardson: 2 C(2n) - C(n)).

Run: .venv/bin/python validation/contact_kalker_linear.py  [--quick]
Writes validation/figures/contact_rolling_kalker.png.
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling, solve_tangential
from railvti.material import Material

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
TABLE = ROOT / "python" / "railvti" / "data" / "kalker_table_e3.csv"
MAT = Material(shear_modulus=82.0e9, poisson=0.25)
FN = 10.0e3
MU = 1.0e3  # full adhesion
EPS = 1.0e-6  # creepage xi, eta; spin EPS / sqrt(a b)


def kalker_table(a_over_b: float) -> tuple[float, float, float]:
    """(C11, C22, C23) at nu = 0.25 from Table E.3, linear in a/b between rows."""
    rows = [r for r in csv.reader(line for line in TABLE.open() if not line.startswith("#"))]
    head, data = rows[0], np.array(rows[1:], dtype=float)
    col = {name: data[:, head.index(name)] for name in head}
    g = col["a_over_b"]
    return tuple(float(np.interp(a_over_b, g, col[k])) for k in ("c11_nu025", "c22_nu025", "c23_nu025"))


def gap_for_ratio(a_over_b: float) -> tuple[float, float]:
    """Gap coefficients (A, B) whose Hertz ellipse has the ratio a/b."""
    A = 0.5 / 0.3

    def f(lb: float) -> float:
        h = hertz(A, A * np.exp(lb), FN, MAT)
        return np.log(h.a / h.b) - np.log(a_over_b)

    if abs(a_over_b - 1.0) < 1e-12:
        return A, A
    lb = brentq(f, -12.0, 12.0, xtol=1e-12)
    return A, A * float(np.exp(lb))


def coefficients_bem(a_over_b: float, n: int) -> np.ndarray:
    """The same end to end: BEM normal solution (solve_rolling) instead of Hertz's pressure."""
    A, B = gap_for_ratio(a_over_b)
    h = hertz(A, B, FN, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.15)
    gap = hertz_gap(grid, A, B)
    G, ab = MAT.shear_modulus, h.a * h.b
    phi = EPS / np.sqrt(ab)
    return np.array(
        [
            -solve_rolling(gap, grid, MAT, MU, FN, (EPS, 0.0, 0.0), 1.0).fx / (G * ab * EPS),
            -solve_rolling(gap, grid, MAT, MU, FN, (0.0, EPS, 0.0), 1.0).fy / (G * ab * EPS),
            -solve_rolling(gap, grid, MAT, MU, FN, (0.0, 0.0, phi), 1.0).fy / (G * ab**1.5 * phi),
        ]
    )


def coefficients(a_over_b: float, n: int, method: str = "fftgs") -> tuple[np.ndarray, float, int]:
    A, B = gap_for_ratio(a_over_b)
    h = hertz(A, B, FN, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.1)
    p = h.pressure(grid)
    G, ab = MAT.shear_modulus, h.a * h.b
    t0 = time.perf_counter()
    phi = EPS / np.sqrt(ab)
    rx = solve_tangential(p, grid, MAT, MU, (EPS, 0.0, 0.0), 1.0, method=method)
    ry = solve_tangential(p, grid, MAT, MU, (0.0, EPS, 0.0), 1.0, method=method)
    rs = solve_tangential(p, grid, MAT, MU, (0.0, 0.0, phi), 1.0, method=method)
    dt = time.perf_counter() - t0
    c = np.array([-rx.fx / (G * ab * EPS), -ry.fy / (G * ab * EPS), -rs.fy / (G * ab**1.5 * phi)])
    return c, dt, rx.n_contact


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="coarser grids")
    ap.add_argument(
        "--bem",
        action="store_true",
        help="also end to end with the BEM pressure (solve_rolling) on the fine grid",
    )
    args = ap.parse_args()
    n1 = 8 if args.quick else 16
    ratios = [0.2, 0.5, 1.0, 2.0, 5.0]
    names = ("C11", "C22", "C23")
    results = []
    print(f"Kalker linear theory, nu = 0.25, grids n = {n1} and {2 * n1} elements on the shorter semi-axis")
    print(
        f"{'a/b':>5} {'coef':>4} {'table':>7} {'n':>8} {'2n':>8} {'Richardson':>10} {'err 2n %':>9} {'err R %':>8}"
    )
    for g in ratios:
        ref = kalker_table(g)
        c1, t1, _ = coefficients(g, n1)
        c2, t2, nc = coefficients(g, 2 * n1)
        cr = 2.0 * c2 - c1
        results.append((g, ref, c1, c2, cr, nc, t2))
        for k in range(3):
            e2 = 100 * (c2[k] / ref[k] - 1)
            er = 100 * (cr[k] / ref[k] - 1)
            print(
                f"{g:5.2f} {names[k]:>4} {ref[k]:7.3f} {c1[k]:8.3f} {c2[k]:8.3f} {cr[k]:10.3f} {e2:9.2f} {er:8.2f}"
            )
        print(f"      ({nc} elements in contact on the fine grid, 3 solves in {t2:.2f} s)")
    worst2 = max(abs(r[3][k] / r[1][k] - 1) for r in results for k in range(3))
    worstr = max(abs(r[4][k] / r[1][k] - 1) for r in results for k in range(3))
    print(
        f"largest deviation: fine grid {100 * worst2:.2f} %, extrapolated {100 * worstr:.2f} % (acceptance 2 %)"
    )
    if args.bem:
        worst = 0.0
        print(f"\nend to end (solve_rolling, BEM pressure), n = {2 * n1}")
        for g in ratios:
            ref = kalker_table(g)
            c = coefficients_bem(g, 2 * n1)
            worst = max(worst, max(abs(c[k] / ref[k] - 1) for k in range(3)))
            print(
                f"{g:5.2f} "
                + "  ".join(f"{names[k]} {c[k]:.3f} ({100 * (c[k] / ref[k] - 1):+.2f} %)" for k in range(3))
            )
        print(f"largest deviation end to end: {100 * worst:.2f} % (acceptance 2 %)")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gg = np.linspace(0.2, 5.0, 200)
    tab = np.array([kalker_table(x) for x in gg])
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for k, (name, col) in enumerate(zip(names, ("C0", "C1", "C2"))):
        ax.plot(gg, tab[:, k], color=col, lw=1.2, label=f"{name} Kalker Table E.3")
        ax.plot(
            [r[0] for r in results],
            [r[3][k] for r in results],
            "o",
            mfc="none",
            color=col,
            label=f"{name} BEM, n = {2 * n1}",
        )
        ax.plot(
            [r[0] for r in results],
            [r[4][k] for r in results],
            "x",
            color=col,
            label=f"{name} BEM, extrapolated",
        )
    ax.set_xscale("log")
    ax.set_xticks(ratios, [f"{r:g}" for r in ratios])
    ax.minorticks_off()
    ax.set_xlabel("a/b")
    ax.set_ylabel("creep coefficient")
    ax.set_title("Kalker's linear theory, nu = 0.25: table vs steady-rolling BEM")
    ax.legend(fontsize=7, ncol=3)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out = HERE / "figures" / "contact_rolling_kalker.png"
    fig.savefig(out, dpi=100)
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
