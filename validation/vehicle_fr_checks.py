"""Model FR checks of issue 14 (docs/vehicle_integrator.md, "Flexible wheelsets (FR)").

    .venv/bin/python validation/vehicle_fr_checks.py static   # coupled statics vs FE (~1 min)
    .venv/bin/python validation/vehicle_fr_checks.py kick     # lateral kicks, RR and FR (~5 min)
    .venv/bin/python validation/vehicle_fr_checks.py energy   # energy drift by rim rows (~1 min)
    .venv/bin/python validation/vehicle_fr_checks.py timing   # 1 s of centred running (~1 min)

static: the leading wheelset's rim rotation and contact-point displacement of the coupled
static equilibrium (200 km/h, Hertz + Kalker) against the direct static FE solve under the
same contact and journal forces (``static_fe_solve(..., inertia_relief=True)``), with and
without the residual flexibility, at two truncations, and with the rim rows at the taping
line and at the static contact point (+3 mm).
kick: max |y| of the leading wheelset after a lateral kick at 300 km/h (1 s, h = 0.5 ms).
energy: the undamped frictionless coach's energy error (vehicle_fr_energy.py's settings,
vertical motion) with only some of the rims' rows kept.
timing: wall time of 1 s of centred running at 200 km/h, h = 0.5 ms, after the static solve.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from railvti import scenarios
from railvti.vehicle import simulate, static_equilibrium
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_points import (
    attachment_deflection,
    attachment_loads,
    point_forces,
    rim_rail_angle_change,
)
from railvti.vehicle.params import Coach, speed_m_s
from railvti.wheelset import Wheelset
from railvti.wheelset.statics import static_fe_solve

sys.path.insert(0, str(Path(__file__).resolve().parent))


def static() -> None:
    v = speed_m_s(200.0)
    ws = Wheelset()
    table = scenarios.wheel_table()
    print("coupled statics vs static FE solve, leading wheelset, right wheel, 200 km/h")
    for km, fm, s_c in ((2, 800.0, 0.0), (1, 300.0, 0.0), (2, 800.0, 3e-3)):
        body = ws.flexible_body(v, k_max=km, f_max=fm)
        for res in (True, False) if s_c == 0.0 else (True,):
            sy, lay = build_fr(
                Coach(), table, v, body=body, wheelset=ws, residual=res, flexible=(0,), s_contact=s_c
            )
            q, qd, _ = static_equilibrium(sy, v, "hertz-kalker", return_velocity=True)
            f = attachment_loads(sy, lay[0], point_forces(sy, v, q, qd))
            d = attachment_deflection(sy, lay[0], q)
            ref = static_fe_solve(ws, f, s_pair=(s_c, s_c), inertia_relief=True)
            ang = rim_rail_angle_change(sy, q)[:, 0]
            err = ", ".join(
                f"{n} {d[i] * sc:.4f} ({100 * (d[i] / ref[i] - 1):+.3f} %)"
                for n, i, sc in (("camber mrad", 3, 1e3), ("y um", 1, 1e6), ("z um", 2, 1e6))
            )
            print(
                f"  k_max {km} / {fm:.0f} Hz, s = {s_c * 1e3:.0f} mm, residual {res}: {err}; "
                f"rim-rail angle change {ang[0] * 1e3:+.3f} / {ang[1] * 1e3:+.3f} mrad"
            )


def kick() -> None:
    v = speed_m_s(300.0)
    table = scenarios.wheel_table()
    fr, lay = build_fr(Coach(), table, v)

    def rows_zeroed(rows):
        phi = np.array(fr.modal.phi)
        for L in lay:
            phi[L.points.start + np.array(rows)] = 0.0
        return fr.with_modal(dataclasses.replace(fr.modal, phi=phi))

    cases = [
        ("RR", scenarios.coach_system("RR"), 0.1),
        ("RR", scenarios.coach_system("RR"), 0.05),
        ("FR, no residual, no Euler", build_fr(Coach(), table, v, residual=False, euler=False)[0], 0.1),
        ("FR", fr, 0.1),
        ("FR, rim rx rows zero", rows_zeroed([2, 5]), 0.1),
        ("FR, only rim rx rows", rows_zeroed([0, 1, 3, 4]), 0.1),
        ("FR", fr, 0.3),
    ]
    print("lateral kick on the leading wheelset, 300 km/h, 1 s, h = 0.5 ms")
    for name, sy, k in cases:
        q, qd, _ = static_equilibrium(sy, v, "hertz-kalker", return_velocity=True)
        qd = qd.copy()
        qd[sy.index("ws1_y")] += k
        r = simulate(sy, v, 1.0, q0=q, v0=qd, h=5e-4, output_dt=1e-3, progress=False)
        y = r.q[:, sy.index("ws1_y")]
        print(
            f"  {name}, {k} m/s: max |y| {np.abs(y).max() * 1e3:.3f} mm, last 0.1 s "
            f"{np.abs(y[r.t > 0.9]).max() * 1e3:.4f} mm"
        )


def energy() -> None:
    from vehicle_fr_energy import V, run

    table = scenarios.wheel_table()
    f0, lay = build_fr(Coach(), table, V)
    print("undamped frictionless coach, vertical motion, 2 s, h = 0.5 ms: max |E - E0| / E_osc")
    for name, rows in (
        ("all rim rows", []),
        ("only the vertical rows", [0, 2, 3, 5]),
        ("only the lateral rows", [1, 2, 4, 5]),
        ("only the camber rows", [0, 1, 3, 4]),
    ):
        phi = np.array(f0.modal.phi)
        for L in lay:
            for r in rows:
                phi[L.points.start + r] = 0.0
        sy = f0.with_modal(dataclasses.replace(f0.modal, phi=phi))
        fr = dataclasses.replace(sy.without_damping(), friction=0.0)
        print(f"  FR, {name}: {run(fr, 0.0, 5e-4, 2.0)}")


def timing() -> None:
    v = speed_m_s(200.0)
    body = Wheelset().flexible_body(v)
    table = scenarios.wheel_table()
    systems = [
        ("RR", scenarios.coach_system("RR")),
        (
            "FR without residual, Euler, rigid gyro",
            build_fr(Coach(), table, v, body=body, residual=False, euler=False, rigid_gyro=False)[0],
        ),
        ("FR (defaults)", build_fr(Coach(), table, v, body=body)[0]),
    ]
    print("1 s of centred running at 200 km/h, h = 0.5 ms, Hertz + Kalker (best of 2)")
    for name, sy in systems:
        q, qd, _ = static_equilibrium(sy, v, "hertz-kalker", return_velocity=True)
        best = np.inf
        for _ in range(2):
            t0 = time.perf_counter()
            simulate(sy, v, 1.0, q0=q, v0=qd, h=5e-4, progress=False)
            best = min(best, time.perf_counter() - t0)
        print(f"  {name}: {best:.2f} s ({sy.n_state} state entries)")


if __name__ == "__main__":
    tasks = {"static": static, "kick": kick, "energy": energy, "timing": timing}
    for arg in sys.argv[1:] or list(tasks):
        tasks[arg]()
