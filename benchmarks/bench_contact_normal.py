"""Benchmark of solve_normal on Hertz cases (circle, 10 kN, steel).

Each size runs in a fresh subprocess so that its peak memory (ru_maxrss) is its own.
Prints elements, elements in contact, iterations, FFT products, seconds (first
solve with set-up, and a repeated solve on the cached workspace), peak
memory, the time of one FFT product on that grid and the ratio solve/product.

    python benchmarks/bench_contact_normal.py [--quick]

Before/after in one run (issue 33): ``--ab NEW_SITE`` times the 450 x 450 case
(``--side``) with the interpreter's installed railvti ("old", PYTHONPATH unset) and
with the one in NEW_SITE ("new"), alternating for ``--rounds`` rounds; each child takes
the best of ``--repeat`` solves and of as many product timings, and prints the load.
The unit, one FFT-product time, is the plain product (convolve_repeat_c: one r2c of the
zero-padded 2nx x 2ny grid, the product by the complex spectrum, one c2r); builds with the
pruned product (issue 33) also print its CPU time in that unit, with the real spectrum the
solver uses and with the complex one:

    python benchmarks/bench_contact_normal.py --ab $WT/_site --side 450 --rounds 4
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

CHILD = r"""
import json, os, resource, sys, time
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
repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 1
q = np.asfortranarray(gap)
def products(n, clock):
    t0 = clock()
    core.convolve_repeat_c(workspace(grid, STEEL), n, q)
    return clock() - t0
# the solvers' pruned product (issue 33; absent in older builds), in CPU time, with the
# Boussinesq field (point-symmetric: real spectrum) and with it made slightly asymmetric
# (complex spectrum); one plan per call, its making cancels in the difference of counts
# (only with --ab's repeats: its plans and fields would raise the table's peak memory)
has_pruned = hasattr(core, "convolve_field_c") and repeat > 1
if has_pruned:
    from railvti.contact import influence_field
    c_sym = influence_field(grid, STEEL, "zz")
    c_asym = c_sym.copy(order="F")
    c_asym[1, 0] *= 1.0 + 1.0e-6
def pruned(n, spectrum):
    t0 = time.process_time()
    core.convolve_field_c(1, n, c_sym if spectrum else c_asym, q)
    return time.process_time() - t0
nrep = 40 if repeat == 1 else 10
t, t_prod, c, c_prod, c_real, c_cplx = (float("inf"),) * 6
for _ in range(repeat):  # best of repeat, solves and product timings interleaved
    t0, c0 = time.perf_counter(), time.process_time()
    r = solve_normal(gap, grid, STEEL, fn=1.0e4, method=method)  # cold pressure, cached workspace
    t, c = min(t, time.perf_counter() - t0), min(c, time.process_time() - c0)
    t_prod = min(t_prod, (products(nrep + 1, time.perf_counter) - products(1, time.perf_counter)) / nrep)
    c_prod = min(c_prod, (products(nrep + 1, time.process_time) - products(1, time.process_time)) / nrep)
    if has_pruned:
        c_real = min(c_real, (pruned(nrep + 1, 1) - pruned(1, 1)) / nrep)
        c_cplx = min(c_cplx, (pruned(nrep + 1, 0) - pruned(1, 0)) / nrep)
print(json.dumps(dict(side=side, method=method, elements=side * side, contact=r.n_contact,
                      iterations=r.iterations, products=r.fft_products, coarse=r.coarse_fft_products, seconds=t, first=t_first, t_product=t_prod, cpu=c, cpu_product=c_prod,
                      peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                      p0_err=r.pmax / ref.p0 - 1, approach=r.approach, approach_err=r.approach / ref.approach - 1,
                      pruned_real=c_real / c_prod if has_pruned else None,
                      pruned_complex=c_cplx / c_prod if has_pruned else None,
                      load=os.getloadavg()[0])))
"""


def child(side: int, method: str, repeat: int = 1, pythonpath: str | None = None) -> dict:
    """Run one case in a fresh interpreter (PYTHONPATH set to pythonpath, or unset)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(side), method, str(repeat)],
        capture_output=True,
        text=True,
        check=True,
        env=env,
        cwd=tempfile.gettempdir(),
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def compare(new_site: str, side: int, rounds: int, repeat: int) -> None:
    """Old (installed) against new (new_site) on one grid, alternating; the best solve time
    over the best product time of all rounds, on the wall clock and in CPU time (both
    single-threaded, so CPU time is the steadier figure on a loaded machine)."""
    print(f"{side} x {side}: solve / product time, best of {repeat} solves per child, {rounds} rounds")
    best: dict[str, list[dict]] = {}
    for k in range(rounds):
        for name, path in (("old", None), ("new", new_site)):
            r = child(side, "cg", repeat, path)
            ratio = r["seconds"] / r["t_product"]
            pr = ""
            if r.get("pruned_real") is not None:
                pr = f"  pruned product (CPU) {r['pruned_real']:.3f} real / {r['pruned_complex']:.3f} complex spectrum"
            print(
                f"round {k} {name}: solve {r['seconds'] * 1e3:7.1f} ms  product {r['t_product'] * 1e3:6.2f} ms  "
                f"ratio {ratio:5.1f} (CPU time {r['cpu'] / r['cpu_product']:5.1f})  "
                f"products {r['products']} (+{r['coarse']} coarse)  iterations {r['iterations']}  "
                f"p0 err {r['p0_err']:+.3e}  approach {r['approach']:.9e}  load {r['load']:.2f}{pr}",
                flush=True,
            )
            best.setdefault(name, []).append(r)
    for name, rs in best.items():
        wall = min(r["seconds"] for r in rs) / min(r["t_product"] for r in rs)
        cpu = min(r["cpu"] for r in rs) / min(r["cpu_product"] for r in rs)
        print(
            f"best {name}: solve / product time {wall:.1f} wall, {cpu:.1f} CPU "
            f"(solve {min(r['seconds'] for r in rs) * 1e3:.1f} ms, product {min(r['t_product'] for r in rs) * 1e3:.2f} ms)"
        )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--ab", metavar="NEW_SITE", help="compare the installed railvti with the one in NEW_SITE")
    ap.add_argument("--side", type=int, default=450)
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    if args.ab:
        compare(args.ab, args.side, args.rounds, args.repeat)
        return
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
        r = child(side, method, pythonpath=os.environ.get("PYTHONPATH"))
        print(
            f"{r['method']:6s} {r['elements']:9d} {r['contact']:8d} {r['iterations']:5d} {r['products']:5d} "
            f"{r['seconds']:9.4f} {r['first']:8.4f} {r['coarse']:6d} {r['peak_mb']:8.1f} {r['t_product'] * 1e3:9.3f} "
            f"{r['seconds'] / r['t_product']:10.1f} {r['p0_err']:+9.2e}",
            flush=True,
        )


if __name__ == "__main__":
    main()
