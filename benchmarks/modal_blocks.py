"""Modal blocks in the time integration: time per step and memory against the number of modes.

A small rigid system (6 DOFs) carries nm modes in 1 x 1 blocks (frequencies 1.6 - 300 Hz,
2 % damping) through np = 4 attachment points (linear springs/dampers to 4 rigid DOFs).
Each case runs in its own subprocess (peak RSS per case), h = 1 ms, from a displaced start:

- condensed: the modal blocks condensed onto the points (vehicle_newmark; linear in nm);
- dense: the same system assembled as dense M, C, K over all 6 + nm DOFs and run through
  the rigid path (an LU of the (6 + nm)^2 step matrix per tangent: cubic in nm), nm <= 1000;
- coach: the RR coach (53 DOFs, Hertz + Kalker at 300 km/h) with nm modes on 4 points
  sprung to the four wheelsets' z (condensed; nm = 0 is RR itself).

    .venv/bin/python benchmarks/modal_blocks.py [nm ...]
    .venv/bin/python benchmarks/modal_blocks.py --accuracy

``--accuracy`` prints the figures the tests (tests/test_vehicle_modal_blocks.py, whose test
systems it reuses) assert: condensed against dense, energy drift, convergence order, RR.
"""

from __future__ import annotations

import json
import subprocess
import sys

CHILD = r"""
import json, math, resource, sys, time
import numpy as np
from railvti.vehicle import simulate
from railvti.vehicle.assembly import build_rigid_system
from railvti.vehicle.model import ModalBlocks, PointElement
kind, nm, nsteps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
NP, h = 4, 1e-3
rng = np.random.default_rng(0)
om = np.linspace(10.0, 1900.0, max(nm, 1))[:nm]
phi = rng.normal(size=(NP, nm)) / math.sqrt(max(nm, 1))
if kind == "coach":
    from railvti import scenarios
    from railvti.vehicle import static_equilibrium, lateral_disturbance
    sy = scenarios.coach_system()
    speed = 300 / 3.6
    q, vs, _ = static_equilibrium(sy, speed, return_velocity=True)
    q = lateral_disturbance(sy, q, 0.003)
    if nm:
        iz = [sy.index(f"ws{w}_z") for w in (1, 2, 3, 4)]
        els = tuple(PointElement.linear(p, iz[p], 2e6, 1e3, 2e6 * q[iz[p]]) for p in range(NP))
        sy = sy.with_modal(ModalBlocks.diagonal(om, 0.02, phi, els))
    x0 = np.concatenate([q, np.zeros(nm)])
    v0 = np.concatenate([vs, np.zeros(nm)])
else:
    els = tuple(PointElement.linear(p, p, 1e5, 50.0) for p in range(NP))
    m = np.diag([100.0, 120.0, 80.0, 90.0, 200.0, 150.0])
    k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))
    sy = build_rigid_system(m, 0.01 * k, k, modal=ModalBlocks.diagonal(om, 0.02, phi, els))
    if kind == "dense":
        sy = sy.dense_equivalent()
    speed = 1.0
    x0 = np.zeros(6 + nm)
    x0[0] = 1e-3
    x0[6:] = 1e-4
    v0 = None
sy.native                                           # the model sent once, not timed
t0 = time.perf_counter()
r = simulate(sy, speed, nsteps * h, q0=x0, v0=v0, h=h, output_dt=nsteps * h, progress=False)
wall = time.perf_counter() - t0
print(json.dumps({"ms_step": 1e3 * wall / r.stats["steps"], "steps": r.stats["steps"],
                  "newton": r.stats["newton_iterations"] / r.stats["steps"],
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def run(kind: str, nm: int, nsteps: int) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, kind, str(nm), str(nsteps)], capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def accuracy() -> None:
    """The accuracy figures of the condensed integrator on the tests' systems."""
    from pathlib import Path

    import numpy as np
    from scipy.integrate import solve_ivp

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    import test_vehicle_modal_blocks as tm
    from railvti.vehicle import simulate

    def rel(a, b):
        return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))

    sy = tm._linear_system()
    de = sy.dense_equivalent()
    kw = dict(q0=tm._start(sy), h=1e-3, output_dt=1e-3, tol=1e-12)
    r1, r2 = simulate(sy, 1.0, 0.2, **kw), simulate(de, 1.0, 0.2, **kw)
    print(
        f"linear, 2 rigid + 9 modes (blocks 1,2,3,1,2), 3 points, 0.2 s: condensed vs dense "
        f"max rel diff q {rel(r1.q, r2.q):.2e}, v {rel(r1.v, r2.v):.2e}"
    )
    sy3 = tm._linear_system(seed=3)
    kw3 = dict(q0=tm._start(sy3), h=5e-4, output_dt=5e-4, tol=1e-12, alpha=-0.1)
    r1, r2 = simulate(sy3, 1.0, 0.05, **kw3), simulate(sy3.dense_equivalent(), 1.0, 0.05, **kw3)
    print(f"same, HHT alpha = -0.1: max rel diff q {rel(r1.q, r2.q):.2e}")
    su = tm._linear_system(damped=False)
    du = su.dense_equivalent()
    r = simulate(su, 1.0, 2.0, q0=tm._start(su), h=1e-3, output_dt=1e-3, tol=1e-12)
    e = (
        0.5 * np.einsum("ti,ij,tj->t", r.v, du.m, r.v)
        + 0.5 * np.einsum("ti,ij,tj->t", r.q, du.k, r.q)
        - r.q @ du.f0
    )
    x0 = tm._start(su)
    e0 = 0.5 * x0 @ du.k @ x0 - x0 @ du.f0
    print(
        f"undamped gyroscopic, trapezoidal, 2000 steps: max |E - E0| / E0 = "
        f"{np.max(np.abs(e - e0)) / abs(e0):.2e}"
    )
    sh = tm._hertz_system()
    x0 = tm._hertz_start(sh)
    ref = solve_ivp(
        tm._hertz_rhs(sh),
        (0.0, 0.05),
        np.concatenate([x0, np.zeros_like(x0)]),
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
    ).y[: sh.n_state, -1]
    errs = []
    for h in (2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5):
        rr = simulate(sh, 1.0, 0.05, q0=x0, h=h, output_dt=0.05, tol=1e-13, maxsub=0)
        errs.append(float(np.max(np.abs(rr.q[-1] - ref))))
        print(
            f"Hertz point contact, h = {h:.3e} s: error at 0.05 s {errs[-1]:.3e}, Newton "
            f"{rr.stats['newton_iterations'] / rr.stats['steps']:.2f}/step, tangents "
            f"{rr.stats['tangents'] / rr.stats['steps']:.2f}/step"
        )
    print("  observed orders", np.round(np.log2(np.array(errs[:-1]) / np.array(errs[1:])), 3))
    rig, fr, q1, vs, x0, v0, v = tm._coach_with_modes(coupled=False)
    r0 = simulate(rig, v, 0.1, q0=q1, v0=vs, output_dt=1e-3)
    r1 = simulate(fr, v, 0.1, q0=x0, v0=v0, output_dt=1e-3)
    print(
        f"RR coach vs RR + 6 decoupled modes, 0.1 s at 300 km/h: max rel diff q "
        f"{rel(r1.q[:, : rig.n], r0.q):.2e}, wheel outputs bit-identical "
        f"{bool(np.array_equal(r1.wheel, r0.wheel))}"
    )
    rig, fr, q1, vs, x0, v0, v = tm._coach_with_modes(coupled=True)
    kwc = dict(q0=x0, v0=v0, output_dt=1e-3, h=5e-4, tol=1e-12)
    r1, r2 = simulate(fr, v, 0.05, **kwc), simulate(fr.dense_equivalent(), v, 0.05, **kwc)
    print(
        f"RR coach + 6 modes sprung to ws1 z, y (contact on), 0.05 s: condensed vs dense max "
        f"rel diff q {rel(r1.q, r2.q):.2e}, modes up to {np.max(np.abs(r1.q[:, rig.n :])):.2e}"
    )


def main() -> None:
    if "--accuracy" in sys.argv[1:]:
        accuracy()
        return
    nms = [int(a) for a in sys.argv[1:]] or [10, 100, 1000, 10000]
    print(
        "modal blocks: time per step (h = 1 ms) and peak RSS against the number of modes nm "
        "(1 x 1 blocks, np = 4 points)"
    )
    print(f"{'case':<10}{'nm':>7}{'steps':>7}{'ms/step':>10}{'Newton/step':>13}{'RSS MB':>9}")
    for kind in ("condensed", "dense", "coach"):
        for nm in ([0] if kind == "coach" else []) + nms:
            if kind == "dense" and nm > 1000:
                continue
            nsteps = 20 if (kind == "dense" and nm >= 1000) else 200
            r = run(kind, nm, nsteps)
            print(
                f"{kind:<10}{nm:>7}{r['steps']:>7}{r['ms_step']:>10.3f}{r['newton']:>13.2f}"
                f"{r['rss_mb']:>9.0f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
