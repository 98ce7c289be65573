"""Benchmark: all modes up to 3 kHz for k = 0..6 of the default wheelset
(free-free and on the primary suspension), time and peak memory.
Run: .venv/bin/python benchmarks/bench_wheelset.py
"""

from __future__ import annotations

import resource
import time

from railvti.wheelset import Wheelset


def main() -> None:
    t0 = time.perf_counter()
    ws = Wheelset()
    t_mesh = time.perf_counter() - t0
    print(f"mesh: {ws.mesh.n_nodes} nodes, {ws.mesh.n_elements} nine-node elements ({t_mesh:.2f} s)")
    for support in ("free", "suspension"):
        t = time.perf_counter()
        total = 0
        for k in range(7):
            tk = time.perf_counter()
            h = ws.harmonic(k, 3000.0, support)
            total += h.freq_hz.size
            print(
                f"  {support:>10} k={k}: {h.freq_hz.size:3d} modes, {h.n_equations} equations, "
                f"half-bandwidth {h.bandwidth}, {time.perf_counter() - tk:.2f} s"
            )
        print(
            f"{support}: {total} modes (pairs counted once) up to 3 kHz, k = 0..6 in "
            f"{time.perf_counter() - t:.2f} s"
        )
    t = time.perf_counter()
    m = ws.axle_fixed(300 / 3.6, k_max=6, f_max=3000.0)
    print(
        f"axle-fixed model at 300 km/h: {m.n} coordinates in {time.perf_counter() - t:.3f} s (modes cached)"
    )
    import numpy as np

    t = time.perf_counter()
    ws.frf(np.linspace(20, 1000, 1000), 300 / 3.6, model=m)
    print(f"FRF, 1000 frequencies: {time.perf_counter() - t:.3f} s")
    print(f"peak memory (ru_maxrss): {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
