"""The ring's residual coordinates with the truncated modes' inertia and damping.

Model RF keeps the ring modes up to f_limit; the truncated modes' static compliance at each
contact point (the residual flexibility) keeps the static rail deflection right but not the
receptance towards f_limit. With ``ring_residual_inertia`` the residual coordinates also get
the truncated modes' first-order inertia and damping (railvti.vehicle.ring_coupling.
residual_blocks). Checked against the ring's own direct FRF over all its modes
(RingTrack.head_receptance, an independent path through the Fortran ring_frf), from the
blocks the time loop integrates (ModalBlocks.receptance of the RF system).
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import InputError
from railvti.track.coupling import rail_of_wheel
from railvti.vehicle.equilibrium import static_equilibrium
from coarse_ring import COARSE

V = 200.0 / 3.6
F_LIMIT = 250.0
RING = dict(n_sleepers=40, f_limit=F_LIMIT, track_params=COARSE)


def crown_receptance(sy, freqs: np.ndarray, wheelset: int, wheel: int) -> np.ndarray:
    """Receptance (nf, 3, 3) of the rail's crown (u_y, u_z, roll; vehicle frame) under a
    wheel, from the RF system's modal blocks (the ring's three pose rows per wheel)."""
    nw = sy.iws.shape[1]
    p0 = sy.modal.phi.shape[0] - 6 * nw
    pts = p0 + 6 * wheelset + 3 * wheel + np.arange(3)
    h = sy.modal.receptance(pts, freqs)
    yp = (0.5 if wheel == 0 else -0.5) * sy.ring.rail_distance
    ei = np.linalg.inv(np.array([[1, 0, 0], [0, 1, -yp], [0, 0, 1.0]]))  # pose -> crown
    return np.einsum("ab,fbc,dc->fad", ei, h, ei)


@pytest.mark.parametrize("wheelset", [0, 2])
def test_receptance_with_inertia_follows_the_full_ring(wheelset):
    """Right wheel, vertical and lateral: within 2 % of the full ring's direct FRF up to
    f_limit / 2 with the residual's inertia (and better than the static residual)."""
    track = systems.ring_track(40, COARSE)
    f = np.linspace(0.0, 0.5 * F_LIMIT, 126)
    c = 2 * wheelset + 1
    errs = {}
    for inertia in (False, True):
        sy = scenarios.rf_system(speed=V, ring_residual_inertia=inertia, **RING)
        x = float(np.mod(sy.ring.cx0[c], sy.ring.length))
        direct = track.head_receptance(f, x, rail_of_wheel(1).rail)
        h = crown_receptance(sy, f, wheelset, 1)
        errs[inertia] = [
            np.max(np.abs(h[:, i, i] / direct[:, r, r] - 1)) for i, r in ((1, 2), (0, 1))
        ]  # vertical, lateral
    assert max(errs[True]) < 0.02, errs
    assert errs[True][0] < 0.5 * errs[False][0], errs


def test_inertia_keeps_the_static_deflection():
    """The residual's inertia changes no static compliance: the static rail deflection under
    every wheel equals the massless residual's to 1e-6, and the blocks have unit mass."""
    a = scenarios.rf_system(speed=V, **RING)
    b = scenarios.rf_system(speed=V, ring_residual_inertia=True, **RING)
    assert b.modal.massless is None or not any(b.modal.massless)
    qa, _ = static_equilibrium(a, V, "hertz-kalker")
    qb, _ = static_equilibrium(b, V, "hertz-kalker")
    da = a.rail_deflection(np.zeros(1), qa[None])[0]
    db = b.rail_deflection(np.zeros(1), qb[None])[0]
    np.testing.assert_allclose(db, da, rtol=0, atol=1e-6 * np.abs(da).max())


def test_inertia_and_residual_hz_exclude_each_other():
    with pytest.raises(InputError, match="residual_hz and residual_inertia"):
        scenarios.rf_system(speed=V, ring_residual_hz=800.0, ring_residual_inertia=True, **RING)
