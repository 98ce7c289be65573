"""The contact models on a steady curve (issue 34, item 5: the speed-against-accuracy study
extended to curved track), against the BEM at 0.5 mm.

Scene `curve1200`: variant RR on the arc of R = 1200 m, 150 mm cant, at 160 km/h (cant
deficiency 102 mm), started in the steady state on the arc and run for 0.5 s. Compared, as
means over the last 0.2 s: the track-shifting force sum Y of each wheelset (the largest
error over the four), the wheel loads Q, the angle of attack of each wheelset, T gamma of the
outer leading wheel (the most worked one). Cost: CPU time of the whole call, one thread,
over the simulated time (RTF).

Run: OMP_NUM_THREADS=1 .venv/bin/python validation/vehicle_curving_models.py
Prints the table that railvti.vehicle.model_choice keeps for the scene 'curve'.
"""

from __future__ import annotations

import os
import time

import numpy as np

from railvti import scenarios
from railvti.track import TrackCurve
from railvti.vehicle.bem import BemOptions
from railvti.vehicle.simulate import simulate

V = 160 / 3.6
CURVE = TrackCurve(radius=1200.0, cant=0.15, transition_in=100.0, arc_length=1000.0, transition_out=100.0)
DURATION = 0.5
MODELS = [
    ("hertz-kalker (table)", "table", "hertz-kalker", None),
    ("hertz-fastsim (table)", "table", "hertz-fastsim", None),
    ("hertz-kalker (strip)", "strip", "hertz-kalker", None),
    ("hertz-fastsim (strip)", "strip", "hertz-fastsim", None),
    ("bem 1.5 mm", "strip", "bem", 1.5e-3),
    ("bem 1.0 mm", "strip", "bem", 1.0e-3),
    ("bem 0.75 mm", "strip", "bem", 0.75e-3),
    ("bem 0.5 mm", "strip", "bem", 0.5e-3),
]


def _measure(label, geometry, contact, dx):
    sy = scenarios.coach_system("RR", geometry=geometry)
    kw = {"bem_options": BemOptions(dx=dx)} if dx else {}
    t0 = time.process_time()
    r = simulate(
        sy, V, DURATION, contact=contact, curve=CURVE, x_start=500.0, output_dt=0.01, progress=False, **kw
    )
    cpu = time.process_time() - t0
    last = slice(-20, None)
    y = r.wheel_output("Y")[last].mean(axis=0)
    return {
        "rtf": cpu / DURATION,
        "sum_y": y.sum(axis=0),
        "Q": r.wheel_output("Q")[last].mean(axis=0),
        "aoa": np.array([r.dof(f"ws{w}_yaw")[last].mean() for w in (1, 2, 3, 4)]),
        "t_gamma": r.wheel_output("T_gamma")[last].mean(axis=0)[1, 0],
    }


def main() -> None:
    print(f"load {os.getloadavg()[0]:.2f}; scene curve1200: RR, R 1200 m, 150 mm, 160 km/h, {DURATION} s")
    res = {label: _measure(label, g, c, dx) for label, g, c, dx in MODELS}
    ref = res["bem 0.5 mm"]
    scale_y = np.abs(ref["sum_y"]).max()
    print("| model | RTF (CPU) | sum Y | Q | angle of attack | T gamma |")
    print("|---|---|---|---|---|---|")
    for label, m in res.items():
        e_y = 100 * np.abs(m["sum_y"] - ref["sum_y"]).max() / scale_y
        e_q = 100 * np.abs(m["Q"] / ref["Q"] - 1).max()
        e_a = 100 * np.abs(m["aoa"] - ref["aoa"]).max() / np.abs(ref["aoa"]).max()
        e_t = 100 * (m["t_gamma"] / ref["t_gamma"] - 1)
        print(f"| {label} | {m['rtf']:.2f} | {e_y:.2f} % | {e_q:.3f} % | {e_a:.2f} % | {e_t:+.1f} % |")
    print(
        f"reference: sum Y {np.round(ref['sum_y'] / 1e3, 3)} kN, angle of attack {np.round(ref['aoa'] * 1e3, 3)} mrad, T gamma {ref['t_gamma']:.1f} N"
    )


if __name__ == "__main__":
    main()
