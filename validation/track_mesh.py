"""(d) Effect of the number of cross-section elements: section properties, pinned-pinned
frequencies, receptance differences against the finest mesh, and the build time.

    .venv/bin/python validation/track_mesh.py
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railvti.track import RingTrack, rail_section  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"
#: (outline arc step, m; largest triangle, m^2)
MESHES = [(16e-3, 8e-4), (12e-3, 4e-4), (8e-3, 2e-4), (6e-3, 1e-4), (5e-3, 6e-5)]
N_SL = 64


def pinned(tr: RingTrack) -> tuple[float, float, float]:
    out = []
    for d, band in (("vertical", (800, 1400)), ("lateral", (350, 800)), ("lateral", (1500, 2500))):
        f = np.linspace(*band, 601)
        r = np.abs(tr.receptance(f, d, "midspan")) / np.abs(tr.receptance(f, d, "sleeper"))
        out.append(float(f[np.argmax(r)]))
    return tuple(out)


def main() -> None:
    FIG.mkdir(exist_ok=True)
    freq = np.linspace(100.0, 3000.0, 1451)
    rows = []
    for step, area in MESHES:
        sec = rail_section(area, arc_step=step)
        t0 = time.perf_counter()
        tr = RingTrack(N_SL, section=sec, mesh_max_area=area, arc_step=step)
        cost = time.perf_counter() - t0
        hv = tr.receptance(freq, "vertical", "midspan")
        hl = tr.receptance(freq, "lateral", "midspan")
        rows.append((sec.n_elements, 3 * sec.n_nodes, sec.errors(), sec.torsion, pinned(tr), hv, hl, cost))
        print(f"mesh {sec.n_elements:4d} T6 elements done in {cost:.1f} s")
    ref_v, ref_l = rows[-1][5], rows[-1][6]
    print(
        f"\n{'T6':>5s} {'DOF':>5s} {'dA%':>6s} {'dIy%':>6s} {'dIz%':>6s} {'J cm4':>7s} "
        f"{'ppV':>6s} {'ppL1':>6s} {'ppL2':>6s} {'p90 dHv':>8s} {'p90 dHl':>8s} {'build s':>8s}"
    )
    for ne, nd, err, j, pp, hv, hl, cost in rows:
        dv = np.percentile(np.abs(hv - ref_v) / np.abs(ref_v), 90)
        dl = np.percentile(np.abs(hl - ref_l) / np.abs(ref_l), 90)
        print(
            f"{ne:5d} {nd:5d} {100 * err['area']:6.2f} {100 * err['iy']:6.2f} {100 * err['iz']:6.2f} "
            f"{j * 1e8:7.1f} {pp[0]:6.0f} {pp[1]:6.0f} {pp[2]:6.0f} {dv:8.3f} {dl:8.3f} {cost:8.1f}"
        )
    fig, axs = plt.subplots(1, 2, figsize=(10, 3.6))
    for ne, _nd, _err, _j, _pp, hv, hl, _cost in rows:
        axs[0].semilogy(freq, np.abs(hv), lw=0.9, label=f"{ne} T6")
        axs[1].semilogy(freq, np.abs(hl), lw=0.9, label=f"{ne} T6")
    for ax, t in zip(axs, ("vertical, midspan", f"lateral, midspan (n_sl={N_SL})")):
        ax.set_title(t)
        ax.set_xlabel("frequency, Hz")
        ax.grid(True, which="both", alpha=0.3)
    axs[0].set_ylabel("|receptance|, m/N")
    axs[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIG / "track_mesh.png", dpi=72)
    plt.close(fig)


if __name__ == "__main__":
    main()
