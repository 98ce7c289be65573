"""Model FR, hunting (6 mm) and centred running at 300 km/h, 2 s, Hertz + FASTSIM on the strip
contact: the exact modal step at RR's 1 ms against the old default (the trapezoidal modal step
at 0.5 ms, h omega_max <= 2; FR's default is now 'exact-flange', validation/vehicle_fr_flange_step.py) and a converged reference (the trapezoidal step at 1/16 ms, checked
by the exact step at 1/8 ms) (issue 33; docs/vehicle_integrator.md, "Exact modal step").

    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_modal_step.py [duration_s] [variant]

``variant`` 'FR' (default) or 'RF' (the ring track's modes; its reference: the trapezoidal step
at 1/8 ms, checked by the exact step at 1/4 ms).

Measured per run: the leading wheelset's largest lateral displacement over the last 0.5 s
(hunting: the decayed amplitude), the largest wheel load Q over the run (outputs every 2 ms), and
the RMS over time of each modal coordinate (FR: the 108 of the wheelsets) (the error: the norm of the RMS
differences over the norm of the reference's RMS, and the largest single one over the largest
RMS); CPU time, steps, Newton iterations.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from railvti import scenarios

#: (modal_step, h in ms): the reference first.
RUNS = {
    "FR": (("trapezoidal", 0.0625), ("exact", 0.125), ("trapezoidal", 0.5), ("exact", 0.5), ("exact", 1.0)),
    "RF": (("trapezoidal", 0.125), ("exact", 0.25), ("trapezoidal", 0.5), ("exact", 0.5), ("exact", 1.0)),
}


def run(scen: str, modal_step: str, h_ms: float, duration: float, variant: str = "FR") -> dict:
    """One run's measures."""
    kw = dict(contact="hertz-fastsim", duration=duration, output_dt=2e-3, progress=False)
    kw.update(h=h_ms * 1e-3, modal_step=modal_step)
    c0 = time.process_time()
    if scen == "centred":
        c = scenarios.centred_running(300.0, variant=variant, **kw)
        r, sy = c.run, c.system
    else:
        r, sy, _ = scenarios.hunting(300.0, variant=variant, y0=0.006, return_system=True, **kw)
    cpu = time.process_time() - c0
    n = sy.n  # the rigid DOFs; the modal coordinates follow
    late = r.t >= r.t[-1] - 0.5
    rail = getattr(r, "rail", None)  # the rail's pose under the wheels (RF, FF)
    return dict(
        cpu=cpu,
        steps=r.stats["steps"],
        nit=r.stats["newton_iterations"],
        tan=r.stats.get("tangents", np.nan),
        y=float(np.abs(r.y_ws1[late]).max()),
        Q=float(r.Q.max()),
        rail=float(np.abs(rail[late, 1]).max()) if rail is not None else np.nan,
        rms=np.sqrt((r.q[:, n:] ** 2).mean(axis=0)),
    )


def main(duration: float, variant: str = "FR") -> None:
    runs = RUNS[variant]
    for scen in ("hunting", "centred"):
        res = {(ms, h): run(scen, ms, h, duration, variant) for ms, h in runs}
        ref = res[runs[0]]
        print(
            f"{variant} {scen}, {duration:g} s: reference ({runs[0][0]}, {runs[0][1]} ms): max|y_ws1| last 0.5 s "
            f"{ref['y'] * 1e3:.6f} mm, Q max {ref['Q'] / 1e3:.4f} kN"
        )
        for (ms, h), m in res.items():
            dr = m["rms"] - ref["rms"]
            print(
                f"  {ms:11s} h {h:6.4f} ms: y {(m['y'] / ref['y'] - 1) * 100 if ref['y'] > 1e-9 else 0.0:+.3f} %, "
                f"Q max {(m['Q'] - ref['Q']) / 1e3:+.3f} kN, modal RMS {np.linalg.norm(dr) / np.linalg.norm(ref['rms']):.2e} "
                f"(largest {np.abs(dr).max() / ref['rms'].max():.2e}); {m['steps']:.0f} steps, "
                f"{m['nit']:.0f} Newton iterations, CPU {m['cpu']:.2f} s",
                flush=True,
            )


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 2.0, sys.argv[2] if len(sys.argv) > 2 else "FR")
