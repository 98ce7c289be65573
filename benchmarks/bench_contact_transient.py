"""Time per transient step beside one steady rolling solve on the same grid (issue 35).

Each case alternates the transient run and the steady solve (best of ``--repeat`` rounds) so
that the shared machine's load hits both alike; the load average is printed.

Run: PYTHONPATH=_site python benchmarks/bench_contact_transient.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling
from railvti.contact.transient import shift_problem, solve_transient, transient_rolling
from railvti.material import STEEL

MU = 0.3


def _best(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"load average before: {os.getloadavg()}")
    print("case                                   grid      steps  transient ms/step  steady ms/solve  ratio")
    # sphere pair, a = 1.49 mm
    h = hertz(10.0, 10.0, 10e3, STEEL)
    for n in (8, 16):
        g = Grid.covering(h.a, h.a, n, 1.2)
        g = Grid(g.nx + 4, g.ny, g.dx, g.dy, g.x0, g.y0)
        gap = hertz_gap(g, 10.0, 10.0)
        creep = (-0.002, 0.0, 0.0)
        r = transient_rolling(g, STEEL, MU, 10e3, creep, 30.0, 8 * h.a, gap=gap)
        steps = r.fx.size
        tt = _best(lambda: transient_rolling(g, STEEL, MU, 10e3, creep, 30.0, 8 * h.a, gap=gap), args.repeat)
        ts = _best(lambda: solve_rolling(gap, g, STEEL, MU, 10e3, creep, 30.0), args.repeat)
        print(
            f"rolling from rest, {n:2d}/a                {g.nx}x{g.ny}  {steps:5d}  {tt / steps * 1e3:17.2f}"
            f"  {ts * 1e3:15.2f}  {tt / steps / ts:5.2f}"
        )
        q = (7 / 8 * MU * 10e3, 0.0)
        g2 = Grid.covering(h.a, h.a, n, 1.15)
        gap2 = hertz_gap(g2, 10.0, 10.0)
        tt = _best(lambda: shift_problem(gap2, g2, STEEL, MU, 10e3, q, steps=1), args.repeat)
        ts = _best(lambda: solve_rolling(gap2, g2, STEEL, MU, 10e3, creep, 30.0), args.repeat)
        print(
            f"Cattaneo shift in one step, {n:2d}/a        {g2.nx}x{g2.ny}  {1:5d}  {tt * 1e3:17.2f}"
            f"  {ts * 1e3:15.2f}  {tt / ts:5.2f}"
        )
    # wheel-rail ellipse, 80 kN, 200 km/h, Fn (1 + 0.1 sin(2 pi 92.6 t)): normal + tangential per step
    A, B, V = 1.087, 1.6667, 200 / 3.6
    h = hertz(A, B, 80e3, STEEL)
    dx = h.a / 8
    g = Grid(2 * int(1.3 * 8) + 6, 2 * int(1.3 * 8 * h.b / h.a) + 4, dx, dx, -int(1.3 * 8) * dx, None)
    gap = hertz_gap(g, A, B)
    steps = 400
    t = dx / V * np.arange(1, steps + 1)
    fn = 80e3 * (1 + 0.1 * np.sin(2 * np.pi * 92.6 * t))
    creep = (-0.001, 0.0, 0.0)
    tt = _best(
        lambda: solve_transient(
            g, STEEL, MU, fn, steps, dx / V, gap=gap, speed=V, creepage=creep, theta=1 / 3
        ),
        args.repeat,
    )
    ts = _best(lambda: solve_rolling(gap, g, STEEL, MU, 80e3, creep, V), args.repeat)
    print(
        f"load 92.6 Hz at 200 km/h, 8/a           {g.nx}x{g.ny}  {steps:5d}  {tt / steps * 1e3:17.2f}"
        f"  {ts * 1e3:15.2f}  {tt / steps / ts:5.2f}"
    )
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
