"""FASTSIM timings: per case on an ellipse (kernel batch and Python call) and
strip-wise on a BEM grid with about 1,600 elements in contact; peak memory.

Run: ``.venv/bin/python benchmarks/bench_contact_fastsim.py``
"""

from __future__ import annotations

import resource
import time

import numpy as np

from railvti.contact.fastsim import fastsim, fastsim_forces, fastsim_grid
from railvti.contact.grid import Grid
from railvti.contact.hertz import hertz, hertz_gap
from railvti.contact.normal import solve_normal
from railvti.material import STEEL

A, B, FN, MU = 6e-3, 4e-3, 80e3, 0.3
CREEP = (1e-3, 5e-4, 0.5)  # xi, eta, phi (1/m): a combined case with spin


def best_of(fn, repeat: int = 5, number: int = 1) -> float:
    """Smallest mean time over `repeat` runs of `number` calls, s."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def main() -> None:
    rows = []
    rng = np.random.default_rng(1)
    ncase = 2000
    xi = rng.uniform(-0.01, 0.01, ncase)
    eta = rng.uniform(-0.01, 0.01, ncase)
    phi = rng.uniform(-2.0, 2.0, ncase)
    for n in (10, 20, 50):
        t = best_of(lambda: fastsim_forces(A, B, FN, STEEL, MU, xi, eta, phi, nx=n, ny=n), repeat=3)
        rows.append((f"ellipse {n}x{n}, forces only, per case in a batch of {ncase} (kernel)", t / ncase))
        t = best_of(lambda: fastsim(A, B, FN, STEEL, MU, CREEP, nx=n, ny=n), number=20)
        rows.append((f"ellipse {n}x{n}, fastsim() with fields, one Python call", t))
    # strip-wise on the BEM pressure of a Hertz gap: about 1,600 elements in contact
    h = hertz(1.0 / (2 * 0.46), 1.0 / (2 * 0.30), FN, STEEL)  # any curvatures; the grid fits the ellipse
    n_semi = int(round(np.sqrt(1600 / np.pi * h.b / h.a)))
    grid = Grid.covering(h.a, h.b, n_semi)
    normal = solve_normal(hertz_gap(grid, 1.0 / (2 * 0.46), 1.0 / (2 * 0.30)), grid, STEEL, fn=FN)
    t = best_of(lambda: fastsim_grid(normal.pressure, grid, STEEL, MU, CREEP), number=20)
    rows.append((f"strip-wise on a {grid.nx}x{grid.ny} grid, {normal.n_contact} elements in contact", t))
    t = best_of(lambda: fastsim_grid(normal.pressure, grid, STEEL, MU, CREEP, flexibility="strip"), number=20)
    rows.append(("strip-wise, flexibility='strip', same grid", t))
    width = max(len(r[0]) for r in rows)
    print(f"{'case':<{width}}  time per case")
    for name, t in rows:
        print(f"{name:<{width}}  {t * 1e6:10.1f} us")
    print(
        f"peak memory (ru_maxrss): {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.1f} MB "
        "(whole Python process incl. numpy/scipy)"
    )


if __name__ == "__main__":
    main()
