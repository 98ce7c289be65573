"""One wheelset body for models RR and FR (issue 30, item 1; railvti.vehicle.wheelset_body).

Checks: the coach's wheelset defaults are the FE wheelset's rigid part plus its lumped parts
and stay near the Manchester Benchmark's published wheelset (1813 kg, 1120 / 112 kg m^2,
Iwnicki 1998); the FE mass's polar moment equals the exact integration of the meridian
section; RR and FR have the same rigid-body mass matrix and the same gyroscopic damping,
and the gyroscopic term has the sign of dH/dt = M for a wheel spinning about +y.
"""

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_linear import state_tangent
from railvti.vehicle.params import Coach, speed_m_s
from railvti.vehicle.equilibrium import force_and_tangent, static_equilibrium
from railvti.vehicle.wheelset_body import coach_wheelset
from railvti.wheelset import Wheelset

V = speed_m_s(300.0)


@pytest.fixture(scope="module")
def body():
    return Wheelset().flexible_body(V, k_max=1, f_max=300.0)


def test_coach_defaults_are_the_fe_wheelset_plus_parts():
    b = coach_wheelset()
    c = Coach()
    for key, value in b.coach_params().items():
        assert c[key] == pytest.approx(value, rel=1e-5), key
    # the published benchmark wheelset (independent of the FE): mass kept, inertias close
    assert b.mass == pytest.approx(1813.0, rel=1e-12)
    assert b.spin_inertia == pytest.approx(112.0, rel=0.01)
    assert b.roll_inertia == pytest.approx(1120.0, rel=0.03)
    # the rotating parts only spin: axleboxes add mass and roll inertia, no spin inertia
    assert all(p.spin_inertia == 0.0 for p in b.parts if not p.rotating)
    assert b.spin_inertia > b.bare["spin_inertia"]


def test_fe_polar_moment_is_the_bare_wheelsets(body):
    """The FE consistent mass's polar moment (the FR body's) equals the exact integration."""
    assert body.polar_moment == pytest.approx(coach_wheelset().bare["spin_inertia"], rel=1e-9)


def test_rr_and_fr_share_the_rigid_body_and_its_gyroscopic_matrix(body):
    table = scenarios.wheel_table()
    rr = scenarios.coach_system("RR", geometry="table")
    fr, _ = build_fr(Coach(), table, V, body=body, zero_rows=True, residual=False)
    n = rr.n
    assert np.array_equal(fr.m, rr.m)
    assert np.array_equal(fr.spin_inertia, rr.spin_inertia)
    q, v, _ = static_equilibrium(rr, V, "hertz-kalker", return_velocity=True)
    _, _, _, jv_rr = force_and_tangent(rr, q, v, V, "hertz-kalker")
    x = np.concatenate([q, np.zeros(fr.n_state - n)])
    xd = np.concatenate([v, np.zeros(fr.n_state - n)])
    _, _, jv_fr = state_tangent(fr, V, x, xd)
    scale = np.abs(jv_rr).max()
    assert np.max(np.abs(jv_fr[:n, :n] - jv_rr)) < 1e-6 * scale
    # the skew gyroscopic part: without it the roll-yaw entries lose -+ I_y Omega
    rr0 = scenarios.coach_system("RR", geometry="table")
    from dataclasses import replace

    rr0 = replace(rr0, spin_inertia=np.zeros(4))
    _, _, _, jv0 = force_and_tangent(rr0, q, v, V, "hertz-kalker")
    h = Coach()["wheelset_pitch_inertia"] * V / rr.table.r0
    for w in range(4):
        a, b = rr.index(f"ws{w + 1}_roll"), rr.index(f"ws{w + 1}_yaw")
        # dH/dt = M with H = I_y Omega (e_y - yaw e_x + roll e_z): roll force +h yaw'
        assert jv_rr[a, b] - jv0[a, b] == pytest.approx(h, rel=1e-9)
        assert jv_rr[b, a] - jv0[b, a] == pytest.approx(-h, rel=1e-9)


def test_spin_inertia_must_match_the_wheelsets():
    from dataclasses import replace
    from railvti.errors import InputError

    rr = scenarios.coach_system("RR", geometry="table")
    with pytest.raises(InputError, match="spin_inertia"):
        replace(rr, spin_inertia=np.zeros(3))
    with pytest.raises(InputError, match="spin"):
        replace(rr, spin_inertia=np.full(4, -1.0))
