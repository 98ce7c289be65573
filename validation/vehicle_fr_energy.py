"""Energy balance of the undamped, frictionless coach: RR and FR (issue 14's energy check).

Every damper and friction element removed (``System.without_damping``, friction 0), the
coach started from its static equilibrium at 50 m/s with the carbody 10 mm and the leading
bogie 3 mm high (vertical motion), and optionally the leading wheelset 0.5 mm to the side.
The total energy: kinetic (rigid and modal), the linear springs with the preload, the modal
stiffness, the journal springs' elastic parts (the 'split' couplings: 1/2 k u^2 - k (g.q) u
- f0 u) and the Hertz potential of every contact point (wheel output 'energy').

    .venv/bin/python validation/vehicle_fr_energy.py

A contact from a look-up table is not exactly conservative where its Hertz constant (and
contact angle) change with the pose: the force is the gap's gradient times the Hertz law, not
the gradient of 0.4 kH d^2.5 with kH varying. The energy check shows how much that matters,
and the strip contact (``geometry='strip'``: forces the exact gradient of one potential, the
'energy' output that potential) against it.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from railvti import scenarios
from railvti.errors import DivergenceError
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.params import Coach

V = 50.0


def energy(sy, r) -> np.ndarray:
    """Total energy at each output of run r of system sy (rigid + modal), J."""
    n = sy.n
    q, v = r.q[:, :n], r.v[:, :n]
    e = 0.5 * np.einsum("ti,ij,tj->t", v, sy.m, v) + 0.5 * np.einsum("ti,ij,tj->t", q, sy.k, q) \
        - q @ sy.f0 + r.wheel_output("energy").sum(axis=(1, 2))
    mb = sy.modal
    if mb is None:
        return e
    qm, vm = r.q[:, n:], r.v[:, n:]
    o = 0
    for kb in mb.stiffness:
        m = kb.shape[0]
        e += 0.5 * np.einsum("ti,ij,tj->t", qm[:, o:o + m], kb, qm[:, o:o + m])
        o += m
    e += 0.5 * np.sum(mb.mass * vm * vm, axis=1)      # massless (residual) coordinates: none
    cp = mb.couplings
    u = qm @ mb.phi.T
    for j, kind in enumerate(cp.kinds):
        if kind == "split":
            k, _, f0 = cp.params[:, j]
            up = u[:, cp.points[j]]
            e += 0.5 * k * up * up - k * (q @ cp.directions[:, j]) * up - f0 * up
    return e


def run(sy, kick_y: float, h: float, duration: float) -> str:
    x, _ = static_equilibrium(sy, V)
    x1 = x.copy()
    x1[sy.index("carbody_z")] += 0.01
    x1[sy.index("bogie1_z")] += 0.003
    x1[sy.index("ws1_y")] += kick_y
    # the oscillation's energy: the start against the static equilibrium
    try:
        r = simulate(sy, V, duration, q0=x1, h=h, output_dt=0.005, progress=False)
    except DivergenceError as err:
        r = err.result
        if r is None:
            return f"stopped: {err}"
    e = energy(sy, r)
    e_osc = abs(e[0] - energy(sy, type("S", (), {
        "q": x[None, :], "v": np.zeros((1, x.size)),
        "wheel_output": lambda self, name: r.wheel_output(name)[:1] * 0.0})())[0])
    return (f"{r.t[-1]:.2f} s: max |E - E0| = {np.abs(e - e[0]).max():.3g} J of {e_osc:.1f} J "
            f"({np.abs(e - e[0]).max() / e_osc:.2g})")


def main() -> None:
    table = scenarios.contact_table()
    rr = dataclasses.replace(scenarios.coach_system().without_damping(), friction=0.0)
    fr0, _ = build_fr(Coach(), table, V)
    fr = dataclasses.replace(fr0.without_damping(), friction=0.0)
    fz0, _ = build_fr(Coach(), table, V, zero_rows=True, rigid_gyro=False)
    fz = dataclasses.replace(fz0.without_damping(), friction=0.0)
    rrs = dataclasses.replace(scenarios.coach_system(geometry="strip").without_damping(),
                              friction=0.0)
    frs0, _ = scenarios.fr_system(speed=V, geometry="strip")
    frs = dataclasses.replace(frs0.without_damping(), friction=0.0)
    print("undamped, frictionless coach at 50 m/s, 2 s, h = 0.5 ms")
    print("  RR, vertical:                 ", run(rr, 0.0, 5e-4, 2.0))
    print("  FR (k_max 2, 800 Hz), vertical:", run(fr, 0.0, 5e-4, 2.0))
    print("  FR, zero rows, vertical:      ", run(fz, 0.0, 5e-4, 2.0))
    print("  RR, + 0.5 mm lateral:         ", run(rr, 5e-4, 5e-4, 2.0))
    print("  FR, + 0.5 mm lateral:         ", run(fr, 5e-4, 5e-4, 2.0))
    print("strip contact (geometry='strip'):")
    print("  RR, vertical:                 ", run(rrs, 0.0, 5e-4, 2.0))
    print("  RR, + 0.5 mm lateral:         ", run(rrs, 5e-4, 5e-4, 2.0))
    print("  RR, + 0.5 mm lateral, h/2:    ", run(rrs, 5e-4, 2.5e-4, 2.0))
    print("  FR, + 0.5 mm lateral:         ", run(frs, 5e-4, 5e-4, 2.0))
    print("  FR, + 0.5 mm lateral, h/2:    ", run(frs, 5e-4, 2.5e-4, 2.0))


if __name__ == "__main__":
    main()
