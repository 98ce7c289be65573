"""The strip contact's cost against the table's: wall time of the vehicle run, interleaved.

10 s of hunting at 300 km/h (leading bogie released from 4 mm), coach RR model, h = 1 ms,
Hertz + FASTSIM 8 x 8 and Hertz + Kalker, on the table's points and on the strip contact;
each run in its own subprocess, the cases interleaved (table, strip, table, strip, ...) and
repeated, so that the machine's load falls on both alike. With ``--python`` the same cases also
run under other interpreters (e.g. the virtual environment of a previous build), interleaved
with this one: a before/after comparison in one run. Reports the median wall time per case,
the strip/table ratio of both wall and CPU time (the process's own: less noisy when the
machine is oversubscribed), the load average, and the counts (Newton iterations and tangents per
step, sub-stepped steps) and the amplitude of each build.

    .venv/bin/python benchmarks/bench_vehicle_strip.py [duration_s] [--repeat N] [--python PY ...]
        [--contact hertz-fastsim|hertz-kalker]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CASES = [
    ("hertz-fastsim", "table"),
    ("hertz-fastsim", "strip"),
    ("hertz-kalker", "table"),
    ("hertz-kalker", "strip"),
]

CHILD = r"""
import json, sys, time
from railvti import scenarios
contact, dur, geo = sys.argv[1], float(sys.argv[2]), sys.argv[3]
scenarios.wheel_table()
scenarios.coach_system(geometry=geo)
t0 = time.perf_counter()
c0 = time.process_time()
r = scenarios.hunting(300.0, contact=contact, duration=dur, y0=0.004, fastsim_n=8,
                      progress=False, geometry=geo)
wall = time.perf_counter() - t0
cpu = time.process_time() - c0
print(json.dumps({"wall": wall, "cpu": cpu, "amp_mm": scenarios.amplitude(r) * 1e3,
                  "steps": r.stats["steps"], "newton": r.stats["newton_iterations"],
                  "tangents": r.stats["tangents"], "sub": r.stats["substepped_steps"]}))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("duration", nargs="?", type=float, default=10.0, help="simulated s")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--python", nargs="*", default=[], help="further interpreters to compare")
    ap.add_argument(
        "--contact",
        choices=["hertz-fastsim", "hertz-kalker"],
        default=None,
        help="only this contact model (default both)",
    )
    a = ap.parse_args()
    cases = [c for c in CASES if a.contact in (None, c[0])]
    pythons = [sys.executable] + a.python
    runs: dict = {}
    loads = []
    print(
        f"hunting at 300 km/h, {a.duration:g} s simulated, h = 1 ms (RR coach, 8 wheels); "
        f"{a.repeat} interleaved repetitions"
    )
    for _ in range(a.repeat):
        for contact, geo in cases:
            for py in pythons:
                loads.append(os.getloadavg()[0])
                out = subprocess.run(
                    [py, "-c", CHILD, contact, str(a.duration), geo],
                    capture_output=True,
                    text=True,
                    check=True,
                )
                runs.setdefault((py, contact, geo), []).append(
                    json.loads(out.stdout.strip().splitlines()[-1])
                )
    print(
        f"load average (1 min) during the runs: {min(loads):.1f} .. {max(loads):.1f} on "
        f"{os.cpu_count()} cores"
    )
    print(
        f"{'build':>6s} {'contact':>14s} {'geometry':>8s} {'wall s (median)':>15s} {'strip/table':>11s} "
        f"{'CPU s (median)':>14s} {'strip/table':>11s} "
        f"{'amp mm':>7s} {'Newton/step':>11s} {'tangents/step':>13s} {'sub-stepped':>11s}"
    )
    for i, py in enumerate(pythons):
        for contact, geo in cases:
            rs = runs[(py, contact, geo)]
            wall = statistics.median(r["wall"] for r in rs)
            ref = statistics.median(r["wall"] for r in runs[(py, contact, "table")])
            cpu = statistics.median(r["cpu"] for r in rs)
            cref = statistics.median(r["cpu"] for r in runs[(py, contact, "table")])
            d = rs[-1]
            print(
                f"{i:6d} {contact:>14s} {geo:>8s} {wall:15.2f} {wall / ref:11.2f} {cpu:14.2f} {cpu / cref:11.2f} "
                f"{d['amp_mm']:7.3f} "
                f"{d['newton'] / d['steps']:11.2f} {d['tangents'] / d['steps']:13.2f} {d['sub']:11d}"
            )
    for i, py in enumerate(pythons):
        print(f"build {i}: {py}")


if __name__ == "__main__":
    main()
