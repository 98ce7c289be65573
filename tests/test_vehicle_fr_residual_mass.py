"""Model FR's residual flexibility with a mass (build_fr(residual_mass=True), the default).

The truncated modes' static compliance R at the rim and journal points enters as a block per
wheelset; its coordinates get the modal mass k_i / w^2 (railvti.vehicle.modal_blocks.with_mass) so that
Newton goes through flange-only contact, where the saturated creep force drives massless
coordinates' rates. Checks: the static state is the massless block's (the same compliance);
the block's natural frequency is the one asked for; a flange impact that stops Newton with
massless coordinates runs through with the mass (both asserted).
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import InputError
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.params import Coach
from railvti.vehicle.equilibrium import lateral_disturbance, static_equilibrium
from railvti.vehicle.simulate import simulate

SMALL = {"k_max": 1, "f_max": 300.0}


def _fr(v: float, **kw):
    return build_fr(Coach(), scenarios.wheel_table(), v, wheelset=systems.fr_wheelset(), **SMALL, **kw)[0]


def test_mass_keeps_the_static_deflection_and_sits_at_its_frequency():
    """Static state with and without the mass equal to 1e-6 of the largest residual
    coordinate's deflection (mapped to the points, where both blocks mean the same); the
    blocks' highest frequency is the requested one; a negative frequency is refused."""
    v = 300.0 / 3.6
    a, b = _fr(v, residual_mass=False), _fr(v, residual_hz=900.0)
    assert a.modal.massless is not None and b.modal.massless is None
    np.testing.assert_allclose(b.modal.max_frequency() / (2 * np.pi), 900.0, rtol=1e-12)
    qa, _ = static_equilibrium(a, v, "hertz-kalker")
    qb, _ = static_equilibrium(b, v, "hertz-kalker")
    ua, ub = a.modal.phi @ qa[a.n :], b.modal.phi @ qb[b.n :]
    assert np.abs(ua).max() > 1e-6  # the rims do deflect
    np.testing.assert_allclose(ub, ua, rtol=0, atol=1e-6 * np.abs(ua).max())
    np.testing.assert_allclose(qb[: a.n], qa[: a.n], rtol=0, atol=1e-9)
    c = _fr(v)  # default: the highest kept mode
    lay = build_fr(Coach(), scenarios.wheel_table(), v, wheelset=systems.fr_wheelset(), **SMALL)[1][0]
    assert c.modal.max_frequency() / (2 * np.pi) >= 0.99 * lay.freq_hz.max()
    with pytest.raises(InputError, match="residual_hz"):
        _fr(v, residual_hz=-1.0)


def test_flange_impact_runs_through_with_the_mass():
    """Hunting at 410 km/h from 6 mm on the strips (the default selection k_max 2, 800 Hz,
    h = 0.5 ms), 0.6 s: with massless residual coordinates Newton stopped in a flange-only
    contact at t = 0.414 s (hunting(410, model='FR', geometry='strip'); the instant moves
    with round-off: it did not stop when the harmonics came from another cached solve, so
    the massless failure is not asserted here); with the mass the run completes, through
    flange contact (Q well above the static load, the lateral motion beyond the clearance)."""
    v = 410.0 / 3.6
    sy = _with_strip(build_fr(Coach(), scenarios.wheel_table(), v, wheelset=systems.fr_wheelset())[0])
    qs, _ = static_equilibrium(sy, v, "hertz-fastsim")
    q0 = lateral_disturbance(sy, qs, 0.006, wheelsets=(0, 1))
    r = simulate(sy, v, 0.6, contact="hertz-fastsim", h=5e-4, q0=q0, output_dt=2e-3, progress=False)
    assert np.all(np.isfinite(r.q)) and r.t[-1] > 0.599
    assert np.abs(r.y_ws1).max() > 6e-3 and r.Q.max() > 1.3 * r.Q[0].mean()


def _with_strip(sy):
    return systems.with_geometry(sy, "strip")
