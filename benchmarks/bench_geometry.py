"""Benchmark: the rigid contact table of 201 positions (S1002 / UIC60 1:40), geometry only,
and the gap field of one patch. Prints wall times and peak memory.

Run:  .venv/bin/python benchmarks/bench_geometry.py
"""

from __future__ import annotations

import resource
import time

import numpy as np

from railvti import geometry as G
from railvti import profiles as P


def best(f, repeat=5):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t0)
    return min(ts), float(np.median(ts)), out


def main() -> None:
    t0 = time.perf_counter()
    wheel, rail = P.s1002(), P.uic60(cant=1 / 40)
    G.layout(wheel, rail)
    print(f"profiles + layout: {time.perf_counter() - t0:.3f} s (once)")
    y = np.linspace(-0.01, 0.01, 201)
    tmin, tmed, _ = best(lambda: G.geometry_table(wheel, rail, y))
    print(
        f"contact table, 201 positions, yaw 0:        best {tmin:.3f} s, median {tmed:.3f} s (target < 1 s)"
    )
    yaw = 2.4e-3 * np.abs(y) * 1e3 * np.sign(y)
    tmin, tmed, _ = best(lambda: G.geometry_table(wheel, rail, y, yaw=yaw))
    print(f"contact table, 201 positions, yaw 2.4 mrad/mm: best {tmin:.3f} s, median {tmed:.3f} s")
    c = G.contact_points(wheel, rail, 0.0).left[0]
    tmin, tmed, _ = best(lambda: G.gap_field(wheel, rail, c, 2e-4, 2e-4, 100, 100))
    print(f"gap field 100 x 100 (0.2 mm):               best {tmin * 1e3:.1f} ms, median {tmed * 1e3:.1f} ms")
    tmin, tmed, _ = best(lambda: G.creepages(c, 2.0), repeat=50)
    print(f"creepages of one point:                     best {tmin * 1e6:.0f} us")
    print(f"peak memory (ru_maxrss): {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
