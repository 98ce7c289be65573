"""Friction laws (issue 35): time per steady rolling case with a falling friction law
beside today's constant-mu solve on the same grid, and today's steady speed before and
after the change (the default path must not get slower and must give the same bits).

Two builds are compared in one run: the old one (``--old``, a site directory built
from the starting commit) and the new one (``--new``, default ``_site``). Each sample
runs in its own subprocess; old and new subprocesses alternate (the 2 shared cores
carry other work: alternating spreads the load over both). A child solves the
normal problem once, then times ``reps`` tangential solves (best of them) on the
cached workspace, per grid and case, and writes the forces of the last solve:
the parent checks that old and new forces are identical bit for bit.

Cases: the Eurosprinter-like Hertz contact (wheel radius 0.625 m, rail crown 0.3 m,
Fn = 100 kN, V = 40 km/h), creepages xi = 2e-3 (partial slip), 1e-2 (near the peak)
and 0.1 (full slip), mu = 0.55; the new build also with Polach's dry law
(mu0 = 0.55, A = 0.4, B = 0.6 s/m) and a static/kinetic jump law (0.55 / 0.4).

Run: PYTHONPATH=_site python benchmarks/bench_contact_friction.py --old _site_old --new _site [--samples 5]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import json, sys, time
import numpy as np
from railvti.contact import Grid, hertz, hertz_gap, solve_normal, solve_tangential
from railvti.material import Material
n, reps, laws = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3] == "1"
mat = Material(shear_modulus=82e9, poisson=0.28)
A, B, FN, V = 0.8, 1.0 / 0.6, 100e3, 40.0 / 3.6
h = hertz(A, B, FN, mat)
dx, dy = 2.4 * h.a / n, 2.4 * h.b / n
grid = Grid(n, n, dx, dy, -1.15 * h.a, -1.2 * h.b + dy / 2)
p = solve_normal(hertz_gap(grid, A, B), grid, mat, fn=FN).pressure
out = {}
def timed(label, fn):
    best = 1e9
    for _ in range(reps):
        t = time.perf_counter()
        r = fn()
        best = min(best, time.perf_counter() - t)
    out[label] = dict(t=best, fx=float(r[0]), fy=float(r[1]), it=int(r[2]))
for xi in (2e-3, 1e-2, 0.1):
    def const():
        r = solve_tangential(p, grid, mat, 0.55, (xi, 0.0, 0.0), V)
        return r.fx, r.fy, r.iterations
    solve_tangential(p, grid, mat, 0.55, (xi, 0.0, 0.0), V)   # workspace made
    timed(f"constant mu xi={xi:g}", const)
    if laws:
        from railvti.contact.friction import FrictionLaw, solve_tangential_friction
        for name, law in (("Polach dry", FrictionLaw.polach(0.55, 0.4, 0.6)),
                          ("jump 0.55/0.4", FrictionLaw("coulomb", 0.55, 0.4))):
            def run(law=law):
                r = solve_tangential_friction(p, grid, mat, law, (xi, 0.0, 0.0), V)
                return r.fx, r.fy, r.rolling.iterations
            timed(f"{name} xi={xi:g}", run)
print(json.dumps(out))
"""


def child(site: str, n: int, reps: int, laws: bool) -> dict:
    env = dict(os.environ, PYTHONPATH=site, OMP_NUM_THREADS="1")
    res = subprocess.run(
        [sys.executable, "-c", CHILD, str(n), str(reps), "1" if laws else "0"],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        cwd="/",
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", default="_site_old")
    ap.add_argument("--new", default="_site")
    ap.add_argument("--samples", type=int, default=5)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--grids", default="24,48")
    a = ap.parse_args()
    old, new = str(Path(a.old).resolve()), str(Path(a.new).resolve())
    print(f"load before: {os.getloadavg()}")
    for n in (int(s) for s in a.grids.split(",")):
        best_old: dict = {}
        best_new: dict = {}
        for _ in range(a.samples):
            for site, best, laws in ((old, best_old, False), (new, best_new, True)):
                for k, v in child(site, n, a.reps, laws).items():
                    if k not in best or v["t"] < best[k]["t"]:
                        best[k] = v
        print(f"\ngrid {n} x {n} (best of {a.samples} x {a.reps} solves), load {os.getloadavg()[0]:.2f}")
        print(
            f"{'case':28s} {'old ms':>8s} {'new ms':>8s} {'new/old':>8s} {'sweeps':>7s} {'-Fx/Fn':>8s} {'same bits':>9s}"
        )
        for k, v in best_new.items():
            o = best_old.get(k)
            if o is None:
                const = best_new[f"constant mu {k.split()[-1]}"]["t"]
                print(
                    f"{k:28s} {'':>8s} {v['t'] * 1e3:8.2f} {'':>8s} {v['it']:7d} {-v['fx'] / 100e3:8.4f}"
                    f"   ({v['t'] / const:.2f} x constant mu)"
                )
                continue
            same = o["fx"] == v["fx"] and o["fy"] == v["fy"] and o["it"] == v["it"]
            print(
                f"{k:28s} {o['t'] * 1e3:8.2f} {v['t'] * 1e3:8.2f} {v['t'] / o['t']:8.3f} {v['it']:7d} "
                f"{-v['fx'] / 100e3:8.4f} {str(same):>9s}"
            )
    print(f"\nload after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
