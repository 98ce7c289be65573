"""The ring's massless residual coordinates scaled per coordinate (ring_coupling.residual_scaling,
issue 33): the compliance at the contact point is the truncated modes' own, computed here from
the ring's head shapes (RingTrack.head_shapes through wheel_head_shapes), and each coordinate
moves the point's pose by at most 1 per unit over the bay, so that Newton's correction test
(m, rad) measures it by the rail's motion."""

from __future__ import annotations

import numpy as np
import pytest

from railvti.track import RingTrack
from railvti.track.coupling import wheel_head_shapes
from railvti.vehicle.ring_coupling import residual_blocks, residual_scaling, ring_rows
from coarse_ring import COARSE

XW = np.array([10.78, 8.22, -8.22, -10.78])


@pytest.fixture(scope="module")
def ring():
    return RingTrack(40, **COARSE)


def test_scaled_coordinates_keep_the_truncated_modes_compliance(ring):
    """(L D) K^-1 (L D)^T at every table position against sum h h^T / lambda over the modes
    above f_limit, from the ring's head shapes (s = 2: the stiffness factor divides it)."""
    rr = ring_rows(ring, XW, 50.0, f_limit=300.0)
    rs, stiff, damp = residual_blocks(rr, stiffness_scale=2.0)
    trunc = np.setdiff1d(np.arange(ring.lam.size), rr.modes)
    half = 0.5 * ring.params["rail_distance"]
    bay = ring.params["sleeper_spacing"]
    nrx = rr.rtab.shape[2]
    for c, rho in enumerate(rr.crho):
        k = rho - 1
        yp = half if k == 0 else -half
        elem = np.array([[0, 1, 0, 0], [0, 0, 1, -yp], [0, 0, 0, 1.0]])
        for i in range(0, nrx, 5):
            h = elem @ wheel_head_shapes(ring, i * bay / nrx, k)[:, trunc]
            want = (h / ring.lam[trunc]) @ h.T / 2.0
            rows = np.linalg.cholesky(rs.rtab[:, :, i, k]) @ rs.post[:, :, k]
            got = rows @ np.linalg.solve(stiff[c], rows.T)
            assert np.allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
        assert not np.any(damp[c])


def test_each_scaled_column_moves_the_pose_by_at_most_one(ring):
    """The columns of L D reach 1 (largest entry over the bay) and were far apart unscaled:
    the z/roll column of L is ~30 times smaller than the others (the rail head's z and roll
    nearly opposite in R)."""
    rr = ring_rows(ring, XW, 50.0, f_limit=300.0)
    d = residual_scaling(rr)
    for k in range(2):
        ls = np.array([np.linalg.cholesky(rr.rtab[:, :, i, k]) for i in range(rr.rtab.shape[2])])
        raw = np.abs(ls).max(axis=(0, 1))
        scaled = np.abs(ls @ d[:, :, k]).max(axis=(0, 1))
        assert np.allclose(scaled, 1.0, rtol=1e-12)
        assert raw.max() / raw.min() > 5.0  # the scaling is not vacuous on this ring
        assert np.allclose(d[:, :, k], np.diag(np.diag(d[:, :, k])))  # diagonal


def test_residual_tables_cached_per_ring_are_those_built_afresh(ring):
    """ring_rows' residual tables come from a per-ring cache (issue 33: they do not depend on
    the speed): the same bits as a build with the cache emptied, at another speed, read-only."""
    from railvti.vehicle import ring_coupling

    a = ring_rows(ring, XW, 50.0, f_limit=300.0)
    ring_coupling._RESIDUAL_TABLES.clear()
    b = ring_rows(ring, XW, 80.0, f_limit=300.0)
    for name in ("rtab", "mtab", "ctab"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert not getattr(b, name).flags.writeable
    assert a.rscale == b.rscale
    assert b.speed == 80.0
