"""Model FF (flexible wheelsets on the ring track) against RR, FR and RF: wall time of 10 s
at 300 km/h with Hertz + FASTSIM at the default truncation, real-time factors, peak memory.

Each model runs centred running (static equilibrium, then ``duration`` s) in this one process,
one after another, so the machine's load is shared alike (it is printed: the machines are
shared). Defaults: FR/FF wheelsets k_max 2, f_max 800 Hz (steps h = 1/3 ms from the highest
kept mode), ring n_sleepers 40, modes up to 500 Hz with the residual flexibility. The peak
resident memory is the process's (``resource.getrusage``), after each model.

    .venv/bin/python benchmarks/bench_vehicle_ff.py [duration_s] [models, e.g. RR,FF]
"""

from __future__ import annotations

import os
import resource
import sys
import time


from railvti import scenarios
from railvti.vehicle import systems


def main(duration: float = 10.0, models: tuple[str, ...] = ("RR", "FR", "RF", "FF")) -> None:
    print(
        f"load {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores; {duration} s at "
        f"300 km/h, Hertz + FASTSIM, output every 2 ms"
    )
    rtf = {}
    for model in models:
        t0 = time.perf_counter()
        sy = scenarios.coach_system(model, speed_kmh=300.0) if model != "RR" else None
        build = time.perf_counter() - t0
        t0 = time.perf_counter()
        c = scenarios.centred_running(
            300.0, variant=model, contact="hertz-fastsim", duration=duration, output_dt=2e-3, progress=False
        )
        wall = time.perf_counter() - t0
        r = c.run
        loop = r.stats["wall_time"]
        rtf[model] = loop / duration
        nst = 0 if sy is None else sy.n_state - sy.n
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        h = 1e-3 if sy is None else systems.default_step(sy)
        print(
            f"{model}: {nst} modal coordinates; build {build:.1f} s; time loop {loop:.1f} s "
            f"(real-time factor {loop / duration:.2f}), centred_running {wall:.1f} s; "
            f"h {h * 1e3:.3g} ms; Newton iterations "
            f"{r.stats['newton_iterations']:.0f}; Q {r.Q.min() / 1e3:.2f}..{r.Q.max() / 1e3:.2f} kN; "
            f"peak memory {rss:.0f} MB"
        )
    if "RR" in rtf:
        print(
            "real-time factor over RR's: "
            + ", ".join(f"{m} {v / rtf['RR']:.1f}x" for m, v in rtf.items() if m != "RR")
        )
    print(f"load after {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    a = sys.argv[1:]
    main(float(a[0]) if a else 10.0, tuple(a[1].split(",")) if len(a) > 1 else ("RR", "FR", "RF", "FF"))
