"""UIC60 section properties against EN 13674-1, the mesh, and the rail's free-wave dispersion
from the reduced basis against direct solves of the full section FE.

    .venv/bin/python validation/track_section.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402

from railvti.track import RingTrack, rail_section  # noqa: E402

FIG = Path(__file__).resolve().parent / "figures"


def main() -> None:
    FIG.mkdir(exist_ok=True)
    s = rail_section()
    pub = s.published
    print(f"UIC60 (60E1) mesh: {s.n_elements} six-node triangles, {s.n_nodes} nodes")
    print(f"{'property':>10s} {'mesh':>10s} {'EN 13674-1':>11s} {'diff %':>7s}")
    for key, scale, unit in (("area", 1e4, "cm^2"), ("iy", 1e8, "cm^4"), ("iz", 1e8, "cm^4")):
        v, p = getattr(s, key) * scale, pub[key] * scale
        print(f"{key:>10s} {v:10.2f} {p:11.2f} {100 * (v / p - 1):7.2f}  {unit}")
    m = s.mass_per_length()
    print(f"{'mass':>10s} {m:10.2f} {pub['mass']:11.2f} {100 * (m / pub['mass'] - 1):7.2f}  kg/m")
    print(f"{'torsion':>10s} {s.torsion * 1e8:10.1f} {'-':>11s} {'':7s}  cm^4 (Saint-Venant warping solve)")
    print(
        f"{'centroid':>10s} {s.centroid[1] * 1e3:10.2f} {80.9:11.2f} "
        f"{100 * (s.centroid[1] * 1e3 / 80.9 - 1):7.2f}  mm above the foot"
    )

    # Dispersion: reduced basis vs full section FE
    tr = RingTrack(16)
    k0, k1, k2, mm = tr._fe
    w, k0r, k1r, k2r, _ = tr._rom
    kap = np.linspace(0.0, tr.params["kappa_max"], 41)
    red = np.array(
        [np.sqrt(np.clip(np.linalg.eigvalsh(k0r + q * k1r + q * q * k2r)[:14], 0, None)) for q in kap]
    ) / (2 * np.pi)
    chk = kap[1::4]
    full = np.array(
        [
            np.sqrt(
                np.clip(
                    sla.eigh(k0 + q * k1 + q * q * k2, mm, eigvals_only=True, subset_by_index=[0, 13]),
                    0,
                    None,
                )
            )
            for q in chk
        ]
    ) / (2 * np.pi)
    redc = red[1::4]
    sel = full <= 6000.0
    err = np.abs(redc[sel] - full[sel]) / np.maximum(full[sel], 1.0)
    print(
        f"\nreduced basis: {w.shape[1]} vectors for {w.shape[0]} section DOFs; wave frequencies "
        f"<= 6 kHz at {chk.size} wave numbers between the samples: max rel. error {err.max():.2e}"
    )
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
    tri = s.elements[:, :3]
    axs[0].triplot(s.nodes[:, 0] * 1e3, s.nodes[:, 1] * 1e3, tri, lw=0.5)
    axs[0].plot(*(s.outline.T * 1e3), "k", lw=0.8)
    axs[0].plot(*(s.nodes[s.crown_node] * 1e3), "ro")
    axs[0].set_aspect("equal")
    axs[0].set_title(f"60E1 mesh: {s.n_elements} T6")
    axs[0].set_xlabel("eta, mm")
    axs[0].set_ylabel("zeta, mm")
    axs[1].plot(kap, red, "b-", lw=0.8)
    axs[1].plot(chk, np.where(full <= 7000, full, np.nan), "rx", ms=4)
    axs[1].set_ylim(0, 6000)
    axs[1].set_xlabel("wave number kappa, rad/m")
    axs[1].set_ylabel("frequency, Hz")
    axs[1].set_title("free rail waves: reduced basis (lines), full FE (x)")
    axs[1].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(FIG / "track_section.png", dpi=72)
    plt.close(fig)


if __name__ == "__main__":
    main()
