"""Benchmark of the loaded wheelset: the whole A-2.2 sweep at 0.2 mm (both wheels, load
control, normal + steady rolling) and the 201-position contact table (geometry only).

    python benchmarks/bench_contact_wheelset.py
"""
from __future__ import annotations

import logging
import resource
import time

import numpy as np

from railvti import Material, geometry, profiles
from railvti.contact.wheelset import solve_wheelset


def main() -> None:
    logging.disable(logging.WARNING)
    wheel, rail = profiles.s1002(), profiles.uic60()
    mat = Material(shear_modulus=82e9, poisson=0.28)
    y_mm = np.arange(0.0, 10.01, 0.5)
    for label, mu, v in (("normal only", None, None), ("normal + rolling", 0.3, 2.0)):
        for run in ("first (workspaces made)", "repeat"):
            t = []
            for y in y_mm:
                t0 = time.perf_counter()
                solve_wheelset(wheel, rail, y * 1e-3, 2.4e-3 * y, 1.0e4, mu, v, mat, 2e-4)
                t.append(time.perf_counter() - t0)
            t = np.array(t) * 1e3
            print(f"A-2.2 {label:17s} {run:24s}: {t.mean():6.1f} ms per position (median {np.median(t):.1f}, "
                  f"max {t.max():.1f}), sweep {t.sum() / 1e3:.2f} s")
    y = np.linspace(-10e-3, 10e-3, 201)
    geometry.contact_table(wheel, rail, y[:3])
    t0 = time.perf_counter()
    geometry.contact_table(wheel, rail, y)
    print(f"contact table, 201 positions: {time.perf_counter() - t0:.3f} s")
    print(f"peak memory {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main()
