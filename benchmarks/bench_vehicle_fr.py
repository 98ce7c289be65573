"""Model FR against RR: wall time and peak memory of hunting at 300 km/h (issue 14's speed
acceptance: FR with Hertz + FASTSIM, 10 s at 300 km/h, under 4x RR's wall time at the
default truncation).

Each case runs in its own subprocess (the peak resident memory is then the case's own):
RR, FR at the default selection (k_max 2 / 800 Hz, its default step h omega_max <= 2) and
FR at k_max 1 / 300 Hz (the truncation study's choice for steady scenes). All from the
scenario's 4 mm start, Hertz + FASTSIM, one run each; compare figures of one invocation
only (the machine is shared).

    .venv/bin/python benchmarks/bench_vehicle_fr.py [duration_s] [--python PY ...]  # 10 s
    .venv/bin/python benchmarks/bench_vehicle_fr.py bem [duration_s] [RR,FR,RF,FF] [PY ...]  # BEM 0.75 mm

The BEM mode: centred running at 200 km/h with the BEM on all eight wheels from the BEM's
static state (more Newton iterations than the scenario's default, as
validation/vehicle_fr_vs_rr.py), RR and FR (or the models named: RF and FF on the default
ring) at the default selection: the real-time factor (wall time per simulated second) of
the time loop alone. Interpreters given after the models (e.g. an older commit's venv) run
each model in turn, interleaved, so that the builds share the machine's load alike; the
leading wheelset's lateral displacement and its wheels' Q and Y of each build are then
compared with the first build's (largest difference over the run).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

CASES = (("RR", {}), ("FR", {}), ("FR", {"k_max": 1, "f_max": 300.0}))

_CHILD = """
import json, resource, sys, time
from railvti import scenarios
from railvti.vehicle import systems
model, kw, dur = sys.argv[1], json.loads(sys.argv[2]), float(sys.argv[3])
t0, c0 = time.perf_counter(), time.process_time()
r = scenarios.hunting(300.0, model, "hertz-fastsim", duration=dur, progress=False, **kw)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
print(json.dumps({"wall": wall, "cpu": cpu, "amp": scenarios.amplitude(r), "steps": r.stats["steps"],
                  "newton": r.stats["newton_iterations"], "n_state": int(r.q.shape[1]),
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


_BEM_CHILD = """
import json, resource, sys, time
from railvti import scenarios
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.equilibrium import bem_state
model, dur = sys.argv[1], float(sys.argv[2])
v = 200.0 / 3.6
sy = scenarios.coach_system(model, speed_kmh=200.0) if model != "RR" else scenarios.coach_system()
h = systems.default_step(sy)
with bem_state(sy) as st:
    q, qd, _ = static_equilibrium(sy, v, "bem", bem=st, return_velocity=True, tol=1e-9, maxit=200)
    t0 = time.perf_counter()
    r = simulate(sy, v, dur, q0=q, v0=qd, h=h, contact="bem", bem=st, progress=False)
    wall = time.perf_counter() - t0
if len(sys.argv) > 3:
    import numpy as np
    np.savez(sys.argv[3], t=r.t, y=r.y_ws1, q=r.Q[:, :, 0], yf=r.Y[:, :, 0])
print(json.dumps({"wall": wall, "h": h, "steps": r.stats["steps"],
                  "newton": r.stats["newton_iterations"], "pairs": r.stats["bem_normal_solves"],
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def bem(dur: float, models: tuple[str, ...] = ("RR", "FR"), pythons: tuple[str, ...] = ()) -> None:
    pythons = pythons or (sys.executable,)
    print(f"centred running 200 km/h, BEM 0.75 mm on all eight wheels, {dur:g} s simulated (time loop only)")
    print(f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores")
    print(
        f"{'model':22s} {'h ms':>6s} {'wall s':>7s} {'RTF':>6s} {'Newton/step':>11s} "
        f"{'pairs/step':>10s} {'peak RSS MB':>11s}  python"
    )
    import tempfile

    import numpy as np

    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            runs = []
            for i, py in enumerate(pythons):
                out = os.path.join(tmp, f"{model}_{i}.npz")
                p = subprocess.run(
                    [py, "-c", _BEM_CHILD, model, str(dur), out], capture_output=True, text=True, check=True
                )
                o = json.loads(p.stdout.strip().splitlines()[-1])
                runs.append(np.load(out))
                name = model + (" (default selection)" if model in ("FR", "FF") else "")
                steps = max(o["steps"], 1)
                print(
                    f"{name:22s} {o['h'] * 1e3:6.3f} {o['wall']:7.1f} {o['wall'] / dur:6.0f} "
                    f"{o['newton'] / steps:11.2f} {o['pairs'] / steps:10.1f} {o['rss_mb']:11.0f}  {py}"
                )
            for i, r in enumerate(runs[1:], 1):
                a = runs[0]
                print(
                    f"  {model}, build {i} - build 0, largest over the run: y_ws1 "
                    f"{np.abs(r['y'] - a['y']).max():.3g} m (|y| max {np.abs(a['y']).max():.3g} m), "
                    f"Q {np.abs(r['q'] - a['q']).max():.3g} N (Q max {a['q'].max():.6g} N), "
                    f"Y {np.abs(r['yf'] - a['yf']).max():.3g} N (|Y| max {np.abs(a['yf']).max():.4g} N)"
                )
    print(f"load {os.getloadavg()[0]:.2f} (1 min) at the end")


def main() -> None:
    if sys.argv[1:2] == ["bem"]:
        bem(
            float(sys.argv[2]) if len(sys.argv) > 2 else 0.1,
            tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("RR", "FR"),
            tuple(sys.argv[4:]),
        )
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("duration", nargs="?", type=float, default=10.0, help="simulated s")
    ap.add_argument(
        "--python",
        nargs="+",
        default=[sys.executable],
        help="interpreters of the builds to compare (e.g. an older commit's venv); "
        "their cases run interleaved, so they share the machine's load alike",
    )
    args = ap.parse_args()
    dur = args.duration
    print(
        f"hunting 300 km/h from 4 mm, Hertz + FASTSIM, {dur:g} s simulated, one run each "
        "(wall time includes building the model and the static solve); "
        f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores"
    )
    out = {py: [] for py in args.python}
    for model, kw in CASES:
        for py in args.python:
            p = subprocess.run(
                [py, "-c", _CHILD, model, json.dumps(kw), str(dur)],
                capture_output=True,
                text=True,
                check=True,
            )
            out[py].append(json.loads(p.stdout.strip().splitlines()[-1]))
    for py in args.python:
        rr = out[py][0]["wall"]
        print(f"\n{py}")
        print(
            f"{'model':28s} {'wall s':>7s} {'x RR':>5s} {'CPU s':>6s} {'x RR':>5s} {'steps':>6s} "
            f"{'Newton/step':>11s} {'state':>5s} {'peak RSS MB':>11s} {'amplitude mm':>12s}"
        )
        for (model, kw), o in zip(CASES, out[py]):
            name = model + (
                f" k_max {kw['k_max']} / {kw['f_max']:.0f} Hz"
                if kw
                else (" (default selection)" if model == "FR" else "")
            )
            cpu, cpu_rr = o.get("cpu", float("nan")), out[py][0].get("cpu", float("nan"))
            print(
                f"{name:28s} {o['wall']:7.1f} {o['wall'] / rr:5.1f} {cpu:6.1f} {cpu / cpu_rr:5.1f} "
                f"{o['steps']:6d} {o['newton'] / max(o['steps'], 1):11.2f} {o['n_state']:5d} "
                f"{o['rss_mb']:11.0f} {o['amp'] * 1e3:12.3f}"
            )
    print(f"load {os.getloadavg()[0]:.2f} (1 min) at the end")


if __name__ == "__main__":
    main()
