"""Small-grid creep-force benchmark (issue 18 item 4): ms per case of the 11 x 11 case (and 25 x 25).

The case: a Hertzian ellipse (semi-axes a, b from ``hertz``, Fn = 10 kN, steel) on a grid of
11 x 11 elements of 2 (1.57 a) / 11 x 2 (1.57 b), i.e. the grid extends 1.57 semi-axes to
each side of the centre: the smallest such margin with which the contact area stays two
element rows clear of the leading edge, as the three-point slip stencil needs (1.375 is
the bound). Steady rolling with Coulomb friction (mu = 0.3, V = 30 m/s) over a table of
cases: ellipse ratios a/b = 0.5, 1.0, 1.33 (wheel 0.46 m, rail 0.30 m radii) and 2.0, times
creepages xi = 0, 5e-4, 2e-3, eta = 0, 1e-3 and spin phi = 0, 0.5, 2 1/m (72 cases, from
nearly full adhesion to nearly full slip). Every case starts cold (no warm start).

Timed per case, through the public Python API, in a child process with one thread
(OMP_NUM_THREADS = OPENBLAS_NUM_THREADS = 1):

- ``case``: ``solve_rolling`` (the normal problem, then the tangential one), the whole
  creep-force case, one Python call per case;
- ``tangential``: ``solve_tangential`` for the case's pressure (the rolling solver alone);
- ``table``: ``creep_force_table`` (commits that have it) with one gap per case, so that
  every case solves its normal problem from zero as ``case`` does: the same cases, one
  Fortran call per table of 18 (wall and CPU time); ``shared CPU``: one gap per table (the
  normal problem once per a/b, as a contact table of one geometry over the creepages
  needs it), CPU time.

Each figure is the best of ``--repeats`` passes over the table (the least disturbed by the
other processes on the machine), averaged over its cases: wall time, and for the case also
the process's CPU time (less sensitive to the load of a shared machine).

Before / after in one run: with ``--against REV`` (default ``main``) the script exports
that commit's tree (``git archive``, no worktree), builds and installs it once into a
scratch folder (``--scratch``, default ``/tmp/railvti-bench-<rev>``; about 2 min, reused
afterwards) and runs the same child against it through ``PYTHONPATH``, alternating old and
new children ``--rounds`` times so that both see the same machine load. The load average
is printed before and after, and the forces of old and new are compared case by case
(largest difference relative to the largest force of the case).

The grids: 11 x 11 by default; ``--grids 11 25`` times the 25 x 25 grid over the same
extent too, in the same run (the larger-grid comparison).

Run: .venv/bin/python benchmarks/bench_contact_small_grid.py [--against main] [--rounds 3]
     [--repeats 5] [--grids 11 25] [--no-compare]
"""

from __future__ import annotations

import argparse
import io
import json
import os
import subprocess
import sys
import tarfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, sys, time
import numpy as np
import railvti
from railvti.contact import Grid, hertz, hertz_gap, solve_rolling, solve_tangential
from railvti.material import STEEL

repeats = int(sys.argv[1])
N = int(sys.argv[2])
FN, MU, V, MARGIN = 10e3, 0.3, 30.0, 1.57
try:
    from railvti.contact import creep_force_table
except ImportError:            # a commit without the table API
    creep_force_table = None
# curvature pairs (1/m) giving a/b = 0.5, 1.0, 1.33 (a wheel-rail patch) and 2.0
SHAPES = [(2.8, 1.0), (1.0, 1.0), (0.5 / 0.46, 0.5 / 0.30), (0.35, 1.0)]
CREEP = [(xi, eta, phi) for xi in (0.0, 5e-4, 2e-3) for eta in (0.0, 1e-3) for phi in (0.0, 0.5, 2.0)]
problems = []
for A, B in SHAPES:
    h = hertz(A, B, FN, STEEL)
    g = Grid(N, N, 2 * MARGIN * h.a / N, 2 * MARGIN * h.b / N)
    problems.append((g, hertz_gap(g, A, B), h.a / h.b))
CREEP_ARRAY = np.array(CREEP)
STACKS = [np.repeat(gap[None], len(CREEP), axis=0) for _, gap, _ in problems]


def run_cases():
    out = []
    for g, gap, _ in problems:
        for c in CREEP:
            out.append(solve_rolling(gap, g, STEEL, MU, FN, c, V))
    return out


def run_tangential(results):
    out = []
    k = 0
    for g, gap, _ in problems:
        for c in CREEP:
            out.append(solve_tangential(results[k].pressure, g, STEEL, MU, c, V))
            k += 1
    return out


def run_table(shared):
    out = []
    for (g, gap, _), stack in zip(problems, STACKS):
        out.append(creep_force_table(gap if shared else stack, g, STEEL, MU, FN, CREEP_ARRAY, V))
    return out


ref = run_cases()                      # warm-up: workspaces, imports
ncase = len(ref)
best_case = best_tang = best_cpu = float("inf")
best_tab = best_tab_cpu = best_shared = float("inf")
tab_forces = []
if creep_force_table is not None:
    tab_forces = [[t.fx[k], t.fy[k], t.mz[k]] for t in run_table(False) for k in range(len(t))]
    run_table(True)
for _ in range(repeats):
    t0, c0 = time.perf_counter(), time.process_time()
    run_cases()
    t1, c1 = time.perf_counter(), time.process_time()
    run_tangential(ref)
    t2 = time.perf_counter()
    best_case = min(best_case, (t1 - t0) / ncase)
    best_cpu = min(best_cpu, (c1 - c0) / ncase)
    best_tang = min(best_tang, (t2 - t1) / ncase)
    if creep_force_table is not None:
        t0, c0 = time.perf_counter(), time.process_time()
        run_table(False)
        t1, c1 = time.perf_counter(), time.process_time()
        run_table(True)
        c2 = time.process_time()
        best_tab = min(best_tab, (t1 - t0) / ncase)
        best_tab_cpu = min(best_tab_cpu, (c1 - c0) / ncase)
        best_shared = min(best_shared, (c2 - c1) / ncase)
nan = float("nan")
print(json.dumps({"module": railvti.__file__, "ncase": ncase, "case_ms": best_case * 1e3,
                  "tang_ms": best_tang * 1e3, "cpu_ms": best_cpu * 1e3,
                  "table_ms": best_tab * 1e3 if tab_forces else nan,
                  "table_cpu_ms": best_tab_cpu * 1e3 if tab_forces else nan,
                  "shared_ms": best_shared * 1e3 if tab_forces else nan, "table_forces": tab_forces,
                  "ratios": [round(r, 3) for _, _, r in problems],
                  "n_contact": [r.n_contact for r in ref[::len(CREEP)]],
                  "sweeps": float(np.mean([r.iterations for r in ref])),
                  "slip_frac": [float(r.slip.sum() / r.n_contact) for r in ref],
                  "forces": [[r.fx, r.fy, r.mz] for r in ref]}))
"""


def load() -> str:
    a, b, c = os.getloadavg()
    return f"{a:.2f} {b:.2f} {c:.2f} (1, 5, 15 min) on {os.cpu_count()} cores"


def build_commit(rev: str, scratch: Path | None) -> tuple[Path, str]:
    """Install the tree of commit ``rev`` into a scratch folder; returns its site folder."""
    sha = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", rev], capture_output=True, text=True, check=True
    ).stdout.strip()
    scratch = scratch or Path(f"/tmp/railvti-bench-{sha}")
    site = scratch / "site"
    if (site / "railvti").is_dir():
        return site, sha
    src = scratch / "src"
    src.mkdir(parents=True, exist_ok=True)
    tar = subprocess.run(["git", "-C", str(ROOT), "archive", sha], capture_output=True, check=True).stdout
    with tarfile.open(fileobj=io.BytesIO(tar)) as tf:
        tf.extractall(src)
    print(f"building {sha} into {site} (once; about 2 min)", flush=True)
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-build-isolation",
            "--no-deps",
            "--target",
            str(site),
            f"-Cbuild-dir={scratch / 'build'}",
            str(src),
        ],
        check=True,
    )
    return site, sha


def run_child(repeats: int, site: Path | None, n: int) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    if site is not None:
        env["PYTHONPATH"] = str(site)  # else the caller's PYTHONPATH (e.g. a worktree's install)
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(repeats), str(n)],
        capture_output=True,
        text=True,
        check=True,
        env=env,
        cwd="/",
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def largest_difference(fa: list, fb: list) -> float:
    """Largest difference of Fx, Fy over the cases, relative to the case's largest force."""
    worst = 0.0
    for a, b in zip(fa, fb):
        scale = max(abs(a[0]), abs(a[1]), 1e-300)
        worst = max(worst, max(abs(x - y) for x, y in zip(a[:2], b[:2])) / scale)
    return worst


def time_grid(n: int, variants: list[tuple[str, Path | None]], rounds: int, repeats: int) -> None:
    """Alternate old and new children on the n x n grid and print their figures."""
    print(f"{n} x {n} creep-force cases (Hertz ellipse, grid +-1.57 a x +-1.57 b), one thread")
    print(f"load before: {load()}", flush=True)
    rows: dict[str, list[dict]] = {name: [] for name, _ in variants}
    for r in range(rounds):
        order = variants if r % 2 == 0 else variants[::-1]
        for name, site in order:
            d = run_child(repeats, site, n)
            rows[name].append(d)
            print(
                f"  round {r + 1} {name:>18s}: case {d['case_ms']:.3f} ms (CPU {d['cpu_ms']:.3f} ms), "
                f"tangential {d['tang_ms']:.3f} ms, table {d['table_ms']:.3f} ms (CPU {d['table_cpu_ms']:.3f}), "
                f"table shared CPU {d['shared_ms']:.3f} ms   (load {os.getloadavg()[0]:.2f})",
                flush=True,
            )
    print(f"load after:  {load()}")
    d0 = rows[variants[0][0]][0]
    print(
        f"{d0['ncase']} cases; a/b = {d0['ratios']}; in contact {d0['n_contact']}; "
        f"slip fraction {min(d0['slip_frac']):.2f}..{max(d0['slip_frac']):.2f}"
    )
    print(
        f"{'':>18s} {'case ms (best, median)':>24s} {'case CPU':>9s} {'tangential (best, med)':>23s} "
        f"{'table (best, med)':>19s} {'table CPU':>10s} {'shared CPU':>10s} {'sweeps':>7s}"
    )
    for name, _ in variants:
        c = sorted(d["case_ms"] for d in rows[name])
        t = sorted(d["tang_ms"] for d in rows[name])
        tb = sorted(d["table_ms"] for d in rows[name])
        cpu = min(d["cpu_ms"] for d in rows[name])
        tcpu = min(d["table_cpu_ms"] for d in rows[name])
        sh = min(d["shared_ms"] for d in rows[name])
        print(
            f"{name:>18s} {c[0]:11.3f} {c[len(c) // 2]:11.3f} {cpu:9.3f} {t[0]:11.3f} {t[len(t) // 2]:11.3f} "
            f"{tb[0]:9.3f} {tb[len(tb) // 2]:9.3f} {tcpu:10.3f} {sh:10.3f} {rows[name][0]['sweeps']:7.1f}"
        )
    new = rows[variants[-1][0]][0]
    if new["table_forces"]:
        print(
            f"table against solve_rolling (new): Fx, Fy largest difference "
            f"{largest_difference(new['forces'], new['table_forces']):.2e} of the case's largest force"
        )
    if len(variants) == 2:
        old = rows[variants[0][0]][0]
        co = min(d["case_ms"] for d in rows[variants[0][0]])
        cn = min(d["case_ms"] for d in rows[variants[1][0]])
        print(
            f"speed-up of a case (best of each): {co / cn:.2f}x; forces Fx, Fy: largest difference "
            f"{largest_difference(old['forces'], new['forces']):.2e} of the case's largest force"
        )
        if new["table_forces"]:
            tn = min(d["table_ms"] for d in rows[variants[1][0]])
            print(
                f"old case / new table (best of each): {co / tn:.2f}x; forces Fx, Fy: largest difference "
                f"{largest_difference(old['forces'], new['table_forces']):.2e}"
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--against", default="main", help="commit to compare with (built once in --scratch)")
    ap.add_argument("--no-compare", action="store_true", help="time the installed package only")
    ap.add_argument("--scratch", type=Path, default=None, help="build folder of the other commit")
    ap.add_argument("--rounds", type=int, default=3, help="old/new child pairs, alternating")
    ap.add_argument("--repeats", type=int, default=5, help="passes over the table per child (best taken)")
    ap.add_argument(
        "--grids", type=int, nargs="+", default=[11], help="elements per side (11; 25 the larger grid)"
    )
    args = ap.parse_args()
    head = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
    ).stdout.strip()
    dirty = subprocess.run(
        ["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    variants: list[tuple[str, Path | None]] = [(f"new {head}{'+dirty' if dirty else ''}", None)]
    if not args.no_compare:
        site, sha = build_commit(args.against, args.scratch)
        variants.insert(0, (f"old {sha}", site))
    for n in args.grids:
        time_grid(n, variants, args.rounds, args.repeats)


if __name__ == "__main__":
    main()
