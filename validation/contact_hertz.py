"""Normal contact against Hertz: errors of Fn, p0, a, b and solve times, for
A/B = 1, 0.5, 0.2, 0.1 on grids from coarse to fine, for the preconditioned
CG and Gauss-Seidel solvers. Writes a table (markdown) and the chart
validation/figures/contact_hertz_error_vs_time.png (speed against accuracy).

    python validation/contact_hertz.py [--quick]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti import STEEL  # noqa: E402
from railvti.contact import Grid, hertz, hertz_gap, solve_normal  # noqa: E402

FIG = Path(__file__).parent / "figures"
FN = 1.0e4


def semi_axes(r):
    x, y = r.grid.mesh()
    c = r.contact
    return np.abs(x[c]).max() + r.grid.dx / 2, np.abs(y[c]).max() + r.grid.dy / 2


def run_case(ratio, n, method):
    ref = hertz(ratio, 1.0, FN, STEEL)
    grid = Grid.covering(ref.a, ref.b, n_per_semiaxis=n, margin=1.2)
    gap = hertz_gap(grid, ratio, 1.0)
    t0 = time.perf_counter()
    rf = solve_normal(gap, grid, STEEL, fn=FN, method=method)
    t_force = time.perf_counter() - t0
    ra = solve_normal(gap, grid, STEEL, approach=ref.approach, method=method)
    a, b = semi_axes(rf)
    return dict(
        ratio=ratio,
        n=n,
        method=method,
        elements=grid.nx * grid.ny,
        in_contact=rf.n_contact,
        err_fn=ra.fn / FN - 1,
        err_p0=rf.pmax / ref.p0 - 1,
        err_a=(a - ref.a) / grid.dx,
        err_b=(b - ref.b) / grid.dy,
        seconds=t_force,
        iterations=rf.iterations,
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer, coarser grids")
    args = ap.parse_args()
    sizes = {"cg": [5, 10, 15, 20, 30, 40], "gs": [5, 10, 15, 20]}
    if args.quick:
        sizes = {"cg": [5, 10, 15], "gs": [5, 10]}
    rows = [run_case(r, n, m) for m in ("cg", "gs") for r in (1.0, 0.5, 0.2, 0.1) for n in sizes[m]]
    head = (
        "| method | A/B | el./minor semi-axis | elements | in contact | Fn err (approach given) "
        "| p0 err | a err (el.) | b err (el.) | iterations | time (s) |"
    )
    lines = [head, "|" + "---|" * 11]
    for r in rows:
        lines.append(
            f"| {r['method']} | {r['ratio']} | {r['n']} | {r['elements']} | {r['in_contact']} | "
            f"{r['err_fn']:+.2e} | {r['err_p0']:+.2e} | {r['err_a']:+.2f} | {r['err_b']:+.2f} | "
            f"{r['iterations']} | {r['seconds']:.3g} |"
        )
    table = "\n".join(lines)
    print(table)
    FIG.mkdir(exist_ok=True)
    (FIG / "contact_hertz_table.md").write_text(table + "\n")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    colors = {1.0: "C0", 0.5: "C1", 0.2: "C2", 0.1: "C3"}
    for ax, key, label in zip(axes, ("err_fn", "err_p0"), ("|Fn error| (approach prescribed)", "|p0 error|")):
        for m, marker, ls in (("cg", "o", "-"), ("gs", "s", "--")):
            for ratio, c in colors.items():
                sel = [r for r in rows if r["method"] == m and r["ratio"] == ratio]
                ax.loglog(
                    [r["seconds"] for r in sel],
                    [abs(r[key]) for r in sel],
                    marker=marker,
                    ls=ls,
                    color=c,
                    label=f"{m.upper()}, A/B = {ratio}",
                )
        ax.set_xlabel("solve time, force prescribed (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7, ncol=2)
    fig.suptitle("Normal contact vs Hertz: error against time (grids 5-40 elements per minor semi-axis)")
    fig.tight_layout()
    fig.savefig(FIG / "contact_hertz_error_vs_time.png", dpi=100)
    print(f"wrote {FIG / 'contact_hertz_error_vs_time.png'}")


if __name__ == "__main__":
    main()
