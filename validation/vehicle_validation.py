"""Vehicle-track time simulation (model RR) against theory, and the integrator's behaviour.

(a) one suspended wheelset, linear creep: critical speed vs Wickens' closed form (Hurwitz);
(b) kinematic wavelength of a free wheelset at low speed vs Klingel;
(c) energy drift of the undamped, frictionless coach over 10 s;
(d) step-size convergence and cost of a hunting run at 400 km/h, and the step at which
    fixed-step Newton stops converging.
Also: the centred-running check, hunting phase portraits and the bifurcation diagram with
the linear critical speed.

    .venv/bin/python validation/vehicle_validation.py [--quick]
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti import scenarios  # noqa: E402
from railvti.geometry import klingel_wavelength  # noqa: E402
from railvti.vehicle import (
    DivergenceError,
    build_single_wheelset,
    eigenvalues,  # noqa: E402
    lateral_disturbance,
    linearised_table,
    simulate,
    static_equilibrium,
)
from railvti.vehicle.analytic import wickens_critical_speed  # noqa: E402
from railvti.vehicle.table import QUANTITIES  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"
QUICK = "--quick" in sys.argv
WS = dict(mass=1813.0, roll_inertia=1120.0, yaw_inertia=1120.0)  # Iwnicki 1998 wheelset


def _single(lam: float, ky: float, kx: float, axle_load: float = 100e3):
    tab = linearised_table(scenarios.wheel_table(), lam, gravitational=False, spin=False)
    sy = build_single_wheelset(tab, ky=ky, kx=kx, half_spacing=1.0, axle_load=axle_load, **WS)
    return tab, sy


def part_a() -> dict:
    print("\n(a) suspended wheelset, linear creep: critical speed")
    lam = scenarios.equivalent_conicity(0.003)
    rows = []
    for ky, kx in ((0.5e6, 0.5e6), (1e6, 2e6), (2e6, 5e6)):
        tab, sy = _single(lam, ky, kx)
        q, wout = static_equilibrium(sy, 30.0)
        n = wout[0, 0, 0]  # normal = vertical force at zero contact angle
        i0 = int(np.argmin(np.abs(tab.y)))
        g = tab.material.shear_modulus
        a, b = (tab.data[QUANTITIES.index(k), 0, i0] * n ** (1 / 3) for k in ("a1", "b1"))
        c11, c22 = (tab.data[QUANTITIES.index(k), 0, i0] for k in ("c11", "c22"))
        f11, f22 = g * a * b * c11, g * a * b * c22
        l0 = tab.data[1, 0, i0]
        vc = wickens_critical_speed(
            WS["mass"], WS["yaw_inertia"], 2 * ky, 2 * kx * 1.0, f11, f22, lam, l0, tab.r0
        )

        def growth(v):
            ev = eigenvalues(sy, v)
            osc = ev[(np.abs(ev.imag) > 0.1) & (np.abs(ev.imag) < 2 * np.pi * 30)]
            return osc.real.max()

        lo, hi = 0.5 * vc, 1.5 * vc
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if growth(mid) < 0 else (lo, mid)
        vs = 0.5 * (lo + hi)
        # time-domain check: a 1 mm disturbance decays at 0.98 vc, grows at 1.02 vc
        amps = []
        for fac in (0.98, 1.02):
            v = fac * vc
            qs, _ = static_equilibrium(sy, v)
            r = simulate(sy, v, 6.0, q0=lateral_disturbance(sy, qs, 0.001, (0,)), h=1e-3, progress=False)
            y = r.y_ws1
            amps.append(np.ptp(y[r.t > 5.0]) / np.ptp(y[r.t < 1.0]))
        err = vs / vc - 1
        rows.append((ky, kx, vc * 3.6, vs * 3.6, err, amps[0], amps[1]))
        print(
            f"  ky {ky / 1e6:.1f} MN/m, kx {kx / 1e6:.1f} MN/m: Wickens {vc * 3.6:7.2f} km/h, "
            f"railvti eigenvalues {vs * 3.6:7.2f} km/h ({100 * err:+.3f} %); amplitude ratio "
            f"5 s -> at 0.98 Vc {amps[0]:.3f}, at 1.02 Vc {amps[1]:.3f}"
        )
    return {"rows": rows, "conicity": lam}


def part_b() -> dict:
    print("\n(b) free wheelset at low speed: kinematic wavelength vs Klingel")
    lam = scenarios.equivalent_conicity(0.003)
    out = []
    for v in (2.0, 5.0):
        tab, sy = _single(lam, 1.0, 1.0)  # practically free (1 N/m springs)
        qs, _ = static_equilibrium(sy, v)
        dist = 3.2 * klingel_wavelength(lam, tab.r0, tab.data[1, 0, 300])
        r = simulate(
            sy,
            v,
            dist / v,
            q0=lateral_disturbance(sy, qs, 0.001, (0,)),
            h=2e-3,
            output_dt=2e-3,
            progress=False,
        )
        y = r.y_ws1 - r.y_ws1.mean()
        s = np.sign(y)
        idx = np.nonzero(s[1:] * s[:-1] < 0)[0]
        tz = r.t[idx] - y[idx] * (r.t[idx + 1] - r.t[idx]) / (y[idx + 1] - y[idx])
        wl = 2 * np.mean(np.diff(tz)) * v
        i0 = int(np.argmin(np.abs(tab.y)))
        ref = klingel_wavelength(lam, tab.r0, tab.data[1, 0, i0])
        out.append((v, wl, ref, wl / ref - 1, r))
        print(f"  V = {v:.0f} m/s: simulated {wl:.3f} m, Klingel {ref:.3f} m ({100 * (wl / ref - 1):+.2f} %)")
    fig, ax = plt.subplots(figsize=(6.0, 3.0))
    for v, wl, _ref, _e, r in out:
        ax.plot(r.t * v, r.y_ws1 * 1e3, label=f"V = {v:.0f} m/s: {wl:.2f} m")
    ax.set_xlabel("distance, m")
    ax.set_ylabel("y, mm")
    ax.set_title(
        f"free wheelset on rigid rails (equivalent conicity {lam:.3f}): wavelength\n"
        f"against Klingel's {out[0][2]:.2f} m, Hertz + Kalker",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_klingel.png", dpi=80)
    plt.close(fig)
    return {"rows": [o[:4] for o in out]}


def _energy(sy, r) -> np.ndarray:
    kin = 0.5 * np.einsum("ti,ij,tj->t", r.v, sy.m, r.v)
    pot = 0.5 * np.einsum("ti,ij,tj->t", r.q, sy.k, r.q) - r.q @ sy.f0
    return kin + pot + r.wheel_output("energy").sum(axis=(1, 2))


def part_c() -> dict:
    print("\n(c) energy drift of the undamped frictionless coach (vertical and pitch motion), 10 s")
    sy0 = scenarios.coach_system()
    from dataclasses import replace

    sy = replace(sy0.without_damping(), friction=0.0)
    q, _ = static_equilibrium(sy, 50.0)
    e_static = _energy(
        sy,
        type(
            "R",
            (),
            {"v": np.zeros((1, sy.n)), "q": q[None, :], "wheel_output": lambda self, n: np.zeros((1, 2, 4))},
        )(),
    )[0]
    q1 = q.copy()
    q1[sy.index("carbody_z")] += 0.01
    q1[sy.index("carbody_pitch")] += 0.002
    q1[sy.index("bogie1_z")] += 0.003
    rows = []
    fig, ax = plt.subplots(figsize=(6.0, 3.0))
    for h in (2e-3, 1e-3, 5e-4):
        t0 = time.perf_counter()
        r = simulate(sy, 50.0, 10.0, q0=q1, h=h, output_dt=0.01, progress=False)
        e = _energy(sy, r)
        e0 = e[0]
        # the first output is after one step; the oscillation energy is measured above static
        drift = (e - e0) / (e0 - e_static)
        rows.append((h, float(np.abs(drift).max()), float(drift[-1]), time.perf_counter() - t0))
        print(
            f"  h = {h * 1e3:.1f} ms: max |E - E0| / E_osc = {np.abs(drift).max():.2e}, "
            f"at 10 s {drift[-1]:+.2e} (E_osc = {e0 - e_static:.1f} J)"
        )
        ax.plot(r.t, drift, label=f"h = {h * 1e3:.1f} ms")
    ax.set_xlabel("time, s")
    ax.set_ylabel("(E - E0) / E_osc")
    ax.set_title(
        "energy drift of the undamped coach RR at 50 m/s, friction 0\n"
        "(vertical disturbance; E_osc the oscillation energy)",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_energy.png", dpi=80)
    plt.close(fig)
    return {"rows": rows}


def part_d() -> dict:
    print("\n(d) step-size convergence and cost: hunting at 400 km/h, y0 = 4 mm, 2 s")
    sy = scenarios.coach_system()
    v = 400 / 3.6
    qs, _ = static_equilibrium(sy, v)
    q0 = lateral_disturbance(sy, qs, 0.004)
    dur = 2.0
    hs = [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4]
    href = 3.125e-5
    ref = simulate(sy, v, dur, q0=q0, h=href, output_dt=1e-3, progress=False)
    rows = []
    for h in hs:
        t0 = time.perf_counter()
        try:
            r = simulate(sy, v, dur, q0=q0, h=h, output_dt=max(h, 1e-3) if h <= 1e-3 else h, progress=False)
        except DivergenceError as exc:
            print(f"  h = {h * 1e3:.3f} ms: {exc}")
            rows.append((h, math.nan, math.nan, time.perf_counter() - t0, 0, 0))
            continue
        wall = time.perf_counter() - t0
        yr = np.interp(r.t, ref.t, ref.y_ws1)
        k = r.t <= 1.0
        err = float(np.abs(r.y_ws1[k] - yr[k]).max())
        amp = scenarios.amplitude(r, 0.5)
        rows.append(
            (h, err, amp, wall, r.stats["substepped_steps"], r.stats["newton_iterations"] / r.stats["steps"])
        )
        print(
            f"  h = {h * 1e3:6.3f} ms: max |y - y_ref| (0-1 s) {err * 1e3:8.4f} mm, amplitude "
            f"{amp * 1e3:.3f} mm, wall {wall:.2f} s, sub-stepped steps {r.stats['substepped_steps']}, "
            f"Newton it/step {rows[-1][5]:.2f}"
        )
    print(f"  reference h = {href * 1e3:.4f} ms, amplitude {scenarios.amplitude(ref, 0.5) * 1e3:.3f} mm")
    # fixed steps (no sub-stepping): where does Newton stop converging?
    fixed = []
    for h in (2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2):
        try:
            simulate(sy, v, dur, q0=q0, h=h, maxsub=0, progress=False)
            fixed.append((h, "converges"))
        except DivergenceError as exc:
            fixed.append((h, str(exc).split(": ", 1)[0]))
        print(f"  fixed step h = {h * 1e3:.2f} ms (maxsub=0): {fixed[-1][1]}")
    hh = np.array([r[0] for r in rows])
    ee = np.array([r[1] for r in rows])
    ww = np.array([r[3] for r in rows])
    fig, ax = plt.subplots(1, 2, figsize=(8.0, 3.2))
    from matplotlib.ticker import FixedLocator, NullLocator, ScalarFormatter

    ax[0].loglog(hh * 1e3, ee * 1e3, "o-")
    ax[0].loglog(hh * 1e3, ee[2] * 1e3 * (hh / hh[2]) ** 2, "k:", label="slope 2")
    ax[0].set_xlabel("h, ms")
    ax[0].set_ylabel("max |y - y_ref|, mm (0-1 s)")
    ax[0].legend(fontsize=8)
    ax[0].grid(alpha=0.3, which="both")
    ax[0].xaxis.set_major_locator(FixedLocator(hh * 1e3))
    ax[0].xaxis.set_minor_locator(NullLocator())
    ax[0].xaxis.set_major_formatter(ScalarFormatter())
    ax[1].loglog(ww, ee * 1e3, "o-")
    for h, e, w in zip(hh, ee, ww):
        ax[1].annotate(f"{h * 1e3:g} ms", (w, e * 1e3), fontsize=7)
    ax[1].xaxis.set_minor_locator(NullLocator())
    ax[1].xaxis.set_major_formatter(ScalarFormatter())
    ax[1].set_xlabel("wall time for 2 s, s")
    ax[1].set_ylabel("error, mm")
    ax[1].grid(alpha=0.3, which="both")
    fig.suptitle("hunting 400 km/h, Hertz + Kalker: accuracy against cost")
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_step_convergence.png", dpi=80)
    plt.close(fig)
    return {"rows": rows, "fixed": fixed}


def part_hunting() -> dict:
    print("\ncentred running and hunting")
    c = scenarios.centred_running(200.0, duration=1.0, progress=False)
    print(
        f"  centred 200 km/h: max |Q/Q0 - 1| = {c.q_error:.2e} (Q0 = {c.static_wheel_load:.1f} N), "
        f"Y per wheel {c.Y[0, 0]:+.1f} / {c.Y[1, 0]:+.1f} N, net per wheelset "
        f"{np.abs(c.Y.sum(axis=0)).max():.1e} N"
    )
    from railvti.vehicle.plots import plot_patch

    p = c.patch
    plot_patch(
        p.x,
        p.y,
        p.pressure,
        p.tx,
        p.ty,
        p.power_density,
        FIG / "vehicle_patch_centred.png",
        f"centred 200 km/h, leading wheelset right wheel: a = {p.a * 1e3:.2f} mm, "
        f"b = {p.b * 1e3:.2f} mm, Fy = {p.fy:.0f} N, friction power {p.power:.1f} W",
    )
    print(
        f"  contact patch (leading wheelset, right wheel): a {p.a * 1e3:.2f} mm, b {p.b * 1e3:.2f} mm, "
        f"p0 {p.pressure.max() / 1e6:.0f} MPa, Fy {p.fy:.0f} N (spin), friction power {p.power:.1f} W"
    )
    fig, ax = plt.subplots(1, 2, figsize=(9.0, 3.6))
    for kmh in (300, 360, 420):
        r = scenarios.hunting(kmh, duration=6.0 if not QUICK else 3.0, y0=0.004, progress=False)
        k = r.t > r.t[-1] - 1.0
        ax[0].plot(r.t, r.y_ws1 * 1e3, lw=0.7, label=f"{kmh} km/h")
        ax[1].plot(r.y_ws1[k] * 1e3, r.vy_ws1[k], lw=0.8, label=f"{kmh} km/h")
        print(
            f"  hunting {kmh} km/h: amplitude {scenarios.amplitude(r) * 1e3:.2f} mm, "
            f"max flange force {r.wheel_output('N_flange').max() / 1e3:.1f} kN"
        )
        print(f"    {r.wheels().line()}")
    ax[0].set_xlabel("time, s")
    ax[0].set_ylabel("y wheelset 1, mm")
    ax[1].set_xlabel("y wheelset 1, mm")
    ax[1].set_ylabel("dy/dt, m/s")
    ax[0].set_title("leading wheelset from y0 = 4 mm")
    ax[1].set_title("phase portrait (last second)")
    fig.suptitle(
        "Coach RR on track elements, Hertz + Kalker on the strip contact: hunting at 300 / 360 / 420 km/h",
        fontsize=10,
    )
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_hunting.png", dpi=80)
    plt.close(fig)
    return {"centred": c}


def part_bifurcation() -> dict:
    print("\ncritical speed: linear (eigenvalues) and nonlinear (bifurcation)")
    from railvti.vehicle.plots import plot_bifurcation

    t0 = time.perf_counter()
    lin, f = scenarios.linear_critical_speed_kmh()
    t_lin = time.perf_counter() - t0
    sp = np.arange(140.0, 461.0, 20.0 if QUICK else 10.0)
    t0 = time.perf_counter()
    b = scenarios.bifurcation(sp, duration=4.0, progress=False)
    t_nl = time.perf_counter() - t0
    flange = b.speeds_kmh[b.upper > 5e-3]
    print(
        f"  linear (equivalent conicity {scenarios.equivalent_conicity(0.003):.4f} at 3 mm): "
        f"{lin:.1f} km/h, {f:.2f} Hz  [{t_lin:.1f} s]"
    )
    print(
        f"  nonlinear: lowest speed with a sustained limit cycle {b.critical_kmh:.0f} km/h; "
        f"flange-contact cycle (> 5 mm) from {flange.min() if flange.size else math.nan:.0f} km/h  "
        f"[{t_nl:.1f} s]"
    )
    print(f"  {b.message}")
    slide, fs = scenarios.linear_critical_speed_kmh(damper="sliding")
    print(f"  linear with the yaw damper sliding: {slide:.1f} km/h, {fs:.2f} Hz")
    for s, u, d in zip(b.speeds_kmh, b.upper, b.decay):
        print(f"    {s:5.0f} km/h: continuation {u * 1e3:6.2f} mm, from 0.5 mm {d * 1e3:6.2f} mm")
    amps = np.array([0.5, 1.0, 1.5, 2.0, 3.0, 4.0]) * 1e-3
    eq = []
    print("  describing-function check: linear critical speed at the equivalent conicity of A")
    for a in amps:
        lam = scenarios.equivalent_conicity(a)
        vl = scenarios.linear_critical_speed_kmh(conicity=lam)[0]
        eq.append(vl)
        print(f"    A = {a * 1e3:.1f} mm: conicity {lam:.4f} -> {vl:.1f} km/h")
    plot_bifurcation(
        b.speeds_kmh,
        b.upper,
        b.decay,
        lin,
        FIG / "vehicle_bifurcation.png",
        equivalent=(np.array(eq), amps),
        title="Coach RR on track elements, Hertz + Kalker on the strip contact:\n"
        "limit cycles of the leading wheelset",
    )
    return {"linear": lin, "freq": f, "bif": b}


def main() -> None:
    FIG.mkdir(exist_ok=True)
    part_a()
    part_b()
    part_c()
    part_d()
    part_hunting()
    part_bifurcation()


if __name__ == "__main__":
    main()
