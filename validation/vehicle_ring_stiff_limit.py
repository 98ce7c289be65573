"""The stiff limit of the track (issue 30, item 2): model RF's ring track and model RR's rigid
track elements with every track stiffness times ``--scale`` (rail Young's modulus, the pads'
and the ballast's stiffnesses on the ring; the elements' ky, kz, k_roll in RR), masses and
dampers as they are. Both then tend to the same rigid track, so RF must reproduce RR there,
as FR reproduces RR with a stiff wheelset (validation/vehicle_stiff_limit.py).

    .venv/bin/python validation/vehicle_ring_stiff_limit.py            # ~10 min on 2 shared cores
    .venv/bin/python validation/vehicle_ring_stiff_limit.py --scale 100

Prints the linear critical speeds (eigenvalues about centred running, bisection to 0.5 km/h;
RF: the ring's rows averaged over a sleeper bay) of RR and RF at scale 1 and at ``--scale``
(1e3), and RR at 1e6 (the rigid-track limit). The ring keeps the same modes at every scale:
all its frequencies scale by sqrt(scale), so f_limit does too (500 Hz x sqrt(scale)). RR's
track element is fitted to the ring's static receptances and first resonances
(railvti.track.TrackElement.from_ring), so at scale 1 the two differ by the ring's dynamics
only; at 1e3 by what is left of them. The ring has ``scenarios.RF_N_SLEEPERS`` sleepers.
"""

from __future__ import annotations

import argparse
import time

from railvti import scenarios
from railvti.track.ring import DEFAULTS as RING
from railvti.vehicle.params import DEFAULTS as COACH
from railvti.vehicle.params import Coach

#: The ring's stiffnesses scaled, and the rigid track elements'.
RING_STIFF = ("rail_young",) + tuple(k for k in RING if "stiffness" in k)
ELEMENT_STIFF = ("track_ky", "track_kz", "track_kroll")


def rr(scale: float) -> tuple[float, float]:
    coach = Coach(**{k: COACH[k][0] * scale for k in ELEMENT_STIFF})
    c = scenarios.critical_speed("RR", method="linear", tol_kmh=0.5, coach=coach)
    return c.kmh, c.frequency_hz


def rf(scale: float) -> tuple[float, float]:
    tp = {k: RING[k] * scale for k in RING_STIFF}
    c = scenarios.critical_speed(
        "RF", method="linear", tol_kmh=0.5, track_params=tp, f_limit=scenarios.RF_F_LIMIT * scale**0.5
    )
    return c.kmh, c.frequency_hz


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=1e3)
    a = ap.parse_args(argv)
    rows = []
    for name, fn, s in (
        ("RR", rr, 1.0),
        ("RF", rf, 1.0),
        (f"RR x {a.scale:g}", rr, a.scale),
        (f"RF x {a.scale:g}", rf, a.scale),
        ("RR x 1e6 (rigid)", rr, 1e6),
    ):
        t = time.perf_counter()
        v, f = fn(s)
        rows.append((name, v, f, time.perf_counter() - t))
        print(f"  {name}: {v:.3f} km/h [{rows[-1][3]:.0f} s]", flush=True)
    print("| model | linear critical speed, km/h | frequency, Hz | wall time, s |\n|---|---|---|---|")
    for n, v, f, w in rows:
        print(f"| {n} | {v:.3f} | {f:.4f} | {w:.0f} |")
    val = {n: v for n, v, _, _ in rows}
    print(
        f"scale 1: RF - RR = {100 * (val['RF'] / val['RR'] - 1):+.2f} %; "
        f"scale {a.scale:g}: RF - RR = "
        f"{100 * (val[f'RF x {a.scale:g}'] / val[f'RR x {a.scale:g}'] - 1):+.3f} % "
        "(the analogue of FR x 1e3 = RR: 0.5 %); "
        f"RF x {a.scale:g} - rigid track = "
        f"{100 * (val[f'RF x {a.scale:g}'] / val['RR x 1e6 (rigid)'] - 1):+.3f} %"
    )


if __name__ == "__main__":
    main()
