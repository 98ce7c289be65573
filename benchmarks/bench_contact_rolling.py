"""Steady rolling contact benchmark (issue 3): time per case with spin for
Hertzian patches of about 400, 1,600, 6,400 and 25,000 elements in contact,
per method ('fftgs' the fast one, 'gs' the reference).

Grid sizes are rounded up to products of 2, 3, 5 and 7: the FFTs are
2 nx x 2 ny, and a size with a large prime factor (e.g. 178 = 2 x 89) makes
each FFT product about three times slower.

Each case runs in its own subprocess (peak RSS per case): the normal problem
first (solve_normal, CG), then the tangential one (solve_tangential) twice; the
second, on the cached workspace, is the time reported as "tangential s"
(the first includes making the tangential workspace). Creepages
(xi, eta, phi) = (1e-3, 5e-4, 0.3 1/m), mu = 0.3: partial slip with spin.

Run: .venv/bin/python benchmarks/bench_contact_rolling.py [--max-gs 6400] [--tol 1e-7] [--chart]
(--chart writes validation/figures/contact_rolling_bench.png)

Before/after in one run (issue 33, the pruned FFT pair product): ``--ab NEW_SITE`` solves
the 6,400 and 25,000 element cases ('fftgs') with the interpreter's installed railvti
("old", PYTHONPATH unset) and the one in NEW_SITE ("new"), alternating for ``--rounds``
rounds, and prints the tangential solve times, forces and the load.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, resource, sys, time
from railvti.contact import Grid, hertz, hertz_gap, solve_normal, solve_tangential
from railvti.material import STEEL
n, method, tol = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
A, B = 0.5 / 0.46, 0.5 / 0.30
h = hertz(A, B, 10e3, STEEL)
g0 = Grid.covering(h.a, h.b, n, 1.1)


def good(m):
    # FFT-friendly size (factors 2, 3, 5, 7): the padded FFT is 2 nx x 2 ny
    while True:
        k = m
        for f in (2, 3, 5, 7):
            while k % f == 0:
                k //= f
        if k == 1:
            return m
        m += 1


grid = Grid(good(g0.nx), good(g0.ny), g0.dx, g0.dy)
gap = hertz_gap(grid, A, B)
t0 = time.perf_counter()
nr = solve_normal(gap, grid, STEEL, fn=10e3)
t1 = time.perf_counter()
args = (nr.pressure, grid, STEEL, 0.3, (1e-3, 5e-4, 0.3), 30.0)
from railvti.errors import ConvergenceError


def solve():
    try:
        return solve_tangential(*args, method=method, tol=tol), True
    except ConvergenceError as exc:   # reported, not timed as a success
        return exc.result, False


r, ok = solve()
t2 = time.perf_counter()
r, ok = solve()
t3 = time.perf_counter()
print(json.dumps({"converged": ok, "residual": r.residual, "n_contact": r.n_contact, "grid": f"{grid.nx}x{grid.ny}", "sweeps": r.iterations,
                  "normal_s": t1 - t0, "first_s": t2 - t1, "tang_s": t3 - t2, "fx": r.fx, "fy": r.fy,
                  "slip": int(r.slip.sum()),
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--max-gs", type=int, default=6400, help="largest patch solved with 'gs' (elements)")
    ap.add_argument("--tol", type=float, default=1e-7)
    ap.add_argument("--chart", action="store_true", help="write validation/figures/contact_rolling_bench.png")
    ap.add_argument("--ab", metavar="NEW_SITE", help="compare the installed railvti with the one in NEW_SITE")
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args()
    if args.ab:
        compare(args.ab, args.rounds, args.tol)
        return
    rows = []
    # elements on the shorter semi-axis for ~400, 1,600, 6,400, 25,000 in contact (b/a = 0.82)
    sizes = [(400, 10), (1600, 20), (6400, 40), (25000, 80)]
    print(f"steady rolling with spin, Hertz patch a/b = 1.21, tol = {args.tol:g}")
    print(
        f"{'method':>6} {'target':>7} {'grid':>9} {'in contact':>10} {'slip':>6} {'sweeps':>6} "
        f"{'normal s':>9} {'first s':>8} {'tangential s':>12} {'peak RSS MB':>11}"
    )
    for target, n in sizes:
        for method in ("fftgs", "gs"):
            if method == "gs" and target > args.max_gs:
                print(f"{method:>6} {target:>7}   skipped (O(N^2) per sweep; raise --max-gs)")
                continue
            out = subprocess.run(
                [sys.executable, "-c", CHILD, str(n), method, str(args.tol)],
                capture_output=True,
                text=True,
                check=True,
            )
            d = json.loads(out.stdout.strip().splitlines()[-1])
            rows.append((method, d))
            print(
                f"{method:>6} {target:>7} {d['grid']:>9} {d['n_contact']:>10} {d['slip']:>6} {d['sweeps']:>6} "
                f"{d['normal_s']:9.3f} {d['first_s']:8.3f} {d['tang_s']:12.4f} {d['rss_mb']:11.1f}"
                + ("" if d["converged"] else f"  NOT CONVERGED (residual {d['residual']:.2g})"),
                flush=True,
            )
    if args.chart:
        chart(rows)


def compare(new_site: str, rounds: int, tol: float) -> None:
    """Old (installed) against new (new_site), alternating, 'fftgs' at 6,400 and 25,000 elements."""
    for n in (40, 80):
        for k in range(rounds):
            for name, path in (("old", None), ("new", new_site)):
                env = {key: v for key, v in os.environ.items() if key != "PYTHONPATH"}
                if path:
                    env["PYTHONPATH"] = path
                out = subprocess.run(
                    [sys.executable, "-c", CHILD, str(n), "fftgs", str(tol)],
                    capture_output=True,
                    text=True,
                    check=True,
                    env=env,
                    cwd="/",
                )
                d = json.loads(out.stdout.strip().splitlines()[-1])
                print(
                    f"{d['grid']:>9} round {k} {name}: tangential {d['tang_s']:.4f} s  sweeps {d['sweeps']}  "
                    f"fx {d['fx']:.10e}  fy {d['fy']:.10e}  slip {d['slip']}  load {os.getloadavg()[0]:.2f}",
                    flush=True,
                )


def chart(rows: list) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9.0, 3.6))
    for method, mk in (("fftgs", "o-"), ("gs", "s--")):
        sel = [d for m, d in rows if m == method and d["converged"]]
        n = [d["n_contact"] for d in sel]
        ax1.loglog(n, [d["tang_s"] for d in sel], mk, label=method)
        ax2.semilogx(n, [d["sweeps"] for d in sel], mk, label=method)
    ax1.loglog([1600, 25000], [0.05, 5.0], "k+", ms=10, label="targets")
    ax1.set_xlabel("elements in contact")
    ax1.set_ylabel("tangential solve (s)")
    ax1.grid(alpha=0.3, which="both")
    ax1.legend()
    ax2.set_xlabel("elements in contact")
    ax2.set_ylabel("sweeps to tol")
    ax2.grid(alpha=0.3)
    fig.suptitle("Steady rolling with spin (Hertz, partial slip), 2 shared cores")
    fig.tight_layout()
    out = Path(__file__).resolve().parent.parent / "validation" / "figures" / "contact_rolling_bench.png"
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
