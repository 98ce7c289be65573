"""The cost of an irregular track in the time loop (issue 34 item 1; docs/vehicle_irregularity.md).

    .venv/bin/python benchmarks/bench_vehicle_irregularity.py [duration_s] [--variant RR] [--repeat 3]

The same run, 120 km/h, Hertz + Kalker on the strips, from the static equilibrium on perfect
track, three ways, alternated ``repeat`` times in one process: on perfect track, on an
irregularity of zeros (the inputs evaluated at every sub-step: the bookkeeping alone) and on a
rough irregularity (four channels, sines 3-30 m, about 1 mm). Prints the median wall time of
each, their ratio to the perfect track's, the Newton iterations per step (the rough track's
extra work is the motion it causes) and the load average.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from railvti.track.irregularity import TrackIrregularity
from railvti.vehicle.equilibrium import static_equilibrium
from railvti.vehicle.simulate import simulate
from railvti.vehicle.systems import scenario_system, time_step


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    duration = float(args[0]) if args else 2.0
    variant = sys.argv[sys.argv.index("--variant") + 1] if "--variant" in sys.argv else "RR"
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 3
    v = 120 / 3.6
    sy, _ = scenario_system(variant, None, v, {})
    h = time_step(sy, None)
    q0, v0, _ = static_equilibrium(sy, v, "hertz-kalker", return_velocity=True)
    x = np.arange(-30.0, v * duration + 30.0, 0.1)
    fade = np.clip(x / 10.0, 0.0, 1.0)
    rough = {
        "vertical_level": 1e-3 * np.sin(2 * np.pi * x / 7.0) * fade,
        "alignment": 1e-3 * np.sin(2 * np.pi * x / 23.0 + 1.0) * fade,
        "cross_level": 6e-4 * np.sin(2 * np.pi * x / 11.0 + 2.0) * fade,
        "gauge": 5e-4 * np.sin(2 * np.pi * x / 3.3) * fade,
    }
    cases = {
        "perfect": None,
        "zeros": TrackIrregularity(x, *(np.zeros_like(x),) * 4),
        "rough": TrackIrregularity(x, **rough),
    }
    wall = {k: [] for k in cases}
    iters = {}
    for _ in range(repeat):
        for name, irr in cases.items():
            t0 = time.perf_counter()
            r = simulate(sy, v, duration, h=h, q0=q0, v0=v0, irregularity=irr, x_start=-11.0, progress=False)
            wall[name].append(time.perf_counter() - t0)
            iters[name] = r.stats["newton_iterations"] / r.stats["steps"]
    base = np.median(wall["perfect"])
    print(f"{variant}, {duration:g} s at 120 km/h, h = {h:g} s, {repeat} alternated repeats")
    for name in cases:
        m = np.median(wall[name])
        print(f"  {name:8s} wall {m:.3f} s (x{m / base:.3f}), Newton iterations per step {iters[name]:.2f}")
    print(f"load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
