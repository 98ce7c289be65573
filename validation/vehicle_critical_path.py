"""RR's nonlinear critical speed by path-following (the fold) and its decay boundary, and how
little they move with the search's settings (issue 30 item 5).

``railvti.critical_search.nonlinear_critical_speed`` with the defaults (RR, Hertz + Kalker on
the strip geometry; 6 mm at 420 km/h carried down in 20 km/h steps, bisection to 2.5 km/h;
4 s per run, h = 1 ms; living cycle: envelope growth rate over the run's second half
>= -0.05 1/s, last 0.5 s window >= 0.25 mm and, carried in, >= 0.5 x the run's first
window; decay boundary from 0.5 mm, grows = last envelope window above the first), then the
same with one setting changed:

* ``threshold``: the floor and the rate tolerance halved (0.125 mm, 0.025 1/s; the
  collapse fraction kept at 0.5; the decay test has no threshold, so its boundary is not
  recomputed),
* ``duration``: 8 s per run (doubled run length),
* ``h``: 0.5 ms (halved time step),
* ``segments``: every run as two continued ``simulate`` calls of half the length (chunking:
  the state handed over between calls),
* ``step``: the walk's coarse step 10 km/h (a different continuation path),
* ``fine``, ``fine_duration``, ``fine_h``, ``fine_threshold``, ``fine_collapse``: the
  baseline, doubled run length, halved step, halved floor / rate tolerance and halved
  collapse fraction (0.25) with a 4x finer bracket (0.625 km/h), to see differences the
  2.5 km/h grid hides.

Prints the table of both numbers per variant and their differences from the baseline of the
same resolution against the bound (one bracket width), saves
validation/figures/vehicle_critical_path.npz and draws vehicle_critical_path.png.

Another variant: ``--model FR --cheap`` (k_max 1 / 300 Hz as the four-variant study; files
vehicle_critical_path_fr.*).

Run: python validation/vehicle_critical_path.py   (about 55 min of runs: on 2 cores run it
     as two processes, below, about 30 min)
     --variants base,duration --parts DIR   (a subset, each variant to DIR/<name>.npz)
     --replot --parts DIR                   (table, npz and figure from the parts)
"""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

import numpy as np

from railvti.critical_search import nonlinear_critical_speed
from railvti.scenarios import critical_speed

HERE = Path(__file__).resolve().parent
FIG = HERE / "figures"
VARIANTS = {
    "base": ("baseline", {}),
    "threshold": ("floor and rate tolerance halved", dict(threshold=0.125e-3, rate_tol=0.025, decay=False)),
    "duration": ("run length doubled (8 s)", dict(duration=8.0)),
    "h": ("time step halved (0.5 ms)", dict(h=0.5e-3)),
    "segments": ("each run in two continued calls", dict(segments=2)),
    "step": ("walk step halved (10 km/h)", dict(step_kmh=10.0)),
    # the same at a 4x finer bracket (0.625 km/h): differences hidden by the 2.5 km/h grid
    "fine": ("fine: baseline", dict(resolution_kmh=0.625)),
    "fine_duration": ("fine: run length doubled", dict(resolution_kmh=0.625, duration=8.0)),
    "fine_h": ("fine: time step halved", dict(resolution_kmh=0.625, h=0.5e-3)),
    "fine_threshold": (
        "fine: floor and rate tol. halved",
        dict(resolution_kmh=0.625, threshold=0.125e-3, rate_tol=0.025, decay=False),
    ),
    "fine_collapse": (
        "fine: collapse fraction halved",
        dict(resolution_kmh=0.625, collapse=0.25, decay=False),
    ),
}
#: The variant searched (``--model``) and the flexible wheelsets' mode selection (``--cheap``:
#: k_max 1 / 300 Hz, as the four-variant study's FR/FF).
MODEL = "RR"
SELECTION: dict = {}
FIELDS = (
    "path_speeds",
    "path_amplitudes",
    "path_rates",
    "path_alive",
    "path_durations",
    "decay_speeds",
    "decay_amplitudes",
    "decay_rates",
)


def run_variant(name: str, parts: Path | None) -> dict:
    label, kw = VARIANTS[name]
    t0 = time.perf_counter()
    c = nonlinear_critical_speed(MODEL, speed_top_kmh=420.0, **SELECTION, **{"resolution_kmh": 2.5, **kw})
    wall = time.perf_counter() - t0
    print(f"[{name}] {c.message} [{wall:.0f} s]", flush=True)
    out = {f: np.asarray(getattr(c, f)) for f in FIELDS}
    out.update(
        resolution_kmh=c.settings["resolution"] * 3.6,
        fold_kmh=c.fold_kmh,
        fold_bracket_kmh=np.array(c.fold_bracket_kmh),
        decay_kmh=c.decay_boundary_kmh,
        decay_bracket_kmh=np.array(c.decay_bracket_kmh),
        fold_amplitude=c.fold_amplitude,
        fold_branch=c.fold_branch,
        wall=wall,
        label=label,
        method=c.method,
        has_decay=kw.get("decay", True),
    )
    if parts is not None:
        parts.mkdir(parents=True, exist_ok=True)
        np.savez(parts / f"{name}.npz", **out)
    return out


def load(parts: Path) -> dict:
    res = {}
    for name in VARIANTS:
        p = parts / f"{name}.npz"
        if p.exists():
            with np.load(p, allow_pickle=False) as z:
                res[name] = {k: (z[k].item() if z[k].ndim == 0 else z[k]) for k in z.files}
    return res


def table(res: dict) -> None:
    print(
        f"\n{MODEL}, Hertz + Kalker (strips); diff against the baseline of the same resolution; "
        "bound: one bracket width (the resolution)"
    )
    print(
        f"{'variant':34s} {'fold km/h':>10s} {'bracket':>15s} {'diff':>6s} "
        f"{'decay km/h':>10s} {'bracket':>15s} {'diff':>6s} {'wall s':>7s}"
    )
    for name, r in res.items():
        b = res["fine"] if name.startswith("fine") and "fine" in res else res["base"]
        bound = float(r.get("resolution_kmh", 2.5))
        df = r["fold_kmh"] - b["fold_kmh"]
        line = (
            f"{str(r['label']):34s} {r['fold_kmh']:10.2f} "
            f"[{r['fold_bracket_kmh'][0]:6.2f},{r['fold_bracket_kmh'][1]:6.2f}] {df:+6.2f} "
        )
        if r["has_decay"]:
            dd = r["decay_kmh"] - b["decay_kmh"]
            line += (
                f"{r['decay_kmh']:10.2f} [{r['decay_bracket_kmh'][0]:6.2f},"
                f"{r['decay_bracket_kmh'][1]:6.2f}] {dd:+6.2f} "
            )
        else:
            line += f"{'(same test)':>10s} {'':15s} {'':6s} "
        ok = abs(df) <= bound + 1e-9 and (not r["has_decay"] or abs(dd) <= bound + 1e-9)
        print(line + f"{r['wall']:7.0f} {'within' if ok else 'OUTSIDE'}")


def figure(res: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    b = res["base"]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8), gridspec_kw=dict(width_ratios=[3, 2]))
    ps, pa, al = b["path_speeds"] * 3.6, b["path_amplitudes"] * 1e3, b["path_alive"]
    ax.semilogy(ps[al], pa[al], "o", color="C0", label="upper branch (from 6 mm, carried): cycle")
    ax.semilogy(ps[~al], pa[~al], "o", mfc="none", color="C0", label="upper branch: died (last 0.5 s window)")
    order = np.argsort(ps[al])
    ax.semilogy(ps[al][order], pa[al][order], "-", color="C0", lw=0.8)
    ds, da = b["decay_speeds"] * 3.6, b["decay_amplitudes"] * 1e3
    grow = b["decay_rates"] > 0
    ax.semilogy(ds[grow], da[grow], "s", color="C3", label="from 0.5 mm: grows")
    ax.semilogy(ds[~grow], da[~grow], "s", mfc="none", color="C3", label="from 0.5 mm: decays")
    fb, db = b["fold_bracket_kmh"], b["decay_bracket_kmh"]
    ax.axvspan(fb[0], fb[1], color="C0", alpha=0.25)
    ax.axvline(b["fold_kmh"], color="C0", ls="--", label=f"fold {b['fold_kmh']:.1f} km/h")
    ax.axvspan(db[0], db[1], color="C3", alpha=0.25)
    ax.axvline(b["decay_kmh"], color="C3", ls=":", label=f"decay boundary {b['decay_kmh']:.1f} km/h")
    ax.axhline(0.25, color="grey", lw=0.8, ls="-.", label="living-cycle floor 0.25 mm")
    lin = float(critical_speed(MODEL, method="linear", **SELECTION))  # context: eigenvalues
    ax.axvline(lin, color="k", lw=0.8, ls="--", label=f"linear critical speed {lin:.1f} km/h (damper stuck)")
    ax.set_xlabel("speed, km/h")
    ax.set_ylabel("leading wheelset amplitude (last 0.5 s), mm")
    ax.set_title(f"{MODEL}, Hertz + Kalker (strips): path down from 420 km/h")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3, which="both")
    names = list(res)
    y = np.arange(len(names))[::-1]
    for k, n in zip(y, names):
        r = res[n]
        ax2.plot(r["fold_bracket_kmh"], [k, k], "-", color="C0", lw=4, alpha=0.5)
        ax2.plot(r["fold_kmh"], k, "o", color="C0")
        if r["has_decay"]:
            ax2.plot(r["decay_bracket_kmh"], [k, k], "-", color="C3", lw=4, alpha=0.5)
            ax2.plot(r["decay_kmh"], k, "s", color="C3")
    ax2.plot([], [], "o-", color="C0", label="fold (bracket)")
    ax2.plot([], [], "s-", color="C3", label="decay boundary (bracket)")
    ax2.set_ylim(-0.6, len(names) + 0.4)
    ax2.margins(x=0.1)
    ax2.set_yticks(y)
    ax2.set_yticklabels([str(res[n]["label"]) for n in names], fontsize=8)
    ax2.set_xlabel("speed, km/h")
    ax2.set_title("the two numbers per search setting")
    ax2.legend(fontsize=7, loc="upper center", ncol=2)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def save(res: dict, path: Path) -> None:
    flat = {}
    for n, r in res.items():
        for k, v in r.items():
            flat[f"{n}__{k}"] = np.asarray(v)
    np.savez(path, variants=np.array(list(res)), **flat)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--variants", default=",".join(VARIANTS))
    p.add_argument("--parts", type=Path, default=None, help="directory of one npz per variant")
    p.add_argument("--replot", action="store_true", help="only combine the parts")
    p.add_argument("-v", action="store_true", help="log every run")
    p.add_argument(
        "--model",
        default="RR",
        choices=("RR", "FR", "RF", "FF"),
        help="the variant (files: vehicle_critical_path_<model> unless RR)",
    )
    p.add_argument("--cheap", action="store_true", help="FR/FF at k_max 1 / 300 Hz")
    a = p.parse_args()
    global MODEL, SELECTION
    MODEL = a.model
    SELECTION = {"k_max": 1, "f_max": 300.0} if a.cheap and MODEL in ("FR", "FF") else {}
    if a.v:
        logging.basicConfig(level=logging.INFO, format="%(message)s")
    if a.replot:
        res = load(a.parts)
    else:
        res = {n: run_variant(n, a.parts) for n in a.variants.split(",")}
        if a.parts is not None:
            res = load(a.parts)
    if "base" not in res:
        return
    res = {"base": res.pop("base"), **res}
    table(res)
    FIG.mkdir(exist_ok=True)
    stem = "vehicle_critical_path" + ("" if MODEL == "RR" else f"_{MODEL.lower()}")
    save(res, FIG / f"{stem}.npz")
    figure(res, FIG / f"{stem}.png")


if __name__ == "__main__":
    main()
