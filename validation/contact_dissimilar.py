"""Dissimilar materials (issue 35, deliver 2): Spence's progressive compression and the
Bentall-Johnson free rolling of dissimilar cylinders against the published results, with the
time per case beside the quasi-identical solve's.

* Spence (1975): a sphere (G1, nu1 = 0) pressed progressively onto a rigid half-space with
  friction mu keeps a central stick zone of constant c/a. Published point: beta = 0.5,
  mu = 0.2986 (beta/mu = 1.6745) gives c/a = 0.5 (Spence 1975; Kalker 1990 sect. 5.3.1;
  CONTACT's example spence35). The curve c/a(beta/mu) at beta = 0.5 is railvti's (31 x 31
  elements, the radius growing one element per step over 25 steps; c/a from the adhesion and
  contact areas, mean of the last 5 steps); the published point is also solved on 45 x 45
  elements in 35 steps, as CONTACT's example.
* Bentall and Johnson (1967): aluminium (23 GPa, 0.31) on steel (82 GPa, 0.28), a = 0.1 mm,
  R = 25 mm, plane strain (a strip of 200 elements across the patch, dy = 1000 a), free
  rolling Fx = 0. Theory at vanishing friction: xi = 0.457 kappa a / R, kappa = 2 beta, the
  traction -mu p sgn(s) reversing at |x| = 0.404 a. CONTACT's user guide (sect. 'The 2D
  Bentall-Johnson test-case') reports xi = 5.260e-4, 4.29e-4, 3.59e-4 at mu = 1e-4, 0.05,
  10 and the peak pressure 103.14 -> 103.81 MPa.

Run: PYTHONPATH=_site python validation/contact_dissimilar.py [--quick]
Writes validation/figures/contact_dissimilar.png.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np

from railvti import Material
from railvti.contact import Grid, hertz_gap, solve_normal, solve_rolling
from railvti.contact.dissimilar import BodyPair, solve_dissimilar_rolling, solve_progressive_compression

HERE = Path(__file__).resolve().parent
SPENCE_POINT = (0.5 / 0.2986, 0.5)  # (beta/mu, c/a), Spence 1975 via Kalker 1990 / CONTACT
BJ_CONTACT = {1e-4: 5.260e-4, 0.05: 4.29e-4, 10.0: 3.59e-4}  # CONTACT user guide
A_BJ, R_BJ = 1.0e-4, 0.025


def spence_case(mu: float, n: int, steps: int, pair: BodyPair | None = None, normal_coupling: bool = True):
    """(c/a, seconds, seconds of the same steps' decoupled normal solves, the result)."""
    pair = pair or BodyPair(Material(0.5e9, 0.0), Material(0.5e14, 0.0))
    R, dx = 0.1215, 2.0e-4
    grid = Grid(n, n, dx, dx)
    gap = hertz_gap(grid, 1 / (2 * R), 1 / (2 * R))
    a_end = dx * steps / 2
    fns = [4 * (a_end * k / steps) ** 3 * pair.contact_modulus / (3 * R) for k in range(1, steps + 1)]
    t = time.perf_counter()
    res = solve_progressive_compression(
        gap, grid, pair, mu, fns, outer_tol=1e-5, normal_coupling=normal_coupling
    )
    t_dis = time.perf_counter() - t
    t = time.perf_counter()
    for fn in fns:
        solve_normal(gap, grid, pair.combined, fn=fn, tol=1e-9)
    t_qi = time.perf_counter() - t
    return float(res.stick_ratio[-5:].mean()), t_dis, t_qi, res


def bentall_case(mu: float, n: int = 200):
    pair = BodyPair(Material(23.0e9, 0.31), Material(82.0e9, 0.28))
    dx = 2 * A_BJ / n
    grid = Grid(int(round(2.16 * A_BJ / dx)), 4, dx, 1000 * A_BJ)
    gap = hertz_gap(grid, 1 / (2 * R_BJ), 0.0)
    gap[:, [0, 3]] = 1.0
    fn = 2 * grid.dy * math.pi * A_BJ**2 * pair.contact_modulus / (4 * R_BJ)
    t = time.perf_counter()
    res = solve_dissimilar_rolling(gap, grid, pair, mu, fn, (0, 0, 0), 10.0, free_rolling=True)
    t_dis = time.perf_counter() - t
    t = time.perf_counter()
    solve_rolling(gap, grid, pair.combined, mu, fn, res.creepage, 10.0)
    t_qi = time.perf_counter() - t
    return pair, grid, res, t_dis, t_qi


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer points on the Spence curve")
    args = ap.parse_args()
    print(f"load average {os.getloadavg()}")

    ratios = [0.25, 0.5, 1.0, SPENCE_POINT[0], 2.5, 4.0] if args.quick else [
        0.25, 0.375, 0.5, 0.75, 1.0, 1.25, SPENCE_POINT[0], 2.0, 2.5, 3.0, 4.0, 6.0
    ]  # fmt: skip
    print("Spence: beta = 0.5, sphere nu = 0 on a rigid plane, 31 x 31 elements, 25 steps")
    print(" beta/mu     mu     c/a   time (s)  decoupled normal solves (s)")
    curve = []
    for r in ratios:
        ca, t_dis, t_qi, _ = spence_case(0.5 / r, 31, 25)
        curve.append(ca)
        print(f"{r:8.4f} {0.5 / r:7.4f} {ca:7.4f} {t_dis:9.2f} {t_qi:9.2f}")
    ca45, t45, tq45, res45 = spence_case(0.2986, 45, 35)
    print(
        f"published point beta/mu = {SPENCE_POINT[0]:.4f}: Spence c/a = 0.5; railvti 45 x 45 / 35 steps "
        f"{ca45:.4f} ({100 * (ca45 / 0.5 - 1):+.1f} %), {t45:.1f} s (decoupled normal solves {tq45:.1f} s), "
        f"outer iterations per step {res45.outer_iterations[-1]}, Gauss-Seidel sweeps {res45.sweeps}"
    )

    print("\nc/a at beta/mu = 1.6745, full coupling against Johnson's process (31 x 31, 25 steps)")
    for w, r in (
        (Material(0.5e9, 0.0), Material(0.5e14, 0.0)),
        (Material(1e9, 0.25), Material(1e14, 0.25)),
        (Material(23.0e9, 0.31), Material(82.0e9, 0.28)),
    ):
        pair = BodyPair(w, r)
        mu = pair.beta / SPENCE_POINT[0]
        full = spence_case(mu, 31, 25, pair)[0]
        decoupled = spence_case(mu, 31, 25, pair, normal_coupling=False)[0]
        print(
            f"  beta {pair.beta:.3f} nu {pair.poisson:.3f}: full {full:.4f}  Johnson's process {decoupled:.4f}"
        )

    print("\nBentall-Johnson: aluminium on steel, free rolling, 200 elements across 2a")
    rows = {}
    for mu in (1e-4, 0.05, 10.0):
        pair, grid, res, t_dis, t_qi = bentall_case(mu)
        rows[mu] = (grid, res)
        xi = abs(res.creepage[0])
        print(
            f"mu = {mu:g}: |xi| = {xi:.4e} (CONTACT {BJ_CONTACT[mu]:.4e}, {100 * (xi / BJ_CONTACT[mu] - 1):+.2f} %), "
            f"pmax {res.rolling.pmax / 1e6:.2f} MPa, outer {res.outer_iterations}, "
            f"{t_dis:.2f} s (quasi-identical solve at that xi {t_qi:.2f} s)"
        )
    theory = 0.457 * 2 * pair.beta * A_BJ / R_BJ
    grid, res = rows[1e-4]
    tx = res.rolling.tx[:, 1]
    flips = grid.x[:-1][np.diff(np.sign(tx)) != 0] + grid.dx / 2
    flips = flips[np.abs(flips) < 0.9 * A_BJ] / A_BJ
    print(
        f"theory mu -> 0: |xi| = 0.457 kappa a/R = {theory:.4e}; railvti {abs(res.creepage[0]):.4e} "
        f"({100 * (abs(res.creepage[0]) / theory - 1):+.2f} %); slip reversal at x/a = "
        f"{', '.join(f'{f:+.3f}' for f in flips)} (theory +-0.404)"
    )
    plot(ratios, curve, ca45, rows, pair)


def plot(ratios, curve, ca45, rows, pair) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(16.0, 4.8))
    a1.plot(ratios, curve, "o-", label="railvti BEM, 31 x 31, 25 load steps")
    a1.plot([SPENCE_POINT[0]], [ca45], "s", color="C2", label="railvti BEM, 45 x 45, 35 load steps")
    a1.plot(
        [SPENCE_POINT[0]], [SPENCE_POINT[1]], "*", ms=14, color="C3", label="Spence (1975), via Kalker (1990)"
    )
    a1.set_xscale("log")
    a1.set_xticks([0.25, 0.5, 1, 2, 4, 6])
    a1.xaxis.set_major_formatter(ScalarFormatter())
    a1.xaxis.set_minor_formatter(NullFormatter())
    a1.set_xlabel("beta / mu (1)")
    a1.set_ylabel("stick-zone radius c / a (1)")
    a1.set_ylim(0, 1.05)
    a1.set_title("Spence: sphere (nu = 0) on a rigid plane, beta = 0.5")
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=8)

    grid, res = rows[1e-4]
    p = res.rolling.pressure[:, 1]
    x = grid.x / A_BJ
    a2.plot(x, res.rolling.tx[:, 1] / (1e-4 * p.max()), label=f"railvti, xi = {res.creepage[0]:.4e}")
    a2.plot(x, p / p.max(), "k--", lw=0.8, label="+- p / p_max")
    a2.plot(x, -p / p.max(), "k--", lw=0.8)
    for x0 in (-0.404, 0.404):
        a2.axvline(x0, color="C3", lw=0.8, ls=":")
    a2.set_xlim(-1.2, 1.2)
    a2.set_xlabel("x / a (particles move in -x)")
    a2.set_ylabel("t_x on the aluminium wheel / (mu p_max) (1)")
    a2.set_title(
        "Bentall-Johnson, mu = 1e-4: complete slip; dotted: theory's reversal at +-0.404 a", fontsize=9
    )
    a2.grid(True, alpha=0.3)
    a2.legend(fontsize=8, loc="lower left")

    for mu in (0.05, 10.0):
        grid, res = rows[mu]
        p = res.rolling.pressure[:, 1]
        a3.plot(
            grid.x / A_BJ, res.rolling.tx[:, 1] / p.max(), label=f"mu = {mu:g}, xi = {res.creepage[0]:.3e}"
        )
    grid, res = rows[0.05]
    p = res.rolling.pressure[:, 1]
    a3.plot(grid.x / A_BJ, 0.05 * p / p.max(), "k--", lw=0.8, label="+- 0.05 p / p_max")
    a3.plot(grid.x / A_BJ, -0.05 * p / p.max(), "k--", lw=0.8)
    a3.set_xlim(-1.2, 1.2)
    a3.set_xlabel("x / a (particles move in -x)")
    a3.set_ylabel("t_x on the aluminium wheel / p_max (1)")
    a3.set_title(f"Bentall-Johnson free rolling, Al on steel (beta = {pair.beta:.3f})", fontsize=9)
    a3.grid(True, alpha=0.3)
    a3.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    out = HERE / "figures" / "contact_dissimilar.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
