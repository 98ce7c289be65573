"""Benchmark of solve_normal on Hertz cases (circle, 10 kN, steel).

Each size runs in a fresh subprocess so that its peak memory (ru_maxrss) is its own.
Prints elements, elements in contact, iterations, FFT products, seconds (first
solve with set-up, and a repeated solve on the cached workspace), peak
memory, the time of one FFT product on that grid and the ratio solve/product.

    python benchmarks/bench_contact_normal.py [--quick]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time
import numpy as np
from railvti import STEEL
from railvti._native import core
from railvti.contact import Grid, hertz, hertz_gap, solve_normal
from railvti.contact.workspace import workspace
side, method = int(sys.argv[1]), sys.argv[2]
ref = hertz(1.0, 1.0, 1.0e4, STEEL)
h = 2 * 1.2 * ref.a / side              # the patch spans ~83 % of the grid's width
grid = Grid(side, side, h, h)
gap = hertz_gap(grid, 1.0, 1.0)
t0 = time.perf_counter()
solve_normal(gap, grid, STEEL, fn=1.0e4, method=method)   # first solve: makes the workspace
t_first = time.perf_counter() - t0
t0 = time.perf_counter()
r = solve_normal(gap, grid, STEEL, fn=1.0e4, method=method)  # cold pressure, cached workspace
t = time.perf_counter() - t0
q = np.asfortranarray(r.pressure)
def products(n):
    t0 = time.perf_counter()
    core.convolve_repeat_c(workspace(grid, STEEL), n, q)
    return time.perf_counter() - t0
nrep = 40
t_prod = (products(nrep + 1) - products(1)) / nrep
print(json.dumps(dict(side=side, method=method, elements=side * side, contact=r.n_contact,
                      iterations=r.iterations, products=r.fft_products, coarse=r.coarse_fft_products, seconds=t, first=t_first, t_product=t_prod,
                      peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                      p0_err=r.pmax / ref.p0 - 1)))
"""


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    runs = (
        [("cg", s) for s in (32, 64, 128, 256, 450, 500)]
        + [("pk", s) for s in (128, 450)]
        + [("gs", s) for s in (32, 50, 71, 100)]
    )
    if args.quick:
        runs = [("cg", 32), ("cg", 128), ("gs", 32)]
    print(
        "seconds: a solve from zero pressure on a cached workspace; first: the first solve on the grid,\n"
        "including influence coefficients, spectra and FFTW plans; prod: FFT products on the grid;\n"
        "coarse: products on the coarser grids of the nested start (each <= 1/4 of a fine one);\n"
        "solve/prod = seconds / t_prod (all work, coarse grids and passes included)"
    )
    print(
        f"{'method':6s} {'elements':>9s} {'contact':>8s} {'iter':>5s} {'prod':>5s} {'seconds':>9s} {'first':>8s} "
        f"{'coarse':>6s} {'peak MB':>8s} {'t_prod ms':>9s} {'solve/prod':>10s} {'p0 err':>9s}"
    )
    for method, side in runs:
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(side), method], capture_output=True, text=True, check=True
        ).stdout
        r = json.loads(out.strip().splitlines()[-1])
        print(
            f"{r['method']:6s} {r['elements']:9d} {r['contact']:8d} {r['iterations']:5d} {r['products']:5d} "
            f"{r['seconds']:9.4f} {r['first']:8.4f} {r['coarse']:6d} {r['peak_mb']:8.1f} {r['t_product'] * 1e3:9.3f} "
            f"{r['seconds'] / r['t_product']:10.1f} {r['p0_err']:+9.2e}",
            flush=True,
        )


if __name__ == "__main__":
    main()
