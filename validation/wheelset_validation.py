"""Validation of the flexible wheelset (issue 6).

(a) axisymmetric FE against closed forms: free-free Timoshenko shaft (k = 1),
    Kirchhoff annular plate clamped inside / free outside (k = 0, 1, 2);
(b) frequency error against DOFs and solve time (mesh refinement);
(c) rotation: split of k = 1, 2 modes against k Omega, k = 0 unmoved;
(d) the default wheelset beside the paper's 147 / 304 / 345 Hz.
Prints tables, writes validation/figures/wheelset_*.png.
Run: .venv/bin/python validation/wheelset_validation.py
"""
from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti.wheelset import Wheelset, analytic, rectangle_mesh, solve_harmonic  # noqa: E402
from railvti.wheelset.plots import plot_frf, plot_mode  # noqa: E402

E, NU, RHO = 210e9, 0.3, 7850.0
FIG = Path(__file__).resolve().parent / "figures"
FIG.mkdir(exist_ok=True)


def shaft(ny: int, nr: int = 2):
    t = time.perf_counter()
    h = solve_harmonic(rectangle_mesh(0.0, 0.1, -1.0, 1.0, nr, ny), 1, E, NU, RHO, 1500.0)
    return h.freq_hz[h.freq_hz > 1.0][:3], h.n_equations, time.perf_counter() - t


def plate(k: int, nr: int, nt: int):
    m = rectangle_mesh(0.1, 0.5, 0.0, 0.01, nr, nt)
    fixed = np.zeros((m.n_nodes, 3), bool)
    fixed[np.isclose(m.nodes[:, 0], 0.1)] = True
    t = time.perf_counter()
    h = solve_harmonic(m, k, E, NU, RHO, 1200.0, fixed=fixed)
    bend = [f for f, s in zip(h.freq_hz, h.shapes) if np.abs(s[:, 1]).max() > np.abs(s[:, [0, 2]]).max()]
    return np.array(bend[:2]), h.n_equations, time.perf_counter() - t


def part_a_b() -> None:
    ref = analytic.timoshenko_free_free(2.0, 0.2, E, NU, RHO, 3)
    print("\n(a) free-free shaft L = 2 m, D = 0.2 m, k = 1 bending (Timoshenko, kappa Cowper)")
    print(f"{'elements':>9} {'DOFs':>6} {'time s':>7} " + " ".join(f"{'mode' + str(i + 1):>18}" for i in range(3)))
    rows = []
    for ny in (4, 8, 16, 32, 64):
        f, n, t = shaft(ny)
        err = f / ref - 1.0
        rows.append((n, t, np.abs(err).max()))
        print(f"{2 * ny:>9} {n:>6} {t:>7.3f} " + " ".join(f"{fi:9.2f} ({e:+.2%})" for fi, e in zip(f, err)))
    print(f"{'theory':>24} " + " ".join(f"{r:18.2f}" for r in ref))
    prow = {}
    print("\n(a) annular plate b = 0.1, a = 0.5, h = 0.01 m, clamped inside, free outside (Kirchhoff)")
    for k in (0, 1, 2):
        ref_p = analytic.annular_plate_clamped_free(0.1, 0.5, 0.01, E, NU, RHO, k, 2)
        prow[k] = []
        for nr, nt in ((4, 1), (8, 1), (16, 1), (32, 2), (64, 2)):
            f, n, t = plate(k, nr, nt)
            err = f / ref_p - 1.0
            prow[k].append((n, t, np.abs(err).max()))
            print(f"k={k} {nr:>3}x{nt} DOFs {n:>5} {t:6.3f} s  " +
                  "  ".join(f"{fi:8.2f} ({e:+.2%})" for fi, e in zip(f, err)) +
                  f"   theory {ref_p[0]:.2f}, {ref_p[1]:.2f}")
    fig, axs = plt.subplots(1, 2, figsize=(8, 3.2), dpi=90)
    for lab, data in [("shaft k=1 (3 modes)", rows)] + [(f"plate k={k} (2 modes)", prow[k]) for k in prow]:
        d = np.array(data)
        axs[0].loglog(d[:, 0], d[:, 2], "o-", ms=3, label=lab)
        axs[1].loglog(d[:, 1], d[:, 2], "o-", ms=3, label=lab)
    axs[0].set_xlabel("degrees of freedom")
    axs[1].set_xlabel("solve time, s")
    for ax in axs:
        ax.set_ylabel("max |relative error|")
        ax.axhline(0.02, color="k", lw=0.6, ls="--")
        ax.grid(True, which="both", lw=0.3)
    axs[0].legend(fontsize=7)
    fig.suptitle("axisymmetric 9-node harmonic elements vs theory (2% line dashed)", fontsize=9)
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_convergence.png")
    plt.close(fig)


def part_c_d() -> None:
    ws = Wheelset()
    t = time.perf_counter()
    table = ws.modes(k_max=2, f_max=600.0)
    print(f"\n(d) default wheelset, free-free modes up to 600 Hz ({time.perf_counter() - t:.1f} s)")
    for k in (0, 1, 2):
        print(f"  k={k}: " + ", ".join(f"{f:.1f}" for kk, f in zip(table.k, table.freq_hz) if kk == k))
    f1 = [f for kk, f in zip(table.k, table.freq_hz) if kk == 1 and f > 1.0]
    f0 = [f for kk, f in zip(table.k, table.freq_hz) if kk == 0 and f > 1.0]
    f2 = [f for kk, f in zip(table.k, table.freq_hz) if kk == 2]
    # umbrella: k = 0 modes dominated by axial motion
    umb = [f for kk, f, s in zip(table.k, table.freq_hz, table.shapes)
           if kk == 0 and f > 1.0 and np.sum(s[:, 1] ** 2) > 0.8 * np.sum(s ** 2)]
    print("\n  mode                 paper (Hz)   this (Hz)   difference")
    for lab, p, v in (("first k=1 (flexible)", 147.0, f1[0]), ("second k=1", 147.0, f1[1]),
                      ("k=0 umbrella (1st)", 304.0, umb[0]), ("k=0 umbrella (2nd)", 304.0, umb[1]),
                      ("first k=2", 345.0, f2[0])):
        print(f"  {lab:<22} {p:8.0f} {v:11.1f} {v / p - 1.0:+11.1%}")

    fig, axs = plt.subplots(2, 2, figsize=(8, 5), dpi=90)
    picks = [(1, f1[0]), (1, f1[1]), (0, umb[0]), (2, f2[0])]
    for ax, (k, f) in zip(axs.ravel(), picks):
        i = [j for j, (kk, ff) in enumerate(zip(table.k, table.freq_hz)) if kk == k and ff == f][0]
        plot_mode(ax, table.mesh, table.shapes[i], f"k={k}, {f:.1f} Hz")
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_modes.png")
    plt.close(fig)

    print("\n(c) rotation in the bogie (axle-fixed frame), eigenfrequencies (Hz)")
    m0 = ws.axle_fixed(0.0, k_max=3, f_max=3000.0)
    freqs = np.linspace(20.0, 800.0, 1200)
    curves = {}
    for v_kmh in (0.0, 200.0, 300.0):
        m = ws.axle_fixed(v_kmh / 3.6, k_max=6, f_max=3000.0)
        om = m.omega / (2.0 * np.pi)
        print(f"  {v_kmh:.0f} km/h, Omega/2pi = {om:.2f} Hz")
        for k in (0, 1, 2):
            fb = m0.eigenfrequencies(k)
            fr = m.eigenfrequencies(k)
            base = fb[fb > 60.0][0] if k != 1 else fb[fb > 60.0][0]
            if k == 0:
                new = fr[np.argmin(abs(fr - umb[0]))]
                base = fb[np.argmin(abs(fb - umb[0]))]
                print(f"    k=0 umbrella {base:.2f} -> {new:.2f} Hz ({new / base - 1.0:+.3%})")
            else:
                lo = fr[np.argmin(abs(fr - (base - k * om)))]
                hi = fr[np.argmin(abs(fr - (base + k * om)))]
                exp = k * om
                half = 0.5 * (hi - lo)
                print(f"    k={k} {base:.1f} -> {lo:.1f} / {hi:.1f} Hz: half-split {half:.2f} Hz, "
                      f"k Omega/2pi = {exp:.2f} Hz" + (f" ({half / exp - 1.0:+.1%})" if exp > 0 else ""))
        curves[f"{v_kmh:.0f} km/h"] = ws.frf(freqs, v_kmh / 3.6, model=m)
    plot_frf(FIG / "wheelset_frf.png", freqs, curves,
             "lateral force -> lateral displacement at the contact point, wheelset in bogie")


if __name__ == "__main__":
    part_a_b()
    part_c_d()
