"""FR's modal step at RR's 1 ms (issue 33): the exact modal step with sub-steps in flange contact
('exact-flange', FR's default) against the plain exact step, the trapezoidal step at 0.5 ms (FR's
default before) and a converged reference (the trapezoidal step at 1/16 ms); and the stability
analysis of the force interpolations that were tried instead (docs/vehicle_integrator.md,
"Exact modal step: sub-steps in flange contact").

    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_flange_step.py [part ...]

Parts: 'stability' (numpy only, seconds): the spectral radius of one step of a mode
Q'' + 2 zeta w Q' + w^2 Q = f coupled at a point to the ground by a spring k or a damper c
taken implicitly at the step's end (Newton's view), for the point force linear in time over the
step (the exact step), held at its mean (B0 = B1), and the two split at h w = pi (mean below,
linear above), over h w in [0, 10], h sqrt(k) in [0, 1000], h c in [0, 100]; and two modes on one
point with the split. 'cycle420' (FR released at 6 mm at 420 km/h, 4 s: a flange limit cycle;
Hertz + Kalker, the critical-speed study's contact), 'hunting' (300 km/h from 6 mm, 2 s,
Hertz + FASTSIM, the benchmark's scene), 'decay' (330 km/h from 0.5 mm, 3 s, Hertz + Kalker):
per run the leading wheelset's amplitude (largest |y| over the last 0.5 s), Q max and Y max
(outputs every 2 ms), steps, sub-stepped steps, Newton iterations and CPU time. Default: all.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.linalg import expm

from railvti import scenarios

#: (modal_step, h in ms): the reference first.
RUNS = (("trapezoidal", 0.0625), ("trapezoidal", 0.5), ("exact", 1.0), ("exact-flange", 1.0))
#: scene: (speed km/h, y0 m, duration s, contact)
SCENES = {
    "cycle420": (420.0, 0.006, 4.0, "hertz-kalker"),
    "hunting": (300.0, 0.006, 2.0, "hertz-fastsim"),
    "decay": (330.0, 0.0005, 3.0, "hertz-kalker"),
}


def step_matrices(h: float, w: float, zeta: float, rule: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A, B0, B1 of one mode's step z1 = A z0 + B0 f0 + B1 f1 (z = (Q, V)), exact for the
    mode: the force linear in time ('linear', the exact step), held at its mean ('mean'), or
    'split' (mean for h w <= pi, linear above). Van Loan's block exponential."""
    x = np.zeros((4, 4))
    x[:2, :2] = h * np.array([[0.0, 1.0], [-w * w, -2.0 * zeta * w]])
    x[1, 2] = 1.0
    x[2, 3] = 1.0
    e = expm(x)
    a, gam, lin = e[:2, :2], h * e[:2, 2], h * e[:2, 3]
    mean = rule == "mean" or (rule == "split" and h * w <= np.pi)
    b1 = gam / 2.0 if mean else lin
    return a, gam - b1, b1


def radius(modes: list, phi: np.ndarray, k: float, c: float) -> float:
    """Spectral radius of one step of the modes (step_matrices) on one point u = phi . Q with
    the point force g = -k u - c u' at the step's end (solved with it, as Newton does)."""
    n = len(modes)
    a = np.zeros((2 * n, 2 * n))
    b0 = np.zeros(2 * n)
    b1 = np.zeros(2 * n)
    for i, (ai, b0i, b1i) in enumerate(modes):
        a[2 * i : 2 * i + 2, 2 * i : 2 * i + 2] = ai
        b0[2 * i : 2 * i + 2] = b0i * phi[i]
        b1[2 * i : 2 * i + 2] = b1i * phi[i]
    g = np.zeros(2 * n)
    g[0::2] = k * phi
    g[1::2] = c * phi
    m = np.linalg.inv(np.eye(2 * n) + np.outer(b1, g))
    t = np.zeros((2 * n + 1, 2 * n + 1))
    t[: 2 * n, : 2 * n] = m @ a
    t[: 2 * n, -1] = m @ b0
    t[-1, :] = -g @ t[: 2 * n, :]
    return float(np.abs(np.linalg.eigvals(t)).max())


def _intervals(ws: np.ndarray, r: np.ndarray) -> str:
    """The grid points of ws where r > 1, as intervals ('none' if none)."""
    bad = r > 1.0 + 1e-9
    out, i = [], 0
    while i < ws.size:
        if bad[i]:
            j = i
            while j + 1 < ws.size and bad[j + 1]:
                j += 1
            out.append(f"[{ws[i]:.2f}, {ws[j]:.2f}]")
            i = j
        i += 1
    return " ".join(out) if out else "none"


def stability() -> None:
    """The stability analysis (h = 1: h w, h sqrt(k), h c)."""
    ks = np.concatenate([np.linspace(0.0, 10.0, 41), np.logspace(1, 3, 21)]) ** 2
    cs = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 20.0, 100.0)
    ws = np.linspace(0.0, 10.0, 201)
    print("one mode, a point spring k or damper c to the ground (h = 1): largest spectral radius")
    for rule in ("linear", "mean", "split"):
        for zeta in (0.0, 0.005, 0.05):
            one = [step_matrices(1.0, w, zeta, rule) for w in ws]
            rk = np.array([max(radius([m], np.ones(1), k, 0.0) for k in ks) for m in one])
            rc = np.array([max(radius([m], np.ones(1), 0.0, c) for c in cs) for m in one])
            print(
                f"  {rule:6s} zeta {zeta:5.3f}: spring: max {rk.max():7.3f}, unstable for h w in "
                f"{_intervals(ws, rk)}; damper: max {rc.max():7.3f}, unstable for h w in {_intervals(ws, rc)}"
            )
    print("two modes (zeta 0.005) on one point, split at h w = pi, a spring: largest spectral radius")
    for w1, w2 in ((0.5, 3.5), (2.6, 3.5), (2.0, 4.0), (1.0, 5.0)):
        for r1 in (0.3, 1.0, 3.0):
            modes = [step_matrices(1.0, w1, 0.005, "split"), step_matrices(1.0, w2, 0.005, "split")]
            r = max(radius(modes, np.array([r1, 1.0]), k, 0.0) for k in ks)
            print(f"  h w {w1:3.1f} (mean) and {w2:3.1f} (linear), phi ({r1:3.1f}, 1): {r:6.3f}")


def run(scene: str, modal_step: str, h_ms: float) -> dict:
    """One FR run's measures."""
    speed, y0, duration, contact = SCENES[scene]
    c0 = time.process_time()
    r = scenarios.hunting(
        speed, variant="FR", y0=y0, duration=duration, h=h_ms * 1e-3, modal_step=modal_step,
        contact=contact, output_dt=2e-3, progress=False,
    )  # fmt: skip
    cpu = time.process_time() - c0
    late = r.t >= r.t[-1] - 0.5
    return dict(
        amp=float(np.abs(r.y_ws1[late]).max()),
        Q=float(r.Q.max()),
        Y=float(np.abs(r.Y).max()),
        steps=r.stats["steps"],
        sub=r.stats["substepped_steps"],
        nit=r.stats["newton_iterations"],
        cpu=cpu,
    )


def scene_table(scene: str) -> None:
    res = {(ms, h): run(scene, ms, h) for ms, h in RUNS}
    ref = res[RUNS[0]]
    print(
        f"FR {scene}: reference ({RUNS[0][0]} {RUNS[0][1]} ms): amplitude {ref['amp'] * 1e3:.6f} mm, "
        f"Q max {ref['Q'] / 1e3:.3f} kN, Y max {ref['Y'] / 1e3:.3f} kN"
    )
    for (ms, h), m in res.items():
        print(
            f"  {ms:12s} {h:6.4f} ms: amplitude {(m['amp'] / ref['amp'] - 1) * 100:+.3f} %, "
            f"Q max {m['Q'] / 1e3:8.3f} kN ({(m['Q'] / ref['Q'] - 1) * 100:+.2f} %), "
            f"Y max {m['Y'] / 1e3:8.3f} kN; {m['steps']:.0f} steps ({m['sub']:.0f} sub-stepped), "
            f"{m['nit']:.0f} Newton iterations, CPU {m['cpu']:.2f} s",
            flush=True,
        )


def main(parts: list[str]) -> None:
    for part in parts or ["stability", *SCENES]:
        if part == "stability":
            stability()
        elif part in SCENES:
            scene_table(part)
        else:
            raise SystemExit(f"unknown part {part!r}: 'stability' or one of {list(SCENES)}")


if __name__ == "__main__":
    main(sys.argv[1:])
