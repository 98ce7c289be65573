"""The nonlinear critical speed of RR with the defaults, and hunting on either side of it.

With the default contact (Hertz + Kalker) and its default geometry (the strip contact,
``scenarios.DEFAULT_GEOMETRY``), ``critical_speed(model='RR', method='nonlinear')`` follows the
upper branch down from a 6 mm limit cycle in 20 km/h steps (4 s per speed) to the lowest
speed with a sustained cycle. The check of a critical speed is what it predicts for a plain
hunting run from the default 4 mm disturbance: 20 km/h above it the motion settles on a
cycle of more than 1 mm (amplitude over the last second), 20 km/h below it it decays below
0.5 mm. The same with the table geometry (``--table``) shows its artefact: a tread cycle
that the strips and the BEM do not have (issue 29).

Run: python validation/vehicle_critical_default.py [--duration 8] [--table]
(about 4 min on 2 cores; --table adds about 3 min)
"""

from __future__ import annotations

import argparse
import time

from railvti import scenarios


def check(geometry: str | None, duration: float) -> None:
    label = geometry or f"default ({scenarios.DEFAULT_GEOMETRY['hertz-kalker']})"
    t0 = time.perf_counter()
    kw = {} if geometry is None else {"geometry": geometry}
    c = scenarios.critical_speed(variant="RR", method="nonlinear", progress=False, **kw)
    b = c.bifurcation
    print(f"RR, Hertz + Kalker, geometry {label}: {c.message} [{time.perf_counter() - t0:.0f} s]")
    for s, u, d in zip(b.speeds_kmh, b.upper, b.decay):
        print(f"   {s:5.0f} km/h  upper branch {u * 1e3:6.2f} mm  from 0.5 mm {d * 1e3:6.2f} mm")
    if c.kmh != c.kmh:
        return
    for dv in (+20.0, -20.0):
        r = scenarios.hunting(c.kmh + dv, duration=duration, progress=False, **kw)
        amp = scenarios.amplitude(r)
        want = "> 1 mm" if dv > 0 else "< 0.5 mm"
        ok = amp > 1e-3 if dv > 0 else amp < 0.5e-3
        print(
            f"   hunting at {c.kmh + dv:.0f} km/h from 4 mm, {duration:g} s: amplitude over the "
            f"last second {amp * 1e3:.3f} mm (want {want}: {'yes' if ok else 'NO'})"
        )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=8.0, help="hunting runs, s")
    p.add_argument("--table", action="store_true", help="also the table geometry")
    a = p.parse_args()
    check(None, a.duration)
    if a.table:
        check("table", a.duration)


if __name__ == "__main__":
    main()
