"""Ring track: static check, reduced-basis accuracy, receptance properties, bad input."""
import numpy as np
import pytest
import scipy.linalg as sla

from railvti.errors import InputError
from railvti.track import RingTrack
from railvti.track.static import static_direct

COARSE = dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12.0)


@pytest.fixture(scope="module")
def ring8():
    return RingTrack(8, **COARSE)


@pytest.mark.parametrize("direction", ["vertical", "lateral"])
@pytest.mark.parametrize("position", ["midspan", "sleeper"])
def test_static_modal_sum_equals_direct_solve(ring8, direction, position):
    a = ring8.static_modal(direction, position)
    b = static_direct(ring8, direction, position)
    assert a == pytest.approx(b, rel=0.01)


def test_reduced_rail_basis_reproduces_full_section_modes(ring8):
    k0, k1, k2, m = ring8._fe
    w, k0r, k1r, k2r, _ = ring8._rom
    for kap in (3.3, 11.7, 23.1):   # between the sample wave numbers
        full = sla.eigh(k0 + kap * k1 + kap ** 2 * k2, m, eigvals_only=True)
        red = np.linalg.eigvalsh(k0r + kap * k1r + kap ** 2 * k2r)
        lim = (2 * np.pi * 3000.0) ** 2
        f_full = np.sqrt(np.clip(full[full < lim], 0, None))
        f_red = np.sqrt(np.clip(red[: f_full.size], 0, None))
        assert np.allclose(f_red, f_full, rtol=2e-3, atol=2 * np.pi * 1.0)


def test_receptance_low_frequency_tends_to_static(ring8):
    h = ring8.receptance(np.array([0.0, 1.0]), "vertical", "midspan")
    assert h[0].real == pytest.approx(ring8.static_modal("vertical", "midspan"), rel=1e-10)
    assert abs(h[1].imag) < 0.1 * abs(h[1].real)


def test_generalized_forces_continuous_and_periodic(ring8):
    a = ring8.params["sleeper_spacing"]
    f = np.array([0.0, 0.0, 1.0, 0.0])
    q0 = ring8.generalized_forces(0.1, 2, f)
    q1 = ring8.generalized_forces(0.1 + 1e-7, 2, f)
    assert np.max(np.abs(q1 - q0)) < 1e-4 * np.max(np.abs(q0))
    # the ring closes: x and x + L give the same shapes
    q2 = ring8.generalized_forces(0.1 + ring8.length, 2, f)
    assert np.allclose(q2, q0, atol=1e-9 * np.max(np.abs(q0)))
    # cyclic symmetry: the point-receptance is periodic with the sleeper spacing
    s1 = ring8.head_shapes(0.13, 2)[2]
    s2 = ring8.head_shapes(0.13 + 3 * a, 2)[2]
    assert np.sum(s1 ** 2 / ring8.lam) == pytest.approx(np.sum(s2 ** 2 / ring8.lam), rel=1e-8)


@pytest.mark.parametrize("kw, msg", [
    (dict(pad_stiffness_vertical=-1e8), "pad_stiffness_vertical"),
    (dict(sleeper_mass=-10.0), "sleeper_mass"),
    (dict(ballast_stiffness_vertical=0.0), "ballast_stiffness_vertical"),
    (dict(sleeper_spacing=0.0), "sleeper_spacing"),
    (dict(sleeper_spacing=-0.6), "sleeper_spacing"),
    (dict(pad_damping_vertical=-1.0), "pad_damping_vertical"),
    (dict(rail_density=float("nan")), "rail_density"),
    (dict(foo=1.0), "unknown"),
])
def test_bad_track_parameters(kw, msg):
    with pytest.raises(InputError, match=msg):
        RingTrack(8, **kw)


@pytest.mark.parametrize("n", [1, 0, -4, 2.5])
def test_too_few_sleepers(n):
    with pytest.raises(InputError, match="n_sleepers"):
        RingTrack(n)


def test_bad_receptance_arguments(ring8):
    with pytest.raises(InputError, match="direction"):
        ring8.receptance([10.0], "sideways")
    with pytest.raises(InputError, match="position"):
        ring8.receptance([10.0], "vertical", "nowhere")
    with pytest.raises(InputError, match="freqs"):
        ring8.receptance([-1.0])
