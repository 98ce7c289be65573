"""Vehicle-track time simulation: real-time factor and memory per contact model.

10 s of hunting at 300 km/h (leading bogie released from 4 mm), coach RR model, time step
1 ms with sub-stepping, each case in its own subprocess (peak RSS per case). The BEM contact
(0.75 mm grids at all eight wheels) runs over a shorter time, ``bem_duration_s`` (default
1 s), unless given; its RTF is wall / simulated time of that run. The Hertz contacts run on
the table's points and on the strip contact (``geometry='strip'``).

    .venv/bin/python benchmarks/bench_vehicle.py [duration_s] [bem_duration_s]
"""
from __future__ import annotations

import json
import subprocess
import sys

CASES = [("hertz-kalker", 8, "table"), ("hertz-fastsim", 8, "table"), ("hertz-fastsim", 16, "table"),
         ("hertz-kalker", 8, "strip"), ("hertz-fastsim", 8, "strip"), ("bem", 0, "table")]

CHILD = r"""
import json, resource, sys, time
from railvti import scenarios
contact, n, dur, geo = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
scenarios.contact_table()                      # table build (cached per process)
scenarios.coach_system(geometry=geo)           # the strip arrays too
t0 = time.perf_counter()
r = scenarios.hunting(300.0, contact=contact, duration=dur, y0=0.004, fastsim_n=max(n, 1),
                     progress=False, geometry=geo)
wall = time.perf_counter() - t0
print(json.dumps({"wall": wall, "rtf": wall / dur, "amp_mm": scenarios.amplitude(r) * 1e3,
                  "bem_per_step": r.stats.get("bem_solves_per_step", 0.0),
                  "grid": list(r.stats.get("bem_grid", ()))[:2],
                  "steps": r.stats["steps"], "newton": r.stats["newton_iterations"],
                  "tangents": r.stats["tangents"], "sub": r.stats["substepped_steps"],
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def main() -> None:
    dur = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    dur_bem = float(sys.argv[2]) if len(sys.argv) > 2 else min(dur, 1.0)
    print(f"hunting at 300 km/h, {dur:g} s simulated ({dur_bem:g} s with the BEM), h = 1 ms "
          "(RR coach, 53 DOF, 8 wheels)")
    print(f"{'contact':>14s} {'geometry':>8s} {'n':>3s} {'sim s':>6s} {'wall s':>8s} {'RTF':>8s} {'amp mm':>7s} "
          f"{'steps':>6s} {'Newton/step':>11s} {'tangents':>8s} {'sub-stepped':>11s} "
          f"{'BEM/step':>8s} {'peak RSS MB':>11s}")
    for contact, n, geo in CASES:
        d_run = dur_bem if contact == "bem" else dur
        out = subprocess.run([sys.executable, "-c", CHILD, contact, str(n), str(d_run), geo],
                             capture_output=True, text=True, check=True)
        d = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{contact:>14s} {geo:>8s} {n:3d} {d_run:6.2f} {d['wall']:8.2f} {d['rtf']:8.3f} "
              f"{d['amp_mm']:7.2f} {d['steps']:6d} {d['newton'] / d['steps']:11.2f} "
              f"{d['tangents']:8d} {d['sub']:11d} {d['bem_per_step']:8.1f} {d['rss_mb']:11.0f}")
        if contact == "bem":
            print(f"{'':>23s} BEM grid {d['grid'][0]} x {d['grid'][1]} elements of 0.75 mm per "
                  "wheel and candidate point; BEM/step = normal + rolling solve pairs per step")


if __name__ == "__main__":
    main()
