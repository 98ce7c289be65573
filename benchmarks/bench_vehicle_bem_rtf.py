"""The BEM coach's real-time factor, split (issue 33 item 2): table, system, static solve and
time loop of ``scenarios.hunting(300, variant="RR", contact="bem", duration=10, threads=1)``,
with the solves, linear updates and Newton iterations per step, before/after in one run.

Each case runs in its own process, one after the other (alternating builds: ``--old`` gives
the PYTHONPATH of a build of the starting commit, e.g. ``$WT/_site_old``), from a fresh
process: the table and the system are built inside the timed call, as a user's first call
builds them. Cases: ``new`` (this build, defaults), ``old`` (the old build), ``new-solve``
(this build with ``update_band=0``: every patch solved, the linear updates' effect alone)
and ``old-tight`` (the old build with ``tol_normal=1e-8``, ``tol_rolling=1e-5``: how far the
BEM's own tolerances move the results, the yardstick of the others). Prints per case the
wall time and RTF of the whole call and of its parts, the CPU time of the call (the steadier
figure on a loaded machine), and the leading wheelset's amplitude
per second (half peak-to-peak of y_ws1), Q max and |Y| max against the first case's.

    PYTHONPATH=$WT/_site python benchmarks/bench_vehicle_bem_rtf.py [duration_s] [--old PATH]
        [--cases old,new,new-solve,old-tight] [--speed 300] [--variant RR]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
from railvti import scenarios
from railvti.vehicle import BemOptions
dur, out, speed, variant, opts = float(sys.argv[1]), sys.argv[2], float(sys.argv[3]), sys.argv[4], json.loads(sys.argv[5])
t1 = time.perf_counter()
c1 = time.process_time()
scenarios.wheel_table()
t2 = time.perf_counter()
scenarios.coach_system(variant) if variant == "RR" else scenarios.coach_system(variant, speed_kmh=speed)
t3 = time.perf_counter()
kw = {"bem_options": BemOptions(**opts)} if opts else {}
r = scenarios.hunting(speed, variant=variant, contact="bem", duration=dur, threads=1, progress=False, **kw)
t4 = time.perf_counter()
c4 = time.process_time()
s = r.stats
np.savez(out, t=r.t, y=r.y_ws1, q=r.Q, yf=r.Y)
print(json.dumps({"import": t1 - t0, "table": t2 - t1, "system": t3 - t2, "hunting": t4 - t3,
                  "loop": s["wall_time"], "cpu": c4 - c1, "steps": s["steps"], "newton": s["newton_iterations"],
                  "pairs": s["bem_normal_solves"], "updates": s.get("bem_linear_updates", 0),
                  "lin_err": s.get("bem_max_linear_error", 0.0)}))
"""

CASES = {
    "new": ("new", {}),
    "old": ("old", {}),
    "new-solve": ("new", {"update_band": 0.0}),
    "old-tight": ("old", {"tol_normal": 1e-8, "tol_rolling": 1e-5}),
}


def run(case: str, pythonpath: str, dur: float, speed: float, variant: str, tmp: str) -> dict:
    """One case in its own process: its timings and its output arrays."""
    build, opts = CASES[case]
    out = os.path.join(tmp, case + ".npz")
    env = dict(os.environ, PYTHONPATH=pythonpath)
    p = subprocess.run(
        [sys.executable, "-c", CHILD, str(dur), out, str(speed), variant, json.dumps(opts)],
        capture_output=True,
        text=True,
        env=env,
    )
    if p.returncode != 0:
        raise SystemExit(f"case {case} failed:\n{p.stderr[-2000:]}")
    import numpy as np

    d = json.loads(p.stdout.strip().splitlines()[-1])
    d.update(dict(np.load(out)))
    return d


def amplitudes(d: dict, dur: float) -> list[float]:
    """Half peak-to-peak of y_ws1 per second of the run, m."""
    t, y = d["t"], d["y"]
    return [0.5 * float(np.ptp(y[(t >= k) & (t <= k + 1)])) for k in range(max(int(round(dur)), 1))]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("duration", nargs="?", type=float, default=10.0, help="simulated time, s")
    ap.add_argument("--old", help="PYTHONPATH of the old build (cases old, old-tight)")
    ap.add_argument("--cases", default=None, help="comma-separated cases, in this order")
    ap.add_argument("--speed", type=float, default=300.0, help="km/h")
    ap.add_argument("--variant", default="RR")
    args = ap.parse_args()
    cases = (args.cases or ("old,new" if args.old else "new")).split(",")
    paths = {"new": os.environ.get("PYTHONPATH", ""), "old": args.old}
    tmp = tempfile.mkdtemp()
    load0 = os.getloadavg()
    res = {}
    for c in cases:
        build = CASES[c][0]
        if paths[build] is None:
            raise SystemExit(f"case {c} needs --old")
        res[c] = run(c, paths[build], args.duration, args.speed, args.variant, tmp)
    dur = args.duration
    print(
        f"BEM 0.75 mm, {args.variant}, hunting at {args.speed:g} km/h from 4 mm, {dur:g} s, 1 thread, cases one "
        f"after the other; load (1, 5, 15 min) {tuple(round(x, 2) for x in load0)} -> "
        f"{tuple(round(x, 2) for x in os.getloadavg())} on {os.cpu_count()} cores"
    )
    print(
        f"{'case':>10s} {'call s':>7s} {'RTF':>6s} {'CPU s':>6s} | {'import':>6s} {'table':>6s} {'system':>6s} {'static':>6s} "
        f"{'loop':>7s} {'loop RTF':>8s} | {'Newton':>6s} {'solves':>6s} {'updates':>7s} /step {'lin err N':>9s}"
    )
    for c, d in res.items():
        call = d["table"] + d["system"] + d["hunting"]
        static = d["hunting"] - d["loop"]
        n = d["steps"]
        print(
            f"{c:>10s} {call:7.1f} {call / dur:6.2f} {d['cpu']:6.1f} | {d['import']:6.2f} {d['table']:6.2f} {d['system']:6.2f} "
            f"{static:6.2f} {d['loop']:7.1f} {d['loop'] / dur:8.2f} | {d['newton'] / n:6.2f} {d['pairs'] / n:6.2f} "
            f"{d['updates'] / n:7.2f}      {d['lin_err']:9.2f}"
        )
    base = cases[0]
    b = res[base]
    amp_b = amplitudes(b, dur)
    print(f"against {base}: amplitude of y_ws1 per second (half peak-to-peak), Q max, |Y| max")
    for c, d in res.items():
        amp = amplitudes(d, dur)
        parts = []
        for k, (x, y) in enumerate(zip(amp, amp_b)):
            if y < 1e-6:
                parts.append(f"{k}-{k + 1} s {x * 1e3:.2e} mm (old < 1 um)")
                break
            parts.append(f"{k}-{k + 1} s {x * 1e3:.4f} mm ({100 * (x / y - 1):+.3f} %)")
        dy = float(np.abs(d["y"] - b["y"]).max()) if d["y"].shape == b["y"].shape else float("nan")
        print(
            f"{c:>10s}: Q max {d['q'].max():.1f} N ({d['q'].max() - b['q'].max():+.1f}), |Y| max "
            f"{np.abs(d['yf']).max():.1f} N ({np.abs(d['yf']).max() - np.abs(b['yf']).max():+.1f}), "
            f"y_ws1 within {dy * 1e3:.2e} mm"
        )
        print("            " + "; ".join(parts))


if __name__ == "__main__":
    import numpy as np

    main()
