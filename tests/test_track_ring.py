"""Ring track: static checks, reduced-basis accuracy, receptance properties, bad input."""
import numpy as np
import pytest
import scipy.linalg as sla

from railvti.errors import InputError
from railvti.track import RingTrack
from track_reference import beam_on_sleepers_static, jourawski_shear_coefficient, static_direct

COARSE = dict(kappa_max=30.0, mesh_max_area=4e-4, arc_step=12e-3)


@pytest.fixture(scope="module")
def ring8():
    return RingTrack(8, **COARSE)


@pytest.fixture(scope="module")
def ring8_flat():
    return RingTrack(8, cant=0.0, **COARSE)


@pytest.mark.parametrize("position", ["midspan", "sleeper"])
def test_static_deflection_against_timoshenko_beam_on_sleepers(ring8_flat, position):
    """Independent reference: one rail as a Timoshenko beam (axial, deflection, rotation) on the
    same ring of discrete pads (vertical and longitudinal springs over the pad length), rigid
    sleepers and ballast, by FE along x (track_reference.beam_on_sleepers_static), with the
    section's A, I_y and centroid and the shear coefficient from Jourawski's shear-stress
    distribution over the outline (0.42 for 60E1; 0.4 is the value usually taken).

    Rails without cant, so a vertical load pattern loads nothing else. The 2.5-D ring has
    everything the beam has plus the deformation of the cross-section (local compression under
    the crown load, web compression, foot bending over the pads), which only adds flexibility:
    the ring must be softer than the beam, by a few per cent (1.9 % at mid-span, 2.5 % above a
    sleeper for this mesh; 3.5 / 4.1 % on the default mesh, whose finer head deforms more
    locally under the crown node, docs/track.md table (d)). Shear matters:
    the shear-rigid (Euler-Bernoulli) beam is 10 % stiffer, so the test would see a lost shear
    term or a pad stiffness spread over the wrong area.
    """
    tr = ring8_flat
    p, sec = tr.params, tr.section
    x0 = {"midspan": 0.5 * p["sleeper_spacing"], "sleeper": 0.0}[position]
    kw = dict(n_sleepers=8, spacing=p["sleeper_spacing"], young=p["rail_young"],
              poisson=p["rail_poisson"], area=sec.area, iy=sec.iy, centroid_height=sec.centroid[1],
              pad_length=p["pad_length"], k_pad_vertical=p["pad_stiffness_vertical"],
              k_pad_longitudinal=p["pad_stiffness_longitudinal"],
              k_ballast_seat=0.5 * p["ballast_stiffness_vertical"], x_load=x0)
    kappa = jourawski_shear_coefficient(sec.outline)
    assert 0.35 < kappa < 0.5
    timoshenko = beam_on_sleepers_static(shear_coefficient=kappa, **kw)
    euler = beam_on_sleepers_static(shear_coefficient=None, **kw)
    ring = tr.static_modal("vertical", position)
    assert euler < timoshenko < ring
    assert ring / euler - 1 > 0.06
    assert 0.0 < ring / timoshenko - 1 < 0.04


def test_reference_beam_and_shear_coefficient_against_closed_forms():
    """The references themselves: Jourawski's coefficient of a rectangle is 5/6; the beam on
    pads that touch (pad length = spacing) over very stiff ballast is a Euler-Bernoulli beam
    on a Winkler foundation k_f = k_pad / spacing: w = beta / (2 k_f), beta^4 = k_f / (4 EI)."""
    b, h = 0.02, 0.04
    rect = np.array([[-b / 2, 0], [b / 2, 0], [b / 2, h], [-b / 2, h], [-b / 2, 0]])
    assert jourawski_shear_coefficient(rect) == pytest.approx(5 / 6, rel=1e-3)
    e, iy, kp, a = 2.1e11, 3.0e-5, 60e6, 0.6
    kf = kp / a
    beta = (kf / (4 * e * iy)) ** 0.25
    w = beam_on_sleepers_static(n_sleepers=24, spacing=a, young=e, poisson=0.3, area=7.7e-3,
                                iy=iy, centroid_height=0.08, pad_length=a, k_pad_vertical=kp,
                                k_pad_longitudinal=0.0, k_ballast_seat=1e6 * kp, x_load=0.3,
                                elements_per_pad=40)
    assert w == pytest.approx(beta / (2 * kf), rel=1e-3)


@pytest.mark.parametrize("direction", ["vertical", "lateral"])
@pytest.mark.parametrize("position", ["midspan", "sleeper"])
def test_static_modal_sum_equals_direct_solve(ring8, direction, position):
    """The modal form against the unreduced system of the same discretisation (every section
    DOF of every wave number, a sparse direct solve): all modes of the reduced system are kept,
    so the static deflections differ only by the rail's reduced basis and the residual
    attachments, measured 1e-5 (vertical) and 4e-4 (lateral)."""
    a = ring8.static_modal(direction, position)
    b = static_direct(ring8, direction, position)
    assert a == pytest.approx(b, rel=2e-5 if direction == "vertical" else 1e-3)


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


_MIRROR = np.diag([1.0, -1.0, 1.0, -1.0])


def _head_compliances(ring, x):
    h1, h2 = ring.head_shapes(x, 1), ring.head_shapes(x, 2)
    return (h1 / ring.lam) @ h1.T, _MIRROR @ ((h2 / ring.lam) @ h2.T) @ _MIRROR


def test_rails_mirror_each_other(ring8):
    """The ring's lateral axis: rail 1 at y = -d/2, rail 2 at +d/2, y to the right (the
    vehicle's y points to the left: docs/track.md). The track is symmetric about y = 0, so
    rail 1's static head compliance is rail 2's mirrored, G1 = M G2 M with
    M = diag(1, -1, 1, -1) over (x, y, z, roll): the lateral displacement and the roll about x
    change sign under y -> -y. Basis-free (degenerate cyclic pairs may mix). Checked here:
    the diagonal and the lateral-roll coupling (the vertical-roll one: next test)."""
    for x in (0.0, 0.13, 0.31):
        g1, g2m = _head_compliances(ring8, x)
        scale = np.abs(g1).max()
        for i, j in ((0, 0), (1, 1), (2, 2), (3, 3), (1, 3), (1, 2)):
            assert g1[i, j] == pytest.approx(g2m[i, j], abs=1e-4 * scale), (x, i, j)


@pytest.mark.xfail(strict=True, reason="known defect (session 7): the rails' vertical-roll head "
                   "compliance does not mirror (flat rails: -5.4e-4 against -1.33e-3 of the roll "
                   "compliance), as if both rails were the same section translated, not mirrored "
                   "(docs/track.md, 'Limits')")
def test_rails_mirror_vertical_roll_coupling(ring8):
    """The vertical-roll entry of the mirror test above: G1[z, roll] = -G2[z, roll]."""
    g1, g2m = _head_compliances(ring8, 0.13)
    assert g1[2, 3] == pytest.approx(g2m[2, 3], rel=0.02)


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
