"""FR against RR like for like (issue 33): are the FR - RR differences closer to their converged
values with both at RR's 1 ms (FR's modal blocks stepped exactly) than with RR at 1 ms and FR at
its old default (the trapezoidal modal step at 0.5 ms, h omega_max <= 2)? In tread hunting mostly
yes; in the flange cycle at 420 km/h ('cycle420') no, by far (FR's Q max 398 kN against 104 kN):
so the plain exact step did not become FR's default (docs/speed_accuracy.md, "FR at RR's 1 ms");
the exact step with sub-steps in flange contact did (validation/vehicle_fr_flange_step.py).

    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_rr_like_for_like.py [scene ...]
    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_rr_like_for_like.py --replot
    OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_fr_rr_like_for_like.py --boundary

Scenes (Hertz + Kalker on the strip contact, the scenarios' default, and the critical-speed
study's): 'hunting' (300 km/h, 6 mm release, 2 s), 'decay' (330 km/h, between RR's and FR's
decay boundaries, 0.5 mm release, 3 s), 'centred' (300 km/h, 0.5 s). Per scene and run: the
leading wheelset's amplitude (largest |y| over the last 0.5 s), Q max and Y max over the run
(outputs every 2 ms), the hunting frequency (upward zero crossings of y over the last 1 s, interpolated) and the
growth rate of the amplitude (a line through log of the peaks of |y| after 0.5 s, 1/s: > 0
grows; its sign change over speed is the decay boundary). 'cycle420' and 'cycle340' (6 mm
released at 420 and 340 km/h, 4 s: the flange limit cycle the critical-speed path starts
from, its first run at 420 km/h).

Runs: RR at 1 ms, 1/8 and 1/16 ms; FR trapezoidal at 0.5 ms (the default), exact at 1 ms
(the candidate), trapezoidal at 1/8 and 1/16 ms (the converged reference, 1/16 ms) and exact
at 1/16 ms (a check of the reference by the other scheme). The FR - RR difference of each
measure is formed per pair (RR 1 ms with FR old, RR 1 ms with FR new, both 1/8 ms, both 1/16
ms) and compared with the converged one (both 1/16 ms). Results go to
validation/figures/vehicle_fr_rr_like_for_like.npz (per scene, a rerun replaces it) and the
chart vehicle_fr_rr_like_for_like.png.

``--boundary``: the decay test of the critical-speed search (railvti.critical_search: 0.5 mm
from the static state, 4 s, growth_rate) per run at the speeds around RR's and FR's decay
boundaries (BOUNDARY): where its sign changes is the decay boundary.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios

FIG = Path(__file__).resolve().parent / "figures"
STORE = FIG / "vehicle_fr_rr_like_for_like.npz"
#: (label, variant, modal_step, h in ms).
RUNS = (
    ("RR 1", "RR", None, 1.0),
    ("RR 1/8", "RR", None, 0.125),
    ("RR 1/16", "RR", None, 0.0625),
    ("FR trap 0.5", "FR", "trapezoidal", 0.5),
    ("FR exact 1", "FR", "exact", 1.0),
    ("FR trap 1/8", "FR", "trapezoidal", 0.125),
    ("FR trap 1/16", "FR", "trapezoidal", 0.0625),
    ("FR exact 1/16", "FR", "exact", 0.0625),
)
#: FR - RR pairs: (label, RR run, FR run); the last is the converged reference.
PAIRS = (
    ("default: RR 1 ms, FR trap 0.5 ms", "RR 1", "FR trap 0.5"),
    ("both 1 ms (FR exact)", "RR 1", "FR exact 1"),
    ("both 1/8 ms", "RR 1/8", "FR trap 1/8"),
    ("both 1/16 ms (FR exact)", "RR 1/16", "FR exact 1/16"),
    ("converged: both 1/16 ms", "RR 1/16", "FR trap 1/16"),
)
MEASURES = (
    ("amp", "amplitude", 1e3, "mm"),
    ("Q", "Q max", 1e-3, "kN"),
    ("Y", "Y max", 1e-3, "kN"),
    ("f", "frequency", 1.0, "Hz"),
    ("rate", "growth rate", 1.0, "1/s"),
)
SCENES = {
    "hunting": (300.0, 0.006, 2.0),
    "decay": (330.0, 0.0005, 3.0),
    "centred": (300.0, 0.0, 0.5),
    "cycle420": (420.0, 0.006, 4.0),
    "cycle340": (340.0, 0.006, 4.0),
}


def _measures(t: np.ndarray, y: np.ndarray, Q: np.ndarray, Y: np.ndarray) -> dict:
    late = t >= t[-1] - 0.5
    tl, yl = t[t >= t[-1] - 1.0], y[t >= t[-1] - 1.0]
    up = np.flatnonzero((yl[:-1] < 0.0) & (yl[1:] >= 0.0))  # upward zero crossings, interpolated
    tc = tl[up] - yl[up] * (tl[up + 1] - tl[up]) / (yl[up + 1] - yl[up])
    f = (tc.size - 1) / (tc[-1] - tc[0]) if tc.size >= 2 and np.abs(yl).max() > 1e-7 else np.nan
    a = np.abs(y)
    pk = (a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:]) & (t[1:-1] > 0.5) & (a[1:-1] > 1e-7)
    rate = np.polyfit(t[1:-1][pk], np.log(a[1:-1][pk]), 1)[0] if pk.sum() >= 3 else np.nan
    return dict(amp=float(a[late].max()), Q=float(Q.max()), Y=float(np.abs(Y).max()), f=f, rate=float(rate))


def run(scene: str, variant: str, modal_step: str | None, h_ms: float) -> dict:
    speed, y0, duration = SCENES[scene]
    kw = dict(duration=duration, h=h_ms * 1e-3, output_dt=2e-3, progress=False)
    if modal_step is not None:
        kw["modal_step"] = modal_step
    c0 = time.process_time()
    if scene == "centred":
        r = scenarios.centred_running(speed, variant=variant, **kw).run
    else:
        r = scenarios.hunting(speed, variant=variant, y0=y0, **kw)
    out = _measures(r.t, r.y_ws1, r.Q, r.Y)
    out["cpu"] = time.process_time() - c0
    return out


def report(res: dict, scene: str) -> None:
    print(f"\n{scene} {SCENES[scene]}:")
    for lab, *_ in RUNS:
        m = res[lab]
        print(
            f"  {lab:14s} "
            + ", ".join(f"{n} {m[k] * s:.5g} {u}" for k, n, s, u in MEASURES)
            + f"; CPU {m['cpu']:.1f} s"
        )
    ref = PAIRS[-1]
    dref = {k: res[ref[2]][k] - res[ref[1]][k] for k, *_ in MEASURES}
    print("  FR - RR (error against the converged FR - RR):")
    for lab, rr, fr in PAIRS:
        d = {k: res[fr][k] - res[rr][k] for k, *_ in MEASURES}
        print(
            f"    {lab:32s} "
            + ", ".join(f"{n} {d[k] * s:+.4g} ({(d[k] - dref[k]) * s:+.3g}) {u}" for k, n, s, u in MEASURES)
        )


def plot(store: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = [s for s in SCENES if s != "centred" and f"{s}|RR 1|amp" in store]  # centred: no motion
    fig, axes = plt.subplots(len(scenes), 1, figsize=(9, 3.2 * len(scenes)), squeeze=False)
    for ax, scene in zip(axes[:, 0], scenes):
        ref = PAIRS[-1]
        width = 0.8 / (len(PAIRS) - 1)
        for j, (lab, rr, fr) in enumerate(PAIRS[:-1]):
            err = []
            for k, *_ in MEASURES:
                d = store[f"{scene}|{fr}|{k}"] - store[f"{scene}|{rr}|{k}"]
                dref = store[f"{scene}|{ref[2]}|{k}"] - store[f"{scene}|{ref[1]}|{k}"]
                scale = max(abs(dref), 1e-12)
                err.append(abs(d - dref) / scale * 100.0)
            ax.bar(np.arange(len(MEASURES)) + j * width, err, width, label=lab)
        ax.set_xticks(np.arange(len(MEASURES)) + 0.4 - width / 2, [n for _, n, *_ in MEASURES])
        ax.set_yscale("log")
        ax.set_ylabel("|error of FR - RR| / |FR - RR|, %")
        v, y0, dur = SCENES[scene]
        ax.set_title(
            f"{scene} ({v:g} km/h, {y0 * 1e3:g} mm, {dur:g} s): error of FR - RR against both at "
            "1/16 ms (FR trapezoidal)",
            fontsize=9,
        )
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIG / "vehicle_fr_rr_like_for_like.png", dpi=110)
    plt.close(fig)


#: The decay test of railvti.critical_search (a 0.5 mm release from the static state, 4 s,
#: growth_rate over 0.5 s windows: > 0 grows) at the speeds around each variant's decay
#: boundary (the four-variant study: RR 295.0, FR 330.0-332.5 km/h), km/h.
BOUNDARY = {"RR": (292.5, 295.0), "FR": (327.5, 330.0, 332.5)}


def boundary(store: dict) -> None:
    """The decay test's growth rate per run of RUNS at the speeds of BOUNDARY."""
    from railvti.envelope_criteria import growth_rate

    for lab, variant, modal_step, h_ms in RUNS:
        for v in BOUNDARY[variant]:
            kw = dict(duration=4.0, y0=0.0005, h=h_ms * 1e-3, progress=False)
            if modal_step is not None:
                kw["modal_step"] = modal_step
            r = scenarios.hunting(v, variant=variant, **kw)
            rate = growth_rate(r.t, r.y_ws1, 0.5)
            store[f"boundary|{lab}|{v:g}"] = np.array(rate)
            print(f"  decay test {lab:14s} {v:6.1f} km/h: growth rate {rate:+.5f} 1/s", flush=True)


def main(argv: list[str]) -> None:
    store = dict(np.load(STORE)) if STORE.exists() else {}
    if argv == ["--boundary"]:
        boundary(store)
        fresh = dict(np.load(STORE)) if STORE.exists() else {}
        fresh.update({k: v for k, v in store.items() if k.startswith("boundary|")})
        np.savez(STORE, **fresh)
        return
    if argv != ["--replot"]:
        for scene in argv or list(SCENES):
            res = {lab: run(scene, v, ms, h) for lab, v, ms, h in RUNS}
            store = dict(np.load(STORE)) if STORE.exists() else {}
            store.update({f"{scene}|{lab}|{k}": np.array(v) for lab, m in res.items() for k, v in m.items()})
            FIG.mkdir(exist_ok=True)
            np.savez(STORE, **store)
    for scene in SCENES:
        if f"{scene}|RR 1|amp" in store:
            report(
                {
                    lab: {
                        k: float(store[f"{scene}|{lab}|{k}"]) for k in ("amp", "Q", "Y", "f", "rate", "cpu")
                    }
                    for lab, *_ in RUNS
                },
                scene,
            )
    plot(store)


if __name__ == "__main__":
    main(sys.argv[1:])
