"""Model RF's truncated ring (kept modes + residual flexibility, ring_coupling.ring_rows) against
the ring's direct FRF over all its modes (RingTrack.head_receptance, RingTrack.receptance):
issue 15's acceptance point 2 on a small, coarse ring (validation/track_modal_receptance.py
does the RF default ring, n_sl = 40, and says why the 2 % does not reach f_limit / 2 there).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti.track import RingTrack
from railvti.vehicle.ring_coupling import ring_rows

COARSE = dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12e-3, f_max=1000.0)
#: (name, vehicle-frame crown component, track-frame row)
DIRECTIONS = (("vertical", 1, 2), ("lateral", 0, 1))


@pytest.fixture(scope="module")
def ring():
    return RingTrack(16, **COARSE)


def _rf_point(track, x, freqs, f_limit, residual=True):
    """Crown receptance (u_y, u_z, roll) of the right wheel's point from RF's rows and table."""
    rr = ring_rows(track, np.array([x]), 1.0, f_limit=f_limit, residual=residual)
    ph = rr.rows(0.0)[0][:, 1, :]  # right wheel: rail 2
    w = 2 * math.pi * np.asarray(freqs)[:, None]
    den = track.lam[rr.modes] - w**2 + 1j * w * track.cmod[rr.modes]
    h = np.einsum("im,fm,jm->fij", ph, 1.0 / den, ph)
    if residual:
        lr = rr.residual_rows(0.0)[0][:, :, 1]
        h = h + lr @ lr.T * rr.rscale**2
    half = 0.5 * track.params["rail_distance"]
    ei = np.linalg.inv(np.array([[1, 0, 0], [0, 1, half], [0, 0, 1.0]]))  # pose -> crown
    return np.einsum("ab,fbc,dc->fad", ei, h, ei)


@pytest.mark.parametrize("where", ["midspan", "sleeper"])
def test_residual_flexibility_restores_static_receptance(ring, where):
    """At 0 Hz the kept modes plus the residual table give the direct static receptance exactly
    (vertical and lateral); the kept modes alone fall more than 5 % (vertical: 10 %) short."""
    x = 0.5 * ring.params["sleeper_spacing"] if where == "midspan" else 0.0
    f = np.zeros(1)
    direct = ring.head_receptance(f, x, 2)[0]
    rf = _rf_point(ring, x, f, 500.0)[0]
    bare = _rf_point(ring, x, f, 500.0, residual=False)[0]
    for _, comp, row in DIRECTIONS:
        assert rf[comp, comp].real == pytest.approx(direct[row, row].real, rel=1e-6)
        assert abs(bare[comp, comp].real / direct[row, row].real - 1) > 0.05
    assert abs(bare[1, 1].real / direct[2, 2].real - 1) > 0.10


@pytest.mark.parametrize("where", ["midspan", "sleeper"])
def test_truncated_receptance_within_two_percent(ring, where):
    """f_limit = 500 Hz: within 2 % of the direct FRF up to f_limit / 4 (vertical and lateral);
    f_limit = 1000 Hz: the vertical within 2 % up to f_limit / 2. (At 500 Hz the vertical error
    reaches 7-9 % at f_limit / 2: the truncated modes' inertia and damping, which a static
    residual lacks; see validation/track_modal_receptance.py.)"""
    x = 0.5 * ring.params["sleeper_spacing"] if where == "midspan" else 0.0
    f = np.linspace(0.0, 125.0, 26)
    direct = ring.head_receptance(f, x, 2)
    rf = _rf_point(ring, x, f, 500.0)
    for name, comp, row in DIRECTIONS:
        err = np.abs(rf[:, comp, comp] / direct[:, row, row] - 1)
        assert err.max() < 0.02, (name, err.max())
    f = np.linspace(0.0, 500.0, 51)
    direct = ring.head_receptance(f, x, 2)[:, 2, 2]
    rf = _rf_point(ring, x, f, 1000.0)[:, 1, 1]
    assert np.max(np.abs(rf / direct - 1)) < 0.02


def test_pattern_receptance_vertical(ring):
    """RingTrack.receptance's in-phase vertical pattern (both rails loaded) from RF's rows of
    both wheels: RF keeps no residual compliance between contact points, yet the vertical
    pattern agrees within 2 % up to f_limit / 4 (the cross-rail share of the truncated
    compliance is small)."""
    x = 0.3
    f = np.linspace(0.0, 125.0, 26)
    rr = ring_rows(ring, np.array([x]), 1.0, f_limit=500.0)
    rows = rr.rows(0.0)[0]
    half = 0.5 * ring.params["rail_distance"]
    zl, zr = rows[1, 0] + half * rows[2, 0], rows[1, 1] - half * rows[2, 1]
    w = 2 * math.pi * f[:, None]
    den = ring.lam[rr.modes] - w**2 + 1j * w * ring.cmod[rr.modes]
    rf = _rf_point(ring, x, f, 500.0)[:, 1, 1] + (zr * zl / den).sum(1)
    direct = ring.receptance(f, "vertical", x)
    assert np.max(np.abs(rf / direct - 1)) < 0.02
