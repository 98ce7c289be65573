"""Validation of the flexible wheelset (issue 6).

(a) axisymmetric FE against closed forms: free-free Timoshenko shaft (k = 1),
    Kirchhoff annular plate clamped inside / free outside (k = 0, 1, 2);
(b) frequency error against DOFs and solve time (mesh refinement);
(c) rotation: split of k = 1, 2 modes against k Omega, k = 0 unmoved;
(d) the default wheelset beside the paper's 147 / 304 / 345 Hz: every mode classified by its
    mirror symmetry and strain-energy split, an independent stepped-beam + rigid-wheel
    check of the k = 1 pair, and the axle-diameter sensitivity of the symmetric bending;
    mass properties; every mode named by its shape beside the paper and beside a published
    high-speed wheelset (Wu et al. 2020);
(e) the paper's Fig. 3 set-up: lateral force -> lateral displacement at the contact point,
    wheelset in its bogie, standstill: every FRF peak with its magnitude and the mode behind it.
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

from scipy import optimize, signal  # noqa: E402

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
    print(
        f"{'elements':>9} {'DOFs':>6} {'time s':>7} "
        + " ".join(f"{'mode' + str(i + 1):>18}" for i in range(3))
    )
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
            print(
                f"k={k} {nr:>3}x{nt} DOFs {n:>5} {t:6.3f} s  "
                + "  ".join(f"{fi:8.2f} ({e:+.2%})" for fi, e in zip(f, err))
                + f"   theory {ref_p[0]:.2f}, {ref_p[1]:.2f}"
            )
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


PAPER = {"k1": 147.0, "k0": 304.0, "k2": 345.0}  # Kaiser, the paper's wheelset (issue 6, 6d)
# Wu, Cai, Jin, Xiao et al., Key factors of the initiation and development of polygonal wear in
# the wheels of a high-speed train, Appl. Sci. 10 (2020) 5880, doi:10.3390/app10175880, Fig. 8:
# FE bending modes of a Chinese high-speed (EMU) wheelset, 0-800 Hz.
WU2020_BENDING = (87.0, 143.0, 284.0, 576.0)


def shape_name(
    k: int, f: float, sym: float, e: np.ndarray, theta_frac: float, n_bend: int, fam: str = "AB"
) -> str:
    """Name of a mode from its harmonic, mirror symmetry, strain-energy split
    (axle, hub, web + rim) and, for k = 0, the share of u_theta in the shape."""
    s = "sym" if sym > 0.5 else ("anti" if sym < -0.5 else "one wheel")
    if k == 0:
        if f < 40.0:
            return "rigid lateral translation on the primary suspension"
        if theta_frac > 0.9:
            return "axle torsion (wheels twist against each other)"
        return (
            "umbrella, wheels in anti-phase (axle centre at rest)"
            if s == "sym"
            else "umbrella, wheels in phase (axle moves axially against them)"
        )
    if k == 1:
        if f < 60.0:
            if fam == "B":
                what = "longitudinal translation" if s == "sym" else "yaw"
                return f"rigid {what} on the primary suspension"
            return "rigid " + ("bounce" if s == "sym" else "roll") + " on the primary suspension"
        what = ["1st", "2nd", "3rd", "4th", "5th"][min(n_bend, 4)]
        if s == "sym":
            return f"{what} bending, symmetric: axle bows, wheels tilt opposite"
        return f"{what} bending, antisymmetric: S-shaped axle, wheels rock in phase"
    return f"wheel mode, {k} nodal diameters ({s})"


def named_modes(ws: Wheelset, f_max: float, support: str, k_max: int = 3) -> list[dict]:
    """Every mode up to f_max with its shape name, symmetry and strain-energy split."""
    table = ws.modes(k_max=k_max, f_max=f_max, support=support)
    out = []
    for k in range(k_max + 1):
        for fam in sorted({table.family[i] for i in range(len(table)) if table.k[i] == k}):
            idx = [
                i
                for i in range(len(table))
                if table.k[i] == k and table.family[i] == fam and table.freq_hz[i] > 1.0
            ]
            split = strain_energy_split(ws, k, [table.shapes[i] for i in idx])
            n_bend = 0
            for i, e in zip(idx, split):
                s = table.shapes[i]
                th = float(np.sum(s[:, 2] ** 2) / np.sum(s**2))
                sym = table.mirror_symmetry(i) if k < 2 else 0.0
                name = shape_name(k, table.freq_hz[i], sym, e, th, n_bend, fam)
                if "bending" in name:
                    n_bend += 1
                twin = any(r["k"] == k and abs(r["f"] - table.freq_hz[i]) < 1e-6 * r["f"] for r in out)
                if k >= 2 and twin:
                    continue  # the two wheels' identical k >= 2 modes: list once
                out.append(dict(k=k, fam=fam, f=float(table.freq_hz[i]), sym=sym, e=e, name=name, i=i))
    return out


def strain_energy_split(ws: Wheelset, k: int, shapes) -> np.ndarray:
    """Fractions of each mode's strain energy in the axle (r < seat radius),
    the hub (seat .. hub radius) and the web + rim, from the element matrices."""
    g, mesh = ws.geometry, ws.mesh
    rc = mesh.nodes[mesh.conn[:, 4], 0]
    region = np.where(rc < g.seat_radius, 0, np.where(rc < g.hub_radius, 1, 2))
    kes = [
        core.wheelset_element_c(k, np.asfortranarray(mesh.nodes[c].T), g.young, g.poisson, g.density)[0]
        for c in mesh.conn
    ]
    out = []
    for s in shapes:
        en = np.array([s[c].ravel() @ ke @ s[c].ravel() for c, ke in zip(mesh.conn, kes)])
        out.append([en[region == j].sum() / en.sum() for j in range(3)])
    return np.array(out)


def body_sensitivity() -> None:
    """First two flexible k = 1 modes against the axle body diameter (FE and beam)."""
    print(
        "\n(d) k = 1 bending against the axle body diameter (free-free; beam = stepped "
        "Timoshenko axle + rigid wheels)"
    )
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
    print(
        f"  a symmetric bending mode at {PAPER['k1']:.0f} Hz needs a {d147 * 1e3:.0f} mm axle body "
        "even with rigid wheels (beam; wheel seat 25 mm larger, hub wall unchanged)"
    )


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
    mp = analytic.wheelset_mass_properties(ws.geometry)
    print(
        f"  mass properties (no brake discs, no axleboxes): wheel {mp['wheel_mass']:.0f} kg "
        f"(diametral inertia {mp['wheel_diametral_inertia']:.1f} kg m^2), axle {mp['axle_mass']:.0f} kg, "
        f"wheelset {mp['mass']:.0f} kg, spin inertia {mp['spin_inertia']:.1f} kg m^2, "
        f"roll/yaw inertia {mp['roll_inertia']:.0f} kg m^2"
    )
    m_w, _, j_w = analytic.wheel_rigid_body(ws.geometry)
    print(
        f"  independent check, stepped Timoshenko axle + rigid wheels ({m_w:.0f} kg, "
        f"J_d {j_w:.1f} kg m^2): k = 1 {beam[0]:.1f} (sym), {beam[1]:.1f} Hz (anti)"
    )

    def pick(k, sign, n=0):
        sel = [r for r in rows if r[0] == k and r[2] * sign > 0.5]
        return sel[n]

    k1s, k1a = pick(1, +1), pick(1, -1)
    # umbrella modes: k = 0 with most strain energy in the webs (torsion lives in the axle)
    umbrella = [r for r in rows if r[0] == 0 and r[3][2] > 0.5]
    k0s = [r for r in umbrella if r[2] > 0.5][0]
    k0a = [r for r in umbrella if r[2] < -0.5][0]
    k2 = [r for r in rows if r[0] == 2][0]
    by_shape_table(ws)
    body_sensitivity()

    fig, axs = plt.subplots(3, 2, figsize=(9, 6.4), dpi=80)
    k1b = pick(1, +1, 1)
    for ax, r in zip(axs.ravel(), (k1s, k1a, k1b, k0s, k0a, k2)):
        sym = "sym" if r[2] > 0.5 else ("anti" if r[2] < -0.5 else "one wheel")
        plot_mode(
            ax,
            table.mesh,
            table.shapes[r[4]],
            f"k={r[0]}, {r[1]:.1f} Hz, {sym}; strain energy axle {r[3][0]:.0%}, web+rim {r[3][2]:.0%}",
        )
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
        (line,) = axs[0].plot(yax, ur * scale, label=f"{r[1]:.1f} Hz {lab}: axle U_r")
        axs[0].plot(
            [g.contact_y, -g.contact_y],
            np.array(tilt) * scale,
            mk,
            ms=ms,
            color=line.get_color(),
            label=f"{r[1]:.1f} Hz: rim U_y at the contact points (wheel tilt)",
        )
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


def by_shape_table(ws: Wheelset) -> None:
    """Every mode to 600 Hz named by its shape, free-free and in the bogie, beside the
    paper's three values and the published high-speed wheelset bending modes."""
    free = named_modes(ws, 600.0, "free", k_max=2)
    bogie = named_modes(ws, 600.0, "suspension", k_max=2)
    paper = {
        "1st bending, sym": ("147 (first k=1)", PAPER["k1"]),
        "2nd bending, anti": ("147 (if it is this shape)", PAPER["k1"]),
        "umbrella, wheels in anti": ("304 (first umbrella)", PAPER["k0"]),
        "umbrella, wheels in phase": ("304", PAPER["k0"]),
        "wheel mode, 2": ("345 (first k=2)", PAPER["k2"]),
    }
    print(
        "\n  by shape: free-free | in the bogie (A vertical / B longitudinal plane) | Wu et al. 2020 | paper"
    )
    for r in free:
        bo = [b for b in bogie if b["k"] == r["k"] and b["name"] == r["name"]]
        bs = " / ".join(f"{b['f']:.1f}" for b in bo) if bo else "-"
        wu = "-"
        if "bending" in r["name"]:
            n = int(r["name"][0]) - 1
            wu = f"{WU2020_BENDING[n]:.0f} ({r['f'] / WU2020_BENDING[n] - 1.0:+.1%})" if n < 4 else "-"
        pp = next(((lab, v) for key, (lab, v) in paper.items() if r["name"].startswith(key)), None)
        ps = f"{pp[0]} ({r['f'] / pp[1] - 1.0:+.1%})" if pp else "-"
        print(f"  k={r['k']} {r['name']:<68} {r['f']:7.1f} | {bs:>13} | {wu:>14} | {ps}")
    rigid = [b for b in bogie if "rigid" in b["name"]]
    for b in rigid:
        print(f"  k={b['k']} {b['name']:<68} {'-':>7} | {b['f']:13.1f} ({b['fam']})")


def part_e() -> None:
    """The paper's Fig. 3 set-up at standstill: every peak of the lateral point receptance
    at the contact point, with the mode behind it (largest modal peak contribution)."""
    ws = Wheelset()
    model = ws.axle_fixed(0.0, k_max=6, f_max=3000.0)
    freqs = np.arange(5.0, 1000.0, 0.05)
    h = ws.frf(freqs, 0.0, model=model)
    a = np.abs(h)
    names = {
        (r["k"], r["fam"], round(r["f"], 1)): r["name"]
        for r in named_modes(ws, 1000.0, "suspension", k_max=3)
    }
    c = model.contact[0, 0]
    w = 2.0 * np.pi * model.freq_hz
    contrib = np.where(w > 0, c**2 / (2.0 * 0.005 * np.maximum(w, 1e-9) ** 2), 0.0)
    pk, props = signal.find_peaks(a, prominence=0.0)
    print(
        "\n(e) lateral force -> lateral displacement at the right contact point, wheelset in "
        "its bogie, standstill (Fig. 3 set-up)"
    )
    print("  peak Hz    |H| m/N     rel. to 87 Hz   mode behind it")
    rows = []
    for p in pk:
        if a[p] < 1e-10 or props["prominences"][list(pk).index(p)] < 0.3 * a[p]:
            continue
        near = np.abs(model.freq_hz - freqs[p]) < 0.02 * freqs[p] + 0.5
        j = int(np.argmax(np.where(near, contrib, -1.0)))
        key = (
            int(model.k[j]),
            "A" if model.k[j] == 1 else ("0" if model.k[j] == 0 else "AB"),
            round(float(model.freq_hz[j]), 1),
        )
        name = names.get(key, f"k={model.k[j]}")
        rows.append((freqs[p], a[p], int(model.k[j]), name))
    ref = [r for r in rows if abs(r[0] - 87.0) < 5.0]
    for f, m, k, name in rows:
        rel = f"{m / ref[0][1]:10.2f}" if ref else "-"
        print(f"  {f:8.2f}  {m:10.3e}  {rel:>12}      k={k} {name}")
    fig, ax = plt.subplots(figsize=(7.5, 3.8), dpi=85)
    ax.semilogy(freqs, a, lw=0.9)
    for f, m, k, _name in rows:
        if f > 60.0:
            ax.annotate(f"{f:.0f} Hz k={k}", (f, m), textcoords="offset points", xytext=(2, 4), fontsize=6)
    ax.axvline(PAPER["k1"], color="C3", lw=0.6, ls="--", label="paper: first k = 1 (147 Hz)")
    ax.set_xlabel("frequency, Hz")
    ax.set_ylabel("|receptance|, m/N")
    ax.set_title(
        "lateral force -> lateral displacement at the contact point, wheelset in bogie, standstill",
        fontsize=8,
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIG / "wheelset_frf_peaks.png")
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
                print(
                    f"    k={k} {base:.1f} -> {lo:.1f} / {hi:.1f} Hz: half-split {half:.2f} Hz, "
                    f"k Omega/2pi = {exp:.2f} Hz" + (f" ({half / exp - 1.0:+.1%})" if exp > 0 else "")
                )
        curves[f"{v_kmh:.0f} km/h"] = ws.frf(freqs, v_kmh / 3.6, model=m)
    plot_frf(
        FIG / "wheelset_frf.png",
        freqs,
        curves,
        "lateral force -> lateral displacement at the contact point, wheelset in bogie",
    )


if __name__ == "__main__":
    part_a_b()
    part_d()
    part_e()
    part_c()
