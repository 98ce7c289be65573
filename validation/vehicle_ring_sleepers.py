"""Ring length of model RF, cost against error (issue 30 item 4): how many sleepers the ring
needs for the study's results to be those of the paper's 128-sleeper ring.

For each n_sleepers (default 40, 48, 64, 96, 128; the coach's wheelsets span 21.56 m, so a
ring needs at least 38 bays of 0.6 m and 20 is refused) and the same ring modes (up to
``--f-limit``, default scenarios.RF_F_LIMIT) with the residual flexibility on, in a process of
its own (so that its peak memory is its own):

* cost: the system's build time (ring modes, rows, residual table: scenarios.rf_system),
  the peak resident memory of the process (ru_maxrss), and the CPU time per simulated second
  of each run (the process's CPU time around the call, all its threads: on a shared machine
  the wall time is inflated by the other jobs, the CPU time is not; the wall times are kept
  in the .npz as ``*_wall*``);
* (i) centred running at ``--centred-kmh`` (200): the static state on the ring, then
  ``--centred-duration`` s (0.5), Hertz + Kalker on the strips (as
  validation/vehicle_rf_ring_length.py): the vertical wheel loads' peak-to-peak fluctuation
  and their sleeper-passing harmonic (v / 0.6 m), each the mean over the eight wheels, over
  the last ``--centred-window`` s (0.3);
* (ii) hunting at ``--hunting-kmh`` (400) from the 4 mm shift of scenarios.hunting for
  ``--hunting-duration`` s (2.5): the leading wheelset's amplitude over the last second,
  the largest Q and |Y| of all wheels over the last second;
* (iii) the linear critical speed, scenarios.linear_critical_speed_kmh('RF', ...) with its
  default bay-averaged rows (8 offsets).

Errors are relative to the largest ring (the reference, 128 by default). Prints a markdown
table and writes validation/figures/vehicle_ring_sleepers.npz and .png (cost against error).

    python validation/vehicle_ring_sleepers.py [--n-sleepers 40 48 64 96 128]
        [--parts centred hunting linear] [--hunting-duration 2.5] [--f-limit 500]

Each ring runs as ``python validation/vehicle_ring_sleepers.py --one N --out FILE`` (the
parent starts these one after the other; ``--jobs`` > 1 runs them side by side, which
distorts the times on a shared machine).
"""

from __future__ import annotations

import argparse
import json
import logging
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

FIG = Path(__file__).parent / "figures"
PARTS = ("centred", "hunting", "linear")


def harmonic(t: np.ndarray, s: np.ndarray, f: float) -> float:
    """Amplitude of the harmonic at f (Hz) in s(t): least squares of mean + cos + sin."""
    a = np.stack([np.ones_like(t), np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)], 1)
    c = np.linalg.lstsq(a, s, rcond=None)[0]
    return float(np.hypot(c[1], c[2]))


def _rss_mb() -> float:
    """Peak resident memory of this process so far, MB (Linux: ru_maxrss in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def one_ring(n: int, args: argparse.Namespace) -> dict:
    """The costs and results of one ring of n sleepers (run in a process of its own)."""
    from railvti import scenarios
    from railvti.vehicle import systems
    from railvti.vehicle.equilibrium import static_equilibrium
    from railvti.vehicle.simulate import simulate
    from railvti.errors import ConvergenceError

    out: dict = {"n": n, "rss_start_mb": _rss_mb()}
    t0, c0 = time.perf_counter(), time.process_time()
    sy = scenarios.rf_system(speed_kmh=args.centred_kmh, n_sleepers=n, f_limit=args.f_limit, geometry="strip")
    out["build_wall_s"] = time.perf_counter() - t0
    out["build_s"] = time.process_time() - c0
    out["ring_modes"] = int(sy.ring.n_modes)
    out["rss_build_mb"] = _rss_mb()
    if "centred" in args.parts:
        v = args.centred_kmh / 3.6
        q0, v0, _ = static_equilibrium(sy, v, tol=1e-11, return_velocity=True)
        h = systems.default_step(sy)
        c0 = time.process_time()
        r = simulate(sy, v, args.centred_duration, h=h, q0=q0, v0=v0, output_dt=h, progress=False)
        cpu = time.process_time() - c0
        k = r.t > r.t[-1] - args.centred_window
        t, q = r.t[k], r.Q[k]
        f_sl = v / float(sy.ring.bay)
        amp = np.array([[harmonic(t, q[:, i, w], f_sl) for w in range(q.shape[2])] for i in range(2)])
        out.update(
            centred_ptp=float(np.ptp(q, axis=0).mean()),
            centred_harmonic=float(amp.mean()),
            centred_wall_per_s=r.stats["wall_time"] / args.centred_duration,
            centred_cpu_per_s=cpu / args.centred_duration,
            centred_h=float(r.h),
            rss_centred_mb=_rss_mb(),
        )
    if "hunting" in args.parts:
        c0, t0 = time.process_time(), time.perf_counter()
        try:
            res = scenarios.hunting(
                args.hunting_kmh,
                variant="RF",
                duration=args.hunting_duration,
                n_sleepers=n,
                f_limit=args.f_limit,
                progress=False,
            )
            failed = float("nan")
        except ConvergenceError as exc:  # recorded, not fatal: the other rings still run
            res, failed = exc.result, float(exc.result.t[-1])
        cpu = time.process_time() - c0
        k = res.t >= res.t[-1] - 1.0
        ok = np.isnan(failed)
        out.update(
            hunting_amplitude=scenarios.amplitude(res, 1.0) if ok else float("nan"),
            hunting_q_max=float(res.Q[k].max()) if ok else float("nan"),
            hunting_y_max=float(np.abs(res.Y[k]).max()) if ok else float("nan"),
            hunting_failed_at=failed,
            hunting_wall_per_s=(time.perf_counter() - t0) / float(res.t[-1]),
            hunting_cpu_per_s=cpu / float(res.t[-1]),
            hunting_h=float(res.h),
            rss_hunting_mb=_rss_mb(),
        )
    if "linear" in args.parts:
        t0, c0 = time.perf_counter(), time.process_time()
        vc, fc = scenarios.linear_critical_speed_kmh("RF", n_sleepers=n, f_limit=args.f_limit)
        out.update(
            linear_kmh=float(vc),
            linear_hz=float(fc),
            linear_wall_s=time.perf_counter() - t0,
            linear_s=time.process_time() - c0,
        )
    out["rss_peak_mb"] = _rss_mb()
    return out


#: Result columns compared with the reference: key -> (label, unit scale, unit).
QUANTITIES = {
    "centred_ptp": ("centred: Q peak to peak", 1e-3, "kN"),
    "centred_harmonic": ("centred: Q sleeper harmonic", 1e-3, "kN"),
    "hunting_amplitude": ("hunting: amplitude", 1e3, "mm"),
    "hunting_q_max": ("hunting: Q max", 1e-3, "kN"),
    "hunting_y_max": ("hunting: |Y| max", 1e-3, "kN"),
    "linear_kmh": ("linear critical speed", 1.0, "km/h"),
}


def _reference(rows: list[dict], key: str) -> dict | None:
    """The largest ring with a finite value of key (the reference of its errors)."""
    have = [r for r in rows if np.isfinite(r.get(key, np.nan))]
    return have[-1] if have else None


def table(rows: list[dict]) -> str:
    """The markdown table: costs, results and their errors against the largest ring that has
    each (the header names it)."""
    ref = {k: v for r in rows for k, v in r.items()}
    head = ["n_sl", "ring modes", "build, CPU s", "peak RSS, MB"]
    cost_keys = [
        ("centred_cpu_per_s", "centred: CPU s / sim s"),
        ("hunting_cpu_per_s", "hunting: CPU s / sim s"),
        ("linear_s", "linear: CPU s"),
        ("linear_wall_s", "linear: wall s"),
    ]
    head += [lab for key, lab in cost_keys if key in ref]
    qkeys = [k for k in QUANTITIES if k in ref]
    head += [f"{QUANTITIES[k][0]}, {QUANTITIES[k][2]} (error % vs {_reference(rows, k)['n']})" for k in qkeys]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [
            str(r["n"]),
            str(r["ring_modes"]),
            f"{r.get('build_s', np.nan):.1f}",
            f"{r.get('rss_peak_mb', np.nan):.0f}",
        ]
        cells += [f"{r.get(key, float('nan')):.1f}" for key, _ in cost_keys if key in ref]
        for k in qkeys:
            lab, sc, unit = QUANTITIES[k]
            if not np.isfinite(r.get(k, float("nan"))):
                fail = r.get("hunting_failed_at", float("nan"))
                cells.append(f"stopped at {fail:.3f} s" if np.isfinite(fail) else "-")
                continue
            err = 100.0 * (r[k] / _reference(rows, k)[k] - 1.0)
            cells.append(f"{r[k] * sc:.4g} ({err:+.2f})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def figure(rows: list[dict], path: Path, args: argparse.Namespace) -> None:
    """Cost against error: per quantity, |error| against 128 over the time-loop cost."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ref = {k: v for r in rows for k, v in r.items()}
    qkeys = [k for k in QUANTITIES if k in ref]
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    ns = np.array([r["n"] for r in rows])
    cost_key = "hunting_cpu_per_s" if "hunting_cpu_per_s" in ref else "centred_cpu_per_s"
    for j, k in enumerate(qkeys):
        if k == "linear_kmh":  # no error to draw at the bisection's resolution: a note
            lin = [r for r in rows if np.isfinite(r.get(k, np.nan))]
            ax[0].text(
                0.02,
                0.03,
                "linear critical speed (bay average, bisection to 0.5 km/h):\n"
                + ", ".join(f"{r[k]:.1f}" for r in lin)
                + " km/h at n_sl = "
                + ", ".join(str(r["n"]) for r in lin),
                transform=ax[0].transAxes,
                fontsize=8,
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="0.8"),
            )
            continue
        rk = _reference(rows, k)
        sub = [r for r in rows if r["n"] < rk["n"]]
        err = np.array([abs(r.get(k, np.nan) / rk[k] - 1.0) * 100.0 for r in sub])
        # the linear run's cost is its own (CPU s per critical speed); the others' the hunting
        cost = np.array([r.get(cost_key, np.nan) for r in sub])
        ax[0].plot(
            cost, np.maximum(err, 1e-3), "o", color=f"C{j}", label=f"{QUANTITIES[k][0]} (vs n_sl = {rk['n']})"
        )
        for c, e, n in zip(cost, err, [r["n"] for r in sub]):
            ax[0].annotate(str(n), (c, max(e, 1e-3)), fontsize=7, xytext=(3, 3), textcoords="offset points")
    if len(rows) > 1:  # (one ring alone has no errors to draw)
        ax[0].set_xscale("log")
        ax[0].set_yscale("log")
    ax[0].set_xlabel(f"time-loop cost, CPU s per simulated s ({cost_key.split('_')[0]} run)")
    ax[0].set_ylabel("|error| against the largest ring, %")
    ax[0].set_title("cost against error (labels: n_sl; one run each)")
    ax[0].grid(alpha=0.3, which="both")
    ax[0].legend(fontsize=8)
    for key, lab, mk in (
        ("build_s", "system build, CPU s", "s-"),
        ("rss_peak_mb", "peak RSS / 100, MB", "^-"),
        ("centred_cpu_per_s", "centred: CPU s per sim s", "o-"),
        ("hunting_cpu_per_s", "hunting: CPU s per sim s", "d-"),
        ("linear_s", "linear critical speed / 10, CPU s", "v-"),
        ("linear_wall_s", "linear critical speed / 10, wall s (shared machine)", "v--"),
    ):
        if key not in ref:
            continue
        sc = 0.01 if key == "rss_peak_mb" else (0.1 if key.startswith("linear") else 1.0)
        ax[1].plot(ns, [r.get(key, np.nan) * sc for r in rows], mk, label=lab)
    ax[1].set_xlabel("sleepers on the ring, n_sl")
    ax[1].set_yscale("log")
    ax[1].set_ylabel("cost (units in the legend), log scale")
    ax[1].set_title("cost against ring length")
    ax[1].grid(alpha=0.3)
    ax[1].legend(fontsize=8)
    fig.suptitle(
        f"Model RF: ring of n_sl sleepers (0.6 m), ring modes up to {args.f_limit:g} Hz + "
        f"residual; centred {args.centred_kmh:g} km/h, hunting {args.hunting_kmh:g} km/h "
        f"({args.hunting_duration:g} s), Hertz + Kalker on strips"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    from railvti import scenarios

    ap = argparse.ArgumentParser()
    ap.add_argument("--n-sleepers", type=int, nargs="*", default=[40, 48, 64, 96, 128])
    ap.add_argument("--parts", nargs="+", default=list(PARTS), choices=PARTS)
    ap.add_argument("--f-limit", type=float, default=scenarios.RF_F_LIMIT, help="Hz")
    ap.add_argument("--centred-kmh", type=float, default=200.0)
    ap.add_argument("--centred-duration", type=float, default=0.5, help="s")
    ap.add_argument("--centred-window", type=float, default=0.3, help="s")
    ap.add_argument("--hunting-kmh", type=float, default=400.0)
    ap.add_argument("--hunting-duration", type=float, default=2.5, help="s")
    ap.add_argument("--one", type=int, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--out", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--npz", default=str(FIG / "vehicle_ring_sleepers.npz"))
    ap.add_argument(
        "--merge",
        nargs="*",
        default=[],
        help="earlier .npz of this script (e.g. a --parts linear run) to merge by n_sl",
    )
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    if args.one is not None:
        Path(args.out).write_text(json.dumps(one_ring(args.one, args)))
        return
    ns = sorted(args.n_sleepers)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        base = [
            sys.executable,
            __file__,
            "--parts",
            *args.parts,
            "--f-limit",
            str(args.f_limit),
            "--centred-kmh",
            str(args.centred_kmh),
            "--centred-duration",
            str(args.centred_duration),
            "--centred-window",
            str(args.centred_window),
            "--hunting-kmh",
            str(args.hunting_kmh),
            "--hunting-duration",
            str(args.hunting_duration),
        ]
        pending = list(ns)
        running: list = []
        while pending or running:
            while pending and len(running) < args.jobs:
                n = pending.pop(0)
                out = Path(tmp) / f"ring_{n}.json"
                running.append(
                    (
                        n,
                        out,
                        subprocess.Popen(base + ["--one", str(n), "--out", str(out)]),
                        time.perf_counter(),
                    )
                )
            n, out, p, t0 = running.pop(0)
            if p.wait() != 0:
                raise SystemExit(f"n_sleepers = {n} failed (exit {p.returncode})")
            r = json.loads(out.read_text())
            r["process_s"] = time.perf_counter() - t0
            print(
                f"n_sl = {n}: {json.dumps({k: round(v, 6) if isinstance(v, float) else v for k, v in r.items()})}",
                flush=True,
            )
            rows.append(r)
    for path in args.merge:  # earlier runs: their keys join the rows of the same n
        old = np.load(path)
        for i, n in enumerate(old["n"]):
            row = next((r for r in rows if r["n"] == int(n)), None)
            if row is None:
                row = {"n": int(n)}
                rows.append(row)
            for k in old.files:
                v = old[k][i]
                if k not in row and np.isfinite(v):
                    row[k] = float(v) if k != "ring_modes" else int(v)
    rows.sort(key=lambda r: r["n"])
    print(table(rows))
    FIG.mkdir(exist_ok=True)
    keys = sorted({k for r in rows for k in r})
    np.savez(args.npz, **{k: np.array([r.get(k, np.nan) for r in rows]) for k in keys})
    png = Path(args.npz).with_suffix(".png")
    figure(rows, png, args)
    print(f"wrote {args.npz} and {png}")


if __name__ == "__main__":
    main()
