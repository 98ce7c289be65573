"""The linear method's sleeper-bay average of the ring's contact rows (models RF and FF).

Checks against independent paths: the bay-averaged spectrum against the tangents recomputed
through the frozen path at each offset (build_rf, static_equilibrium, state_tangent) and
averaged here; a nearly rigid ring against RR on rigid ground (build_coach(track=False), its
own eigenvalues). Small rings (coarse section mesh), few offsets.
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle.linear_stability import bay_rates
from railvti.errors import InputError
from railvti.track import RingTrack
from railvti.track.ring import DEFAULTS
from railvti.vehicle.assembly import build_coach
from railvti.vehicle.flexible_linear import eigenvalues as fr_eigenvalues
from railvti.vehicle.params import Coach
from railvti.vehicle.ring_coupling import build_rf
from railvti.vehicle.equilibrium import eigenvalues
from railvti.vehicle.table import linearised_table
from coarse_ring import COARSE


def _hunting_growth(ev: np.ndarray) -> float:
    ev = ev[np.isfinite(ev)]
    osc = ev[(np.abs(ev.imag) > 0.1) & (np.abs(ev.imag) < 2 * np.pi * 20)]
    return float(osc.real.max())


def _table():
    return linearised_table(scenarios.wheel_table(), scenarios.equivalent_conicity(0.003))


def test_bay_average_is_mean_of_frozen_growth():
    """At 320 km/h, 4 offsets: the bay average's growth rates are those of four frozen
    systems built here (build_rf at each offset, flexible_linear.eigenvalues), their mean the rate
    the bisection uses; the offsets differ (the average is not one frozen position)."""
    n, v = 4, 320.0 / 3.6
    ring = RingTrack(40, **COARSE)
    spacing = ring.params["sleeper_spacing"]
    table = _table()
    frozen = [
        _hunting_growth(
            fr_eigenvalues(build_rf(Coach(), table, v, ring, f_limit=300.0, x_offset=k * spacing / n), v)
        )
        for k in range(n)
    ]
    rates, _ = bay_rates(
        "RF",
        Coach(),
        table,
        v,
        n,
        k_max=1,
        f_max=300.0,
        ring=dict(n_sleepers=40, f_limit=300.0, track_params=COARSE),
    )
    print(f"frozen growth per offset {np.round(frozen, 6)} 1/s, mean {np.mean(frozen):.6f}")
    np.testing.assert_allclose(rates, frozen, rtol=0, atol=1e-9)
    assert abs(np.mean(rates) - np.mean(frozen)) < 1e-9
    assert np.ptp(frozen) > 1e-3


@pytest.mark.slow
def test_stiff_ring_reproduces_rigid_ground():
    """A ring with rail, pads and ballast 100 times stiffer (modes kept to 5 kHz): the
    bay-averaged linear critical speed of RF within 0.5 % of RR's on rigid ground
    (build_coach(track=False), bisected here on its own eigenvalues). Model RR proper runs on
    its own compliant track elements (317.5 km/h), not on rigid ground."""
    sy = build_coach(Coach(), _table(), track=False)
    lo, hi = 300.0, 400.0
    while hi - lo > 1.0:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if _hunting_growth(eigenvalues(sy, mid / 3.6)) > 0 else (mid, hi)
    rigid = 0.5 * (lo + hi)
    stiff = dict(
        COARSE,
        f_max=5000.0,
        **{
            k: 100.0 * v
            for k, v in DEFAULTS.items()
            if k.startswith(("pad_stiffness", "ballast_stiffness", "rail_young"))
        },
    )
    v_stiff, _ = scenarios.linear_critical_speed_kmh(
        "RF",
        track_params=stiff,
        n_sleepers=40,
        f_limit=5000.0,
        v_lo_kmh=300.0,
        v_hi_kmh=400.0,
        tol_kmh=1.0,
        n_offsets=2,
    )
    print(f"rigid ground {rigid:.1f} km/h, stiff ring (bay average) {v_stiff:.1f} km/h")
    assert abs(v_stiff / rigid - 1) < 0.005


def test_ring_rows_bad_input():
    with pytest.raises(InputError, match="ring_rows"):
        scenarios.linear_critical_speed_kmh("RF", ring_rows="floquet", n_sleepers=40)
    with pytest.raises(InputError, match="n_offsets"):
        scenarios.linear_critical_speed_kmh("RF", n_offsets=0, n_sleepers=40)
