"""Time of the subsurface stresses (railvti.contact.subsurface): a Hertz patch on 100 x 100
elements (the patch covers 76 % of the grid) with the pressure and a sliding traction,
stresses at all element centres on 30 depths, by the per-depth FFT and by direct summation
(the direct sum on 1 of the 30 depths, scaled; not on 200 x 200), and the x-z plane alone (direct).

Run: PYTHONPATH=_site python benchmarks/bench_contact_subsurface.py
"""

from __future__ import annotations

import os
import time

import numpy as np

from railvti.contact import Grid
from railvti.contact.subsurface import subsurface_stress_fields

A = 1.0e-3


def _case(n: int) -> tuple[Grid, np.ndarray]:
    g = Grid(n, n, 2.2 * A / n, 2.2 * A / n)
    x, y = g.mesh()
    return g, 1e9 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))


def _time(fn, repeat: int = 3) -> float:
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main() -> None:
    print(f"load {os.getloadavg()}, OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}")
    z = np.linspace(0.02, 1.5, 30) * A
    for n in (50, 100, 200):
        g, p = _case(n)
        q = 0.3 * p
        loaded = int(np.count_nonzero(p))
        t_fft = _time(lambda: subsurface_stress_fields(g, p, q, poisson=0.3, z=z, method="fft"))
        t_dir1 = np.nan
        if n <= 100:
            t_dir1 = _time(
                lambda: subsurface_stress_fields(g, p, q, poisson=0.3, z=z[:1], method="direct"), 1
            )
        t_xz = _time(
            lambda: subsurface_stress_fields(g, p, q, poisson=0.3, z=z, y=[g.y[n // 2]], method="direct"), 1
        )
        print(
            f"{n} x {n} elements ({loaded} loaded) x 30 depths: fft {t_fft:.3f} s, direct "
            f"{t_dir1 * 30:.1f} s (1 depth {t_dir1:.2f} s x 30); x-z plane only (direct) {t_xz:.3f} s"
        )
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
