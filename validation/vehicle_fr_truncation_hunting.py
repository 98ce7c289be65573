"""FR mode selection for hunting: the limit-cycle amplitude against the cost (issue 14 item 4,
the hunting half; the centred-running half is validation/vehicle_fr_truncation.py).

Hunting from the scenario's 4 mm start at 350 km/h (FR's Newton fails in flange impacts
above 380 km/h: docs/vehicle.md), Hertz + Kalker, each selection (k_max, f_max) at its own
default step (h omega_max <= 2, systems.default_step) and with the residual flexibility;
the amplitude is the leading wheelset's over the last second (scenarios.amplitude). The
error is against the richest selection run. The cost is the wall time per simulated second
of one run (the machine is shared: compare within one invocation). Prints a table and writes
validation/figures/vehicle_fr_truncation_hunting.png.

    .venv/bin/python validation/vehicle_fr_truncation_hunting.py [duration_s]   # default 6 s
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.errors import DivergenceError

SPEED_KMH = 350.0
SELECTIONS = [(k, f) for k in (0, 1, 2) for f in (300.0, 800.0)] + [(3, 1500.0)]
FIG = Path(__file__).resolve().parent / "figures" / "vehicle_fr_truncation_hunting.png"


def main() -> None:
    dur = float(sys.argv[1]) if len(sys.argv) > 1 else 6.0
    rows = []
    rr0 = time.perf_counter()
    rr = scenarios.hunting(SPEED_KMH, "RR", duration=dur, progress=False)
    rr_cost = (time.perf_counter() - rr0) / dur
    print(
        f"hunting {SPEED_KMH:.0f} km/h from 4 mm, Hertz + Kalker, {dur:g} s; RR: amplitude "
        f"{scenarios.amplitude(rr) * 1e3:.3f} mm, {rr_cost:.2f} s per simulated s",
        flush=True,
    )
    for k, f in SELECTIONS:
        t0 = time.perf_counter()
        try:
            r = scenarios.hunting(SPEED_KMH, "FR", duration=dur, progress=False, k_max=k, f_max=f)
            amp = scenarios.amplitude(r)
        except DivergenceError as e:
            amp = np.nan
            print(f"  k_max {k} / {f:.0f} Hz: failed ({str(e)[:80]})", flush=True)
        cost = (time.perf_counter() - t0) / dur
        rows.append((k, f, amp, cost))
        print(
            f"  k_max {k} / {f:5.0f} Hz: amplitude {amp * 1e3:.4f} mm, {cost:.2f} s per simulated s",
            flush=True,
        )
    ref = rows[-1][2]
    print(
        f"\n{'k_max':>5s} {'f_max Hz':>8s} {'amplitude mm':>12s} {'error mm':>9s} "
        f"{'error %':>7s} {'cost s/s':>8s} {'x RR':>5s}"
    )
    for k, f, amp, cost in rows:
        print(
            f"{k:5d} {f:8.0f} {amp * 1e3:12.4f} {abs(amp - ref) * 1e3:9.4f} "
            f"{abs(amp - ref) / ref * 100:7.2f} {cost:8.2f} {cost / rr_cost:5.1f}"
        )
    _plot(rows, ref, rr_cost, scenarios.amplitude(rr), dur)


def _plot(rows, ref: float, rr_cost: float, rr_amp: float, dur: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    floor = 1e-5
    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    for k in sorted({r[0] for r in rows[:-1]}):
        sel = [r for r in rows[:-1] if r[0] == k]
        c = [r[3] for r in sel]
        e = [max(abs(r[2] - ref) * 1e3, floor) for r in sel]
        (line,) = ax.plot(c, e, "o-", label=f"k_max {k}")
        for r, ci, ei in zip(sel, c, e):
            tag = f"{r[1]:.0f} Hz" + (" (= reference)" if abs(r[2] - ref) * 1e3 < floor else "")
            ax.annotate(
                tag, (ci, ei), textcoords="offset points", xytext=(5, 5), fontsize=7, color=line.get_color()
            )
    ax.axvline(rr_cost, color="k", ls=":", label=f"RR's cost (RR amplitude {rr_amp * 1e3:.2f} mm)")
    ax.set_xlabel("cost, wall s per simulated s (one run each)")
    ax.set_ylabel(f"|amplitude - reference|, mm (below {floor:g}: drawn at {floor:g})")
    ax.set_yscale("log")
    ax.set_title(
        f"FR hunting {SPEED_KMH:.0f} km/h from 4 mm, Hertz + Kalker, {dur:g} s: "
        f"limit-cycle amplitude\nagainst k_max 3 / 1500 Hz ({ref * 1e3:.3f} mm); "
        "points labelled by f_max",
        fontsize=9,
    )
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="center right")
    fig.tight_layout()
    fig.savefig(FIG, dpi=110)
    print(f"wrote {FIG}")


if __name__ == "__main__":
    main()
