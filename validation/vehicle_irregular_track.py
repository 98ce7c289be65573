"""The coach over an irregular track, models RR and RF (issue 34 item 1; docs/vehicle_irregularity.md).

    .venv/bin/python validation/vehicle_irregular_track.py            # ~1 min (RF ~40 s)
    .venv/bin/python validation/vehicle_irregular_track.py --replot   # the figure from the last run

The track: 260 m of the four channels, each a sum of 60 sines with random phases (seed 34)
over wavelengths 3 to 70 m and an amplitude falling as the wavelength to the power 1.5 (rms
about 1.5 mm vertical level, 1 mm alignment, 0.7 mm cross level, 0.5 mm gauge): a stand-in for a
standard spectrum (railvti.track.irregularity_spectra, issue 34). The coach at 120 km/h,
Hertz + Kalker on the strip geometry, ``scenarios.irregular_track`` (the static equilibrium on
perfect track, the irregularity faded in over 20 m ahead of the leading wheelset).

Plotted over each wheel's own track position x (so the wheelsets' traces lie on one another
where they respond alike to the same piece of track): the input channels; Q and Y of the four
left wheels, RR and RF (RF: its sleeper passing, v / 0.6 m = 56 Hz, moves Q by +-3 kN on
perfect track too; drawn thin, with the mean over one sleeper bay bold); the leading wheelset's lateral and vertical displacement against its
rails' (the mean of the two rails' positions under it). Prints the maxima and the RR-RF
differences. Writes validation/figures/vehicle_irregular_track.png.
"""

from __future__ import annotations

import pickle
import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.track.irregularity import TrackIrregularity

FIG = Path(__file__).resolve().parent / "figures"
CACHE = Path(__file__).resolve().parent / "output" / "vehicle_irregular_track.pkl"
SPEED_KMH = 120.0
BAY = 0.6  # the ring's sleeper spacing, m
RMS = {"vertical_level": 1.5e-3, "alignment": 1.0e-3, "cross_level": 0.7e-3, "gauge": 0.5e-3}


def track(seed: int = 34, length: float = 260.0, dx: float = 0.1) -> TrackIrregularity:
    """Sums of sines with random phases, 3 to 70 m, amplitude ~ lambda^1.5, scaled to RMS."""
    rng = np.random.default_rng(seed)
    x = np.arange(0.0, length + dx, dx)
    lam = np.geomspace(3.0, 70.0, 60)
    ch = {}
    for name, rms in RMS.items():
        ph = rng.uniform(0.0, 2 * np.pi, lam.size)
        s = (lam**1.5 * np.sin(2 * np.pi * x[:, None] / lam + ph)).sum(axis=1)
        ch[name] = s * rms / s.std()
    src = f"60 random-phase sines 3-70 m, amplitude ~ lambda^1.5, seed {seed} (validation)"
    return TrackIrregularity(x, **ch, source=src)


def run() -> dict:
    irr = track()
    out = {"irr": irr}
    for variant in ("RR", "RF"):
        t0 = time.perf_counter()
        r, sy, _ = scenarios.irregular_track(SPEED_KMH, irr, variant, return_system=True)
        print(f"{variant}: {r.t[-1]:.2f} s simulated in {time.perf_counter() - t0:.1f} s; {r.irregularity}")
        out[variant] = {
            "t": r.t,
            "Q": r.Q,
            "Y": r.Y,
            "y": np.stack([r.dof(f"ws{w + 1}_y") for w in range(4)], 1),
            "z": np.stack([r.dof(f"ws{w + 1}_z") for w in range(4)], 1),
            "u": r.track_input,
            "xw": np.asarray(sy.x_wheelsets),
            "x_start": float(r.irregularity.rsplit("x_start = ", 1)[1].split(" ")[0]),
            "speed": r.speed,
        }
    return out


def _bay_mean(s: np.ndarray, nb: int) -> np.ndarray:
    """Moving mean over nb samples along the first axis (valid part only)."""
    c = np.cumsum(np.concatenate([np.zeros((1,) + s.shape[1:]), s]), axis=0)
    return (c[nb:] - c[:-nb]) / nb


def report(d: dict) -> None:
    rr, rf = d["RR"], d["RF"]
    t = rf["t"]  # RF's output interval resolves the sleeper passing: RR's interpolated on it
    k = t <= rr["t"][-1]
    nb = max(1, int(round(BAY / (rf["speed"] * (t[1] - t[0])))))
    for name in ("Q", "Y"):
        b = rf[name][k].reshape(k.sum(), -1)
        a = np.stack([np.interp(t[k], rr["t"], c) for c in rr[name].reshape(rr["t"].size, -1).T], 1)
        print(
            f"{name}: RR range {a.min() / 1e3:.1f} .. {a.max() / 1e3:.1f} kN, RF {b.min() / 1e3:.1f} .. "
            f"{b.max() / 1e3:.1f} kN; max |RF - RR| {np.abs(a - b).max() / 1e3:.2f} kN, rms "
            f"{np.sqrt(np.mean((a - b) ** 2)) / 1e3:.2f} kN"
        )
        am, bm = _bay_mean(a, nb), _bay_mean(b, nb)
        print(
            f"  over one sleeper bay: RR std {am.std(axis=0).mean() / 1e3:.2f} kN, RF "
            f"{bm.std(axis=0).mean() / 1e3:.2f} kN; rms |RF - RR| {np.sqrt(np.mean((am - bm) ** 2)) / 1e3:.2f} kN"
        )


def plot(d: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    irr = d["irr"]
    fig, ax = plt.subplots(4, 2, figsize=(13, 12), sharex=True)
    for j, names in enumerate((("vertical_level", "alignment"), ("cross_level", "gauge"))):
        for name in names:
            ax[0, j].plot(irr.x, getattr(irr, name) * 1e3, lw=0.8, label=name.replace("_", " "))
        ax[0, j].set_ylabel("irregularity, mm")
        ax[0, j].legend(loc="upper right", fontsize=8)
        ax[0, j].set_title("input (the run fades it in over 20 m)")
    for j, variant in enumerate(("RR", "RF")):
        r = d[variant]
        # on the ring the sleeper passing (v / 0.6 m) moves the loads by kN: shown thin, and
        # the mean over one sleeper bay bold
        nb = max(1, int(round(BAY / (r["speed"] * (r["t"][1] - r["t"][0]))))) if variant == "RF" else 1
        for w in range(4):
            x = r["x_start"] + r["speed"] * r["t"] + r["xw"][w]
            for i, name in ((1, "Q"), (2, "Y")):
                s = r[name][:, 0, w] / 1e3
                if nb > 1:
                    ax[i, j].plot(x, s, lw=0.3, alpha=0.25, color=f"C{w}")
                    s = np.convolve(s, np.ones(nb) / nb, mode="same")
                    s[: nb // 2], s[-(nb // 2) :] = np.nan, np.nan
                ax[i, j].plot(
                    x, s, lw=0.8, color=f"C{w}", label=f"ws{w + 1} left" + (" (bay mean)" if nb > 1 else "")
                )
        x = r["x_start"] + r["speed"] * r["t"] + r["xw"][0]
        u = r["u"][:, :, :, 0]
        ax[3, j].plot(x, r["y"][:, 0] * 1e3, lw=0.8, label="ws1 y")
        ax[3, j].plot(x, u[:, 0].mean(axis=1) * 1e3, "--", lw=0.8, label="rails' mean y under ws1")
        ax[3, j].plot(x, (r["z"][:, 0] - r["z"][0, 0]) * 1e3, lw=0.8, label="ws1 z (from its start)")
        ax[3, j].plot(x, u[:, 1].mean(axis=1) * 1e3, "--", lw=0.8, label="rails' mean z under ws1")
        ax[1, j].set_title(f"model {variant}, {SPEED_KMH:g} km/h, Hertz + Kalker (strip)")
        ax[1, j].set_ylabel("Q, kN")
        ax[2, j].set_ylabel("Y, kN (track y, + left)")
        ax[3, j].set_ylabel("mm")
        ax[3, j].set_xlabel("the wheel's track position x, m")
        for i in (1, 2, 3):
            ax[i, j].legend(loc="upper right", fontsize=7, ncol=2)
    for a in ax.ravel():
        a.grid(alpha=0.3)
    fig.suptitle(f"coach over an irregular track: {irr.source}", fontsize=10)
    fig.tight_layout()
    FIG.mkdir(exist_ok=True)
    path = FIG / "vehicle_irregular_track.png"
    fig.savefig(path, dpi=110)
    return path


def main() -> None:
    if "--replot" in sys.argv and CACHE.exists():
        d = pickle.loads(CACHE.read_bytes())
    else:
        d = run()
        CACHE.parent.mkdir(exist_ok=True)
        CACHE.write_bytes(pickle.dumps(d))
    report(d)
    print(plot(d))


if __name__ == "__main__":
    main()
