"""The four variants side by side (issue 33): centred running and hunting at 300 km/h, 2 s,
Hertz + FASTSIM, each variant's default model (FR/FF wheelsets k_max 2, f_max 800 Hz; ring
n_sleepers 40, modes to 500 Hz with the residual flexibility), in one process, one thread.

Each variant's system is built first (its build time printed apart: the rings and the FE
wheelset are cached per process), then each scenario is timed as a whole call (static
equilibrium and time loop; wall and CPU time: on a loaded machine the CPU time of this one-thread
process is the steadier figure) and its time loop alone, with the ratio to RR's. The results
printed (the leading wheelset's largest lateral displacement, the largest wheel load, the
modal coordinates' RMS and the rail's largest vertical deflection under the wheels) let two
builds be compared: run this script under each and compare the lines.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/bench_vehicle_variants.py [duration_s] [variants] [modal_step]

``modal_step`` ('exact' or 'trapezoidal', default: simulate's) is passed to the modal variants;
with 'exact' their default step is RR's 1 ms (docs/vehicle_integrator.md, "Exact modal step").

To compare two builds in one run, give each its own install (pip install --target DIR .)
and alternate: ``for p in OLD NEW OLD NEW; do PYTHONPATH=$p python bench...; done``.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from railvti import scenarios
from railvti.vehicle.run_result import _dof_unit


def main(
    duration: float = 2.0, variants: tuple[str, ...] = ("RR", "FR", "RF", "FF"), modal_step: str | None = None
) -> None:
    print(
        f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores; railvti from {scenarios.__file__}"
    )
    kw = dict(contact="hertz-fastsim", duration=duration, output_dt=2e-3, progress=False)
    if modal_step is not None:
        kw["modal_step"] = modal_step
        print(f"modal_step={modal_step!r}")
    times: dict[tuple[str, str], tuple[float, float]] = {}
    for v in variants:
        t0 = time.perf_counter()
        scenarios.centred_running(300.0, variant=v, **{**kw, "duration": 0.002})  # builds, caches
        build = time.perf_counter() - t0
        for scen in ("centred", "hunting"):
            t0, c0 = time.perf_counter(), time.process_time()
            if scen == "centred":
                r = scenarios.centred_running(300.0, variant=v, **kw).run
            else:
                r = scenarios.hunting(300.0, variant=v, y0=0.006, **kw)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            loop = r.stats["wall_time"]
            times[v, scen] = (cpu, loop)
            late = r.t >= r.t[-1] - 0.5
            modal = [i for i, n in enumerate(r.dof_names) if _dof_unit(n, False) == "1"]
            extra = ""
            if modal:  # the mass-normalised modal coordinates (wheelsets', ring's), and the rail
                extra += f"; modal RMS last 0.5 s {np.sqrt(np.mean(r.q[late][:, modal] ** 2)):.6e}"
            if r.rail is not None:
                extra += f", max|rail z| {np.abs(r.rail[late, 1]).max() * 1e3:.6f} mm"
            print(
                f"{v} {scen:8s}: call {wall:6.2f} s wall, {cpu:6.2f} s CPU, loop {loop:6.2f} s (RTF {loop / duration:5.2f}); "
                f"{r.stats['steps']:.0f} steps, {r.stats['newton_iterations']:.0f} Newton iterations, "
                f"{r.stats['tangents']:.0f} tangents; max|y_ws1| last 0.5 s {np.abs(r.y_ws1[late]).max() * 1e3:.6f} mm, "
                f"Q max {r.Q.max() / 1e3:.4f} kN{extra}; (build {build:.1f} s)",
                flush=True,
            )
    if "RR" in variants:
        for scen in ("centred", "hunting"):
            w0, l0 = times["RR", scen]
            print(
                f"{scen} over RR (call CPU / loop wall): "
                + ", ".join(
                    f"{v} {times[v, scen][0] / w0:.1f}x / {times[v, scen][1] / l0:.1f}x"
                    for v in variants
                    if v != "RR"
                )
            )
    print(f"load after {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    dur = float(sys.argv[1]) if len(sys.argv) > 1 else 2.0
    vs = tuple(sys.argv[2].split(",")) if len(sys.argv) > 2 else ("RR", "FR", "RF", "FF")
    main(dur, vs, sys.argv[3] if len(sys.argv) > 3 else None)
