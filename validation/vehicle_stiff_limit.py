"""The stiff limit of the flexible wheelset (issue 30, item 2): model FR with the FE wheelset's
Young's modulus times ``wheelset_stiffness_scale`` = 1e3 (every elastic frequency x 31.6, the
same modes kept) against model RR, which carries the same wheelset body
(railvti.vehicle.wheelset_body) and gyroscopic moments.

    .venv/bin/python validation/vehicle_stiff_limit.py            # ~15 min on 2 shared cores
    .venv/bin/python validation/vehicle_stiff_limit.py --duration 2

Prints the linear critical speeds (eigenvalues, bisection to 0.5 km/h) of RR, FR and FR x 1e3,
and the hunting amplitude at 400 km/h (Hertz + Kalker on the strips, from 4 mm, the amplitude of
the leading wheelset over the last second) of RR and FR x 1e3. Acceptance: FR x 1e3 within
0.5 % of RR's linear critical speed and 1 % of its amplitude. FR runs with k_max = 1 and f_max
= 300 Hz (the study's cheap selection) so that the stiff modes (up to 9.5 kHz) need a step of
33 us rather than 12 us.
"""

from __future__ import annotations

import argparse
import time

from railvti import scenarios
from railvti.vehicle.params import Coach

SEL = dict(k_max=1, f_max=300.0)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=3.0, help="hunting run, s")
    ap.add_argument("--speed-kmh", type=float, default=400.0)
    a = ap.parse_args(argv)
    stiff = Coach(wheelset_stiffness_scale=1e3)
    rows = []
    t = time.perf_counter()
    rr = scenarios.critical_speed("RR", method="linear", tol_kmh=0.5)
    rows.append(("RR", "linear", rr.kmh, time.perf_counter() - t))
    for name, coach in (("FR", Coach()), ("FR x 1e3", stiff)):
        t = time.perf_counter()
        c = scenarios.critical_speed("FR", method="linear", tol_kmh=0.5, coach=coach, **SEL)
        rows.append((name, "linear", c.kmh, time.perf_counter() - t))
    amp = {}
    for name, model, kw in (("RR", "RR", {}), ("FR x 1e3", "FR", dict(coach=stiff, **SEL))):
        t = time.perf_counter()
        r = scenarios.hunting(a.speed_kmh, model, duration=a.duration, **kw)
        amp[name] = scenarios.amplitude(r)
        rows.append((name, f"hunting {a.speed_kmh:g} km/h", amp[name] * 1e3, time.perf_counter() - t))
    print("| model | quantity | value | wall time, s |\n|---|---|---|---|")
    for n, q, v, w in rows:
        unit = "km/h" if q == "linear" else "mm"
        print(f"| {n} | {q} | {v:.3f} {unit} | {w:.0f} |")
    lin = {n: v for n, q, v, _ in rows if q == "linear"}
    print(
        f"linear: FR x 1e3 - RR = {100 * (lin['FR x 1e3'] / lin['RR'] - 1):+.3f} % "
        f"(acceptance 0.5 %); FR - RR = {100 * (lin['FR'] / lin['RR'] - 1):+.2f} %"
    )
    print(f"hunting: FR x 1e3 - RR = {100 * (amp['FR x 1e3'] / amp['RR'] - 1):+.3f} % (acceptance 1 %)")


if __name__ == "__main__":
    main()
