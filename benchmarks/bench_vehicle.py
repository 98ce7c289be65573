"""Vehicle-track time simulation: real-time factor and memory per contact model.

10 s of hunting at 300 km/h (leading bogie released from 4 mm), coach RR model, time step
1 ms with sub-stepping, each case in its own subprocess (peak RSS per case).

    .venv/bin/python benchmarks/bench_vehicle.py [duration_s]
"""
from __future__ import annotations

import json
import subprocess
import sys

CASES = [("hertz-kalker", 8), ("hertz-fastsim", 8), ("hertz-fastsim", 16)]

CHILD = r"""
import json, resource, sys, time
from railvti import scenarios
contact, n, dur = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
scenarios.contact_table()                      # table build (cached per process)
t0 = time.perf_counter()
r = scenarios.hunting(300.0, contact=contact, duration=dur, y0=0.004, fastsim_n=n, progress=False)
wall = time.perf_counter() - t0
print(json.dumps({"wall": wall, "rtf": wall / dur, "amp_mm": scenarios.amplitude(r) * 1e3,
                  "steps": r.stats["steps"], "newton": r.stats["newton_iterations"],
                  "tangents": r.stats["tangents"], "sub": r.stats["substepped_steps"],
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def main() -> None:
    dur = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    print(f"hunting at 300 km/h, {dur:g} s simulated, h = 1 ms (RR coach, 45 DOF, 8 wheels)")
    print(f"{'contact':>14s} {'n':>3s} {'wall s':>8s} {'RTF':>7s} {'amp mm':>7s} {'steps':>6s} "
          f"{'Newton/step':>11s} {'tangents':>8s} {'sub-stepped':>11s} {'peak RSS MB':>11s}")
    for contact, n in CASES:
        out = subprocess.run([sys.executable, "-c", CHILD, contact, str(n), str(dur)],
                             capture_output=True, text=True, check=True)
        d = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{contact:>14s} {n:3d} {d['wall']:8.2f} {d['rtf']:7.3f} {d['amp_mm']:7.2f} "
              f"{d['steps']:6d} {d['newton'] / d['steps']:11.2f} {d['tangents']:8d} {d['sub']:11d} "
              f"{d['rss_mb']:11.0f}")
    print("BEM (0.75 mm) contact: not wired into the time loop (see docs/vehicle.md)")


if __name__ == "__main__":
    main()
