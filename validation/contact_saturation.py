"""Saturation of the creep force (issue 3, validation c) and creep-force curves.

Pure longitudinal creepage xi = 0.05 on Hertzian patches (BEM normal solution,
then steady rolling): |Fx| must be within 0.5 % of mu Fn. The chart shows
Fx / (mu Fn) against the normalised creepage G a b C11 xi / (mu Fn) for
a/b = 0.2, 1, 5 with Kalker's linear slope (Table E.3, nu = 0.25) beside it.

Run: .venv/bin/python validation/contact_saturation.py [--quick]
Writes validation/figures/contact_rolling_saturation.png.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from contact_kalker_linear import FN, MAT, gap_for_ratio, kalker_table  # noqa: E402

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n = 10 if args.quick else 20
    print(f"Saturation, xi = 0.05, {n} elements on the shorter semi-axis")
    print(
        f"{'a/b':>5} {'mu':>5} {'|Fx|/(mu Fn)':>13} {'err %':>8} {'slip elements':>14} {'sweeps':>6} {'s':>6}"
    )
    worst = 0.0
    curves = {}
    for g in (0.2, 1.0, 5.0):
        A, B = gap_for_ratio(g)
        h = hertz(A, B, FN, MAT)
        grid = Grid.covering(h.a, h.b, n, 1.2)
        gap = hertz_gap(grid, A, B)
        for mu in (0.1, 0.3, 0.6):
            t0 = time.perf_counter()
            r = solve_rolling(gap, grid, MAT, mu, FN, (0.05, 0.0, 0.0), 1.0)
            ratio = abs(r.fx) / (mu * r.fn)
            worst = max(worst, abs(ratio - 1))
            print(
                f"{g:5.2f} {mu:5.2f} {ratio:13.6f} {100 * (ratio - 1):8.4f} {int(r.slip.sum()):>7d}/{r.n_contact:<6d}"
                f" {r.iterations:6d} {time.perf_counter() - t0:6.2f}"
            )
        # creep-force curve, mu = 0.3
        c11 = kalker_table(g)[0]
        scale = MAT.shear_modulus * h.a * h.b * c11 / (0.3 * FN)
        xs = np.geomspace(0.02, 4.0, 14) / scale
        t = None
        ys = []
        for xi in xs:
            r = solve_rolling(gap, grid, MAT, 0.3, FN, (xi, 0.0, 0.0), 1.0, t0=t)
            t = (r.tx, r.ty)
            ys.append(-r.fx / (0.3 * r.fn))
        curves[g] = (xs * scale, np.array(ys))
    print(f"largest |Fx|/(mu Fn) - 1 at xi = 0.05: {100 * worst:.4f} % (acceptance 0.5 %)")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for g, (xn, y) in curves.items():
        ax.plot(xn, y, "o-", ms=3, label=f"BEM, a/b = {g}")
    xx = np.linspace(0, 1.2, 50)
    ax.plot(xx, xx, "k:", lw=0.8, label="Kalker linear (C11)")
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set_xscale("log")
    ax.set_xlabel(r"$G a b C_{11} \xi / (\mu F_n)$")
    ax.set_ylabel(r"$-F_x / (\mu F_n)$")
    ax.set_ylim(0, 1.1)
    ax.set_title(f"Creep force curves, mu = 0.3, {n} elements per semi-axis")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out = HERE / "figures" / "contact_rolling_saturation.png"
    fig.savefig(out, dpi=100)
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
