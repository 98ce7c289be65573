"""The variants against each other per scene (issue 34, item 5: model='auto'), FF the
reference (the richest model).

Scene `centred`: centred running at 300 km/h, Hertz + FASTSIM, 0.2 s, each variant's default
model: the dynamic wheel load (largest peak-to-peak of Q over the last 0.05 s: the sleeper
passing) and Q max; cost: CPU time of the call over the simulated time, one thread.
Scene `critical-speed`: the strip folds of the four-variant study (README, validation/
vehicle_four_study.py): RR 292.5, FR 277.5, RF 292.5, FF 280.0 km/h; costs: hunting at
300 km/h (benchmarks/bench_vehicle_variants.py, session 19: RR 0.67 s, FR 1.61, RF 4.59,
FF 5.00 s CPU for 2 s).

Run: OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_variant_choice.py
"""

from __future__ import annotations

import os
import time

from railvti import scenarios


def main() -> None:
    print(f"load {os.getloadavg()[0]:.2f}")
    out = {}
    for v in ("RR", "FR", "RF", "FF"):
        scenarios.centred_running(300, v, "hertz-fastsim", duration=0.002)  # build, cached
        t0 = time.process_time()
        c = scenarios.centred_running(300, v, "hertz-fastsim", duration=0.2, output_dt=2.5e-4)
        cpu = time.process_time() - t0
        q = c.run.wheel_output("Q")
        last = c.run.t >= c.run.t[-1] - 0.05
        dq = float((q[last].max(axis=0) - q[last].min(axis=0)).max())
        out[v] = (cpu / 0.2, dq, float(q.max()))
    ref = out["FF"]
    print("| variant | RTF (CPU) | dynamic Q | error | Q max | error |")
    print("|---|---|---|---|---|---|")
    for v, (rtf, dq, qm) in out.items():
        print(
            f"| {v} | {rtf:.2f} | {dq / 1e3:.3f} kN | {100 * abs(dq / ref[1] - 1):.1f} % | {qm / 1e3:.3f} kN | "
            f"{100 * abs(qm / ref[2] - 1):.2f} % |"
        )


if __name__ == "__main__":
    main()
