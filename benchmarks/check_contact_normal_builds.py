"""Do two builds of railvti give the same normal solves? (issue 33: the pruned FFT product)

Solves Hertz cases (steel, 10 kN; A/B = 1 and 3.3; force and approach control; grids of
``--sides``) with the interpreter's installed railvti ("old", PYTHONPATH unset) and with
the one in NEW_SITE ("new"), each in a fresh process, and prints per case the contact
sets' difference (elements), and the largest relative differences of approach, force and
pressure (pressure relative to its peak). Then repeats the new build with
OMP_NUM_THREADS=2 and with OPENBLAS_CORETYPE=Haswell / Sandybridge and reports whether
those results are bit-identical to the first new run.

    python benchmarks/check_contact_normal_builds.py NEW_SITE [--sides 256 450]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

CHILD = r"""
import sys
import numpy as np
from railvti import STEEL
from railvti.contact import Grid, hertz, hertz_gap, solve_normal
out, sides = sys.argv[1], [int(s) for s in sys.argv[2].split(",")]
res = {}
for side in sides:
    for ab in (1.0, 3.3):
        A, B = 1.0, 1.0 / ab
        ref = hertz(A, B, 1.0e4, STEEL)
        h = 2 * 1.2 * max(ref.a, ref.b) / side
        grid = Grid(side, side, h, h)
        gap = hertz_gap(grid, A, B)
        for control in ("fn", "approach"):
            kw = dict(fn=1.0e4) if control == "fn" else dict(approach=ref.approach)
            r = solve_normal(gap, grid, STEEL, **kw)
            key = f"{side}_{ab}_{control}"
            res[key + "_p"] = r.pressure
            res[key + "_s"] = np.array([r.fn, r.approach, r.fft_products, r.coarse_fft_products])
np.savez(out, **res)
"""


def run(path: str | None, sides: list[int], env_extra: dict[str, str]) -> dict[str, np.ndarray]:
    """Solve the cases in a fresh interpreter (PYTHONPATH = path, or unset) and load them."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.setdefault("OMP_NUM_THREADS", "1")
    env.update(env_extra)
    if path:
        env["PYTHONPATH"] = path
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "r.npz")
        subprocess.run(
            [sys.executable, "-c", CHILD, out, ",".join(map(str, sides))],
            check=True,
            env=env,
            cwd=tempfile.gettempdir(),
        )
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("new_site")
    ap.add_argument("--sides", type=int, nargs="+", default=[256, 450])
    args = ap.parse_args()
    old = run(None, args.sides, {})
    new = run(args.new_site, args.sides, {})
    print(
        f"{'case':22s} {'set diff':>8s} {'approach':>9s} {'force':>9s} {'pressure':>9s} {'products old/new':>18s}"
    )
    for key in sorted(k[:-2] for k in old if k.endswith("_p")):
        po, pn = old[key + "_p"], new[key + "_p"]
        so, sn = old[key + "_s"], new[key + "_s"]
        dset = int(np.count_nonzero((po > 0) != (pn > 0)))
        rel = np.abs(sn[:2] - so[:2]) / np.abs(so[:2])
        dp = np.abs(pn - po).max() / po.max()
        prods = f"{int(so[2])}+{int(so[3])} / {int(sn[2])}+{int(sn[3])}"
        print(f"{key:22s} {dset:8d} {rel[1]:9.1e} {rel[0]:9.1e} {dp:9.1e} {prods:>18s}")
    for name, extra in (
        ("OMP_NUM_THREADS=2", {"OMP_NUM_THREADS": "2"}),
        ("OPENBLAS_CORETYPE=Haswell", {"OPENBLAS_CORETYPE": "Haswell"}),
        ("OPENBLAS_CORETYPE=Sandybridge", {"OPENBLAS_CORETYPE": "Sandybridge"}),
    ):
        other = run(args.new_site, args.sides, extra)
        same = all(np.array_equal(new[k], other[k]) for k in new)
        print(f"new build with {name}: {'bit-identical' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
