"""Speed against accuracy of the contact models in the time loop, per scene (issue 18 item 5).

Scenes (``SCENES``; each a model, a scenario, a speed and a simulated time, h = the model's
default step):

- ``hunting300``: RR released from 4 mm at 300 km/h, 1 s (the BEM's motion decays here: the
  amplitude is that of the decaying transient over the last half);
- ``hunting350``: RR released from 4 mm at 350 km/h, 2 s (a slowly decaying tread cycle);
- ``hunting400``: RR released from 4 mm at 400 km/h, 1.5 s (growing into flange contact);
- ``centred300_ff``: FF (flexible wheelsets on the ring track) in centred running at
  300 km/h from each model's own static state, 0.1 s (sleeper passing at 139 Hz).

Contact models: Hertz + Kalker (table), Hertz + FASTSIM 8 x 8 on the table's points and on
the strip contact, and the BEM (normal + steady rolling at every wheel) on grids of 1.5, 1.0,
0.75 and 0.5 mm. The finest BEM (0.5 mm) is the reference (not an exact solution: its own
discretisation error is not in the chart). Quantities compared, relative to the reference's:

- hunting: the amplitude (half the peak-to-peak y of the leading wheelset over the last half
  of the run, ``scenarios.amplitude``), the largest wheel load Q max and the largest lateral
  wheel force |Y| max over all eight wheels and the whole run;
- centred running: the dynamic wheel load (the largest peak-to-peak of Q over the last half,
  any wheel), Q max and |Y| max.

Each case runs in its own process; its real-time factor is its CPU time (static equilibrium
and time loop; the system's build excluded) over the simulated time, one thread. The machine
is shared: wall time, also recorded, depends on the load, which is printed.

    .venv/bin/python validation/vehicle_bem_speed_accuracy.py [scene ...]   # default: all
    .venv/bin/python validation/vehicle_bem_speed_accuracy.py --replot

Writes validation/figures/vehicle_bem_speed_accuracy_<scene>.json per scene and the chart
validation/figures/vehicle_bem_speed_accuracy.png from every scene's JSON found.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

FIG = Path(__file__).resolve().parent / "figures"

#: scene -> (model, scenario, speed km/h, simulated s, title)
SCENES = {
    "hunting300": ("RR", "hunting", 300.0, 1.0, "RR hunting 300 km/h, 1 s"),
    "hunting350": ("RR", "hunting", 350.0, 2.0, "RR hunting 350 km/h, 2 s"),
    "hunting400": ("RR", "hunting", 400.0, 1.5, "RR hunting 400 km/h, 1.5 s"),
    "centred300_ff": ("FF", "centred", 300.0, 0.1, "FF centred 300 km/h, 0.1 s"),
}

#: output interval per scenario, s: fine enough for the peaks of Q and Y (flange impacts in
#: hunting; the sleeper-passing period of 7.2 ms at 300 km/h in centred running on the ring)
OUTPUT_DT = {"hunting": 1e-3, "centred": 2.5e-4}

#: (label, contact, geometry, BEM element size m or None); the last is the reference
CASES = [
    ("Hertz + Kalker (table)", "hertz-kalker", "table", None),
    ("Hertz + FASTSIM (table)", "hertz-fastsim", "table", None),
    ("Hertz + FASTSIM (strip)", "hertz-fastsim", "strip", None),
    ("BEM 1.5 mm", "bem", "table", 1.5e-3),
    ("BEM 1.0 mm", "bem", "table", 1.0e-3),
    ("BEM 0.75 mm", "bem", "table", 0.75e-3),
    ("BEM 0.5 mm (reference)", "bem", "table", 0.5e-3),
]

#: quantity key -> (label, scenes it applies to)
QUANTITIES = {
    "amp": ("amplitude", "hunting"),
    "qpp": ("dynamic Q (peak-to-peak)", "centred"),
    "qmax": ("Q max", "any"),
    "ymax": ("|Y| max", "any"),
}

CHILD = r"""
import json, sys, time
import numpy as np
from railvti import scenarios
from railvti.vehicle.bem import BemOptions
model, scenario, contact, geo = sys.argv[1:5]
dx, speed, dur, out_dt = (float(a) for a in sys.argv[5:9])
scenarios.wheel_table()
scenarios.coach_system(model, speed_kmh=speed, geometry=geo)       # built and cached, not timed
kw = {"bem_options": BemOptions(dx=dx)} if contact == "bem" else {}
kw["output_dt"] = out_dt
if contact != "bem":
    kw["fastsim_n"] = 8
from railvti.errors import ConvergenceError
t0, c0 = time.perf_counter(), time.process_time()
try:
    if scenario == "hunting":
        r = scenarios.hunting(speed, model, contact, duration=dur, y0=0.004, progress=False,
                              geometry=geo, **kw)
    else:
        r = scenarios.centred_running(speed, model, contact, duration=dur, progress=False,
                                      geometry=geo, **kw).run
except ConvergenceError as e:       # a method that fails in this scene is a result too
    r = getattr(e, "result", None)
    print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                      "failed": str(e).split(";")[0],
                      "t_end": float(r.t[-1]) if r is not None else 0.0}))
    sys.exit(0)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
q, y = r.Q, r.Y
late = r.t >= r.t[-1] - 0.5 * dur
print(json.dumps({"wall": wall, "cpu": cpu, "amp": scenarios.amplitude(r, 0.5 * dur),
                  "qmax": float(q.max()), "ymax": float(np.abs(y).max()),
                  "qpp": float(np.ptp(q[late], axis=0).max()), "steps": r.stats["steps"]}))
"""


def run_case(scene: str, contact: str, geo: str, dx: float | None) -> dict:
    """One case of a scene in its own process; its JSON line."""
    model, scenario, speed, dur, _ = SCENES[scene]
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            CHILD,
            model,
            scenario,
            contact,
            geo,
            str(dx or 0.0),
            str(speed),
            str(dur),
            str(OUTPUT_DT[scenario]),
        ],
        capture_output=True,
        text=True,
    )
    if out.returncode != 0:
        raise RuntimeError(f"{scene} {contact} {geo} {dx}: {out.stderr.strip().splitlines()[-1]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def quantities(scene: str) -> list[str]:
    """The quantities compared in a scene."""
    kind = SCENES[scene][1]
    return [k for k, (_, where) in QUANTITIES.items() if where in ("any", kind)]


def run_scene(scene: str) -> dict:
    """All contact models of one scene; errors against the reference; written as JSON."""
    model, scenario, speed, dur, title = SCENES[scene]
    load0 = os.getloadavg()[0]
    rows = []
    for label, contact, geo, dx in CASES:
        d = run_case(scene, contact, geo, dx)
        d.update(
            label=label,
            contact=contact,
            geometry=geo,
            dx=dx,
            rtf_cpu=d["cpu"] / dur,
            rtf_wall=d["wall"] / dur,
        )
        rows.append(d)
        if "failed" in d:
            print(f"  {scene} {label:>24s}: CPU {d['cpu']:8.1f} s: {d['failed']}", flush=True)
            continue
        print(
            f"  {scene} {label:>24s}: CPU {d['cpu']:8.1f} s wall {d['wall']:8.1f} s "
            + " ".join(f"{k} {d[k]:.6g}" for k in quantities(scene)),
            flush=True,
        )
    ref = rows[-1]
    if "failed" in ref:
        raise RuntimeError(f"{scene}: the reference failed ({ref['failed']}); no errors to chart")
    for r in rows:
        for k in quantities(scene):
            r["err_" + k] = r[k] / ref[k] - 1.0 if "failed" not in r else None
    out = {
        "scene": scene,
        "title": title,
        "model": model,
        "scenario": scenario,
        "speed_kmh": speed,
        "duration_s": dur,
        "load": [load0, os.getloadavg()[0]],
        "rows": rows,
    }
    print(
        f"{title}; load {load0:.2f} -> {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
        "reference BEM 0.5 mm"
    )
    print(
        f"{'model':>24s} {'RTF cpu':>8s} {'RTF wall':>8s} "
        + " ".join(f"{'err ' + k:>9s}" for k in quantities(scene))
    )
    for r in rows:
        if "failed" in r:
            print(f"{r['label']:>24s} stopped at t = {r['t_end']:.4g} s: {r['failed']}")
            continue
        print(
            f"{r['label']:>24s} {r['rtf_cpu']:8.2f} {r['rtf_wall']:8.2f} "
            + " ".join(f"{100 * r['err_' + k]:8.2f}%" for k in quantities(scene))
        )
    (FIG / f"vehicle_bem_speed_accuracy_{scene}.json").write_text(json.dumps(out, indent=1))
    return out


def _unit(key: str, value: float) -> str:
    return f"{value * 1e3:.2f} mm" if key == "amp" else f"{value / 1e3:.1f} kN"


def plot(scenes: list[dict], path: Path) -> None:
    """One row per scene: CPU real-time factor against the |error| of each quantity."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(
        len(scenes), 3, figsize=(15, 3.6 * len(scenes)), constrained_layout=True, squeeze=False
    )
    markers = dict(zip([c[0] for c in CASES], "ovDs^<>"))
    for row, sc in zip(axes, scenes):
        ref = sc["rows"][-1]
        keys = quantities(sc["scene"])
        for ax, key in zip(row, keys):
            for r in sc["rows"][:-1]:
                if "failed" in r:  # listed under the row's panels, not drawn
                    continue
                err = max(abs(r["err_" + key]), 1e-6)  # a 1e-4 % floor (agreement to 1e-6): log axes
                ax.loglog(
                    r["rtf_cpu"],
                    100 * err,
                    markers[r["label"]],
                    ms=7,
                    label=r["label"],
                    color="C0" if r["contact"] == "bem" else "C1",
                )
            ax.axvline(ref["rtf_cpu"], color="0.6", ls="--", lw=1, label="reference BEM 0.5 mm: its RTF")
            ax.axvline(1.0, color="0.8", ls=":", lw=1, label="real time")
            ax.set_title(f"{sc['title']}: {QUANTITIES[key][0]} (ref. {_unit(key, ref[key])})", fontsize=9)
            ax.set_xlabel("real-time factor (CPU s / simulated s, one core)", fontsize=8)
            ax.set_ylabel("|error| against BEM 0.5 mm, %", fontsize=8)
            ax.grid(True, which="both", alpha=0.3)
            ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.tick_params(axis="y", which="minor", labelsize=7)
        for ax in row[len(keys) :]:
            ax.set_visible(False)
        failed = [
            f"{r['label']} stopped at t = {r['t_end']:.3g} s (Newton)" for r in sc["rows"] if "failed" in r
        ]
        if failed:
            row[0].text(
                0.02,
                0.03,
                "not drawn:\n" + "\n".join(failed),
                transform=row[0].transAxes,
                fontsize=7,
                color="C3",
                va="bottom",
                bbox=dict(facecolor="white", edgecolor="C3", alpha=0.9),
            )
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=5, fontsize=8)
    fig.suptitle(
        "Speed against accuracy of the contact models (S1002 / UIC60 1:40, coach, "
        "released from 4 mm; error floor drawn at 1e-4 %)"
    )
    fig.savefig(path, dpi=110)


def main() -> None:
    args = sys.argv[1:]
    FIG.mkdir(exist_ok=True)
    if args[:1] != ["--replot"]:
        unknown = [a for a in args if a not in SCENES]
        if unknown:
            sys.exit(f"unknown scene(s) {unknown}; known: {list(SCENES)}")
        for scene in args or list(SCENES):
            run_scene(scene)
    found = [
        json.loads(p.read_text())
        for s in SCENES
        if (p := FIG / f"vehicle_bem_speed_accuracy_{s}.json").exists()
    ]
    path = FIG / "vehicle_bem_speed_accuracy.png"
    plot(found, path)
    print(f"wrote {path} ({', '.join(s['scene'] for s in found)})")


if __name__ == "__main__":
    main()
