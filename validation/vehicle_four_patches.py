"""Pressure and friction power of the four variants side by side (issue 30 item 8): centred
running at 200 km/h, the BEM at 0.75 mm, the leading wheelset's left wheel.

    .venv/bin/python validation/vehicle_four_patches.py

Reads the runs of validation/vehicle_fr_vs_rr.py (``--model FR``, ``--model RF`` and
``--model FF``, each against RR; they cache their runs in /tmp/vehicle_<model>_vs_rr.pkl: run
them first) and draws validation/figures/vehicle_four_patches.png: the pressure along the
patch's lateral centre line and the friction power per unit width across the patch, RR, FR,
RF, FF on one chart each, with the flange- and field-side maxima of the friction power
density printed beside the paper's (Kaiser: RR 13 / 7, FF 4 / 5 W/mm^2).
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from vehicle_fr_vs_rr import _two_maxima  # noqa: E402  (the sibling script's analysis)

FIG = HERE / "figures"
VARIANTS = ("RR", "FR", "RF", "FF")
STYLE = {"RR": ("k", "--"), "FR": ("C0", "-"), "RF": ("C2", "-."), "FF": ("C3", "-")}


def load() -> dict:
    """The left wheel's BEM patch of the leading wheelset per variant."""
    out = {}
    for flex in ("FR", "RF", "FF"):
        cache = Path(f"/tmp/vehicle_{flex.lower()}_vs_rr.pkl")
        if not cache.exists():
            raise SystemExit(f"{cache} is missing: run validation/vehicle_fr_vs_rr.py --model {flex}")
        _, bm = pickle.loads(cache.read_bytes())
        out.setdefault("RR", bm["RR"]["patches"][0])
        out[flex] = bm[flex]["patches"][0]
    return out


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    patches = load()
    fig, ax = plt.subplots(1, 2, figsize=(12.0, 4.6))
    print(
        "| variant | friction power, W | flange-side max, W/mm^2 (y, mm) | field-side max, W/mm^2 "
        "(y, mm) | pressure max, MPa |\n|---|---|---|---|---|"
    )
    for m in VARIANTS:
        p = patches[m]
        col, ls = STYLE[m]
        i0 = int(np.argmin(np.abs(p.x[:, 0])))
        y = p.y[0] * 1e3
        dx = p.x[1, 0] - p.x[0, 0]
        ax[0].plot(y, p.pressure[i0] / 1e6, ls, color=col, label=m)
        ax[1].plot(
            y, p.power_density.sum(axis=0) * dx / 1e3, ls, color=col, label=f"{m} (total {p.power:.1f} W)"
        )
        (qf, yf), (qo, yo) = _two_maxima(p, 0, "power_density")
        print(
            f"| {m} | {p.power:.2f} | {qf / 1e6:.2f} ({yf * 1e3:+.1f}) | {qo / 1e6:.2f} "
            f"({yo * 1e3:+.1f}) | {p.pressure.max() / 1e6:.0f} |"
        )
    ax[0].set_title("pressure along the patch's lateral centre line (x = 0)", fontsize=10)
    ax[0].set_ylabel("pressure, MPa")
    ax[1].set_title("friction power per unit width (density integrated along x)", fontsize=10)
    ax[1].set_ylabel("friction power, W/mm")
    for a in ax:
        a.set_xlabel("y (track lateral, + left), mm; flange side -y")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
        a.set_xlim(-14, 10)
    fig.suptitle(
        "The four variants, centred running 200 km/h, BEM 0.75 mm: leading wheelset, left wheel", fontsize=11
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    path = FIG / "vehicle_four_patches.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
