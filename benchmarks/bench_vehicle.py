"""Vehicle-track time simulation: real-time factor and memory per contact model.

10 s of hunting at 300 km/h (leading bogie released from 4 mm), coach RR model, time step
1 ms with sub-stepping, each case in its own subprocess (peak RSS per case). The BEM contact
(0.75 mm grids at all eight wheels) runs over a shorter time, ``bem_duration_s`` (default
1 s), unless given; its RTF is wall / simulated time of that run. The Hertz contacts run on
the table's points and on the strip contact (``geometry='strip'``).

    .venv/bin/python benchmarks/bench_vehicle.py [duration_s] [bem_duration_s] [--threads 1,2] [--bem-only]
    .venv/bin/python benchmarks/bench_vehicle.py --profile [duration_s] [--threads N]   (default 0.3 s)

``--threads``: the BEM case once per thread count given (``simulate(threads=)``: the patches of
the eight wheels solved concurrently; default: all cores), each in its own process, one after
the other, so the counts are compared in one run; the amplitude and Q max of each say that
the results are the same. ``--bem-only`` skips the Hertz cases.

``--compare OLD_PYTHON``: the BEM case (RR, 1 thread) run by this interpreter's railvti and by
another build's (e.g. the previous commit installed in a worktree: ``/tmp/old/.venv/bin/python``)
at the same time, one process per core, so that both share the machine's load; prints each
run's wall time, RTF, Newton iterations and solve pairs per step, and how far the new run's
results are from the old one's: the leading wheelset's lateral displacement (largest
difference over the run, amplitude per second while the motion exceeds 1 um), Q max and Q at
every output step (issue 18's acceptance: amplitude within 0.5 %, Q within 0.1 %).

    .venv/bin/python benchmarks/bench_vehicle.py --compare OLD_PYTHON [bem_duration_s] [--speed 300]   (10 s)

``--profile``: where the time of one BEM run goes (issue 18 item 1; one thread unless
``--threads`` says otherwise: the patch timers sum the patches' own wall times, which overlap
with several threads). The same hunting run with
the BEM (RR, 300 km/h, 0.75 mm), on its own BEM state so that its wall-time counters
(``BemState.timers``: system_clock around the solves in fortran/vehicle/vehicle_bem.f90) can
be read: time in normal solves, in rolling solves, in the rest of the BEM patches (gap field
interpolation, checks, force sums), and outside the patches (contact geometry from the table,
Newton residuals and line search, tangents and their LU, the chunks in Python), with the
counts per step (Newton iterations, tangents, normal + rolling solve pairs) and per solve (CG
iterations, rolling sweeps). With ``perf`` on the path, ``--perf`` also samples the child and
splits the time outside the patches by module.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

CASES = [
    ("hertz-kalker", 8, "table"),
    ("hertz-fastsim", 8, "table"),
    ("hertz-fastsim", 16, "table"),
    ("hertz-kalker", 8, "strip"),
    ("hertz-fastsim", 8, "strip"),
    ("bem", 0, "table"),
]

CHILD = r"""
import json, resource, sys, time
from railvti import scenarios
contact, n, dur, geo, thr = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]
scenarios.wheel_table()                      # table build (cached per process)
scenarios.coach_system(geometry=geo)           # the strip arrays too
kw = {"threads": int(thr)} if contact == "bem" and thr != "all" else {}
t0, c0 = time.perf_counter(), time.process_time()
r = scenarios.hunting(300.0, contact=contact, duration=dur, y0=0.004, fastsim_n=max(n, 1),
                     progress=False, geometry=geo, **kw)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
print(json.dumps({"wall": wall, "cpu": cpu, "rtf": wall / dur, "amp_mm": scenarios.amplitude(r) * 1e3,
                  "qmax_kn": float(r.Q.max()) / 1e3, "threads": r.stats.get("bem_threads", 1),
                  "bem_per_step": r.stats.get("bem_solves_per_step", 0.0),
                  "grid": list(r.stats.get("bem_grid", ()))[:2],
                  "steps": r.stats["steps"], "newton": r.stats["newton_iterations"],
                  "tangents": r.stats["tangents"], "sub": r.stats["substepped_steps"],
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


PROFILE_CHILD = r"""
import json, sys, time
from railvti import scenarios
from railvti.vehicle.equilibrium import bem_state
dur, thr = float(sys.argv[1]), int(sys.argv[2])
sy = scenarios.coach_system("RR")
scenarios.wheel_table()
with bem_state(sy) as st:
    t0, c0 = time.perf_counter(), time.process_time()
    r = scenarios.hunting(300.0, contact="bem", duration=dur, y0=0.004, progress=False, bem=st,
                          threads=thr)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    tm = st.timers()
s = r.stats
print(json.dumps({"wall": wall, "cpu": cpu, "sim_wall": s["wall_time"], "timers": tm,
                  "steps": s["steps"], "newton": s["newton_iterations"], "tangents": s["tangents"],
                  "sub": s["substepped_steps"], "normal": s["bem_normal_solves"],
                  "cg": s["bem_cg_iterations"], "rolling": s["bem_rolling_solves"],
                  "sweeps": s["bem_rolling_sweeps"], "open": s["bem_open_points"],
                  "grid": list(s["bem_grid"])}))
"""

COMPARE_CHILD = r"""
import json, sys, time
import numpy as np
from railvti import scenarios
dur, out, speed = float(sys.argv[1]), sys.argv[2], float(sys.argv[3])
scenarios.wheel_table()
scenarios.coach_system("RR")
t0 = time.perf_counter()
r = scenarios.hunting(speed, contact="bem", duration=dur, y0=0.004, progress=False, threads=1)
wall = time.perf_counter() - t0
s = r.stats
np.savez(out, t=r.t, y=r.y_ws1, q=r.Q)
print(json.dumps({"wall": wall, "steps": s["steps"], "newton": s["newton_iterations"],
                  "pairs": s["bem_normal_solves"], "cg": s["bem_cg_iterations"],
                  "sweeps": s["bem_rolling_sweeps"]}))
"""

#: perf symbol prefixes -> the part of the run they belong to (--perf)
PERF_GROUPS = [
    ("__contact_normal_MOD", "normal solver"),
    ("__contact_rolling_MOD", "rolling solver"),
    ("__contact_convolution_MOD", "FFT products (normal + rolling)"),
    ("fftw", "FFT products (normal + rolling)"),
    ("__vehicle_bem_MOD", "BEM patch set-up"),
    ("__vehicle_contact_MOD", "contact geometry + Hertz/Kalker"),
    ("__vehicle_newmark_MOD", "Newton / HHT"),
    ("__vehicle_model_MOD", "forces / tangent"),
    ("__vehicle_modal_MOD", "modal blocks"),
    ("__common_", "common (Anderson, dense)"),
    ("lapack", "LAPACK / BLAS"),
    ("blas", "LAPACK / BLAS"),
    ("libpython", "Python + numpy"),
    ("_multiarray", "Python + numpy"),
    ("kernel", "kernel"),
    ("libc", "libc (memory)"),
]


def profile(dur: float, use_perf: bool, threads: int = 1) -> None:
    """Print where the time of one BEM run goes (see the module doc)."""
    import shutil
    import tempfile

    cmd = [sys.executable, "-c", PROFILE_CHILD, str(dur), str(threads)]
    perf_data = None
    if use_perf and shutil.which("perf"):
        perf_data = os.path.join(tempfile.mkdtemp(), "perf.data")
        cmd = ["perf", "record", "-q", "-o", perf_data, "--"] + cmd
    load0 = os.getloadavg()[0]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    d = json.loads(out.stdout.strip().splitlines()[-1])
    tm, steps = d["timers"], d["steps"]
    wall = d["sim_wall"]
    rest_patch = tm["patch_seconds"] - tm["normal_seconds"] - tm["rolling_seconds"]
    outside = wall - tm["patch_seconds"]
    print(
        f"profile of one BEM run: RR coach, hunting at 300 km/h, {dur:g} s simulated, h = 1 ms, "
        f"grid {d['grid'][0]} x {d['grid'][1]} of {d['grid'][2] * 1e3:.2f} mm, {threads} thread(s); "
        f"load {load0:.2f} -> {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"
    )
    print(
        f"  wall {wall:.2f} s in simulate (RTF {wall / dur:.1f}), {steps} steps; CPU {d['cpu']:.2f} s "
        f"for the whole hunting call (static equilibrium included, RTF {d['cpu'] / dur:.1f}; the "
        "timers below are wall time, inflated by the load)"
    )
    rows = [
        (
            "normal solves",
            tm["normal_seconds"],
            f"{d['normal']} solves, {d['cg'] / max(d['normal'], 1):.1f} CG iterations and "
            f"{tm['normal_seconds'] / max(d['normal'], 1) * 1e3:.3f} ms each",
        ),
        (
            "rolling solves",
            tm["rolling_seconds"],
            f"{d['rolling']} solves, {d['sweeps'] / max(d['rolling'], 1):.1f} sweeps and "
            f"{tm['rolling_seconds'] / max(d['rolling'], 1) * 1e3:.3f} ms each",
        ),
        (
            "rest of the BEM patches",
            rest_patch,
            f"gap field interpolation, checks, sums; {d['open']} points found open",
        ),
        (
            "outside the BEM patches",
            outside,
            "contact geometry (table), Newton residuals + line search, tangents + LU, Python",
        ),
    ]
    for name, t, note in rows:
        print(f"  {name:>24s} {t:8.2f} s {100 * t / wall:5.1f} %   {note}")
    print(
        f"  per step: {d['newton'] / steps:.2f} Newton iterations, {d['tangents'] / steps:.2f} tangents, "
        f"{d['normal'] / steps:.1f} normal + rolling solve pairs ({d['sub']} steps sub-stepped)"
    )
    if perf_data:
        report = subprocess.run(
            ["perf", "report", "-i", perf_data, "--no-children", "--stdio", "--sort", "dso,sym"],
            capture_output=True,
            text=True,
        ).stdout
        share: dict[str, float] = {}
        for line in report.splitlines():
            parts = line.split()
            if len(parts) < 3 or not parts[0].endswith("%"):
                continue
            dso_sym = parts[1] + " " + parts[-1]  # e.g. '_core...so __contact_rolling_MOD_field'
            group = next((g for key, g in PERF_GROUPS if key.lower() in dso_sym.lower()), "other")
            share[group] = share.get(group, 0.0) + float(parts[0][:-1])
        print("  perf samples of the whole child (imports and the static equilibrium included):")
        for g, v in sorted(share.items(), key=lambda kv: -kv[1]):
            print(f"  {g:>34s} {v:5.1f} %")


def compare(old_python: str, dur: float, speed_kmh: float = 300.0) -> None:
    """Run the BEM case with this build and old_python's side by side (see the module doc)."""
    import tempfile
    import numpy as np

    tmp = tempfile.mkdtemp()
    builds = {"new": sys.executable, "old": old_python}
    load0 = os.getloadavg()[0]
    procs = {
        k: subprocess.Popen(
            [py, "-c", COMPARE_CHILD, str(dur), os.path.join(tmp, k + ".npz"), str(speed_kmh)],
            stdout=subprocess.PIPE,
            text=True,
        )
        for k, py in builds.items()
    }
    res = {}
    for k, p in procs.items():
        out, _ = p.communicate()
        if p.returncode != 0:
            raise SystemExit(f"the {k} build's run failed ({builds[k]})")
        res[k] = json.loads(out.strip().splitlines()[-1])
        res[k].update(dict(np.load(os.path.join(tmp, k + ".npz"))))
    print(
        f"BEM 0.75 mm, RR, hunting at {speed_kmh:g} km/h from 4 mm, {dur:g} s, 1 thread per run, both runs "
        f"at once; load {load0:.2f} -> {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"
    )
    print(
        f"{'build':>5s} {'wall s':>8s} {'RTF':>6s} {'Newton/step':>11s} {'pairs/step':>10s} "
        f"{'CG/solve':>8s} {'sweeps/solve':>12s} {'Q max kN':>10s}  python"
    )
    for k, d in res.items():
        print(
            f"{k:>5s} {d['wall']:8.1f} {d['wall'] / dur:6.2f} {d['newton'] / d['steps']:11.2f} "
            f"{d['pairs'] / d['steps']:10.2f} {d['cg'] / d['pairs']:8.2f} "
            f"{d['sweeps'] / d['pairs']:12.2f} {d['q'].max() / 1e3:10.4f}  {builds[k]}"
        )
    a, b = res["new"], res["old"]
    if a["t"].shape != b["t"].shape or not np.array_equal(a["t"], b["t"]):
        raise SystemExit("the two runs have different output times")
    dy = np.abs(a["y"] - b["y"]).max()
    print(
        f"y_ws1: largest difference {dy * 1e3:.3g} mm over the run ({dy / np.abs(b['y']).max():.2e} "
        f"of its largest |y|, {np.abs(b['y']).max() * 1e3:.3f} mm)"
    )
    print("amplitude of y_ws1 per second (half peak-to-peak, mm), while the old run's exceeds 1 um:")
    for k in range(int(round(dur))):
        m = (b["t"] >= k) & (b["t"] <= k + 1)
        amp_b, amp_a = 0.5 * np.ptp(b["y"][m]), 0.5 * np.ptp(a["y"][m])
        if amp_b < 1e-6:
            print(
                f"  {k}-{k + 1} s: old {amp_b * 1e3:.2e} mm, new {amp_a * 1e3:.2e} mm (decayed: not compared)"
            )
            break
        print(
            f"  {k}-{k + 1} s: old {amp_b * 1e3:.5f}, new {amp_a * 1e3:.5f} mm ({100 * (amp_a / amp_b - 1):+.3f} %)"
        )
    dq = np.abs(a["q"] - b["q"]).max()
    print(
        f"Q max: old {b['q'].max():.1f} N, new {a['q'].max():.1f} N ({100 * (a['q'].max() / b['q'].max() - 1):+.4f} %); "
        f"Q at every output step within {dq:.1f} N ({100 * dq / b['q'].max():.4f} % of Q max)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("duration", nargs="?", type=float, help="simulated time, s")
    ap.add_argument("bem_duration", nargs="?", type=float, help="simulated time with the BEM, s")
    ap.add_argument("--profile", action="store_true", help="where the time of one BEM run goes")
    ap.add_argument("--perf", action="store_true", help="with --profile: perf samples too")
    ap.add_argument(
        "--threads",
        default=None,
        help="BEM threads, comma-separated counts each run in turn (default: all cores; --profile: 1)",
    )
    ap.add_argument("--bem-only", action="store_true", help="skip the Hertz cases")
    ap.add_argument("--compare", metavar="OLD_PYTHON", help="the BEM case against another build's python")
    ap.add_argument("--speed", type=float, default=300.0, help="with --compare: the speed, km/h")
    args = ap.parse_args()
    if args.compare:
        compare(args.compare, args.bem_duration or args.duration or 10.0, args.speed)
        return
    if args.profile:
        profile(args.duration or 0.3, args.perf, int(args.threads or 1))
        return
    dur = args.duration if args.duration is not None else 10.0
    dur_bem = args.bem_duration if args.bem_duration is not None else min(dur, 1.0)
    threads = args.threads.split(",") if args.threads else ["all"]
    print(
        f"hunting at 300 km/h, {dur:g} s simulated ({dur_bem:g} s with the BEM), h = 1 ms "
        "(RR coach, 53 DOF, 8 wheels)"
    )
    print(
        f"load {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; RTF from wall time, RTF cpu from the "
        "child's CPU time (both include the static equilibrium)"
    )
    print(
        f"{'contact':>14s} {'geometry':>8s} {'n':>3s} {'thr':>3s} {'sim s':>6s} {'wall s':>8s} {'RTF':>8s} "
        f"{'RTF cpu':>8s} {'amp mm':>9s} {'Q max kN':>9s} "
        f"{'steps':>6s} {'Newton/step':>11s} {'tangents':>8s} {'sub-stepped':>11s} "
        f"{'BEM/step':>8s} {'peak RSS MB':>11s}"
    )
    for contact, n, geo in CASES:
        if args.bem_only and contact != "bem":
            continue
        d_run = dur_bem if contact == "bem" else dur
        for thr in threads if contact == "bem" else ["all"]:
            out = subprocess.run(
                [sys.executable, "-c", CHILD, contact, str(n), str(d_run), geo, thr],
                capture_output=True,
                text=True,
                check=True,
            )
            d = json.loads(out.stdout.strip().splitlines()[-1])
            print(
                f"{contact:>14s} {geo:>8s} {n:3d} {d['threads']:3d} {d_run:6.2f} {d['wall']:8.2f} "
                f"{d['rtf']:8.3f} {d['cpu'] / d_run:8.3f} {d['amp_mm']:9.5f} {d['qmax_kn']:9.4f} "
                f"{d['steps']:6d} {d['newton'] / d['steps']:11.2f} "
                f"{d['tangents']:8d} {d['sub']:11d} {d['bem_per_step']:8.1f} {d['rss_mb']:11.0f}"
            )
        if contact == "bem":
            print(
                f"{'':>23s} BEM grid {d['grid'][0]} x {d['grid'][1]} elements of 0.75 mm per "
                "wheel and candidate point; BEM/step = normal + rolling solve pairs per step; "
                f"load now {os.getloadavg()[0]:.2f}"
            )


if __name__ == "__main__":
    main()
