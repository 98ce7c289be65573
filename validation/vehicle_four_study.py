"""The four-variant study like for like (issue 30): RR, FR, RF, FF by three methods.

    .venv/bin/python validation/vehicle_four_study.py                  # all; hours with FF
    .venv/bin/python validation/vehicle_four_study.py --models RR,FR   # some variants
    .venv/bin/python validation/vehicle_four_study.py --bem RR         # BEM brackets of RR
    .venv/bin/python validation/vehicle_four_study.py --replot         # table and charts again

Every variant on the same coach and the same wheelset body (railvti.vehicle.wheelset_body:
RR's rigid wheelset is the FE wheelset's rigid part plus its discs and axleboxes, with the
gyroscopic moments), S1002 / UIC60 1:40, the scenarios' defaults (flexible wheelsets k_max 2 /
800 Hz with their residual flexibility; the ring of ``scenarios.RF_N_SLEEPERS`` sleepers with
its residual flexibility), unless ``--cheap`` (k_max 1 / 300 Hz).

1. **linear**: ``scenarios.critical_speed(model, method='linear')`` (eigenvalues about centred
   running at the equivalent conicity, the yaw damper stuck; RF and FF: the ring's rows
   averaged over a sleeper bay).
2. **nonlinear, strip**: ``railvti.critical_search.nonlinear_critical_speed`` with Hertz +
   Kalker on the strip geometry (the default contact): the fold (lowest speed with a limit
   cycle, path-following down from 6 mm at 420 km/h, 20 km/h steps, bisection to
   ``--resolution``) and the decay boundary (a 0.5 mm disturbance grows).
3. **nonlinear, BEM** (``--bem`` models): the BEM contact (0.75 mm elements) on the upper
   branch around the strip model's fold: a path from ``--bem-above`` (40) km/h above it down
   in ``--bem-step`` (10) km/h steps, the fold bracketed to half a step.

Each finished item is written at once to validation/figures/vehicle_four_study.npz (a run
interrupted keeps what finished; a rerun skips what is stored unless ``--force``). Prints the
table with the paper's claims and each item's wall time and the process's peak memory;
charts: vehicle_four_study_bifurcation.png (the four diagrams: the upper branch and the decay
tests), vehicle_four_study_speeds.png (the table as a chart).
"""

from __future__ import annotations

import argparse
import resource
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.critical_search import nonlinear_critical_speed

FIG = Path(__file__).resolve().parent / "figures"
STORE = FIG / "vehicle_four_study.npz"
VARIANTS = ("RR", "FR", "RF", "FF")
#: Kaiser's critical speeds, km/h (the paper's summary: FF <= 330 < FR ~ RF ~ 350 < RR ~ 390).
PAPER_KMH = {"RR": 390.0, "FR": 350.0, "RF": 350.0, "FF": 330.0}


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _load(*paths: Path) -> dict:
    out: dict = {}
    for p in paths or (STORE,):
        if p.exists():
            out.update(dict(np.load(p, allow_pickle=False)))
    return out


def _save(out: dict) -> None:
    FIG.mkdir(exist_ok=True)
    tmp = STORE.with_name(STORE.stem + ".tmp.npz")
    np.savez(tmp, **out)
    tmp.replace(STORE)


def _selection(model: str, cheap: bool) -> dict:
    return {"k_max": 1, "f_max": 300.0} if cheap and model in ("FR", "FF") else {}


def linear(model: str, cheap: bool) -> tuple[float, float]:
    c = scenarios.critical_speed(model, method="linear", tol_kmh=0.5, **_selection(model, cheap))
    return c.kmh, c.frequency_hz


def path(model: str, contact: str, cheap: bool, **kw) -> dict:
    c = nonlinear_critical_speed(model, contact, **_selection(model, cheap), **kw)
    print("  " + c.message, flush=True)
    return {
        "fold": c.fold_kmh,
        "fold_lo": c.fold_bracket_kmh[0],
        "fold_hi": c.fold_bracket_kmh[1],
        "decay": c.decay_boundary_kmh,
        "decay_lo": c.decay_bracket_kmh[0],
        "decay_hi": c.decay_bracket_kmh[1],
        "amp": c.fold_amplitude,
        "branch": c.fold_branch,
        "path_kmh": np.asarray(c.path_speeds) * 3.6,
        "path_amp": np.asarray(c.path_amplitudes),
        "path_alive": np.asarray(c.path_alive),
        "decay_kmh": np.asarray(c.decay_speeds) * 3.6,
        "decay_amp": np.asarray(c.decay_amplitudes),
        "decay_rate": np.asarray(c.decay_rates),
        "failure": c.failure,
    }


def _store(out: dict, prefix: str, d: dict, wall: float) -> None:
    for k, v in d.items():
        out[f"{prefix}_{k}"] = np.asarray(v)
    out[f"{prefix}_wall"] = np.array(wall)
    out[f"{prefix}_peak_mb"] = np.array(_peak_mb())
    _save(out)


def run(
    models: list[str],
    bem: list[str],
    resolution: float,
    duration: float,
    cheap: bool,
    force: bool,
    bem_above: float = 40.0,
    bem_step: float = 10.0,
    bem_h: float | None = None,
    bem_ring_inertia: bool = False,
    bem_below: float = 25.0,
    bem_resolution: float | None = None,
) -> dict:
    out = _load()
    out["selection"] = np.array("k_max 1 / 300 Hz" if cheap else "k_max 2 / 800 Hz")
    for m in models:
        if force or f"{m}_linear" not in out:
            t = time.perf_counter()
            v, f = linear(m, cheap)
            print(f"{m} linear: {v:.1f} km/h, {f:.2f} Hz [{time.perf_counter() - t:.0f} s]", flush=True)
            _store(out, f"{m}_linear", {"kmh": v, "hz": f}, time.perf_counter() - t)
        if force or f"{m}_strip_fold" not in out:
            t = time.perf_counter()
            d = path(m, "hertz-kalker", cheap, resolution_kmh=resolution, duration=duration)
            _store(out, f"{m}_strip", d, time.perf_counter() - t)
            print(f"{m} strip path [{time.perf_counter() - t:.0f} s]", flush=True)
    for m in bem:
        fold = float(out.get(f"{m}_strip_fold", np.nan))
        if not np.isfinite(fold):
            print(f"{m}: no strip fold stored: run the strip path first")
            continue
        if force or f"{m}_bem_fold_hi" not in out or not np.isfinite(out[f"{m}_bem_fold_hi"]):
            t = time.perf_counter()
            d = path(
                m,
                "bem",
                cheap,
                speed_top_kmh=min(fold + bem_above, 460.0),
                speed_floor_kmh=fold - bem_below,
                step_kmh=bem_step,
                resolution_kmh=bem_resolution or bem_step / 2.0,
                duration=duration,
                decay=False,
                h=bem_h,
                **({"ring_residual_inertia": True} if bem_ring_inertia else {}),
            )
            _store(out, f"{m}_bem", d, time.perf_counter() - t)
            print(f"{m} BEM bracket [{time.perf_counter() - t:.0f} s]", flush=True)
    return out


def _f(out: dict, key: str) -> float:
    return float(out[key]) if key in out else float("nan")


def _bem_bracket(out: dict, m: str) -> tuple[float, float]:
    """The BEM fold bracket (lo, hi), km/h: the path's, its lower side from the low path
    (validation/vehicle_four_study_ff_low.py) where the path lived down to its floor."""
    lo, hi = _f(out, f"{m}_bem_fold_lo"), _f(out, f"{m}_bem_fold_hi")
    if np.isnan(lo) and np.isfinite(hi) and f"{m}_bem_low_fold_hi" in out:
        low_lo, low_hi = _f(out, f"{m}_bem_low_fold_lo"), _f(out, f"{m}_bem_low_fold_hi")
        if np.isfinite(low_hi):  # the low path's top lived: it extends the path
            lo, hi = low_lo, low_hi
    return lo, hi


def _bem_value(out: dict, m: str) -> tuple[float, bool]:
    """The BEM fold to draw and whether it is bracketed. A path whose top run already had no
    cycle gives no bound (a cycle may live there from a larger start: RR's did, issue 30)."""
    lo, hi = _bem_bracket(out, m)
    return hi, bool(np.isfinite(hi) and np.isfinite(lo))


def _bem_text(out: dict, m: str) -> str:
    """The BEM column of the table."""
    if f"{m}_bem_fold_hi" not in out:
        return "not run"
    lo, hi = _bem_bracket(out, m)
    if np.isfinite(hi):
        return f"[{lo:.0f}, {hi:.0f}]" if np.isfinite(lo) else f"<= {hi:.0f} (alive down to there)"
    sp = out[f"{m}_bem_path_kmh"]
    dead = sp[~out[f"{m}_bem_path_alive"].astype(bool) & np.isfinite(out[f"{m}_bem_path_amp"])]
    why = str(out.get(f"{m}_bem_failure", ""))
    parts = ([f"no cycle at {', '.join(f'{v:.0f}' for v in dead)} km/h from 6 mm"] if dead.size else []) + (
        [why] if why else []
    )
    return "not bracketed: " + "; ".join(parts)


def table(out: dict) -> str:
    rows = [
        "| variant | linear, km/h | nonlinear strip: fold [bracket], km/h | decay boundary, "
        "km/h | nonlinear BEM: fold bracket, km/h | paper | wall time (lin / strip / BEM) |",
        "|---|---|---|---|---|---|---|",
    ]
    for m in VARIANTS:
        if f"{m}_linear_kmh" not in out:
            continue
        bem = _bem_text(out, m)
        walls = " / ".join(
            f"{_f(out, f'{m}_{k}_wall'):.0f} s" if f"{m}_{k}_wall" in out else "-"
            for k in ("linear", "strip", "bem")
        )
        rows.append(
            f"| {m} | {_f(out, f'{m}_linear_kmh'):.1f} | {_f(out, f'{m}_strip_fold'):.1f} "
            f"[{_f(out, f'{m}_strip_fold_lo'):.1f}, {_f(out, f'{m}_strip_fold_hi'):.1f}] "
            f"| {_f(out, f'{m}_strip_decay'):.1f} | {bem} | ~{PAPER_KMH[m]:.0f} | {walls} |"
        )
    peak = max((_f(out, k) for k in out if k.endswith("_peak_mb")), default=float("nan"))
    return "\n".join(rows) + f"\n\npeak memory of the runs: {peak:.0f} MB"


def plot(out: dict) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8), sharex=True, sharey=True)
    for ax, m in zip(axes.flat, VARIANTS):
        ax.set_title(m, fontsize=10)
        ax.grid(alpha=0.3)
        if f"{m}_strip_path_kmh" not in out:
            ax.text(0.5, 0.5, "not run", transform=ax.transAxes, ha="center")
            continue
        s, a = out[f"{m}_strip_path_kmh"], out[f"{m}_strip_path_amp"] * 1e3
        alive = out[f"{m}_strip_path_alive"].astype(bool)
        ax.plot(s[alive], a[alive], "o", color="C0", label="upper branch (cycle alive)")
        ax.plot(s[~alive], a[~alive], "x", color="C0", label="upper branch (died)")
        if f"{m}_strip_decay_kmh" in out:
            ax.plot(
                out[f"{m}_strip_decay_kmh"],
                out[f"{m}_strip_decay_amp"] * 1e3,
                "s",
                mfc="none",
                color="C1",
                label="from 0.5 mm (decay test)",
            )
        if f"{m}_bem_path_kmh" in out:
            sb, ab = out[f"{m}_bem_path_kmh"], out[f"{m}_bem_path_amp"] * 1e3
            ok = out[f"{m}_bem_path_alive"].astype(bool)
            if f"{m}_bem_low_path_kmh" in out and np.isfinite(_f(out, f"{m}_bem_low_fold_hi")):
                sb = np.concatenate([sb, out[f"{m}_bem_low_path_kmh"]])
                ab = np.concatenate([ab, out[f"{m}_bem_low_path_amp"] * 1e3])
                ok = np.concatenate([ok, out[f"{m}_bem_low_path_alive"].astype(bool)])
            for sel, mfc, lab in ((ok, "C3", "BEM: cycle alive"), (~ok, "none", "BEM: died")):
                if sel.any():
                    ax.plot(sb[sel], ab[sel], "D", mfc=mfc, color="C3", label=lab)
        for key, ls, lab in (
            ("strip_fold", "-", "fold (strip)"),
            ("strip_decay", "--", "decay boundary"),
            ("linear_kmh", ":", "linear"),
        ):
            if np.isfinite(_f(out, f"{m}_{key}")):
                ax.axvline(_f(out, f"{m}_{key}"), ls=ls, color="k", lw=0.8, label=lab)
        ax.legend(fontsize=7)
    for ax in axes[1]:
        ax.set_xlabel("speed, km/h")
    for ax in axes[:, 0]:
        ax.set_ylabel("leading wheelset amplitude, mm")
    fig.suptitle(
        "Bifurcation diagrams of the four variants: Hertz + Kalker on the strips "
        f"(BEM where run); FR, FF: {out.get('selection', 'selection not stored')}",
        fontsize=11,
    )
    fig.tight_layout()
    p1 = FIG / "vehicle_four_study_bifurcation.png"
    fig.savefig(p1, dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    x = np.arange(len(VARIANTS))
    series = [
        ("linear", [_f(out, f"{m}_linear_kmh") for m in VARIANTS]),
        ("fold, strip", [_f(out, f"{m}_strip_fold") for m in VARIANTS]),
        ("decay boundary, strip", [_f(out, f"{m}_strip_decay") for m in VARIANTS]),
        ("fold, BEM", [_bem_value(out, m)[0] for m in VARIANTS]),
        ("paper (Kaiser)", [PAPER_KMH[m] for m in VARIANTS]),
    ]
    wdt = 0.16
    brackets = {
        "fold, strip": [(_f(out, f"{m}_strip_fold_lo"), _f(out, f"{m}_strip_fold_hi")) for m in VARIANTS],
        "fold, BEM": [_bem_bracket(out, m) for m in VARIANTS],
    }
    for i, (lab, vals) in enumerate(series):
        bars = ax.bar(x + (i - 2) * wdt, vals, wdt, label=lab)
        if lab in brackets:  # the bracket [lo, hi] as a whisker below the bar's top
            lo = np.array([b[0] for b in brackets[lab]])
            hi = np.array([b[1] for b in brackets[lab]])
            ok = np.isfinite(lo) & np.isfinite(hi)
            ax.errorbar(
                (x + (i - 2) * wdt)[ok],
                hi[ok],
                yerr=[hi[ok] - lo[ok], 0 * hi[ok]],
                fmt="none",
                ecolor="k",
                capsize=3,
                lw=1,
            )
        if lab == "fold, BEM":
            for b, m in zip(bars, VARIANTS):
                if f"{m}_bem_fold_hi" not in out or _bem_value(out, m)[1]:
                    continue
                if np.isfinite(_bem_value(out, m)[0]):  # alive down to there: <=
                    b.set_hatch("//")
                    ax.annotate(
                        "<=", (b.get_x() + wdt / 2, b.get_height()), ha="center", va="bottom", fontsize=8
                    )
                else:
                    ax.annotate(
                        "BEM:\nnot\nbracketed",
                        (b.get_x() + wdt / 2, 205.0),
                        ha="center",
                        va="bottom",
                        fontsize=7,
                    )
    ax.set_xticks(x, VARIANTS)
    ax.set_ylabel("critical speed, km/h")
    ax.set_ylim(200, 450)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8, ncol=3, loc="upper right")
    ax.set_title(
        "Critical speeds of the four variants (folds drawn at the bracket's top, whisker: "
        "the bracket)\nmissing bars: not run or not bracketed; hatched: an upper bound, "
        "the cycle alive down to there",
        fontsize=10,
    )
    fig.tight_layout()
    p2 = FIG / "vehicle_four_study_speeds.png"
    fig.savefig(p2, dpi=110)
    plt.close(fig)
    return [p1, p2]


def main(argv: list[str] | None = None) -> None:
    global STORE
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default=",".join(VARIANTS))
    ap.add_argument("--bem", default="", help="models bracketed with the BEM, e.g. RR,FF")
    ap.add_argument("--resolution", type=float, default=2.5, help="fold bracket, km/h")
    ap.add_argument("--duration", type=float, default=4.0, help="s per speed")
    ap.add_argument("--cheap", action="store_true", help="FR/FF at k_max 1 / 300 Hz")
    ap.add_argument(
        "--bem-above",
        type=float,
        default=40.0,
        help="the BEM path starts this far above the strip fold, km/h",
    )
    ap.add_argument(
        "--bem-step", type=float, default=10.0, help="the BEM path's step, km/h (bracket: half of it)"
    )
    ap.add_argument(
        "--bem-below",
        type=float,
        default=25.0,
        help="the BEM path's floor this far below the strip fold, km/h",
    )
    ap.add_argument(
        "--bem-resolution",
        type=float,
        default=None,
        help="the BEM fold bracket's width, km/h (default: half the step)",
    )
    ap.add_argument(
        "--bem-h", type=float, default=None, help="the BEM runs' time step, s (default: the scenarios')"
    )
    ap.add_argument(
        "--bem-ring-inertia",
        action="store_true",
        help="the BEM path with the ring's residual inertia (ring_residual_inertia: "
        "FF's flange impacts need it with the BEM)",
    )
    ap.add_argument("--force", action="store_true", help="recompute stored items")
    ap.add_argument("--replot", action="store_true")
    ap.add_argument(
        "--store",
        type=Path,
        default=STORE,
        help="results file (two runs side by side: one each, then --merge)",
    )
    ap.add_argument(
        "--merge",
        type=Path,
        nargs="*",
        default=[],
        help="with --replot: results files to merge into --store first",
    )
    a = ap.parse_args(argv)
    STORE = a.store
    if a.merge:
        _save(_load(STORE, *a.merge))
    models = [m for m in a.models.split(",") if m]
    bem = [m for m in a.bem.split(",") if m]
    for m in models + bem:
        if m not in VARIANTS:
            raise SystemExit(f"unknown variant {m!r}: {VARIANTS}")
    out = (
        _load()
        if a.replot
        else run(
            models,
            bem,
            a.resolution,
            a.duration,
            a.cheap,
            a.force,
            a.bem_above,
            a.bem_step,
            a.bem_h,
            a.bem_ring_inertia,
            a.bem_below,
            a.bem_resolution,
        )
    )
    print(table(out))
    for p in plot(out):
        print(f"wrote {p}")


if __name__ == "__main__":
    main()
