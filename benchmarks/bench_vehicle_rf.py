"""Model RF against RR: centred running at 200 km/h, Q and rail deflection under the wheels,
wall time of the time loop (one process, the same conditions for both).

Ring of ``n_sleepers`` sleepers with the RingTrack defaults but ``f_max`` = max(f_limit, 500)
Hz, ring modes up to ``f_limit`` Hz plus the residual flexibility at the contact points,
Hertz + Kalker, h = 0.5 ms, outputs every step; the first fifth of the run is skipped.

    .venv/bin/python benchmarks/bench_vehicle_rf.py [n_sleepers] [f_limit_hz] [duration_s]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from railvti import scenarios


def main(n_sl: int = 40, f_limit: float = 500.0, dur: float = 0.5) -> None:
    tp = dict(f_max=max(f_limit, 500.0))
    t0 = time.perf_counter()
    sy = scenarios.rf_system(speed_kmh=200.0, n_sleepers=n_sl, f_limit=f_limit, track_params=tp)
    print(
        f"RF ring n_sl={n_sl} {tp}: {sy.ring.n_modes} ring modes <= {f_limit} Hz + "
        f"{sy.ring.n_residual} residual coordinates; build {time.perf_counter() - t0:.1f} s"
    )
    half = 0.5 * sy.ring.rail_distance
    for model in ("RR", "RF"):
        kw = dict(n_sleepers=n_sl, f_limit=f_limit, track_params=tp) if model == "RF" else {}
        t0 = time.perf_counter()
        c = scenarios.centred_running(
            200.0, variant=model, duration=dur, progress=False, output_dt=5e-4, h=5e-4, **kw
        )
        wall = time.perf_counter() - t0
        r = c.run
        rw = r.stats["wall_time"]
        n0 = len(r.t) // 5
        q = r.Q[n0:]
        print(
            f"{model}: time loop {rw:.2f} s for {dur} s (real-time factor {rw / dur:.2f}; "
            f"Newton iterations {r.stats['newton_iterations']:.0f}); centred_running {wall:.2f} s"
        )
        print(f"  Q mean [kN] (rows left/right, wheelsets 1..4):\n{np.round(q.mean(0) / 1e3, 3)}")
        print(
            f"  Q min / max [kN]: {q.min() / 1e3:.3f} / {q.max() / 1e3:.3f} "
            f"(static {c.static_wheel_load / 1e3:.3f})"
        )
        if c.rail is None:
            continue
        z = c.rail[n0:, 1] + np.array([half, -half])[:, None] * c.rail[n0:, 2]
        print(f"  rail crown z under the wheels, mean [mm]:\n{np.round(z.mean(0) * 1e3, 4)}")
        dt = r.t[1] - r.t[0]
        for name, sig in (("Q wheel 1L", q[:, 0, 0]), ("z wheel 1L", z[:, 0, 0])):
            s = sig - sig.mean()
            f = np.fft.rfftfreq(s.size, dt)
            a = np.abs(np.fft.rfft(s * np.hanning(s.size)))
            print(
                f"  {name}: peak-to-peak {np.ptp(sig):.4g}, dominant {f[a.argmax()]:.1f} Hz "
                f"(sleeper passing {200 / 3.6 / 0.6:.1f} Hz; resolution {f[1]:.1f} Hz)"
            )


if __name__ == "__main__":
    a = sys.argv[1:]
    main(int(a[0]) if a else 40, float(a[1]) if len(a) > 1 else 500.0, float(a[2]) if len(a) > 2 else 0.5)
