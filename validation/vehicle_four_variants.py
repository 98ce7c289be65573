"""The paper's four variants side by side: RR, FR, RF, FF (rigid or flexible wheelsets on
rigid track elements or on the flexible ring track; issue 15 item 5, Kaiser's Figs 15-16).

    .venv/bin/python validation/vehicle_four_variants.py            # ~20-40 min on 2 cores
    .venv/bin/python validation/vehicle_four_variants.py --replot   # tables and charts again
    .venv/bin/python validation/vehicle_four_variants.py --speeds 330,380,420   # fewer speeds

Every variant on the same coach, S1002 / UIC60 1:40, Hertz + FASTSIM on the strip geometry
(``geometry='strip'``: the table's point jump sustains an artificial tread cycle from about
250 km/h that the BEM does not show; docs/vehicle.md "Strip contact"), the scenario defaults: flexible wheelsets k_max 2, f_max 800 Hz with their residual flexibility;
the ring of 40 sleepers (24 m, longer than the 21.6 m wheelset span plus two bays), modes up
to 500 Hz.

1. Centred running at 200 km/h, 1 s after the static equilibrium (the first 0.2 s skipped):
   Q of every wheel over time, its spectrum (the sleeper-passing frequency v0 / 0.6 m =
   92.6 Hz), its range beside the paper's FF (59-60.8 kN; the paper's coach is heavier:
   its static wheel load is about 60 kN, ours 54.5 kN, so the comparison is the relative
   fluctuation), the rims' camber (FR, FF: ``CentredRunning.rim_camber``; the rim-rail relative angle,
   camber minus the rail head's roll, is ``rim_angle``).
2. Hunting from a 6 mm shift of the leading bogie's wheelsets, 3 s at each speed: phase
   portraits of the leading wheelset (last 1.5 s) in a grid of variants x speeds, and the
   amplitude over the last second against speed. The ring's residual flexibility is off in
   the hunting runs of RF and FF (``ring_residual=False``): with it, Newton fails in
   flange-only contact at 400 km/h (docs/vehicle.md, "Models RF and FF: limits"); the ring's
   500 Hz modes stay.
3. The critical speed of each variant from the hunting runs: the lowest speed of the grid
   whose cycle from 6 mm is sustained (amplitude > 0.5 mm after 3 s): an upper-branch
   estimate on the grid's 10 km/h step, not the full continuation of
   ``scenarios.bifurcation`` (which runs every variant too, but takes hours with FF).

Writes validation/figures/vehicle_four_variants_q.png, vehicle_four_variants_phase.png,
vehicle_four_variants_amplitude.png and prints the tables; the numbers are kept in
validation/figures/vehicle_four_variants.npz for --replot.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from railvti import scenarios

VARIANTS = ("RR", "FR", "RF", "FF")
SLEEPER_HZ = 200.0 / 3.6 / 0.6
FIG = Path(__file__).resolve().parent / "figures"
STORE = FIG / "vehicle_four_variants.npz"
THRESHOLD = 0.5e-3
GEOMETRY = "strip"


def centred(model: str) -> dict:
    """Centred running at 200 km/h: Q history, spectrum peak, rim camber, wall time."""
    t0 = time.perf_counter()
    c = scenarios.centred_running(
        200.0,
        variant=model,
        contact="hertz-fastsim",
        duration=1.0,
        output_dt=5e-4,
        progress=False,
        geometry=GEOMETRY,
    )
    r = c.run
    k = r.t >= r.t[0] + 0.2
    q = r.Q[k]  # (nt, 2, 4)
    dt = float(r.t[1] - r.t[0])
    s = q[:, 0, 0] - q[:, 0, 0].mean()
    f = np.fft.rfftfreq(s.size, dt)
    a = np.abs(np.fft.rfft(s * np.hanning(s.size))) * 2 / s.size
    band = f > 20.0  # above the carbody and bogie modes
    fpk = float(f[band][np.argmax(a[band])])
    rim = c.rim_camber if c.rim_camber is not None else np.zeros((2, 4))
    return dict(
        t=r.t[k], q=q, f=f, a=a, fpk=fpk, rim=rim, load=c.static_wheel_load, wall=time.perf_counter() - t0
    )


def hunting(model: str, kmh: float) -> dict:
    """Hunting from 6 mm at kmh for 3 s: leading wheelset's y, vy; amplitude; or the error."""
    kw = {"ring_residual": False} if model in ("RF", "FF") else {}
    t0 = time.perf_counter()
    try:
        r = scenarios.hunting(
            kmh,
            variant=model,
            contact="hertz-fastsim",
            duration=3.0,
            y0=0.006,
            progress=False,
            geometry=GEOMETRY,
            **kw,
        )
    except Exception as e:  # a failed run is recorded, the study goes on
        return dict(ok=False, error=f"{type(e).__name__}: {e}"[:160], wall=time.perf_counter() - t0)
    k = r.t >= r.t[-1] - 1.5
    return dict(
        ok=True,
        t=r.t[k],
        y=r.y_ws1[k],
        vy=r.vy_ws1[k],
        amp=scenarios.amplitude(r),
        qmax=float(r.Q.max()),
        wall=time.perf_counter() - t0,
    )


def run(speeds: list[float]) -> dict:
    out: dict = {"speeds": np.array(speeds)}
    for m in VARIANTS:
        c = centred(m)
        print(
            f"centred {m}: dominant Q frequency {c['fpk']:.1f} Hz (sleeper passing "
            f"{SLEEPER_HZ:.1f} Hz), Q 1L {c['q'][:, 0, 0].min() / 1e3:.2f}.."
            f"{c['q'][:, 0, 0].max() / 1e3:.2f} kN, wall {c['wall']:.0f} s",
            flush=True,
        )
        for key, val in c.items():
            out[f"c_{m}_{key}"] = np.asarray(val)
        for s in speeds:
            h = hunting(m, s)
            tag = f"h_{m}_{s:.0f}"
            out[f"{tag}_ok"] = np.array(h["ok"])
            out[f"{tag}_wall"] = np.array(h["wall"])
            if h["ok"]:
                for key in ("t", "y", "vy", "amp", "qmax"):
                    out[f"{tag}_{key}"] = np.asarray(h[key])
                print(
                    f"hunting {m} {s:.0f} km/h: amplitude {h['amp'] * 1e3:.2f} mm, Q max "
                    f"{h['qmax'] / 1e3:.0f} kN, wall {h['wall']:.0f} s",
                    flush=True,
                )
            else:
                out[f"{tag}_error"] = np.array(h["error"])
                print(f"hunting {m} {s:.0f} km/h: FAILED {h['error']}", flush=True)
        np.savez(STORE, **out)  # what is finished is kept
    return dict(np.load(STORE))


def report(d: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    speeds = d["speeds"]
    # 1. centred running
    fig, ax = plt.subplots(2, 1, figsize=(9, 7))
    print("\nCentred running at 200 km/h (Hertz + FASTSIM), leading wheelset, left wheel:")
    print("| variant | Q min..max, kN | Q p-p / static | dominant f, Hz | rim camber, mrad | wall, s |")
    print("|---|---|---|---|---|---|")
    for m in VARIANTS:
        q = d[f"c_{m}_q"][:, 0, 0]
        t = d[f"c_{m}_t"]
        ax[0].plot(t, q / 1e3, lw=0.8, label=m)
        steady = np.ptp(q) < 1.0  # rigid track elements: Q constant (round-off only)
        if not steady:
            ax[1].semilogy(d[f"c_{m}_f"], d[f"c_{m}_a"] / 1e3 + 1e-9, lw=0.8, label=m)
        load = float(d[f"c_{m}_load"])
        rim = d[f"c_{m}_rim"][0, 0] * 1e3
        fpk = "none (Q constant)" if steady else f"{float(d[f'c_{m}_fpk']):.1f}"
        print(
            f"| {m} | {q.min() / 1e3:.2f}..{q.max() / 1e3:.2f} | {np.ptp(q) / load:.4f} | "
            f"{fpk} | {rim:+.3f} | {float(d[f'c_{m}_wall']):.0f} |"
        )
    print(f"(paper, FF: Q 59-60.8 kN, p-p / static about 0.03, at {SLEEPER_HZ:.1f} Hz)")
    ax[0].set(
        xlabel="time, s",
        ylabel="Q, kN",
        title="Centred running at 200 km/h: Q at the leading left wheel (FASTSIM, strips)",
    )
    ax[1].axvline(SLEEPER_HZ, color="k", ls=":", lw=0.8, label=f"sleeper passing {SLEEPER_HZ:.1f} Hz")
    ax[1].set(
        xlim=(0, 400),
        ylim=(1e-4, None),
        xlabel="frequency, Hz",
        ylabel="amplitude of Q, kN",
        title="Spectrum of Q (Hann window, t > 0.2 s; RR, FR: Q constant, not drawn)",
    )
    for a in ax:
        a.legend(fontsize=8, ncol=5, loc="upper right", framealpha=0.9)
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_four_variants_q.png", dpi=120)
    plt.close(fig)
    # 2. phase portraits
    fig, ax = plt.subplots(
        len(VARIANTS),
        len(speeds),
        figsize=(2.0 * len(speeds), 2.0 * len(VARIANTS)),
        sharex=True,
        sharey=True,
        squeeze=False,
    )
    for i, m in enumerate(VARIANTS):
        for j, s in enumerate(speeds):
            tag = f"h_{m}_{s:.0f}"
            a = ax[i, j]
            if bool(d[f"{tag}_ok"]):
                a.plot(d[f"{tag}_y"] * 1e3, d[f"{tag}_vy"], lw=0.6)
            else:
                a.text(
                    0.5,
                    0.5,
                    "run failed",
                    ha="center",
                    va="center",
                    transform=a.transAxes,
                    fontsize=8,
                    color="r",
                )
            if i == 0:
                a.set_title(f"{s:.0f} km/h", fontsize=9)
            if j == 0:
                a.set_ylabel(f"{m}\nvy, m/s", fontsize=9)
            if i == len(VARIANTS) - 1:
                a.set_xlabel("y, mm", fontsize=9)
            a.grid(alpha=0.3)
    fig.suptitle(
        "Hunting from a 6 mm shift: leading wheelset's phase portraits, last 1.5 s of "
        "3 s (Hertz + FASTSIM on the strips)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_four_variants_phase.png", dpi=110)
    plt.close(fig)
    # 3. amplitude against speed and the critical speeds
    fig, a = plt.subplots(figsize=(7, 4.2))
    print("\nHunting from 6 mm, 3 s: amplitude of the leading wheelset over the last second, mm")
    print("| variant | " + " | ".join(f"{s:.0f}" for s in speeds) + " | critical (between), km/h |")
    print("|---|" + "---|" * (len(speeds) + 1))
    for m in VARIANTS:
        amp = np.array(
            [float(d[f"h_{m}_{s:.0f}_amp"]) if bool(d[f"h_{m}_{s:.0f}_ok"]) else np.nan for s in speeds]
        )
        a.plot(speeds, amp * 1e3, "o-", ms=4, label=m)
        # the lowest speed from which every run that completed sustains its cycle (failed
        # runs are left out and named)
        ok = np.isfinite(amp)
        sp_ok, alive = speeds[ok], amp[ok] > THRESHOLD
        order = np.argsort(sp_ok)
        al = alive[order]
        k = len(al)
        while k > 0 and al[k - 1]:
            k -= 1
        crit = (
            "none sustained"
            if k == len(al)
            else f"<= {sp_ok[order][0]:.0f}"
            if k == 0
            else f"{sp_ok[order][k - 1]:.0f}-{sp_ok[order][k]:.0f}"
        )
        if not ok.all():
            crit += f" (runs at {', '.join(f'{x:.0f}' for x in speeds[~ok])} failed)"
        cells = " | ".join("failed" if not np.isfinite(x) else f"{x * 1e3:.2f}" for x in amp)
        print(f"| {m} | {cells} | {crit} |")
    print("(paper: RR about 390, FR and RF about 350, FF 330 km/h or lower)")
    a.axhline(THRESHOLD * 1e3, color="k", ls=":", lw=0.8, label="sustained-cycle threshold")
    a.set(
        xlabel="speed, km/h",
        ylabel="amplitude, mm",
        title="Hunting from 6 mm: leading "
        "wheelset's amplitude after 3 s (FASTSIM, strips;\nfailed runs not drawn)",
    )
    a.legend(fontsize=8, loc="lower right")
    a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_four_variants_amplitude.png", dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replot", action="store_true")
    ap.add_argument("--speeds", default="330,340,350,360,370,380,390,400,410,420")
    a = ap.parse_args()
    d = dict(np.load(STORE)) if a.replot else run([float(x) for x in a.speeds.split(",")])
    report(d)


if __name__ == "__main__":
    main()
