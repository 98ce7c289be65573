"""Bifurcation diagrams with the strip contact: RR on the table, RR and FR on the strips.

The table contact's single Hertz point per slot jumps at y = 0.2 mm (S1002 / UIC60 1:40) and
is up to 50 % off the BEM's sink in the band where RR keeps a 2 mm tread cycle at 300 km/h
(validation/contact_table_stiffness.py); its Newton fails in FR's flange impacts above
380 km/h. The strip contact (``geometry='strip'``; docs/vehicle.md "Strip contact") is
continuous and conservative. This script sweeps the speed down with continuation
(``scenarios.bifurcation``: the upper branch from 6 mm, the decay test from 0.5 mm) for

* RR, table (the default until now),
* RR, strip,
* FR, strip (k_max 1, f_max 300 Hz: the selection documented for critical-speed sweeps,
  validation/vehicle_fr_truncation_hunting.py; h = 0.5 ms: at 1 ms, the default for this
  selection, Newton fails in the flange impacts at 460 km/h even with h/64 sub-steps),

with Hertz + Kalker, and prints each branch and nonlinear critical speed; the figure is
validation/figures/vehicle_strip_bifurcation.png.

Run: python validation/vehicle_strip_bifurcation.py [duration_s]   (default 3 s per speed;
about 10 min on 2 cores)
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.errors import DivergenceError

FIG = Path(__file__).resolve().parent / "figures" / "vehicle_strip_bifurcation.png"
SPEEDS = list(range(460, 239, -20))
RUNS = (("RR", "table", {}), ("RR", "strip", {}), ("FR", "strip", {"k_max": 1, "f_max": 300.0, "h": 5e-4}))


def main() -> None:
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
    out, stopped = {}, []
    for model, geo, kw in RUNS:
        t0 = time.perf_counter()
        try:
            b = scenarios.bifurcation(SPEEDS, model, duration=duration, geometry=geo, progress=False, **kw)
        except DivergenceError as err:
            print(f"{model} {geo}: stopped, {err}")
            stopped.append(f"{model}, {geo}")
            continue
        wall = time.perf_counter() - t0
        out[(model, geo)] = b
        print(f"{model} {geo}: critical {b.critical_kmh:.0f} km/h ({b.branch}), {wall:.0f} s")
        for s, u, d in zip(b.speeds_kmh, b.upper, b.decay):
            print(f"   {s:5.0f} km/h  upper {u * 1e3:6.2f} mm  decay test {d * 1e3:6.2f} mm")
        sys.stdout.flush()
    _plot(out, duration, stopped)


def _plot(out: dict, duration: float, stopped: list[str]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for (model, geo), b in out.items():
        (line,) = ax.plot(
            b.speeds_kmh,
            np.asarray(b.upper) * 1e3,
            "o-",
            label=f"{model}, {geo}: upper branch (critical {b.critical_kmh:.0f} km/h)",
        )
        ax.plot(
            b.speeds_kmh,
            np.asarray(b.decay) * 1e3,
            "x--",
            color=line.get_color(),
            label=f"{model}, {geo}: from 0.5 mm",
        )
    ax.set_xlabel("speed, km/h")
    ax.set_ylabel("limit-cycle amplitude of wheelset 1, mm")
    ax.set_title(
        f"Bifurcation of hunting (coach, straight track), Hertz + Kalker, "
        f"{duration:g} s per speed:\ntable against strip contact"
        + (f"; not drawn (Newton failed in a flange impact): {', '.join(stopped)}" if stopped else ""),
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    FIG.parent.mkdir(exist_ok=True)
    fig.savefig(FIG, dpi=130)
    print(f"wrote {FIG}")


if __name__ == "__main__":
    main()
