"""Contact geometry and pressure over a flange-hunting cycle, RR against FF at 420 km/h
(issue 15's study, the paper's Fig 17).

Hunting from 6 mm at 420 km/h, Hertz + FASTSIM on the strip geometry, 3 s (as
``vehicle_four_variants.py``: FF with the ring's residual off); the last second (the limit
cycle) of the leading wheelset: against its lateral displacement y (+ left), per wheel, the
contact angle and the Hertz peak pressure p0 = 1.5 N / (pi a b) of the wheel's most loaded
patch, and the tread and flange normal forces.

    .venv/bin/python validation/vehicle_four_contact_cycle.py [--speed 420] [--replot]

Writes validation/figures/vehicle_four_contact_cycle.png; the runs are kept in
/tmp/vehicle_four_contact_cycle.pkl for --replot.
"""

from __future__ import annotations

import argparse
import logging
import pickle
import time
from pathlib import Path

import numpy as np

from railvti import scenarios

FIG = Path(__file__).resolve().parent / "figures"
CACHE = Path("/tmp/vehicle_four_contact_cycle.pkl")
VARIANTS = ("RR", "FF")
SIDES = ("left", "right")


def run(model: str, kmh: float) -> dict:
    """The last second of the leading wheelset: y and the wheel outputs (nt, 2 wheels)."""
    kw = {"ring_residual": False} if model in ("RF", "FF") else {}
    t0 = time.perf_counter()
    r = scenarios.hunting(
        kmh,
        variant=model,
        contact="hertz-fastsim",
        duration=3.0,
        y0=0.006,
        progress=False,
        geometry="strip",
        **kw,
    )
    k = r.t >= r.t[-1] - 1.0
    out = {"y": r.y_ws1[k], "wall": time.perf_counter() - t0, "amplitude": scenarios.amplitude(r)}
    for name in ("N_tread", "N_flange", "contact_angle", "a", "b", "y_cp"):
        out[name] = r.wheel_output(name)[k][:, :, 0]  # leading wheelset
    n = np.maximum(out["N_tread"], out["N_flange"])
    ab = out["a"] * out["b"]
    out["p0"] = np.where(ab > 0, 1.5 * n / (np.pi * np.where(ab > 0, ab, 1.0)), 0.0)
    return out


def plot(res: dict, kmh: float) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 2, figsize=(11.0, 9.0), sharex=True)
    for m, (col, ls) in zip(VARIANTS, (("C0", "--"), ("C3", "-"))):
        d = res[m]
        y = d["y"] * 1e3
        for w in (0, 1):
            ax[0, w].plot(
                y,
                np.degrees(d["contact_angle"][:, w]),
                ls,
                color=col,
                lw=1,
                label=f"{m} (amplitude {d['amplitude'] * 1e3:.2f} mm)",
            )
            ax[1, w].plot(y, d["p0"][:, w] / 1e6, ls, color=col, lw=1, label=m)
            ax[2, w].plot(y, d["N_flange"][:, w] / 1e3, ls, color=col, lw=1, label=f"{m}, flange")
            ax[2, w].plot(y, d["N_tread"][:, w] / 1e3, ":", color=col, lw=1, label=f"{m}, tread")
    for w in (0, 1):
        ax[0, w].set_title(f"{SIDES[w]} wheel: contact angle of the most loaded patch", fontsize=9)
        ax[1, w].set_title(f"{SIDES[w]} wheel: Hertz peak pressure of that patch", fontsize=9)
        ax[2, w].set_title(f"{SIDES[w]} wheel: normal forces", fontsize=9)
        ax[0, w].set_ylabel("contact angle, deg")
        ax[1, w].set_ylabel("p0 = 1.5 N / (pi a b), MPa")
        ax[2, w].set_ylabel("normal force, kN")
        ax[2, w].set_xlabel("leading wheelset's lateral displacement y (+ left), mm")
        for a in ax[:, w]:
            a.grid(alpha=0.3)
        ax[0, w].legend(fontsize=8)
        ax[2, w].legend(fontsize=7, ncol=2)
    fig.suptitle(
        f"Flange hunting at {kmh:.0f} km/h, the last second of 3 s from 6 mm (Hertz + "
        "FASTSIM, strips): RR against FF, leading wheelset",
        fontsize=10,
    )
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    path = FIG / "vehicle_four_contact_cycle.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--speed", type=float, default=420.0, help="km/h")
    ap.add_argument("--replot", action="store_true", help="charts from the kept runs")
    args = ap.parse_args()
    logging.disable(logging.WARNING)
    if args.replot and CACHE.exists():
        res = pickle.loads(CACHE.read_bytes())
    else:
        res = {m: run(m, args.speed) for m in VARIANTS}
        CACHE.write_bytes(pickle.dumps(res))
    print(
        f"{'model':6s} {'amplitude mm':>12s} {'angle max deg':>13s} {'p0 max MPa':>10s} "
        f"{'N_flange max kN':>15s} {'wall s':>7s}"
    )
    for m in VARIANTS:
        d = res[m]
        print(
            f"{m:6s} {d['amplitude'] * 1e3:12.2f} {np.degrees(d['contact_angle'].max()):13.1f} "
            f"{d['p0'].max() / 1e6:10.0f} {d['N_flange'].max() / 1e3:15.1f} {d['wall']:7.1f}"
        )
    print(f"wrote {plot(res, args.speed)}")


if __name__ == "__main__":
    main()
