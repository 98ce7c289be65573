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

The energy-conserving integrator (``simulate(integrator='energy')``; docs/vehicle.md,
"Energy-conserving integrator"), second part (alone: ``vehicle_fr_energy.py scheme``): model
FR at the scenario defaults (k_max 2, f_max 800 Hz, residual flexibility) on the strip
geometry, undamped and frictionless, at 200 km/h, the leading wheelset released 0.5 mm to the
side, 10 s at h = 0.5 ms with both schemes: the largest relative energy error over every step
and the wall times, the chart validation/figures/vehicle_fr_energy.png; then the order check
(the trajectory at h = 125, 62.5, 31.25 us against h = 3.9 us over 0.02 s).
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

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
    e = (
        0.5 * np.einsum("ti,ij,tj->t", v, sy.m, v)
        + 0.5 * np.einsum("ti,ij,tj->t", q, sy.k, q)
        - q @ sy.f0
        + r.wheel_output("energy").sum(axis=(1, 2))
    )
    mb = sy.modal
    if mb is None:
        return e
    qm, vm = r.q[:, n:], r.v[:, n:]
    o = 0
    for kb in mb.stiffness:
        m = kb.shape[0]
        e += 0.5 * np.einsum("ti,ij,tj->t", qm[:, o : o + m], kb, qm[:, o : o + m])
        o += m
    e += 0.5 * np.sum(mb.mass * vm * vm, axis=1)  # massless (residual) coordinates: none
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
    e_osc = abs(
        e[0]
        - energy(
            sy,
            type(
                "S",
                (),
                {
                    "q": x[None, :],
                    "v": np.zeros((1, x.size)),
                    "wheel_output": lambda self, name: r.wheel_output(name)[:1] * 0.0,
                },
            )(),
        )[0]
    )
    return (
        f"{r.t[-1]:.2f} s: max |E - E0| = {np.abs(e - e[0]).max():.3g} J of {e_osc:.1f} J "
        f"({np.abs(e - e[0]).max() / e_osc:.2g})"
    )


def main() -> None:
    table = scenarios.wheel_table()
    rr = dataclasses.replace(scenarios.coach_system().without_damping(), friction=0.0)
    fr0, _ = build_fr(Coach(), table, V)
    fr = dataclasses.replace(fr0.without_damping(), friction=0.0)
    fz0, _ = build_fr(Coach(), table, V, zero_rows=True)
    fz = dataclasses.replace(fz0.without_damping(), friction=0.0)
    rrs = dataclasses.replace(scenarios.coach_system(geometry="strip").without_damping(), friction=0.0)
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


#: The energy-conserving scheme's run: speed (m/s), kick (m), step (s), Newton tolerance (m).
SPEED_FR, KICK, H_FR, TOL_FR = 200.0 / 3.6, 5e-4, 5e-4, 1e-9
FIG = Path(__file__).parent / "figures" / "vehicle_fr_energy.png"


def fr_conservative():
    """Model FR at the scenario defaults on the strip geometry, undamped and frictionless, and
    its energy E(q, v, W) over the whole state (J): the dense M, K of
    flexible_linear.linear_matrices (coach, modal blocks, residual flexibility, journal
    couplings), the constant loads' work (coach preloads, the couplings' through Phi) and the
    contacts' potential W."""
    from railvti.vehicle.flexible_linear import linear_matrices

    sy0, _ = scenarios.fr_system(speed=SPEED_FR, geometry="strip")
    sy = dataclasses.replace(sy0.without_damping(), friction=0.0)
    m, _, k = linear_matrices(sy)
    k = 0.5 * (k + k.T)
    n, mb = sy.n, sy.modal
    f0 = np.zeros(sy.n_state)
    f0[:n] = sy.f0
    for j, kind in enumerate(mb.couplings.kinds):
        if kind == "split":
            f0[n:] += mb.couplings.params[2, j] * mb.phi[mb.couplings.points[j]]

    def e_of(q, v, w):
        return 0.5 * np.einsum("ti,ij,tj->t", v, m, v) + 0.5 * np.einsum("ti,ij,tj->t", q, k, q) - q @ f0 + w

    return sy, e_of


def kicked(sy):
    """The static state and the start (leading wheelset 0.5 mm to the left, the massless
    coordinates consistent with it: integrator='energy' starts there)."""
    from railvti.vehicle.simulate import consistent_massless

    x, _ = static_equilibrium(sy, SPEED_FR)
    x1 = x.copy()
    x1[sy.index("ws1_y")] += KICK
    return x, consistent_massless(sy, SPEED_FR, x1)


def scheme_run(sy, e_of, integrator: str, duration: float, h: float, output_dt: float):
    """One run from the kick: (result, relative energy error per output, wall time s); the
    error relative to the kick's energy (the start against the static state)."""
    from railvti.vehicle.model import CallSettings

    x, x1 = kicked(sy)

    def w_at(xx):
        return np.array([sy.native.state_force(CallSettings(SPEED_FR, 1), xx, np.zeros_like(xx))[1][8].sum()])

    zero = np.zeros((1, x.size))
    e_static = e_of(x[None], zero, w_at(x))[0]
    e_start = e_of(x1[None], zero, w_at(x1))[0]
    t0 = time.perf_counter()
    r = simulate(
        sy,
        SPEED_FR,
        duration,
        q0=x1,
        h=h,
        output_dt=output_dt,
        progress=False,
        integrator=integrator,
        tol=TOL_FR,
    )
    wall = time.perf_counter() - t0
    e = e_of(r.q, r.v, r.wheel_output("energy").sum(axis=(1, 2)))
    return r, np.abs(e - e_start) / abs(e_start - e_static), wall


def scheme_comparison(duration: float = 10.0) -> None:
    """10 s of the kicked FR run with both schemes: max relative energy error, wall times,
    the chart."""
    sy, e_of = fr_conservative()
    print(
        f"model FR (k_max 2, f_max 800 Hz, residual flexibility), strip, undamped, mu = 0, "
        f"{SPEED_FR * 3.6:.0f} km/h, ws1 +{KICK * 1e3:.1f} mm, {duration:g} s, h = {H_FR * 1e3:g} ms, "
        f"Newton tol {TOL_FR:g} m"
    )
    curves = {}
    for name in ("hht", "energy"):
        r, err, wall = scheme_run(sy, e_of, name, duration, H_FR, H_FR)
        curves[name] = (r.t, err)
        print(
            f"  {name:6s}: max |E - E0| / E_kick = {err.max():.3g} (at {r.t[np.argmax(err)]:.3f} s), "
            f"at the end {err[-1]:.3g}; wall {wall:.1f} s, Newton iterations "
            f"{r.stats['newton_iterations']:.0f}",
            flush=True,
        )
    plot(curves, duration)


def plot(curves: dict, duration: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    labels = {
        "hht": "default: trapezoidal rule (HHT alpha = 0)",
        "energy": "integrator='energy': midpoint + discrete gradient",
    }
    for name, (t, err) in curves.items():
        # the running maximum over each 10 ms: the trapezoidal rule's error oscillates at the
        # contact frequencies
        k = max(1, int(round(0.01 / H_FR)))
        nb = t.size // k
        ax.semilogy(
            t[k - 1 : nb * k : k], err[: nb * k].reshape(nb, k).max(axis=1) + 1e-16, label=labels[name]
        )
    ax.axhline(1e-5, color="k", ls=":", lw=1, label="issue 14 acceptance: 1e-5")
    ax.set_xlabel("time t, s")
    ax.set_ylabel("|E(t) - E(0)| / kick energy (max per 10 ms), 1")
    ax.set_title(
        f"Model FR, undamped, frictionless, strip contact, {SPEED_FR * 3.6:.0f} km/h, "
        f"h = {H_FR * 1e3:g} ms: energy error, {duration:g} s"
    )
    ax.set_xlim(0, duration)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize=9)
    fig.tight_layout()
    fig.savefig(FIG, dpi=110)
    print(f"  chart: {FIG}")


def order_check(duration: float = 0.02, h0: float = H_FR / 4) -> None:
    """The energy scheme's trajectory at h0, h0/2, h0/4 against h0/32: max over the common
    outputs (every h0) of |q - q_ref| over the rigid DOFs (m, rad). Undamped, the track
    elements under the wheels ring at their contact frequencies (omega h near 1 at
    h = 0.5 ms): the asymptotic (second-order) range starts below that, hence h0 = 125 us."""
    sy, e_of = fr_conservative()
    n = sy.n
    h_ref = h0 / 32
    ref, _, _ = scheme_run(sy, e_of, "energy", duration, h_ref, h0)
    print(
        f"order check: integrator='energy', {duration:g} s, reference h = {h_ref * 1e6:.2f} us; "
        "max |q - q_ref| over the rigid DOFs (m, rad), ws1_y (m)"
    )
    prev = None
    for h in (h0, h0 / 2, h0 / 4):
        r, _, wall = scheme_run(sy, e_of, "energy", duration, h, h0)
        dd = np.abs(r.q[:, :n] - ref.q[:, :n]).max(axis=0)
        d = dd.max()
        worst = sy.dof_names[int(np.argmax(dd))]
        dy = np.abs(r.dof("ws1_y") - ref.dof("ws1_y")).max()
        order = "" if prev is None else f", order {np.log2(prev / d):.2f}"
        print(
            f"  h = {h * 1e6:6.2f} us: {d:.3g} ({worst}; ws1_y {dy:.3g}){order}; wall {wall:.1f} s",
            flush=True,
        )
        prev = d


if __name__ == "__main__":
    if sys.argv[1:] != ["scheme"]:
        main()
    scheme_comparison()
    order_check()
