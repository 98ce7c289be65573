"""Validation of the wheel-rail geometry: profiles against the Manchester benchmark files,
rigid contact table of S1002 on UIC60 1:40 (gauge 1435 mm, back-to-back 1360 mm, r0 0.46 m),
equivalent conicity and Klingel wavelength.

Run:  .venv/bin/python validation/geometry_profiles_table.py
Writes validation/figures/geometry_*.png and prints tables.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from railvti import geometry as G
from railvti import profiles as P
from railvti.geometry.plots import plot_profiles, plot_table

FIG = Path(__file__).resolve().parent / "figures"
FIG.mkdir(exist_ok=True)


def polyline_distance(by, bz, gy, gz):
    ay, az, sy, sz = gy[:-1], gz[:-1], np.diff(gy), np.diff(gz)
    qy, qz = by[:, None] - ay, bz[:, None] - az
    t = np.clip((qy * sy + qz * sz) / (sy * sy + sz * sz), 0, 1)
    return np.sqrt(((qy - t * sy) ** 2 + (qz - t * sz) ** 2).min(axis=1))


def main() -> None:
    bw = P.read(P.example_path("MBench_S1002_v3.prw"))
    br = P.read(P.example_path("MBench_UIC60_v3.prr"))
    wheel, rail = P.s1002(), P.uic60(cant=1 / 40)

    print("== Profiles vs Manchester benchmark files")
    e = np.abs(P.s1002_mm(bw.y * 1e3) - bw.z * 1e3)
    print(f"S1002 analytic vs MBench_S1002_v3.prw points ({bw.y.size}): max |dz| = {e.max():.2e} mm")
    ys = bw.y[(bw.y > wheel.y_min) & (bw.y < wheel.y_max)]
    print(
        f"S1002 spline vs benchmark spline: max |dz| = {np.abs(wheel.height(ys) - bw.height(ys)).max() * 1e3:.2e} mm"
    )
    gy, gz = rail.sample(1e-4)
    m = br.z - br.z.min() < 0.033

    def res(p, full=False):
        d = polyline_distance(br.y[m] - p[0], br.z[m] - p[1] - p[2] * (br.y[m] - p[0]), gy, gz)
        inside = (br.y[m] > gy[0] + p[0] + 1e-4) & (br.y[m] < gy[-1] + p[0] - 1e-4)
        return np.where(inside, d, 0.0)

    sol = least_squares(res, [-0.0075, 0.0, 0.0], x_scale=[1e-3, 1e-3, 1e-3])
    d = res(sol.x)
    sol2 = least_squares(lambda p: res([p[0], p[1], 0.0]), [-0.0075, 0.0], x_scale=1e-3)
    d2 = res([*sol2.x, 0.0])
    print(f"UIC60 1:40 generated vs MBench_UIC60_v3.prr (head to 33 mm depth, {int(m.sum())} points):")
    print(
        f"  fitted offset of the benchmark origin: dy = {sol2.x[0] * 1e3:+.3f} mm, dz = {sol2.x[1] * 1e3:+.3f} mm"
        f"  -> max distance {d2.max() * 1e3:.4f} mm, rms {np.sqrt(np.mean(d2[d2 > 0] ** 2)) * 1e3:.4f} mm"
    )
    print(f"  with a free extra rotation: {sol.x[2] * 1e3:+.3f} mrad, max distance {d.max() * 1e3:.4f} mm")

    print("\n== Contact table S1002 / UIC60 1:40, 201 positions, yaw 0")
    y = np.linspace(-0.01, 0.01, 201)
    t = G.geometry_table(wheel, rail, y)
    tb = G.geometry_table(bw, br, y)
    print("   y mm   dr mm   angleL rad angleR rad roll mrad  nL nR statusL/R   | dr (benchmark files)")
    for i in range(100, 201, 10):
        print(
            f"{t.y[i] * 1e3:7.2f} {t.delta_r[i] * 1e3:7.3f} {t.contact_angle[i, 0, 0]:10.4f} "
            f"{t.contact_angle[i, 1, 0]:10.4f} {t.roll[i] * 1e3:9.4f} {t.n_contact[i, 0]:3d} {t.n_contact[i, 1]:2d}"
            f"   {G.STATUS_NAMES[t.status[i, 0]]:>12s}/{G.STATUS_NAMES[t.status[i, 1]]:<5s} | {tb.delta_r[i] * 1e3:7.3f}"
        )
    flange = t.y[np.argmax(t.contact_angle[:, 0, 0] > 1.0)]
    print(
        f"centred contact angle {t.contact_angle[100, 0, 0] * 1e3:.2f} mrad (cant {np.arctan(1 / 40) * 1e3:.2f} mrad); "
        f"flange contact (angle > 1 rad) from y = {flange * 1e3:.1f} mm; benchmark-file profiles: "
        f"{tb.y[np.argmax(tb.contact_angle[:, 0, 0] > 1.0)] * 1e3:.1f} mm"
    )
    okk = t.ok
    mirror = np.nanmax(np.abs(t.delta_r[okk] + t.delta_r[okk][::-1]))
    print(f"mirror check: max |dr(y) + dr(-y)| = {mirror:.1e} m")

    amps = np.linspace(0.0005, 0.006, 23)
    con = G.equivalent_conicity(t, amps)
    conb = G.equivalent_conicity(tb, amps)
    e0 = 0.5 * (t.y_track[100, 0, 0] - t.y_track[100, 1, 0])
    print("\n== Equivalent conicity (EN 15302 regression) and Klingel wavelength")
    print(" amplitude mm  tan(gamma_e)  (benchmark files)  Klingel wavelength m")
    for a_, c_, cb_ in zip(amps[1::4], con[1::4], conb[1::4]):
        print(f"  {a_ * 1e3:8.2f}  {c_:12.4f}  {cb_:12.4f}  {G.klingel_wavelength(c_, 0.46, e0):14.2f}")
    c3 = G.equivalent_conicity(t, 0.003)
    print(
        f"tan(gamma_e) at 3 mm = {c3:.4f}, e0 = {e0 * 1e3:.1f} mm, Klingel wavelength {G.klingel_wavelength(c3, 0.46, e0):.2f} m"
    )

    pts = [G.contact_points(wheel, rail, yy) for yy in (0.0, 0.004, 0.0063)]
    plot_profiles(wheel, rail, pts, FIG / "geometry_profiles.png")
    plot_table(t, FIG / "geometry_contact_table.png", conicity=(amps, con))
    print("\nfigures: validation/figures/geometry_profiles.png, geometry_contact_table.png")


if __name__ == "__main__":
    main()
