"""The cost estimate of railvti.runner.cost against measured runs: wall time and peak memory of a
handful of small cases of each case type, each run in its own subprocess (ru_maxrss is then
the case's own; the memory reported is the peak above the resident size before the run).

Prints, per case, the estimate and the measurement and their ratio (estimate / measured),
then per case type the range of the time ratios. The per-unit costs of railvti.runner.cost were
set from this script's output on the 2-core test machine (one core taken by another job):
the ratios say how far the estimate is from this machine at the time of the run.

    .venv/bin/python benchmarks/bench_cost_estimate.py [TYPE ...] [--timeout 300]
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

from railvti.runner.cost import duration_text, estimate_params
from railvti.resources import size_text

CHILD = r"""
import json, resource, sys, time
from railvti.runner.deck_registry import case_types
name, given = sys.argv[1], json.loads(sys.argv[2])
ctype = case_types()[name]
params = ctype.validate({**ctype.defaults, **given})
def rss():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return float(line.split()[1]) * 1024.0
before = rss()
t0 = time.perf_counter()
out = ctype.run(params)
secs = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0
print(json.dumps({"seconds": secs, "memory": max(peak - before, 0.0), "summary": out.summary[:70]}))
"""

HERTZ = dict(gap="hertz", gap_a=1.087, gap_b=1.6667, fn=1e4)
CASES: list[tuple[str, dict]] = [
    ("normal", dict(HERTZ, nx=40, ny=32, dx=2e-4, dy=2e-4)),
    ("normal", dict(HERTZ, nx=80, ny=64, dx=1e-4, dy=1e-4)),
    ("normal", dict(HERTZ, nx=160, ny=128, dx=5e-5, dy=5e-5)),
    ("normal", dict(HERTZ, nx=320, ny=256, dx=2.5e-5, dy=2.5e-5)),
    ("rolling", dict(HERTZ, nx=40, ny=32, dx=2e-4, dy=2e-4, mu=0.3, speed=30.0, xi=1e-3, eta=5e-4, phi=0.3)),
    ("rolling", dict(HERTZ, nx=80, ny=64, dx=1e-4, dy=1e-4, mu=0.3, speed=30.0, xi=1e-3, eta=5e-4, phi=0.3)),
    (
        "rolling",
        dict(HERTZ, nx=120, ny=96, dx=6.67e-5, dy=6.67e-5, mu=0.3, speed=30.0, xi=1e-3, eta=5e-4, phi=0.3),
    ),
    ("wheel_rail", dict(dx=4e-4, dy=4e-4)),
    ("wheel_rail", dict(side="both", dx=2e-4, dy=2e-4)),
    ("wheel_rail", dict(dx=1e-4, dy=1e-4)),
    ("wheel_rail", dict(dx=5e-5, dy=5e-5)),
    ("loaded_wheelset", dict(n=2, dx=4e-4)),
    ("loaded_wheelset", dict(n=3, dx=2e-4)),
    ("geometry_table", dict(n=51)),
    ("geometry_table", dict(n=201)),
    ("geometry_table", dict(n=2001)),
    ("geometry_table", dict(n=4001)),
    ("wheelset", dict(k_max=0, f_max=3000.0, n_freq=100)),
    ("wheelset", dict(k_max=2, f_max=3000.0, n_freq=100)),
    ("wheelset", dict(k_max=2, f_max=3000.0, n_freq=100, mesh_size=0.015)),
    ("track_receptance", dict(n_sleepers=8, f_max=1000.0, n_freq=200)),
    ("track_receptance", dict(n_sleepers=16, f_max=1000.0, n_freq=200)),
    ("track_receptance", dict(n_sleepers=32, f_max=1000.0, n_freq=200)),
    ("track_element", dict(n_sleepers=16)),
    ("vehicle", dict(scenario="hunting", duration=0.3, geometry="table")),
    ("vehicle", dict(scenario="hunting", duration=0.3, geometry="strip")),
    ("vehicle", dict(scenario="hunting", duration=0.6, contact="hertz-fastsim")),
    ("vehicle", dict(scenario="hunting", duration=0.1, model="FR")),
    ("vehicle", dict(scenario="hunting", duration=0.1, model="FR", f_max=2000.0)),
    ("vehicle", dict(scenario="hunting", duration=0.02, model="FR", f_max=5000.0)),
    ("vehicle", dict(scenario="hunting", duration=0.01, model="FR", f_max=20000.0)),
    ("vehicle", dict(scenario="hunting", duration=0.1, model="RF", n_sleepers=40)),
    ("vehicle", dict(scenario="hunting", duration=0.1, model="FF", n_sleepers=40)),
    ("vehicle", dict(scenario="critical_speed", duration=0.2, speeds_kmh_min=200.0, speeds_kmh_max=240.0)),
    ("vehicle", dict(scenario="hunting", duration=0.02, contact="bem")),
]


def _measure(name: str, params: dict, timeout: float) -> dict:
    try:
        r = subprocess.run(
            [sys.executable, "-c", CHILD, name, json.dumps(params)],
            capture_output=True,
            text=True,
            timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return {"seconds": float("nan"), "memory": float("nan"), "summary": f"timeout {timeout:g} s"}
    try:
        return json.loads(r.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        err = (r.stderr.strip().splitlines() or ["?"])[-1]
        return {"seconds": float("nan"), "memory": float("nan"), "summary": f"failed: {err[:60]}"}


def main(argv: list[str]) -> None:
    timeout = 300.0
    if "--timeout" in argv:
        i = argv.index("--timeout")
        timeout = float(argv[i + 1])
        argv = argv[:i] + argv[i + 2 :]
    types = set(argv)
    import os

    print(f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores")
    print(
        f"{'type':17s} {'params':58s} {'est':>8s} {'meas':>8s} {'ratio':>6s}  {'est mem':>8s} {'meas mem':>8s}"
    )
    ratios: dict[str, list[float]] = {}
    for name, params in CASES:
        if types and name not in types:
            continue
        e = estimate_params(name, params)
        t0 = time.perf_counter()
        m = _measure(name, params, timeout)
        ratio = (
            e.seconds / m["seconds"] if m["seconds"] == m["seconds"] and m["seconds"] > 0 else float("nan")
        )
        if ratio == ratio:
            ratios.setdefault(name, []).append(ratio)
        text = ", ".join(f"{k}={v}" for k, v in params.items() if k not in HERTZ)
        print(
            f"{name:17s} {text[:58]:58s} {duration_text(e.seconds):>8s} {duration_text(m['seconds']) if m['seconds'] == m['seconds'] else 'n/a':>8s} "
            f"{ratio:6.2f}  {size_text(e.memory):>8s} {size_text(m['memory']) if m['memory'] == m['memory'] else 'n/a':>8s}"
            f"  [{e.key}; {time.perf_counter() - t0:.0f} s with start-up] {m['summary'][:40]}",
            flush=True,
        )
    print("\nestimate / measured wall time per case type:")
    for name, r in ratios.items():
        print(f"  {name:17s} {min(r):.2f} .. {max(r):.2f} ({len(r)} cases)")


if __name__ == "__main__":
    main(sys.argv[1:])
