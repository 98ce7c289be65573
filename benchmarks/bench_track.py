"""Ring-track benchmark: time and peak memory to build the modal form (n_sl = 32, 64, 128,
up to 3 kHz) and to compute one 3,000-line FRF. Each case runs in a fresh subprocess so
that ru_maxrss is its own peak.

    .venv/bin/python benchmarks/bench_track.py [n_sl ...]
"""

from __future__ import annotations

import json
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time
import numpy as np
from railvti.track import RingTrack
n = int(sys.argv[1])
t0 = time.perf_counter()
tr = RingTrack(n, f_max=3000.0)
t1 = time.perf_counter()
f = np.linspace(0.0, 3000.0, 3000)
h = tr.receptance(f, "vertical", "midspan")
t2 = time.perf_counter()
print(json.dumps({"n_sl": n, "build_s": t1 - t0, "rail_s": tr.build_time[0],
                  "groups_s": tr.build_time[1], "frf_s": t2 - t1, "n_modes": tr.n_modes,
                  "n_modes_3k": int(tr.modes(3000.0).freq.size),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def main(argv: list[str]) -> None:
    sizes = [int(a) for a in argv] or [32, 64, 128]
    print(
        f"{'n_sl':>5} {'build s':>8} {'(rail':>7} {'groups)':>8} {'FRF s':>7} "
        f"{'modes':>7} {'<=3kHz':>7} {'peak MB':>8}"
    )
    for n in sizes:
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(n)], capture_output=True, text=True, check=True
        )
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(
            f"{r['n_sl']:>5} {r['build_s']:8.2f} {r['rail_s']:7.2f} {r['groups_s']:8.2f} "
            f"{r['frf_s']:7.3f} {r['n_modes']:7d} {r['n_modes_3k']:7d} {r['peak_mb']:8.0f}"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
