"""Critical speeds of the four variants RR, FR, RF, FF by both methods (issue 15, acceptance 5).

    .venv/bin/python validation/vehicle_four_critical.py            # ~1 h on 2 shared cores
    .venv/bin/python validation/vehicle_four_critical.py --replot   # the table again
    .venv/bin/python validation/vehicle_four_critical.py --models RR,FR --step 20

Linear: ``scenarios.critical_speed(model, method='linear')`` (eigenvalues of the system
linearised about centred running with the equivalent conicity, the yaw damper stuck and
sliding; flexible wheelsets' modes, residual coordinates and the ring's modes included, the
ring's contact rows frozen at t = 0). Nonlinear: ``method='nonlinear'``, the continuation
sweep of ``scenarios.bifurcation`` (a limit cycle from 6 mm at the top speed, followed down
in speed; a decay test from 0.5 mm at each speed; extended downward until the cycle dies),
with Hertz + FASTSIM on the strip geometry as validation/vehicle_four_variants.py, runs of
``--duration`` s (default 3 s: the amplitude over the last second is an estimate, not a
settled cycle) and a ``--step`` km/h grid (default 40: a coarse bracket). RF and FF run
without the ring's residual flexibility (docs/vehicle.md, "Models RF and FF: limits").
``--independent``: each speed from its own static state plus 6 mm
(``bifurcation(independent=True)``), not continued.

Prints a markdown table and keeps the numbers in validation/figures/vehicle_four_critical.npz
(each model's row as it finishes).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from railvti import scenarios

STORE = Path(__file__).resolve().parent / "figures" / "vehicle_four_critical.npz"
VARIANTS = ("RR", "FR", "RF", "FF")


def _ring(model: str) -> dict:
    return {"ring_residual": False} if model in scenarios.RING_TRACK else {}


def run(
    models: list[str],
    top: float,
    step: float,
    duration: float,
    bottom: float = 100.0,
    store: Path = STORE,
    independent: bool = False,
) -> dict:
    out = dict(np.load(store)) if store.exists() else {}
    for m in models:
        t0 = time.perf_counter()
        for damper in ("stuck", "sliding"):
            c = scenarios.critical_speed(m, method="linear", damper=damper, **_ring(m))
            out[f"{m}_linear_{damper}"] = np.array([c.kmh, c.frequency_hz])
            print(f"{m} linear ({damper}): {c.kmh:.1f} km/h, {c.frequency_hz:.2f} Hz", flush=True)
        speeds = np.arange(top, bottom, -step)
        c = scenarios.critical_speed(
            m,
            "hertz-fastsim",
            method="nonlinear",
            speeds_kmh=speeds,
            duration=duration,
            progress=False,
            geometry="strip",
            v_min_kmh=float(speeds[-1]),
            independent=independent,
            **_ring(m),
        )
        b = c.bifurcation
        out[f"{m}_nonlinear"] = np.array([c.kmh, c.no_decay_below_kmh])
        out[f"{m}_branch"] = np.array(c.branch)
        out[f"{m}_speeds"] = np.asarray(b.speeds_kmh)
        out[f"{m}_upper"] = np.asarray(b.upper)
        out[f"{m}_decay"] = np.asarray(b.decay)
        out[f"{m}_flange"] = np.array(np.nan if b.flange_kmh is None else b.flange_kmh, dtype=float)
        out[f"{m}_wall"] = np.array(time.perf_counter() - t0)
        print(
            f"{m} nonlinear: {c.kmh:.0f} km/h ({c.branch}), flange cycle from "
            f"{_kmh(out[f'{m}_flange'])}; upper {np.round(np.asarray(b.upper) * 1e3, 2)} mm at "
            f"{b.speeds_kmh}; wall {out[f'{m}_wall']:.0f} s",
            flush=True,
        )
        np.savez(store, **out)
    return out


def _kmh(x) -> str:
    x = float(x)
    return f"{x:.0f} km/h" if np.isfinite(x) else "none"


def report(d: dict, step: float) -> None:
    print(
        "\n| variant | linear, damper stuck | linear, sliding | nonlinear (lowest sustained "
        f"cycle, {step:.0f} km/h grid) | branch | flange cycle from | wall, s |"
    )
    print("|---|---|---|---|---|---|---|")
    for m in VARIANTS:
        if f"{m}_nonlinear" not in d:
            continue
        ls, lf = d[f"{m}_linear_stuck"], d[f"{m}_linear_sliding"]
        nl, below = d[f"{m}_nonlinear"]
        nls = f"{nl:.0f} km/h" if np.isfinite(nl) else f"none found (alive down to {below:.0f})"
        print(
            f"| {m} | {ls[0]:.1f} km/h, {ls[1]:.2f} Hz | {lf[0]:.1f} km/h, {lf[1]:.2f} Hz | "
            f"{nls} | {d[f'{m}_branch']} | {_kmh(d[f'{m}_flange'])} | "
            f"{float(d[f'{m}_wall']):.0f} |"
        )
    print("(paper, Kaiser: RR about 390, FR and RF about 350, FF 330 km/h or lower)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", default=",".join(VARIANTS))
    ap.add_argument("--top", type=float, default=420.0, help="top speed of the sweep, km/h")
    ap.add_argument("--step", type=float, default=40.0, help="sweep step, km/h")
    ap.add_argument("--duration", type=float, default=3.0, help="seconds per run")
    ap.add_argument("--bottom", type=float, default=100.0, help="the sweep's speeds stay above this, km/h")
    ap.add_argument(
        "--store",
        type=Path,
        nargs="*",
        default=[STORE],
        help="npz files: the first is written, all are read for the table (so "
        "models run in parallel processes can be reported together)",
    )
    ap.add_argument(
        "--independent",
        action="store_true",
        help="each speed from its own static state plus 6 mm (no continuation)",
    )
    ap.add_argument("--replot", action="store_true")
    a = ap.parse_args()
    if not a.replot:
        run(
            [m.strip() for m in a.models.split(",")],
            a.top,
            a.step,
            a.duration,
            a.bottom,
            a.store[0],
            a.independent,
        )
    d: dict = {}
    for f in a.store:
        d.update(dict(np.load(f)))
    report(d, a.step)


if __name__ == "__main__":
    main()
