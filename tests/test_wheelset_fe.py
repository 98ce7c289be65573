"""Axisymmetric harmonic elements: element matrices, shaft and plate against theory."""

import numpy as np
import pytest

from railvti import InputError
from railvti._native import core
from railvti._status import Status
from railvti.wheelset import analytic, rectangle_mesh, solve_harmonic

E, NU, RHO = 210e9, 0.3, 7850.0


def _element(r0=0.1, r1=0.2, y0=0.0, y1=0.05):
    r = np.array([r0, 0.5 * (r0 + r1), r1])
    y = np.array([y0, 0.5 * (y0 + y1), y1])
    xe = np.array([[r[i], y[j]] for j in range(3) for i in range(3)]).T
    return np.asfortranarray(xe)


@pytest.mark.parametrize("k", [0, 1, 2, 5])
def test_element_matrices_symmetric_positive(k):
    ke, me, ce, mc, info = core.wheelset_element_c(k, _element(), E, NU, RHO)
    assert info == Status.OK
    assert np.allclose(ke, ke.T, rtol=0, atol=1e-9 * np.abs(ke).max())
    assert np.allclose(me, me.T, rtol=0, atol=1e-12 * np.abs(me).max())
    assert np.linalg.eigvalsh(me).min() > 0.0
    assert np.linalg.eigvalsh(ke).min() > -1e-9 * np.abs(ke).max()


def test_element_mass_and_rigid_modes():
    r0, r1, y0, y1 = 0.1, 0.2, 0.0, 0.05
    mass = RHO * np.pi * (r1**2 - r0**2) * (y1 - y0)
    # k = 0: axial translation is stress-free; its kinetic energy is the ring's mass
    ke, me, _, _, _ = core.wheelset_element_c(0, _element(), E, NU, RHO)
    uy = np.zeros(27)
    uy[1::3] = 1.0
    assert np.abs(ke @ uy).max() < 1e-6 * np.abs(ke).max()
    assert uy @ me @ uy == pytest.approx(mass, rel=1e-12)
    # k = 1: rigid translation u_r = cos, u_th = -sin
    ke, me, ce, mc, _ = core.wheelset_element_c(1, _element(), E, NU, RHO)
    ux = np.zeros(27)
    ux[0::3], ux[2::3] = 1.0, -1.0
    assert np.abs(ke @ ux).max() < 1e-6 * np.abs(ke).max()
    assert ux @ me @ ux == pytest.approx(mass, rel=1e-12)
    assert ux @ ce @ ux == pytest.approx(-mass, rel=1e-12)  # Coriolis coupling of a translation
    assert ux @ mc @ ux == pytest.approx(mass, rel=1e-12)


def test_inverted_element_rejected():
    xe = _element()
    xe[0] = xe[0].reshape(3, 3)[:, ::-1].ravel()  # mirror in r: negative Jacobian
    *_, info = core.wheelset_element_c(1, np.asfortranarray(xe), E, NU, RHO)
    assert info == Status.BAD_ELEMENT


def test_shaft_k1_matches_timoshenko():
    ref = analytic.timoshenko_free_free(2.0, 0.2, E, NU, RHO, 3)
    h = solve_harmonic(rectangle_mesh(0.0, 0.1, -1.0, 1.0, 2, 16), 1, E, NU, RHO, 1400.0)
    flex = h.freq_hz[h.freq_hz > 1.0]
    assert np.sum(h.freq_hz < 1.0) == 2  # translation + rotation
    assert np.allclose(flex[:3], ref, rtol=0.02)


@pytest.mark.parametrize("k", [0, 1, 2])
def test_annular_plate_matches_kirchhoff(k):
    ref = analytic.annular_plate_clamped_free(0.1, 0.5, 0.01, E, NU, RHO, k, 2)
    m = rectangle_mesh(0.1, 0.5, 0.0, 0.01, 16, 1)
    fixed = np.zeros((m.n_nodes, 3), bool)
    fixed[np.isclose(m.nodes[:, 0], 0.1)] = True
    h = solve_harmonic(m, k, E, NU, RHO, 500.0, fixed=fixed)
    bending = [f for f, s in zip(h.freq_hz, h.shapes) if np.abs(s[:, 1]).max() > np.abs(s[:, [0, 2]]).max()]
    assert np.allclose(bending[:2], ref, rtol=0.02)


def test_mesh_refinement_converges():
    ref = analytic.timoshenko_free_free(2.0, 0.2, E, NU, RHO, 3)[2]
    errs = []
    for ny in (4, 8, 16):
        h = solve_harmonic(rectangle_mesh(0.0, 0.1, -1.0, 1.0, 1, ny), 1, E, NU, RHO, 1400.0)
        errs.append(abs(h.freq_hz[h.freq_hz > 1.0][2] / ref - 1.0))
    assert errs[0] > errs[1] > errs[2] - 1e-3
    assert errs[2] < 0.01


@pytest.mark.parametrize("k", [-1, 1.5, "a"])
def test_bad_harmonic(k):
    with pytest.raises(InputError, match="harmonic"):
        solve_harmonic(rectangle_mesh(0.0, 0.1, -1.0, 1.0, 1, 4), k, E, NU, RHO, 1000.0)


def test_inverted_mesh_element_named_in_the_error():
    m = rectangle_mesh(0.0, 0.1, -1.0, 1.0, 2, 4)
    conn = m.conn.copy()
    conn[2] = conn[2].reshape(3, 3)[:, ::-1].ravel()  # mirror element 3 (1-based) in r
    bad = type(m)(nodes=m.nodes, conn=conn)
    with pytest.raises(InputError, match=r"meridian element 3 \(1-based\) is inverted"):
        solve_harmonic(bad, 1, E, NU, RHO, 1000.0)


def test_no_free_dof_is_an_input_error():
    m = rectangle_mesh(0.0, 0.1, -1.0, 1.0, 1, 2)
    with pytest.raises(InputError, match="no free degree of freedom"):
        solve_harmonic(m, 1, E, NU, RHO, 1000.0, fixed=np.ones((m.n_nodes, 3), bool))


def test_mode_buffer_grows_and_shapes_own_their_memory():
    # A 2 x 40 shaft (~500 equations, dense path) has more than the first
    # buffer's 48 modes below 60 kHz: the buffer must grow, and the result must
    # equal a solve capped at exactly those modes.
    mesh = rectangle_mesh(0.0, 0.1, -1.0, 1.0, 2, 40)
    h = solve_harmonic(mesh, 1, E, NU, RHO, 60000.0, n_max=400)
    assert 48 < h.freq_hz.size < 400
    capped = solve_harmonic(mesh, 1, E, NU, RHO, 60000.0, n_max=h.freq_hz.size - 3)
    assert capped.freq_hz.size == h.freq_hz.size - 3
    assert np.allclose(capped.freq_hz[5:], h.freq_hz[5:-3], rtol=1e-9)
    # the shapes are a copy, not a view that would keep the Fortran buffer alive
    assert h.shapes.base is None and h.shapes.shape == (h.freq_hz.size, mesh.n_nodes, 3)
