"""The rail deflection under the wheels after an FF run (issue 33): RingSystem.rail_deflection
over 1001 output times of random modal coordinates (the residual coordinates zero: their
scaling differs between builds), CPU time of one call, and the result saved for comparing
two builds.

    OMP_NUM_THREADS=1 python benchmarks/bench_ring_rail_deflection.py [out.npy]

Run it under each build (cwd outside the source tree) and compare the saved arrays.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from railvti import scenarios


def main(out: str | None = None) -> None:
    sy, _ = scenarios.ff_system(speed_kmh=300.0, geometry="strip")
    t = np.linspace(0.0, 2.0, 1001)
    q = np.random.default_rng(1).standard_normal((t.size, sy.n_state)) * 1e-4
    q[:, sy.n_state - sy.ring.n_residual :] = 0.0
    sy.rail_deflection(t[:2], q[:2])  # any first-call work apart
    c0 = time.process_time()
    d = sy.rail_deflection(t, q)
    cpu = time.process_time() - c0
    print(
        f"rail_deflection, {t.size} times: {cpu:.3f} s CPU (load {os.getloadavg()[0]:.1f}); max |d| {np.abs(d).max():.6e}"
    )
    if out:
        np.save(out, d)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
