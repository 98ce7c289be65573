"""FR mode selection for hunting: the error of each selection against its cost (issue 14 item 4,
the hunting half, re-measured for issue 33 item 5 with FR's 1 ms default step; the
centred-running half is validation/vehicle_fr_truncation.py).

Two scenes, Hertz + Kalker (the critical-speed study's contact):

- ``tread350``: released from 4 mm at 350 km/h, 6 s: a tread-contact limit cycle; its
  amplitude (the leading wheelset's, over the last second, scenarios.amplitude);
- ``flange420``: released from 6 mm at 420 km/h, 4 s: a flange limit cycle; its amplitude,
  Q max and |Y| max over the last second, all eight wheels.

Each selection (k_max, f_max) runs with the residual flexibility at FR's default step (the
exact modal step at 1 ms, 8 sub-steps in flange contact: simulate.default_modal_step), so
only the modes change; the error is against the richest selection. The cost is the CPU time
of the call per simulated second, after a 2 ms call that builds the system (one thread: the
steadier figure on a shared machine), and its ratio to RR's in the same run. Prints a table per scene and writes
validation/figures/vehicle_fr_truncation_hunting.json (the measures) and .png (the chart).

    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_truncation_hunting.py [scene ...]
    .venv/bin/python validation/vehicle_fr_truncation_hunting.py --replot
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.errors import DivergenceError

#: scene -> (speed km/h, release y0 m, simulated s, title)
SCENES = {
    "tread350": (350.0, 0.004, 6.0, "tread cycle, 350 km/h from 4 mm, 6 s"),
    "flange420": (420.0, 0.006, 4.0, "flange cycle, 420 km/h from 6 mm, 4 s"),
}
#: the quantities of a scene: key -> label
QUANTITIES = {
    "tread350": {"amp": "amplitude"},
    "flange420": {"amp": "amplitude", "q": "Q max", "y": "|Y| max"},
}
SELECTIONS = [(k, f) for k in (0, 1, 2) for f in (300.0, 800.0)] + [(3, 1500.0)]
FIG = Path(__file__).resolve().parent / "figures" / "vehicle_fr_truncation_hunting.png"
STORE = FIG.with_suffix(".json")


def measure(scene: str, variant: str, **kw) -> dict:
    """One run's measures (amplitude m, Q max and |Y| max N over the last second) and its CPU
    time per simulated second."""
    speed, y0, dur, _ = SCENES[scene]
    # the system first (the FE wheelset's modes, the tables: built or replayed from the disk cache)
    scenarios.hunting(speed, variant, "hertz-kalker", duration=0.002, y0=y0, progress=False, **kw)
    c0 = time.process_time()
    r = scenarios.hunting(
        speed, variant, "hertz-kalker", duration=dur, y0=y0, output_dt=1e-3, progress=False, **kw
    )
    cost = (time.process_time() - c0) / dur
    late = r.t >= r.t[-1] - 1.0
    return {
        "amp": scenarios.amplitude(r, 1.0),
        "q": float(r.Q[late].max()),
        "y": float(np.abs(r.Y[late]).max()),
        "cost": cost,
    }


def run_scene(scene: str) -> tuple[dict, list]:
    """RR, then FR for every selection; prints the table and returns (RR, rows)."""
    rr = measure(scene, "RR")
    print(
        f"\nFR hunting, {SCENES[scene][3]}, Hertz + Kalker; load {os.getloadavg()[0]:.2f}; RR: "
        f"amplitude {rr['amp'] * 1e3:.3f} mm, Q max {rr['q'] / 1e3:.1f} kN, |Y| max "
        f"{rr['y'] / 1e3:.1f} kN, {rr['cost']:.2f} s CPU per simulated s",
        flush=True,
    )
    rows = []
    for k, f in SELECTIONS:
        try:
            m = measure(scene, "FR", k_max=k, f_max=f)
        except DivergenceError as e:
            print(f"  k_max {k} / {f:.0f} Hz: failed ({str(e)[:80]})", flush=True)
            continue
        rows.append((k, f, m))
        print(
            f"  k_max {k} / {f:5.0f} Hz: amplitude {m['amp'] * 1e3:.4f} mm, Q max {m['q'] / 1e3:.2f} kN, "
            f"|Y| max {m['y'] / 1e3:.2f} kN, {m['cost']:.2f} s per simulated s",
            flush=True,
        )
    ref = rows[-1][2]
    keys = list(QUANTITIES[scene])
    head = " ".join(f"{QUANTITIES[scene][q] + ' err %':>16s}" for q in keys)
    print(f"{'k_max':>5s} {'f_max Hz':>8s} {head} {'cost s/s':>8s} {'x RR':>5s}")
    for k, f, m in rows:
        errs = " ".join(f"{(m[q] / ref[q] - 1) * 100:16.4f}" for q in keys)
        print(f"{k:5d} {f:8.0f} {errs} {m['cost']:8.2f} {m['cost'] / rr['cost']:5.1f}")
    return rr, rows


def plot(results: dict) -> None:
    """One panel per scene and quantity: |error| against the cost in RR's units."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    floor = 1e-4  # per cent
    panels = [(s, q) for s in results for q in QUANTITIES[s]]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4.2), squeeze=False)
    for ax, (scene, q) in zip(axes[0], panels):
        rr, rows = results[scene]
        ref = rows[-1][2]
        for k in sorted({r[0] for r in rows[:-1]}):
            sel = [r for r in rows[:-1] if r[0] == k]
            c = [r[2]["cost"] / rr["cost"] for r in sel]
            e = [max(abs(r[2][q] / ref[q] - 1) * 100, floor) for r in sel]
            (line,) = ax.plot(c, e, "o-", label=f"k_max {k}")
            for r, ci, ei in zip(sel, c, e):
                ax.annotate(
                    f"{r[1]:.0f} Hz", (ci, ei), textcoords="offset points", xytext=(4, 4), fontsize=7,
                    color=line.get_color(),
                )  # fmt: skip
        ax.axvline(ref["cost"] / rr["cost"], color="0.5", ls="--", lw=1, label="reference k_max 3 / 1500 Hz")
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
        ax.set_xlabel("cost, CPU time x RR's (same run)", fontsize=8)
        ax.set_ylabel(f"|error| against the reference, % (floor {floor:g} %)", fontsize=8)
        unit = f"{ref[q] * 1e3:.3f} mm" if q == "amp" else f"{ref[q] / 1e3:.1f} kN"
        ax.set_title(f"{SCENES[scene][3]}:\n{QUANTITIES[scene][q]} (ref. {unit})", fontsize=9)
        ax.grid(alpha=0.3, which="both")
    axes[0, 0].legend(fontsize=7, loc="best")
    fig.suptitle(
        "FR mode selection in hunting (Hertz + Kalker, residual flexibility, 1 ms exact modal step): "
        "error against cost; points labelled by f_max\n(k_max 2 at 300 Hz keeps k_max 1's modes: "
        "no k = 2 mode lies below 300 Hz, so the two points coincide)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(FIG, dpi=110)
    print(f"wrote {FIG}")


def main(scenes: list[str]) -> None:
    unknown = [s for s in scenes if s not in SCENES and s != "--replot"]
    if unknown:
        raise SystemExit(f"unknown scene(s) {unknown}; choose from {list(SCENES)}")
    if scenes == ["--replot"]:
        stored = json.loads(STORE.read_text())
        results = {s: (v["rr"], [tuple(r) for r in v["rows"]]) for s, v in stored.items()}
    else:
        results = {s: run_scene(s) for s in scenes or list(SCENES)}
        STORE.write_text(
            json.dumps({s: {"rr": rr, "rows": rows} for s, (rr, rows) in results.items()}, indent=1)
        )
    plot(results)


if __name__ == "__main__":
    main(sys.argv[1:])
