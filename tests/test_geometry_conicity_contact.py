"""Equivalent conicity of S1002 on UIC60 1:40 at gauge 1435 mm against an independent code's
published output: CONTACT's reference run of the Manchester contact benchmark, case A-2.2.

Source: repository eve70a/CONTACT (E.A.H. Vollebregt, Apache-2.0), examples/mbench_a22_left.ref_out
and mbench_a22_right.ref_out, commit d431cdb; the numbers as copied into
tests/data/contact_a22_reference_{left,right}.csv (see their headers). Inputs of that run (its
.inp decks and the benchmark definition, Shackleton & Iwnicki, Vehicle System Dynamics 46, 2008):
profiles MBench_S1002_v3.prw on MBench_UIC60_v3.prr (UIC60 inclined 1:40 in the file; the decks'
CANT is 0), track gauge 1435 mm measured 14 mm below the rail top, flange-back distance 1360 mm,
nominal wheel radius 460 mm, 10 kN per wheel, elastic contact (G = 82 GPa, nu = 0.28), wheelset
shifted y = 0 .. 10 mm in 0.5 mm steps with the case's yaw 2.4 mrad per mm of shift.

CONTACT prints no conicity; it prints each patch's contact reference point on the wheel profile
(YCP(W), ZCP(W); z points down, away from the axle, so the rolling radius is 460 mm + ZCP(W)). Its
rolling-radius difference Delta-r(y) = ZCP_right(W) - ZCP_left(W), extended as an odd function,
gives tan(gamma_e) by EN 15302's formula (the one checked on the standard's case E1 in
tests/test_geometry_conicity_en15302.py). Measured: CONTACT 0.1824 at 3 mm; railvti's rigid
geometry 0.1786 (S1002 and UIC60 1:40 generated from their standards) and 0.1851 (the benchmark's
profile files). Of the 0.0027 between CONTACT and railvti on the same files, the A-2.2 yaw accounts
for 0.0004 and the 0.5 mm sampling for 0.0001; the rest is elastic against rigid contact next to
the two-point jump (Delta-r at y = 0.5 mm: 0.397 against 0.552 mm).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from railvti import geometry as G
from railvti import profiles as P

DATA = Path(__file__).resolve().parent / "data"
#: Amplitudes compared, mm (EN 15302 and the TSI quote 3 mm).
AMPLITUDES = (2.0, 3.0, 4.0)
#: The issue's tolerance on tan(gamma_e).
TOL = 0.01


def _reference(side: str) -> dict[str, np.ndarray]:
    with open(DATA / f"contact_a22_reference_{side}.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("y_ws", "yaw", "zcp_w")}


@pytest.fixture(scope="module")
def contact_delta_r() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CONTACT's Delta-r (mm) on y in [-10, 10] mm, odd in y, with the cases' yaw (rad)."""
    left, right = _reference("left"), _reference("right")
    assert np.array_equal(left["y_ws"], right["y_ws"]) and np.array_equal(left["yaw"], right["yaw"])
    y, yaw = left["y_ws"], left["yaw"]
    dr = right["zcp_w"] - left["zcp_w"]  # shift to the right: the right wheel rolls on the larger radius
    return (
        np.concatenate([-y[:0:-1], y]),
        np.concatenate([-yaw[:0:-1], yaw]),
        np.concatenate([-dr[:0:-1], dr]),
    )


def _benchmark_profiles():
    return P.read(P.example_path("MBench_S1002_v3.prw")), P.read(P.example_path("MBench_UIC60_v3.prr"))


def _railvti_conicity(wheel, rail) -> np.ndarray:
    y = np.linspace(-0.0045, 0.0045, 181)  # 0.05 mm steps
    table = G.geometry_table(wheel, rail, y)  # gauge 1435 mm at 14 mm, back-to-back 1360 mm, r0 0.46 m
    return np.asarray(G.equivalent_conicity(table, np.array(AMPLITUDES) * 1e-3))


def test_contact_delta_r_is_a_rolling_radius_difference(contact_delta_r):
    """The sign convention read off CONTACT's output: Delta-r grows with the shift on the tread."""
    y, _, dr = contact_delta_r
    tread = (y > 0) & (y <= 4.5)
    assert np.all(np.diff(dr[tread]) > 0) and dr[tread].min() > 0


@pytest.mark.parametrize("profiles", ["standards", "benchmark files"])
def test_s1002_uic60_conicity_within_0_01_of_contact(contact_delta_r, profiles):
    y, _, dr = contact_delta_r
    reference = np.asarray(G.conicity_of_delta_r(y, dr, np.array(AMPLITUDES)))
    if profiles == "standards":
        wheel, rail = P.s1002(), P.uic60(cant=1 / 40)
    else:
        wheel, rail = _benchmark_profiles()
    ours = _railvti_conicity(wheel, rail)
    assert np.all(np.abs(ours - reference) <= TOL), (
        f"{profiles}: {ours.round(4)}, CONTACT {reference.round(4)}"
    )


def test_delta_r_on_the_tread_matches_contact_at_the_benchmark_positions(contact_delta_r):
    """Point by point, at the A-2.2 positions (shift and yaw), on the tread (1 .. 4.5 mm): railvti's
    rigid Delta-r on the benchmark files within 0.04 mm of CONTACT's elastic one."""
    y, yaw, dr = contact_delta_r
    keep = (y >= 1.0) & (y <= 4.5)
    bw, br = _benchmark_profiles()
    table = G.geometry_table(bw, br, y[keep] * 1e-3, yaw[keep])
    assert np.all(table.ok)
    assert np.max(np.abs(table.delta_r * 1e3 - dr[keep])) <= 0.04
