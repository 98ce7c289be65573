"""Ring track: static checks, reduced-basis accuracy, receptance properties, bad input."""

import numpy as np
import pytest
import scipy.linalg as sla

from railvti.errors import InputError
from railvti.track import RingTrack
from track_reference import beam_on_sleepers_static, jourawski_shear_coefficient, static_direct
from coarse_ring import COARSE_SECTION as COARSE


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
    the ring must be softer than the beam, by a few per cent (2.0 % at mid-span, 2.6 % above a
    sleeper for this mesh; 3.3 / 3.9 % on the default mesh, whose finer head deforms more
    locally under the crown node, docs/track.md table (d)). Shear matters:
    the shear-rigid (Euler-Bernoulli) beam is 10 % stiffer, so the test would see a lost shear
    term or a pad stiffness spread over the wrong area.
    """
    tr = ring8_flat
    p, sec = tr.params, tr.section
    x0 = {"midspan": 0.5 * p["sleeper_spacing"], "sleeper": 0.0}[position]
    kw = dict(
        n_sleepers=8,
        spacing=p["sleeper_spacing"],
        young=p["rail_young"],
        poisson=p["rail_poisson"],
        area=sec.area,
        iy=sec.iy,
        centroid_height=sec.centroid[1],
        pad_length=p["pad_length"],
        k_pad_vertical=p["pad_stiffness_vertical"],
        k_pad_longitudinal=p["pad_stiffness_longitudinal"],
        k_ballast_seat=0.5 * p["ballast_stiffness_vertical"],
        x_load=x0,
    )
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
    w = beam_on_sleepers_static(
        n_sleepers=24,
        spacing=a,
        young=e,
        poisson=0.3,
        area=7.7e-3,
        iy=iy,
        centroid_height=0.08,
        pad_length=a,
        k_pad_vertical=kp,
        k_pad_longitudinal=0.0,
        k_ballast_seat=1e6 * kp,
        x_load=0.3,
        elements_per_pad=40,
    )
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
    for kap in (3.3, 11.7, 23.1):  # between the sample wave numbers
        full = sla.eigh(k0 + kap * k1 + kap**2 * k2, m, eigvals_only=True)
        red = np.linalg.eigvalsh(k0r + kap * k1r + kap**2 * k2r)
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
    assert np.sum(s1**2 / ring8.lam) == pytest.approx(np.sum(s2**2 / ring8.lam), rel=1e-8)


_MIRROR = np.diag([1.0, -1.0, 1.0, -1.0])


@pytest.fixture(scope="module")
def ring8_outward():
    return RingTrack(8, cant=-1.0 / 40.0, **COARSE)


def test_rails_mirror_each_other(ring8):
    """The ring's lateral axis: rail 1 at y = -d/2, rail 2 at +d/2, y to the right (the
    vehicle's y points to the left: docs/track.md). Both rails lean inwards by the same cant
    and sit on sleepers that are symmetric about the track centre, so the track is its own
    mirror image under y -> -y: rail 1's static head compliance is rail 2's mirrored,
    G1 = M G2 M with M = diag(1, -1, 1, -1) over (x, y, z, roll) (the lateral displacement
    and the roll about x change sign). Basis-free (degenerate cyclic pairs may mix). Every
    entry, the vertical-roll coupling included: with the section mesh merely translated
    (before the mirror-symmetric mesh) that entry was -5.4e-4 against -1.33e-3 of the roll
    compliance; now the rails mirror to round-off (measured 1e-11)."""
    for x in (0.0, 0.13, 0.31):
        h1, h2 = ring8.head_shapes(x, 1), ring8.head_shapes(x, 2)
        g1 = (h1 / ring8.lam) @ h1.T
        g2m = _MIRROR @ ((h2 / ring8.lam) @ h2.T) @ _MIRROR
        assert np.abs(g1 - g2m).max() < 1e-8 * np.abs(g1).max(), x
        # the coupling the mirror flips is really there (the test can see a sign error)
        assert abs(g1[2, 3]) > 1e-4 * g1[3, 3] and abs(g1[1, 3]) > 1e-2 * g1[3, 3]


def test_section_mesh_is_mirror_symmetric(ring8):
    """Every node has its mirror image about the rail's axis (eta -> -eta), every triangle its
    mirror triangle, and the crown node lies on the axis."""
    sec = ring8.section
    nodes = sec.nodes
    d = np.linalg.norm(nodes[:, None, :] - (nodes * [-1.0, 1.0])[None, :, :], axis=2)
    image = d.argmin(axis=1)
    assert d.min(axis=1).max() == 0.0
    assert {tuple(sorted(e)) for e in sec.elements} == {tuple(sorted(image[e])) for e in sec.elements}
    assert nodes[sec.crown_node, 0] == 0.0 and nodes[sec.crown_node, 1] == nodes[:, 1].max()


@pytest.mark.parametrize("track", ["ring8", "ring8_flat"])
def test_head_receptance_mirrors_between_rails(track, request):
    """The dynamic form of the mirror: H1(f) = M H2(f) M at one x for flat and canted rails
    (vertical unchanged, lateral and roll couplings with their sign flipped), at frequencies
    below, between and above the track's resonances."""
    tr = request.getfixturevalue(track)
    f = np.array([0.0, 80.0, 350.0, 1000.0, 2200.0])
    for x in (0.0, 0.13):
        h1 = tr.head_receptance(f, x, 1)
        h2m = _MIRROR @ tr.head_receptance(f, x, 2) @ _MIRROR
        scale = np.abs(h1).max(axis=(1, 2))
        assert np.all(np.abs(h1 - h2m).max(axis=(1, 2)) < 1e-8 * scale), (track, x)
        assert np.allclose(h1, np.swapaxes(h1, 1, 2))  # reciprocity


def test_mirror_keeps_the_cant(ring8, ring8_outward):
    """Which mirror holds: y -> -y maps the track with inward-leaning rails onto itself (rail 1
    of cant c onto rail 2 of the same cant c), not onto the track with the cant reversed. Rail 2
    leaning outwards couples lateral and vertical with the other sign than rail 1 leaning
    inwards mirrored (static compliance, normalised: -0.039 against +0.072)."""
    h1 = ring8.head_receptance(np.array([0.0]), 0.13, 1)[0].real
    h2 = (_MIRROR @ ring8_outward.head_receptance(np.array([0.0]), 0.13, 2) @ _MIRROR)[0].real
    r1 = h1[1, 2] / np.sqrt(h1[1, 1] * h1[2, 2])
    r2 = h2[1, 2] / np.sqrt(h2[1, 1] * h2[2, 2])
    assert r1 * r2 < 0 and abs(r1 - r2) > 0.05


def _compliance(h1, h2, lam):
    return (h1 / lam) @ h2.T


def test_head_surface_follows_the_outline(ring8):
    """The head's running surface from the mesh: symmetric about the axis, through the crown
    (172 mm, level), on the outline's polygon, and reaching the gauge corner (slope past
    60 degrees) on both sides."""
    hd, sec = ring8.head, ring8.section
    assert np.array_equal(hd.eta, -hd.eta[::-1]) and np.array_equal(hd.zeta, hd.zeta[::-1])
    z0, sl0 = hd.point(0.0)
    assert z0 == pytest.approx(0.172, abs=1e-12) and abs(sl0) < 0.05
    top = sec.outline[sec.outline[:, 1] > 0.15]
    top = top[np.argsort(top[:, 0])]
    for s in np.linspace(hd.eta[0], hd.eta[-1], 37):
        z, _ = hd.point(s)
        assert z == pytest.approx(np.interp(s, top[:, 0], top[:, 1]), abs=1e-9)
    assert hd.point(hd.eta[0])[1] > np.tan(np.radians(60)) and hd.eta[-1] > 0.03
    with pytest.raises(InputError, match="off the rail head"):
        ring8.head_shapes(0.1, 1, hd.eta[-1] + 1e-3)


def test_head_shapes_at_s_zero_are_the_crown_and_continuous(ring8):
    """s = 0 is the crown node: the same values as the crown rows. Along the surface the values
    are continuous across the ends of the mesh's edges (quadratic interpolation per edge)."""
    for rail in (1, 2):
        h0, hs = ring8.head_shapes(0.21, rail), ring8.head_shapes(0.21, rail, 0.0)
        assert np.abs(hs - h0).max() <= 1e-12 * np.abs(h0).max()
        for e in ring8.head.eta[1:-1]:
            a = ring8.head_shapes(0.21, rail, e - 1e-9)
            b = ring8.head_shapes(0.21, rail, e + 1e-9)
            assert np.abs(a - b).max() < 1e-6 * np.abs(a).max()


def test_rails_mirror_at_head_points(ring8):
    """The mirror at a point off the crown: rail 1 at s maps onto rail 2 at -s (s is the
    section's eta, along the ring's y on both rails)."""
    for s in (0.012, -0.025, 0.033):
        h1, h2 = ring8.head_shapes(0.13, 1, s), ring8.head_shapes(0.13, 2, -s)
        g1 = _compliance(h1, h1, ring8.lam)
        g2m = _MIRROR @ _compliance(h2, h2, ring8.lam) @ _MIRROR
        assert np.abs(g1 - g2m).max() < 1e-8 * np.abs(g1).max(), s


@pytest.mark.parametrize("track", ["ring8", "ring8_flat"])
@pytest.mark.parametrize(
    "load, tol", [((0, 0, 0, 1e3), 0.01), ((0, 1e4, 0, 0), 0.01), ((0, 0, -1e5, 0), 0.10)]
)
def test_head_roll_matches_finite_differences_of_the_surface(track, load, tol, request):
    """Finite differences of the static deflection field along the head surface against the
    roll the shapes give at each surface point. On a traction-free surface the shear strain
    between its tangent t and normal n vanishes, so the rotation of the surface line,
    n . du/dsigma (sigma the arc length), is the material rotation, the roll. Static field of
    a crown load one bay (0.6 m) away, central differences inside each edge, in the rail's
    section frame (the track frame turned back by the cant). The moment and lateral loads
    rotate the head nearly rigidly: 0.25 % measured; under a vertical load the roll is a
    small difference of large gradients near the crown (Poisson's anticlastic bending and the
    local deformation under the load): 7 % of the largest roll measured."""
    tr = request.getfixturevalue(track)
    hd = tr.head
    q = (np.array(load, float) @ tr.head_shapes(0.75, 2)) / tr.lam
    b = tr._geom[1][1]
    back = np.array([[np.cos(b), np.sin(b)], [-np.sin(b), np.cos(b)]])  # track -> section
    diff, roll = [], []
    for i in range(len(hd.edges)):
        s = 0.5 * (hd.eta[i] + hd.eta[i + 1])
        h = 0.25 * (hd.eta[i + 1] - hd.eta[i])
        _, slope = hd.point(s)
        du = back @ ((tr.head_shapes(0.15, 2, s + h) - tr.head_shapes(0.15, 2, s - h)) @ q)[1:3]
        du /= 2 * h * np.hypot(1.0, slope)  # d(u_eta, u_zeta)/d sigma
        n = np.array([-slope, 1.0]) / np.hypot(1.0, slope)
        diff.append(n @ du)
        roll.append((tr.head_shapes(0.15, 2, s) @ q)[3])
    diff, roll = np.array(diff), np.array(roll)
    assert np.abs(diff - roll).max() < tol * np.abs(roll).max()
    assert np.abs(roll).max() > 0


@pytest.mark.parametrize("s", [None, 0.021, -0.032])
def test_head_shapes_dx_match_finite_differences_in_x(ring8, s):
    """The convective rows (analytic x-derivative of the trigonometric functions) against
    central differences of head_shapes in x, on both rails, at the crown and off it (step
    1e-5 m: truncation ~ (kappa_max * step)^2 = 1e-7)."""
    d = 1e-5
    for rail in (1, 2):
        for x in (0.0, 0.17, 2.9):
            fd = (ring8.head_shapes(x + d, rail, s) - ring8.head_shapes(x - d, rail, s)) / (2 * d)
            an = ring8.head_shapes_dx(x, rail, s)
            for c in range(4):
                assert np.abs(an[c] - fd[c]).max() < 1e-5 * np.abs(an[c]).max(), (rail, x, c)


def test_contact_rows_of_one_step(ring8):
    """Several contact points in one call: the same rows as one call per point, positions
    taken modulo the ring length; bad shapes are refused."""
    x = np.array([0.1, 2.5, 0.1 + ring8.length, -0.4])
    rail = np.array([1, 2, 1, 2])
    s = np.array([0.0, 0.01, -0.02, 0.03])
    shapes, dx = ring8.contact_rows(x, rail, s)
    assert shapes.shape == (4, 4, ring8.n_modes) and dx.shape == shapes.shape
    for i in range(4):
        assert np.allclose(
            shapes[i], ring8.head_shapes(x[i], rail[i], s[i]), rtol=0, atol=1e-9 * np.abs(shapes[i]).max()
        )
        assert np.array_equal(dx[i], ring8.head_shapes_dx(x[i] % ring8.length, rail[i], s[i]))
    crown, _ = ring8.contact_rows(x[:2], rail[:2])
    assert np.array_equal(crown[1], ring8.head_shapes(2.5, 2))
    with pytest.raises(InputError, match="rail must have the shape"):
        ring8.contact_rows(x, rail[:3])
    with pytest.raises(InputError, match="s must have the shape"):
        ring8.contact_rows(x, rail, s[:2])
    with pytest.raises(InputError, match="rail must be 1 or 2"):
        ring8.contact_rows(x, np.array([1, 2, 3, 1]))


@pytest.mark.parametrize(
    "kw, msg",
    [
        (dict(pad_stiffness_vertical=-1e8), "pad_stiffness_vertical"),
        (dict(sleeper_mass=-10.0), "sleeper_mass"),
        (dict(ballast_stiffness_vertical=0.0), "ballast_stiffness_vertical"),
        (dict(sleeper_spacing=0.0), "sleeper_spacing"),
        (dict(sleeper_spacing=-0.6), "sleeper_spacing"),
        (dict(pad_damping_vertical=-1.0), "pad_damping_vertical"),
        (dict(rail_density=float("nan")), "rail_density"),
        (dict(foo=1.0), "unknown"),
    ],
)
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
