"""Ring-track receptances: (a) low-frequency vertical receptance against a Timoshenko beam on
discrete supports, (b) pinned-pinned frequencies, (c) convergence with the number of sleepers
next to its cost. Prints tables, writes validation/figures/track_*.png.

    .venv/bin/python validation/track_receptance.py
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti.track import DEFAULTS, RingTrack  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"
FREQ = np.linspace(0.0, 3000.0, 3001)
PAPER = {"vertical": 1100.0, "lateral_1": 510.0, "lateral_2": 1920.0}


def timoshenko_discrete(
    f: np.ndarray, n_sl: int, area: float, iy: float, x0: float, shear_coef: float = 0.4, kmax: float = 400.0
) -> np.ndarray:
    """Vertical receptance of a Timoshenko-beam ring on point supports at the sleepers.

    Support per rail seat: pad (k_p + i w c_p) in series with half a sleeper on half the
    ballast. Green's function of the free ring by Fourier series, supports by an n_sl x n_sl
    solve (the classical discretely-supported beam, e.g. Knothe & Grassie 1993).
    """
    p = DEFAULTS
    a = p["sleeper_spacing"]
    L = n_sl * a
    eta = p["rail_loss_factor"]
    E = p["rail_young"] * (1 + 1j * eta)
    G = E / (2 * (1 + p["rail_poisson"]))
    rho = p["rail_density"]
    k = np.arange(int(kmax * L / (2 * math.pi)) + 1)
    kap = 2 * math.pi * k / L
    wts = np.where(k == 0, 1.0 / L, 2.0 / L)
    xs = np.arange(n_sl) * a
    out = np.empty(f.size, complex)
    for i, fi in enumerate(f):
        w = 2 * math.pi * max(fi, 1e-3)
        ka = shear_coef * G * area
        a11 = ka * kap**2 - rho * area * w * w
        a22 = E * iy * kap**2 + ka - rho * iy * w * w
        g = a22 / (a11 * a22 - (ka * kap) ** 2)  # w / F of each Fourier term
        gx = lambda d: np.sum(wts * g * np.cos(np.outer(d, kap)), axis=1)  # noqa: E731
        gss = gx(xs - xs[0])
        gmat = gss[np.abs(np.subtract.outer(np.arange(n_sl), np.arange(n_sl)))]
        kp = p["pad_stiffness_vertical"] + 1j * w * p["pad_damping_vertical"]
        kb = 0.5 * (p["ballast_stiffness_vertical"] + 1j * w * p["ballast_damping_vertical"])
        ms = 0.5 * p["sleeper_mass"]
        ksup = kp * (kb - ms * w * w) / (kp + kb - ms * w * w)
        g0 = gx(xs - x0)
        us = np.linalg.solve(np.eye(n_sl) + gmat * ksup, g0)
        out[i] = gx(np.array([0.0]))[0] - ksup * np.dot(g0, us)
    return out


def pinned_pinned(tr: RingTrack, f: np.ndarray) -> dict[str, float]:
    """Pinned-pinned frequencies: where the mid-span receptance most exceeds the one above a
    sleeper (the mid-span peak / sleeper dip pair), in the bands of the acceptance list."""
    out = {}
    for key, d, band in (
        ("vertical", "vertical", (800, 1400)),
        ("lateral_1", "lateral", (350, 800)),
        ("lateral_2", "lateral", (1500, 2500)),
    ):
        sel = (f >= band[0]) & (f <= band[1])
        hm = np.abs(tr.receptance(f[sel], d, "midspan"))
        hs = np.abs(tr.receptance(f[sel], d, "sleeper"))
        out[key] = float(f[sel][np.argmax(hm / hs)])
    return out


def main() -> None:
    FIG.mkdir(exist_ok=True)
    sizes = [16, 32, 64, 128, 256]
    res: dict[int, dict[str, np.ndarray]] = {}
    cost: dict[int, float] = {}
    tracks: dict[int, RingTrack] = {}
    for n in sizes:
        t0 = time.perf_counter()
        tr = RingTrack(n)
        cost[n] = time.perf_counter() - t0
        tracks[n] = tr
        res[n] = {
            f"{d}_{p}": tr.receptance(FREQ, d, p)
            for d in ("vertical", "lateral")
            for p in ("midspan", "sleeper")
        }
        print(f"n_sl={n:4d}: built in {cost[n]:6.2f} s, {tr.n_modes} modes")

    # Figures like the paper's Figs 6 and 7
    for d in ("vertical", "lateral"):
        fig, axs = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
        for ax, p in zip(axs, ("midspan", "sleeper")):
            for n in sizes[:-1]:
                ax.semilogy(FREQ, np.abs(res[n][f"{d}_{p}"]), lw=0.9, label=f"$n_{{sl}}$={n}")
            ax.set_title(f"{d}, {p}")
            ax.set_xlabel("frequency, Hz")
            ax.grid(True, which="both", alpha=0.3)
        axs[0].set_ylabel("|receptance|, m/N")
        axs[0].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(FIG / f"track_receptance_{d}.png", dpi=72)
        plt.close(fig)

    # (b) pinned-pinned
    print("\n(b) pinned-pinned frequencies, Hz (n_sl = 128)")
    pp = pinned_pinned(tracks[128], np.linspace(300, 2600, 2301))
    print(f"{'':12s} {'railvti':>8s} {'paper':>7s} {'accepted band':>15s}")
    bands = {"vertical": "900-1250", "lateral_1": "400-650", "lateral_2": "1700-2200"}
    for k, v in pp.items():
        print(f"{k:12s} {v:8.0f} {PAPER[k]:7.0f} {bands[k]:>15s}")

    # (c) convergence with n_sl
    print(
        "\n(c) largest relative difference |H_n - H_2n| / |H_2n| over 100-3000 Hz, and its 90th "
        "percentile (narrow peaks excluded by the percentile); build time of the model for 2n"
    )
    band = (FREQ >= 100) & (FREQ <= 3000)
    rows = []
    print(f"{'n -> 2n':>10s} {'quantity':>18s} {'max':>7s} {'p90':>7s} {'cost 2n, s':>10s}")
    for n in sizes[:-1]:
        for key in ("vertical_midspan", "vertical_sleeper", "lateral_midspan", "lateral_sleeper"):
            a, b = res[n][key][band], res[2 * n][key][band]
            rel = np.abs(a - b) / np.abs(b)
            rows.append((n, key, rel.max(), np.percentile(rel, 90), cost[2 * n]))
            print(
                f"{n:4d}->{2 * n:<4d} {key:>18s} {rel.max():7.3f} {np.percentile(rel, 90):7.3f} "
                f"{cost[2 * n]:10.2f}"
            )
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for key, mk in (("vertical_midspan", "o-"), ("lateral_midspan", "s-")):
        pts = [(r[4], r[3]) for r in rows if r[1] == key]
        ax.loglog([c for c, _ in pts], [e for _, e in pts], mk, label=key)
        for (c, e), n in zip(pts, sizes[:-1]):
            ax.annotate(f"{n}->{2 * n}", (c, e), fontsize=7)
    ax.set_xlabel("cost of the 2n model, s")
    ax.set_ylabel("90th pct rel. difference n vs 2n")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "track_convergence_nsl.png", dpi=72)
    plt.close(fig)

    # (a) Timoshenko beam on discrete supports
    print("\n(a) vertical receptance vs Timoshenko beam on discrete supports (n_sl = 64)")
    sec = tracks[64].section
    fa = np.linspace(10.0, 1500.0, 150)
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    print(f"{'position':>9s} {'max rel diff 10-500 Hz':>24s} {'500-800 Hz':>11s} {'p-p beam Hz':>12s}")
    for p, x0 in (("midspan", 0.3), ("sleeper", 0.0)):
        hb = timoshenko_discrete(fa, 64, sec.area, sec.iy, x0)
        hr = tracks[64].receptance(fa, "vertical", p)
        rel = np.abs(np.abs(hr) - np.abs(hb)) / np.abs(hb)
        lo, mid = fa <= 500, (fa > 500) & (fa <= 800)
        ppb = fa[(fa > 800)][np.argmax(np.abs(hb[fa > 800]))] if p == "midspan" else float("nan")
        print(f"{p:>9s} {rel[lo].max():24.3f} {rel[mid].max():11.3f} {ppb:12.0f}")
        ax.semilogy(fa, np.abs(hr), label=f"2.5-D FE, {p}")
        ax.semilogy(fa, np.abs(hb), "--", label=f"Timoshenko, {p}")
    ax.set_xlabel("frequency, Hz")
    ax.set_ylabel("|vertical receptance|, m/N")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "track_timoshenko.png", dpi=72)
    plt.close(fig)


if __name__ == "__main__":
    main()
