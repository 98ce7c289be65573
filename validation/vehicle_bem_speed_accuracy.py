"""Speed against accuracy of the contact models in the time loop (issue 18 item 5).

RR coach, hunting released from 4 mm at ``speed`` km/h (default 350: at 300 km/h the BEM's
motion decays within a second, docs/vehicle.md), ``duration`` s simulated (default 2 s),
h = 1 ms. Contact models: Hertz + Kalker (table), Hertz + FASTSIM 8 x 8 on the table's
points and on the strip contact, and the BEM (normal + steady rolling at every wheel) on
grids of 1.5, 1.0, 0.75 and 0.5 mm. The finest BEM (0.5 mm) is the reference: the errors
are those of the limit-cycle amplitude (half the peak-to-peak y of the leading wheelset
over the last half of the run, ``scenarios.amplitude``) and of the largest wheel load
Q max over the run, relative to the reference's. Each case runs in its own process;
real-time factors from its CPU time (the machine is shared: wall time depends on the
load, which is printed) and its wall time.

    .venv/bin/python validation/vehicle_bem_speed_accuracy.py [speed_kmh] [duration_s]

Writes validation/figures/vehicle_bem_speed_accuracy.png (and a .json of the table).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

FIG = Path(__file__).resolve().parent / "figures"

#: (label, contact, geometry, BEM element size m or None); the last is the reference
CASES = [("Hertz + Kalker (table)", "hertz-kalker", "table", None),
         ("Hertz + FASTSIM (table)", "hertz-fastsim", "table", None),
         ("Hertz + FASTSIM (strip)", "hertz-fastsim", "strip", None),
         ("BEM 1.5 mm", "bem", "table", 1.5e-3),
         ("BEM 1.0 mm", "bem", "table", 1.0e-3),
         ("BEM 0.75 mm", "bem", "table", 0.75e-3),
         ("BEM 0.5 mm (reference)", "bem", "table", 0.5e-3)]

CHILD = r"""
import json, resource, sys, time
import numpy as np
from railvti import scenarios
from railvti.vehicle.bem import BemOptions
contact, geo, dx, speed, dur = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
scenarios.contact_table()
scenarios.coach_system(geometry=geo)
kw = {"bem_options": BemOptions(dx=dx)} if contact == "bem" else {}
t0, c0 = time.perf_counter(), time.process_time()
r = scenarios.hunting(speed, contact=contact, duration=dur, y0=0.004, progress=False, geometry=geo, **kw)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
q = r.wheel_output("Q")
print(json.dumps({"wall": wall, "cpu": cpu, "amp": scenarios.amplitude(r, 0.5 * dur),
                  "qmax": float(q.max()), "grid": list(r.stats.get("bem_grid", ()))[:2],
                  "steps": r.stats["steps"]}))
"""


def run_case(contact: str, geo: str, dx: float | None, speed: float, dur: float) -> dict:
    """One case in its own process; its JSON line."""
    out = subprocess.run([sys.executable, "-c", CHILD, contact, geo, str(dx or 0.0), str(speed),
                          str(dur)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def plot(rows: list[dict], speed: float, dur: float, path: Path) -> None:
    """RTF (CPU) against the relative errors of amplitude and Q max, reference excluded."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    ref = rows[-1]
    for ax, key, name in ((axes[0], "err_amp", f"amplitude (last {0.5 * dur:g} s)"),
                          (axes[1], "err_q", "Q max")):
        for i, r in enumerate(rows[:-1]):
            marker = "s" if r["contact"] == "bem" else "o"
            err = max(abs(r[key]), 1e-6)
            ax.loglog(r["rtf_cpu"], 100 * err, marker, ms=8, label=r["label"])
            ax.annotate(r["label"], (r["rtf_cpu"], 100 * err), textcoords="offset points",
                        xytext=(6, -13) if "FASTSIM" in r["label"] else (6, 6), fontsize=7)
        ax.axvline(ref["rtf_cpu"], color="0.6", ls="--", lw=1,
                   label=f"reference BEM 0.5 mm (RTF {ref['rtf_cpu']:.0f})")
        ax.axvline(1.0, color="0.8", ls=":", lw=1, label="real time")
        ax.set_xlabel("real-time factor (CPU time / simulated time, one core)")
        ax.set_ylabel(f"|error| of {name} against BEM 0.5 mm, %")
        ax.set_title(f"{name}: RR hunting {speed:g} km/h, {dur:g} s")
        ax.grid(True, which="both", alpha=0.3)
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Speed against accuracy of the contact models (reference amplitude "
                 f"{ref['amp'] * 1e3:.2f} mm, Q max {ref['qmax'] / 1e3:.1f} kN)")
    fig.savefig(path, dpi=120)


def main() -> None:
    if sys.argv[1:2] == ["--replot"]:
        d = json.loads((FIG / "vehicle_bem_speed_accuracy.json").read_text())
        plot(d["rows"], d["speed_kmh"], d["duration_s"], FIG / "vehicle_bem_speed_accuracy.png")
        return
    speed = float(sys.argv[1]) if len(sys.argv) > 1 else 350.0
    dur = float(sys.argv[2]) if len(sys.argv) > 2 else 2.0
    FIG.mkdir(exist_ok=True)
    load0 = os.getloadavg()[0]
    rows = []
    for label, contact, geo, dx in CASES:
        d = run_case(contact, geo, dx, speed, dur)
        d.update(label=label, contact=contact, geometry=geo, dx=dx, rtf_cpu=d["cpu"] / dur,
                 rtf_wall=d["wall"] / dur)
        rows.append(d)
        print(f"  {label:>26s}: CPU {d['cpu']:8.1f} s wall {d['wall']:8.1f} s, amplitude "
              f"{d['amp'] * 1e3:6.3f} mm, Q max {d['qmax'] / 1e3:7.2f} kN", flush=True)
    ref = rows[-1]
    for r in rows:
        r["err_amp"] = r["amp"] / ref["amp"] - 1.0
        r["err_q"] = r["qmax"] / ref["qmax"] - 1.0
    print(f"RR hunting at {speed:g} km/h from 4 mm, {dur:g} s, h = 1 ms; load {load0:.2f} -> "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; reference BEM 0.5 mm")
    print(f"{'model':>26s} {'RTF cpu':>8s} {'RTF wall':>8s} {'amp mm':>7s} {'err amp':>8s} "
          f"{'Qmax kN':>8s} {'err Q':>8s}")
    for r in rows:
        print(f"{r['label']:>26s} {r['rtf_cpu']:8.2f} {r['rtf_wall']:8.2f} {r['amp'] * 1e3:7.3f} "
              f"{100 * r['err_amp']:7.2f}% {r['qmax'] / 1e3:8.2f} {100 * r['err_q']:7.3f}%")
    path = FIG / "vehicle_bem_speed_accuracy.png"
    plot(rows, speed, dur, path)
    path.with_suffix(".json").write_text(json.dumps({"speed_kmh": speed, "duration_s": dur,
                                                     "rows": rows}, indent=1))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
