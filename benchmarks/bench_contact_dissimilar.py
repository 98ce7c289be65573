"""Dissimilar materials (issue 35): time per case beside the quasi-identical solve's, and
today's steady rolling before and after the change (the optional extra-slip arguments of
rolling_steady), old and new builds alternated in one run. Times are CPU seconds of the
process (time.process_time, one thread): on the shared 2-core machine the wall clock of the same
build varied 29-54 ms between runs, its CPU time by under 1 %.

Run:
    PYTHONPATH=_site python benchmarks/bench_contact_dissimilar.py [--old _site_old] [--repeat 5]

--old: a build of the starting commit (see /work/helpers' notes: a second worktree installed with
``--target _site_old``); without it only the dissimilar timings are printed.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import time

import numpy as np

ROLLING_SNIPPET = """
import time, numpy as np
from railvti import STEEL
from railvti.contact import Grid, hertz_gap, solve_rolling
out = []
for n, creep in ((40, (1e-3, 0.0, 0.0)), (64, (5e-4, 2e-4, 0.3)), (96, (2e-3, 0.0, 0.0))):
    g = Grid(n, n, 10e-3 / n, 10e-3 / n)
    gap = hertz_gap(g, 1 / (2 * 0.46), 1 / (2 * 0.3))
    solve_rolling(gap, g, STEEL, 0.3, 1e4, creep, 10.0)  # workspace and FFTW plans
    best = 1e9
    for _ in range(5):
        t = time.process_time()
        r = solve_rolling(gap, g, STEEL, 0.3, 1e4, creep, 10.0)
        best = min(best, time.process_time() - t)
    out.append((n, best, r.fx))
print(repr(out))
"""


def rolling_times(site: str) -> list[tuple[int, float, float]]:
    env = dict(os.environ, PYTHONPATH=site, OMP_NUM_THREADS="1")
    res = subprocess.run(
        [sys.executable, "-c", ROLLING_SNIPPET], env=env, capture_output=True, text=True, check=True
    )
    return eval(res.stdout.strip().splitlines()[-1])  # noqa: S307 - our own snippet's repr


def dissimilar_times() -> None:
    from railvti import STEEL, Material
    from railvti.contact import Grid, hertz_gap, solve_normal, solve_rolling
    from railvti.contact.dissimilar import BodyPair, solve_dissimilar_rolling, solve_progressive_compression

    alu = Material(23.0e9, 0.31)
    print("case (CPU seconds)                      dissimilar (s)  quasi-identical (s)  outer it.")
    # 3-D ellipse, aluminium wheel on a steel rail, creepage given
    g = Grid(40, 36, 2.5e-4, 2.5e-4)
    gap = hertz_gap(g, 1 / (2 * 0.46), 1 / (2 * 0.3))
    pair = BodyPair(alu, STEEL)
    t = time.process_time()
    d = solve_dissimilar_rolling(gap, g, pair, 0.3, 1e4, (1e-3, 0.0, 0.0), 10.0)
    td = time.process_time() - t
    t = time.process_time()
    solve_rolling(gap, g, pair.combined, 0.3, 1e4, (1e-3, 0.0, 0.0), 10.0)
    tq = time.process_time() - t
    print(f"ellipse 40 x 36, Al on steel, xi = 1e-3   {td:10.3f}  {tq:18.3f}  {d.outer_iterations:8d}")
    # Bentall-Johnson strip, free rolling
    a, R = 1e-4, 0.025
    dx = 2 * a / 200
    g = Grid(216, 4, dx, 1000 * a)
    gap = hertz_gap(g, 1 / (2 * R), 0.0)
    gap[:, [0, 3]] = 1.0
    fn = 2 * g.dy * math.pi * a * a * pair.contact_modulus / (4 * R)
    for mu in (1e-4, 0.05, 10.0):
        t = time.process_time()
        d = solve_dissimilar_rolling(gap, g, pair, mu, fn, (0, 0, 0), 10.0, free_rolling=True)
        td = time.process_time() - t
        t = time.process_time()
        solve_rolling(gap, g, pair.combined, mu, fn, d.creepage, 10.0)
        tq = time.process_time() - t
        print(f"Bentall-Johnson 216 x 4, free, mu = {mu:<6g} {td:10.3f}  {tq:18.3f}  {d.outer_iterations:8d}")
    # Spence
    sp = BodyPair(Material(0.5e9, 0.0), Material(0.5e14, 0.0))
    for n, steps in ((31, 25), (45, 35)):
        g = Grid(n, n, 2e-4, 2e-4)
        gap = hertz_gap(g, 1 / (2 * 0.1215), 1 / (2 * 0.1215))
        a_end = 2e-4 * steps / 2
        fns = [4 * (a_end * k / steps) ** 3 * sp.contact_modulus / (3 * 0.1215) for k in range(1, steps + 1)]
        t = time.process_time()
        c = solve_progressive_compression(gap, g, sp, 0.2986, fns, outer_tol=1e-5)
        td = time.process_time() - t
        t = time.process_time()
        for f in fns:
            solve_normal(gap, g, sp.combined, fn=f, tol=1e-9)
        tq = time.process_time() - t
        print(
            f"Spence {n} x {n}, {steps} steps                {td:10.3f}  {tq:18.3f}  "
            f"{int(np.max(c.outer_iterations)):8d}  (c/a {c.stick_ratio[-5:].mean():.4f})"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", help="site directory of the starting commit's build")
    ap.add_argument("--repeat", type=int, default=3, help="alternations of old and new builds")
    args = ap.parse_args()
    print(f"load average before: {os.getloadavg()}")
    if args.old:
        new_site = os.environ.get("PYTHONPATH", "_site")
        best = {"old": {}, "new": {}}
        fx = {}
        for _ in range(args.repeat):
            for label, site in (("old", args.old), ("new", new_site)):
                for n, t, f in rolling_times(site):
                    best[label][n] = min(best[label].get(n, 1e9), t)
                    fx.setdefault(n, {})[label] = f
        print("steady rolling (quasi-identical), best of 5 x", args.repeat, "alternations, one thread")
        for n in sorted(best["old"]):
            o, w = best["old"][n], best["new"][n]
            print(
                f"  {n:3d} x {n:<3d}  old {o * 1e3:8.2f} ms  new {w * 1e3:8.2f} ms  new/old {w / o:5.3f}  "
                f"Fx old {fx[n]['old']:.10g}  new {fx[n]['new']:.10g}"
            )
    dissimilar_times()
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
