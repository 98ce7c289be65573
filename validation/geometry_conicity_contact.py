"""Equivalent conicity of S1002 on UIC60 1:40 (gauge 1435 mm, flange-back distance 1360 mm,
r0 460 mm) against CONTACT's published run of the Manchester benchmark, case A-2.2
(eve70a/CONTACT, examples/mbench_a22_{left,right}.ref_out; copied into
tests/data/contact_a22_reference_{left,right}.csv). CONTACT's rolling-radius difference is
ZCP_right(W) - ZCP_left(W) of its contact reference points; EN 15302's formula turns it into
tan(gamma_e), as railvti's own rigid geometry table is turned (tests/test_geometry_conicity_contact.py).

Run:  .venv/bin/python validation/geometry_conicity_contact.py
Prints the Delta-r table and tan(gamma_e) at 1-5 mm, writes validation/figures/geometry_conicity_contact.png.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from railvti import geometry as G
from railvti import profiles as P
from railvti._plotting import pyplot, save_figure

ROOT = Path(__file__).resolve().parent.parent
FIG = ROOT / "validation" / "figures"
FIG.mkdir(exist_ok=True)


def reference(side: str) -> dict[str, np.ndarray]:
    with open(ROOT / "tests" / "data" / f"contact_a22_reference_{side}.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("y_ws", "yaw", "zcp_w")}


def odd(v: np.ndarray) -> np.ndarray:
    return np.concatenate([-v[:0:-1], v])


def main() -> None:
    left, right = reference("left"), reference("right")
    y_c, yaw_c = odd(left["y_ws"]), odd(left["yaw"])
    dr_c = odd(right["zcp_w"] - left["zcp_w"])
    std = P.s1002(), P.uic60(cant=1 / 40)
    bench = P.read(P.example_path("MBench_S1002_v3.prw")), P.read(P.example_path("MBench_UIC60_v3.prr"))
    y = np.linspace(-0.006, 0.006, 241)  # 0.05 mm
    t_std = G.geometry_table(*std, y)
    t_bench = G.geometry_table(*bench, y)
    near = np.abs(y_c) <= 6.0
    t_yaw = G.geometry_table(*bench, y_c[near] * 1e-3, yaw_c[near])
    t_grid = G.geometry_table(*bench, y_c[near] * 1e-3)

    print("Delta-r, mm (A-2.2 positions; CONTACT elastic at 10 kN per wheel, railvti rigid)")
    print("   y mm  yaw mrad   CONTACT  railvti(files, A-2.2 yaw)  railvti(files, yaw 0)  railvti(standards)")
    for i, k in enumerate(np.flatnonzero(near)):
        if y_c[k] < 0:
            continue
        j = int(np.argmin(np.abs(y - y_c[k] * 1e-3)))
        print(
            f"  {y_c[k]:5.1f}  {yaw_c[k] * 1e3:8.1f}  {dr_c[k]:8.4f}  {t_yaw.delta_r[i] * 1e3:16.4f}"
            f"  {t_grid.delta_r[i] * 1e3:20.4f}  {t_std.delta_r[j] * 1e3:17.4f}"
        )

    amps = np.arange(1.0, 5.01, 0.25)
    c_contact = G.conicity_of_delta_r(y_c, dr_c, amps)
    c_std = G.equivalent_conicity(t_std, amps * 1e-3)
    c_bench = G.equivalent_conicity(t_bench, amps * 1e-3)
    c_yaw = G.conicity_of_delta_r(y_c[near], t_yaw.delta_r * 1e3, amps)
    c_grid = G.conicity_of_delta_r(y_c[near], t_grid.delta_r * 1e3, amps)
    print("\ntan(gamma_e), EN 15302 formula")
    print(" A mm  CONTACT  standards  files  files on CONTACT's 0.5 mm grid (yaw 0 / A-2.2 yaw)")
    for a, c0, c1, c2, c3, c4 in zip(amps, c_contact, c_std, c_bench, c_grid, c_yaw):
        if abs(a - round(a)) < 1e-9:
            print(f" {a:4.1f}  {c0:7.4f}  {c1:9.4f}  {c2:5.4f}  {c3:16.4f} / {c4:.4f}")
    k3 = int(np.argmin(np.abs(amps - 3.0)))
    print(
        f"at 3 mm: railvti - CONTACT = {c_std[k3] - c_contact[k3]:+.4f} (standards), "
        f"{c_bench[k3] - c_contact[k3]:+.4f} (benchmark files); of the latter, sampling "
        f"{c_bench[k3] - c_grid[k3]:+.4f}, yaw {c_grid[k3] - c_yaw[k3]:+.4f}, the rest {c_yaw[k3] - c_contact[k3]:+.4f}"
    )

    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(y * 1e3, t_std.delta_r * 1e3, label="railvti, S1002 / UIC60 1:40 (standards)")
    ax1.plot(y * 1e3, t_bench.delta_r * 1e3, "--", label="railvti, benchmark profile files")
    ax1.plot(y_c[near], dr_c[near], "ko", ms=4, label="CONTACT, Manchester A-2.2 (ref_out)")
    ax1.set_xlabel("lateral shift y, mm")
    ax1.set_ylabel("rolling-radius difference, mm")
    ax1.set_title("Delta-r: gauge 1435 mm, back-to-back 1360 mm")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=7)
    ax2.plot(amps, c_std, label="railvti, standards' profiles")
    ax2.plot(amps, c_bench, "--", label="railvti, benchmark files")
    ax2.plot(amps, c_contact, "ko-", ms=3, label="from CONTACT's Delta-r")
    ax2.fill_between(amps, c_contact - 0.01, c_contact + 0.01, color="0.85", label="CONTACT +- 0.01")
    ax2.set_xlabel("amplitude A, mm")
    ax2.set_ylabel("tan(gamma_e), -")
    ax2.set_title("equivalent conicity (EN 15302 formula)")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=7)
    out = FIG / "geometry_conicity_contact.png"
    save_figure(fig, out)
    print(f"\nfigure: {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
