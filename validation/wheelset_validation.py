"""Validation of the flexible wheelset (issue 6).

(a) axisymmetric FE against closed forms: free-free Timoshenko shaft (k = 1),
    Kirchhoff annular plate clamped inside / free outside (k = 0, 1, 2);
(b) frequency error against DOFs and solve time (mesh refinement);
(c) rotation: split of k = 1, 2 modes against k Omega, k = 0 unmoved;
(d) the default wheelset beside the paper's 147 / 304 / 345 Hz: every mode classified by its
    mirror symmetry and strain-energy split, an independent stepped-beam + rigid-wheel
    check of the k = 1 pair, and the axle-diameter sensitivity of the symmetric bending.
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

from scipy import optimize  # noqa: E402

from railvti._native import core  # noqa: E402
from railvti.wheelset import Wheelset, WheelsetGeometry, analytic, rectangle_mesh, solve_harmonic  # noqa: E402
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


PAPER = {"k1": 147.0, "k0": 304.0, "k2": 345.0}   # Kaiser, the paper's wheelset (issue 6, 6d)


def strain_energy_split(ws: Wheelset, k: int, shapes) -> np.ndarray:
    """Fractions of each mode's strain energy in the axle (r < seat radius),
    the hub (seat .. hub radius) and the web + rim, from the element matrices."""
    g, mesh = ws.geometry, ws.mesh
    rc = mesh.nodes[mesh.conn[:, 4], 0]
    region = np.where(rc < g.seat_radius, 0, np.where(rc < g.hub_radius, 1, 2))
    kes = [core.wheelset_element_c(k, np.asfortranarray(mesh.nodes[c].T), g.young, g.poisson,
                                   g.density)[0] for c in mesh.conn]
    out = []
    for s in shapes:
        en = np.array([s[c].ravel() @ ke @ s[c].ravel() for c, ke in zip(mesh.conn, kes)])
        out.append([en[region == j].sum() / en.sum() for j in range(3)])
    return np.array(out)


def body_sensitivity() -> None:
    """First two flexible k = 1 modes against the axle body diameter (FE and beam)."""
    print("\n(d) k = 1 bending against the axle body diameter (free-free; beam = stepped "
          "Timoshenko axle + rigid wheels)")
    print(f"  {'body mm':>8} {'FE sym':>8} {'FE anti':>8} {'beam sym':>9} {'beam anti':>10}")
    for d in (0.16, 0.17, 0.18, 0.19):
        ws = Wheelset(body_radius=d / 2)
        h = ws.harmonic(1, 300.0)
        f = h.freq_hz[h.freq_hz > 1.0][:2]
        b = analytic.wheelset_beam_k1(ws.geometry)
        print(f"  {d * 1e3:8.0f} {f[0]:8.1f} {f[1]:8.1f} {b[0]:9.1f} {b[1]:10.1f}")

    def sym_minus_paper(d: float) -> float:
        seat = max(0.0975, d / 2 + 0.0125)
        g = WheelsetGeometry(body_radius=d / 2, seat_radius=seat, hub_radius=seat + 0.0425)
        return analytic.wheelset_beam_k1(g)[0] - PAPER["k1"]

    d147 = optimize.brentq(sym_minus_paper, 0.17, 0.30)
    print(f"  a symmetric bending mode at {PAPER['k1']:.0f} Hz needs a {d147 * 1e3:.0f} mm axle body "
          "even with rigid wheels (beam; wheel seat 25 mm larger, hub wall unchanged)")


def part_d() -> None:
    ws = Wheelset()
    t = time.perf_counter()
    table = ws.modes(k_max=2, f_max=600.0)
    print(f"\n(d) default wheelset, free-free modes up to 600 Hz ({time.perf_counter() - t:.1f} s)")
    rows = []
    for k in (0, 1, 2):
        idx = [i for i in range(len(table)) if table.k[i] == k and table.freq_hz[i] > 1.0]
        split = strain_energy_split(ws, k, [table.shapes[i] for i in idx])
        for i, e in zip(idx, split):
            rows.append((k, table.freq_hz[i], table.mirror_symmetry(i), e, i))
    print("  k   f (Hz)  mirror sym.  strain energy: axle   hub  web+rim")
    for k, f, sym, e, _ in rows:
        print(f"  {k}  {f:7.1f}  {sym:+10.2f}  {e[0]:20.2f} {e[1]:5.2f} {e[2]:8.2f}")
    beam = analytic.wheelset_beam_k1(ws.geometry)
    m_w, _, j_w = analytic.wheel_rigid_body(ws.geometry)
    print(f"  independent check, stepped Timoshenko axle + rigid wheels ({m_w:.0f} kg, "
          f"J_d {j_w:.1f} kg m^2): k = 1 {beam[0]:.1f} (sym), {beam[1]:.1f} Hz (anti)")

    def pick(k, sign, n=0):
        sel = [r for r in rows if r[0] == k and r[2] * sign > 0.5]
        return sel[n]

    k1s, k1a = pick(1, +1), pick(1, -1)
    # umbrella modes: k = 0 with most strain energy in the webs (torsion lives in the axle)
    umbrella = [r for r in rows if r[0] == 0 and r[3][2] > 0.5]
    k0s = [r for r in umbrella if r[2] > 0.5][0]
    k0a = [r for r in umbrella if r[2] < -0.5][0]
    k2 = [r for r in rows if r[0] == 2][0]
    print("\n  mode                                                paper   this    diff   compared")
    for lab, p, r, cmp in (
            ("k=1 symmetric axle bending (wheels tilt opposite)", PAPER["k1"], k1s, "no"),
            ("k=1 antisymmetric, wheels rock in phase", PAPER["k1"], k1a, "yes"),
            ("k=0 umbrella, wheels in anti-phase", PAPER["k0"], k0s, "yes"),
            ("k=0 umbrella, wheels in phase", PAPER["k0"], k0a, "yes"),
            ("first k=2", PAPER["k2"], k2, "yes")):
        print(f"  {lab:<50} {p:6.0f} {r[1]:7.1f} {r[1] / p - 1.0:+7.1%}   {cmp}")
    body_sensitivity()

    fig, axs = plt.subplots(3, 2, figsize=(9, 6.4), dpi=80)
    k1b = pick(1, +1, 1)
    for ax, r in zip(axs.ravel(), (k1s, k1a, k1b, k0s, k0a, k2)):
        sym = "sym" if r[2] > 0.5 else ("anti" if r[2] < -0.5 else "one wheel")
        plot_mode(ax, table.mesh, table.shapes[r[4]],
                  f"k={r[0]}, {r[1]:.1f} Hz, {sym}; strain energy axle {r[3][0]:.0%}, "
                  f"web+rim {r[3][2]:.0%}")
    fig.suptitle("default wheelset, free-free modes (meridian section, set A at azimuth 0)", fontsize=9)
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_modes.png")
    plt.close(fig)

    # the k = 1 pair: axle centre line and where the strain energy sits
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.8), dpi=80)
    axis = np.isclose(table.mesh.nodes[:, 0], 0.0)
    order = np.argsort(table.mesh.nodes[axis, 1])
    yax = table.mesh.nodes[axis, 1][order]
    g = ws.geometry
    for r, lab, mk, ms in ((k1s, "symmetric", "o", 8), (k1a, "antisymmetric", "s", 5)):
        s = table.shapes[r[4]]
        tilt = [s[table.mesh.node_at(g.wheel_radius, yc), 1] for yc in (g.contact_y, -g.contact_y)]
        ur = s[axis, 0][order]
        scale = 1.0 / np.abs(np.concatenate([ur, tilt])).max()
        line, = axs[0].plot(yax, ur * scale, label=f"{r[1]:.1f} Hz {lab}: axle U_r")
        axs[0].plot([g.contact_y, -g.contact_y], np.array(tilt) * scale, mk, ms=ms, color=line.get_color(),
                    label=f"{r[1]:.1f} Hz: rim U_y at the contact points (wheel tilt)")
    for yw in (g.contact_y, -g.contact_y):
        axs[0].axvline(yw, color="0.6", lw=0.5, ls="--")
    axs[0].set_xlabel("y, m")
    axs[0].set_ylabel("normalised amplitude")
    axs[0].legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    axs[0].set_title("k = 1 pair: axle deflection and wheel tilt", fontsize=8)
    axs[0].grid(True, lw=0.3)
    labels = [f"k={r[0]}\n{r[1]:.0f} Hz" for r in (k1s, k1a, k1b, k0s, k0a, k2)]
    e = np.array([r[3] for r in (k1s, k1a, k1b, k0s, k0a, k2)])
    bottom = np.zeros(len(labels))
    for j, name in enumerate(("axle", "hub", "web + rim")):
        axs[1].bar(labels, e[:, j], bottom=bottom, label=name)
        bottom += e[:, j]
    axs[1].set_ylabel("strain energy fraction")
    axs[1].set_title("where the strain energy sits", fontsize=8)
    axs[1].legend(fontsize=7)
    axs[1].tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_modes_k1.png")
    plt.close(fig)


def part_c() -> None:
    ws = Wheelset()
    table = ws.modes(k_max=0, f_max=600.0)
    umb = [f for i, f in enumerate(table.freq_hz) if f > 1.0 and table.mirror_symmetry(i) > 0.5]
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
    part_d()
    part_c()
