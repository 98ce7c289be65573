"""The ring track's moving rows at RR's 1 ms (issue 33; docs/vehicle_integrator.md, "The ring's
moving rows"): variants RF and FF, hunting (6 mm) and centred running at 300 km/h, Hertz +
FASTSIM on the strip contact. ``modal_step='exact-moving'`` (the ring's modes integrated
exactly over their rows at m + 1 nodes a step, the point forces linear in time) at 1 ms for
m = 1, 2, 4, 8 (and at 0.5 ms for m = 2) against today's default (the trapezoidal modal step at 0.5 ms), the plain exact
step at 1 ms (rows at the step's ends, the force linear in time) and a converged reference (the
trapezoidal step at 1/8 ms, as validation/vehicle_fr_modal_step.py for RF).

    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_ring_moving_rows.py [duration_s] [variants] [scenarios]

Measured per run: the leading wheelset's largest lateral displacement over the last 0.5 s
(hunting: the decayed amplitude), the largest wheel load Q over the run (outputs every 2 ms), the
RMS over time of each modal coordinate (the error: the norm of the RMS differences over the
norm of the reference's RMS), the rail's largest vertical deflection under the wheels over the
last 0.5 s; CPU time, steps, Newton iterations and tangents. The figure
(validation/figures/vehicle_ring_moving_rows.png) draws each run's error in Q max and the modal
RMS against its CPU time.
"""

from __future__ import annotations

import importlib
import sys

import numpy as np

from railvti import scenarios
from vehicle_fr_modal_step import run as modal_step_run

_SIM = importlib.import_module("railvti.vehicle.simulate")

#: (label, modal_step, h in ms, ring nodes m): the reference first.
RUNS = (
    ("reference", "trapezoidal", 0.125, 0),
    ("default", "trapezoidal", 0.5, 0),
    ("exact", "exact", 1.0, 0),
    ("moving m1", "exact-moving", 1.0, 1),
    ("moving m2", "exact-moving", 1.0, 2),
    ("moving m4", "exact-moving", 1.0, 4),
    ("moving m8", "exact-moving", 1.0, 8),
    ("0.5ms m2", "exact-moving", 0.5, 2),
)


def run(variant: str, scen: str, modal_step: str, h_ms: float, nodes: int, duration: float) -> dict:
    """One run's measures (vehicle_fr_modal_step.run) with ``nodes`` ring nodes a step."""
    _SIM.RING_NODES = max(nodes, 1)
    return modal_step_run(scen, modal_step, h_ms, duration, variant)


def report(variant: str, scen: str, res: dict, duration: float) -> list:
    """Print the runs against the reference; the rows (label, cpu, dQ kN, modal RMS error)."""
    ref = res[RUNS[0][0]]
    print(
        f"{variant} {scen}, {duration:g} s: reference (trapezoidal 1/8 ms): max|y_ws1| last 0.5 s "
        f"{ref['y'] * 1e3:.6f} mm, Q max {ref['Q'] / 1e3:.4f} kN, max|rail z| {ref['rail'] * 1e3:.6f} mm"
    )
    rows = []
    for label, m in res.items():
        dr = m["rms"] - ref["rms"]
        err = np.linalg.norm(dr) / np.linalg.norm(ref["rms"])
        dq = (m["Q"] - ref["Q"]) / 1e3
        print(
            f"  {label:10s}: y {(m['y'] / ref['y'] - 1) * 100 if scen == 'hunting' else 0.0:+.3f} %, Q max {dq:+.3f} kN, "
            f"modal RMS {err:.2e}, rail {(m['rail'] / ref['rail'] - 1) * 100:+.3f} %; {m['steps']:.0f} steps, "
            f"{m['nit']:.0f} Newton its, {m['tan']:.0f} tangents, CPU {m['cpu']:.2f} s",
            flush=True,
        )
        if label != RUNS[0][0]:
            rows.append((label, m["cpu"], abs(dq), err))
    return rows


def plot(table: dict, path: str) -> None:
    """|error in Q max| and the modal RMS error against CPU time, one panel per case."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from railvti._plotting import save_figure

    fig, axes = plt.subplots(2, len(table), figsize=(4.2 * len(table), 6.5), squeeze=False)
    for col, ((variant, scen), rows) in enumerate(table.items()):
        for row, (idx, name) in enumerate(((2, "|Q max - reference| (kN)"), (3, "modal RMS error (-)"))):
            ax = axes[row, col]
            for label, *vals in rows:
                ax.semilogy(vals[0], max(vals[idx - 1], 1e-6), "o")
                ax.annotate(
                    label,
                    (vals[0], max(vals[idx - 1], 1e-6)),
                    xytext=(4, 4),
                    textcoords="offset points",
                    fontsize=7,
                )
            ax.set_xlabel("CPU time of the call (s)")
            ax.set_ylabel(name)
            ax.set_title(f"{variant} {scen}, 300 km/h")
            ax.grid(True, which="both", alpha=0.3)
    save_figure(fig, path)


def main(duration: float, variants: tuple[str, ...], scens: tuple[str, ...]) -> None:
    table = {}
    for variant in variants:
        scenarios.centred_running(
            300.0, variant=variant, contact="hertz-fastsim", duration=0.002, progress=False
        )
        for scen in scens:
            res = {label: run(variant, scen, ms, h, m, duration) for label, ms, h, m in RUNS}
            table[variant, scen] = report(variant, scen, res, duration)
    plot(table, "validation/figures/vehicle_ring_moving_rows.png")


if __name__ == "__main__":
    main(
        float(sys.argv[1]) if len(sys.argv) > 1 else 2.0,
        tuple(sys.argv[2].split(",")) if len(sys.argv) > 2 else ("RF", "FF"),
        tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("hunting", "centred"),
    )
