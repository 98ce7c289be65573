"""The strip contact under the wheelset's yaw (railvti.vehicle.strip, vehicle_strip's
ring_deepest): against a brute-force search over the yawed 3-D wheel surface, conservative
with yaw, its linearisation, and mirror-symmetric in the vehicle."""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.geometry import layout
from railvti.vehicle import static_equilibrium
from railvti.vehicle.model import CallSettings
from railvti.vehicle.strip import STRIP_OUTPUTS, strip_geometry, strip_linearise, strip_wheel

N, PM, XC = (STRIP_OUTPUTS.index(k) for k in ("N", "P_max", "xc"))
GRAD = [STRIP_OUTPUTS.index(k) for k in ("dV_dy", "dV_dz", "dV_droll", "dV_dyaw")]
STEP = 2e-4  # the strips' wheel sample step (default)
#: (name, lateral shift, window of wheel profile coordinates around the contact), m
CASES = (("tread", 0.0, (-0.01, 0.01)), ("flange", 7e-3, (-0.045, -0.02)))
YAWS = (0.0, 2e-3, 5e-3, 10e-3)


@pytest.fixture(scope="module")
def setup():
    wheel, rail = systems.profiles()
    return wheel, rail, strip_geometry(wheel, rail, step=STEP)


def brute_force(wheel, rail, y, zc, roll, yaw, s):
    """Largest vertical interference of the wheel over the rail and where it is, searched
    directly: each profile point s of the wheel (a circle of radius r about the axle) is
    turned through angles theta about the axle, the point (r sin(theta), y0, -r cos(theta))
    rolled about x and yawed about z by rotation matrices and set on the centre; the rail is
    the profile extruded along x (its height at the point's track y). A 601-point grid in
    theta over +-0.12 rad, then three refinements by 20x. Returns (P, x, s) of the deepest
    point."""
    lay = layout(wheel, rail)
    r = lay.wheelset.wheel_radius + wheel.height(s)
    y0 = lay.wheelset.contact_y + s
    cr, sr, cy, sy = np.cos(roll), np.sin(roll), np.cos(yaw), np.sin(yaw)
    rot = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]]) @ np.array(
        [[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]]
    )

    def interference(th):
        pts = np.stack([r * np.sin(th), np.broadcast_to(y0, th.shape), -r * np.cos(th)])
        x, yy, z = np.einsum("ij,j...->i...", rot, pts)
        yl = y + yy - lay.rail_offset
        h = lay.rail_top - rail.height(np.clip(yl, rail.y_min, rail.y_max))
        p = h - (lay.wheelset.wheel_radius + zc + z)
        return np.where((yl >= rail.y_min) & (yl <= rail.y_max), p, -np.inf), x

    cols = np.arange(s.size)
    th = np.broadcast_to(np.linspace(-0.12, 0.12, 601)[:, None], (601, s.size))
    for _ in range(4):
        p, x = interference(th)
        k = p.argmax(axis=0)
        step = th[1, 0] - th[0, 0]
        best = th[k, cols]
        th = best[None, :] + np.linspace(-step, step, 41)[:, None]
    p, x = interference(th)
    k = p.argmax(axis=0)
    pj, xj = p[k, cols], x[k, cols]
    j = int(pj.argmax())
    return pj[j], xj[j], s[j], pj


def _light_contact(geo, y, yaw, pmax=2e-6, roll=0.0):
    """The centre height at which the strips' largest interference is pmax (bisection)."""
    lo, hi = -0.02, 0.02
    for _ in range(60):
        zc = 0.5 * (lo + hi)
        out, _ = strip_wheel(geo, y, zc, roll, yaw)
        lo, hi = (zc, hi) if out[:, PM].max() > pmax else (lo, zc)
    return zc


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_yaw_matches_brute_force_on_the_strips_samples(setup, case):
    """At 0, 2, 5 and 10 mrad of yaw, in light contact (2 um), the strips' largest
    interference equals the brute-force search's over the same wheel samples within 10 nm
    (the strips' rail is a C2 spline through the profile at 0.05 mm: its interpolation error)
    and their load-weighted longitudinal contact position the deepest point's within 20 um
    (the 2 um patch covers one to three samples whose lead differs by less than that). The
    contact leads the wheel's lowest point by r psi tan(delta): 13 mm at 10 mrad on the
    flange, 0.1 mm on the tread."""
    wheel, rail, geo = setup
    name, y, (lo, hi) = case
    s = np.arange(wheel.y_min, wheel.y_max + 1e-12, STEP)
    s = s[(s >= lo) & (s <= hi)]
    leads = []
    for yaw in YAWS:
        zc = _light_contact(geo, y, yaw)
        out, _ = strip_wheel(geo, y, zc, 0.0, yaw)
        k = out[:, N].argmax()
        p, x, sj, _ = brute_force(wheel, rail, y, zc, 0.0, yaw, s)
        assert out[:, PM].max() == pytest.approx(p, abs=1e-8), (name, yaw)
        assert out[k, XC] == pytest.approx(x, abs=2e-5), (name, yaw)
        lay = layout(wheel, rail)
        leads.append(x + (lay.wheelset.contact_y + sj) * np.tan(yaw))
    if name == "flange":
        assert 0.010 < leads[-1] < 0.016  # 13 mm at 10 mrad (tan(delta) about 2.8)
    else:
        assert abs(leads[-1]) < 5e-4


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_yaw_within_the_sampling_against_a_fine_brute_force(setup, case):
    """Against the brute force over a 10x finer wheel grid (0.02 mm) the strips' interference
    is lower by at most what sampling at 0.2 mm can miss, max|P''| (0.1 mm)^2 / 2 (P'' the
    interference's second derivative along the profile, from the fine search), and the
    contact position differs by at most the lead's change over half a sample (|dx/ds|
    0.1 mm, from the fine search) plus the patch's 20 um."""
    wheel, rail, geo = setup
    name, y, (lo, hi) = case
    fine = np.arange(lo, hi, STEP / 10)
    for yaw in YAWS:
        zc = _light_contact(geo, y, yaw)
        out, _ = strip_wheel(geo, y, zc, 0.0, yaw)
        k = out[:, N].argmax()
        p, x, sj, pj = brute_force(wheel, rail, y, zc, 0.0, yaw, fine)
        j = int(pj.argmax())
        win = slice(max(j - 10, 0), j + 11)
        pss = np.abs(np.diff(pj[win], 2)).max() / (STEP / 10) ** 2
        bound = 0.5 * pss * (STEP / 2) ** 2 + 1e-8
        assert -1e-8 <= p - out[:, PM].max() <= bound, (name, yaw, p, bound)
        # the lead's rate along the profile, from the deepest points of neighbouring samples
        _, xa, _, _ = brute_force(wheel, rail, y, zc, 0.0, yaw, fine[max(j - 5, 0) : j - 4])
        _, xb, _, _ = brute_force(wheel, rail, y, zc, 0.0, yaw, fine[j + 5 : j + 6])
        dxds = abs(xb - xa) / (10 * STEP / 10)
        assert abs(out[k, XC] - x) <= dxds * STEP / 2 + 2e-5, (name, yaw)


def test_the_forces_with_yaw_are_the_gradient_of_the_potential(setup):
    """With yaw the returned gradient (yaw moment included) equals central differences of
    V, tread and flange (conservative), and the linearisation over (y, zc, roll, yaw) equals
    central differences of every output at steps between the rail's knots."""
    _, _, geo = setup
    for y, roll, yaw in ((0.21e-3, 0.003, 0.004), (3e-3, -0.004, -0.006), (7e-3, 0.002, 0.008)):
        zc = _light_contact(geo, y, yaw, pmax=4e-5, roll=roll)
        out, d = strip_linearise(geo, y, zc, roll, yaw)
        np.testing.assert_array_equal(out, strip_wheel(geo, y, zc, roll, yaw)[0])
        assert out[:, N].sum() > 1e3
        grad = out[:, GRAD].sum(axis=0)
        fd = []
        for k, h in enumerate((1e-7, 1e-8, 1e-7, 1e-7)):
            e = np.zeros(4)
            e[k] = h
            vp = strip_wheel(geo, y + e[0], zc + e[1], roll + e[2], yaw + e[3])[0][:, 1].sum()
            vm = strip_wheel(geo, y - e[0], zc - e[1], roll - e[2], yaw - e[3])[0][:, 1].sum()
            fd.append((vp - vm) / (2 * h))
        np.testing.assert_allclose(grad, fd, rtol=1e-5, atol=1e-5 * np.abs(grad).max())
        for k in range(4):
            e = np.zeros(4)
            e[k] = 2e-10
            fdo = (
                strip_wheel(geo, y + e[0], zc + e[1], roll + e[2], yaw + e[3])[0]
                - strip_wheel(geo, y - e[0], zc - e[1], roll - e[2], yaw - e[3])[0]
            ) / 4e-10
            for i, name in enumerate(STRIP_OUTPUTS):
                if name == "P_max":
                    continue
                scale = max(np.abs(d[:, i, :]).max(), 1e-12)
                np.testing.assert_allclose(
                    d[:, i, k], fdo[:, i], rtol=0, atol=2e-4 * scale, err_msg=f"{name} over pose {k} at y={y}"
                )
        hess = d[:, GRAD, :].sum(axis=0)
        np.testing.assert_allclose(hess, hess.T, rtol=1e-9, atol=1e-9 * np.abs(hess).max())


def test_the_mirrored_yaw_gives_the_mirrored_wheel():
    """The wheelset shifted, rolled and yawed one way gives the other wheel's forces mirrored
    when shifted, rolled and yawed the other way (vehicle y to the left): Q and Fx equal, Y
    opposite; and yaw changes them (the pose reaches the strips)."""
    sy = scenarios.coach_system(geometry="strip")
    q, _ = static_equilibrium(sy, 50.0, "hertz-kalker")
    iy, ir, ip = sy.index("ws1_y"), sy.index("ws1_roll"), sy.index("ws1_yaw")
    outs = []
    for s, yaw in ((1.0, 3e-3), (-1.0, 3e-3), (1.0, 0.0)):
        x = q.copy()
        x[iy] += s * 6.5e-3
        x[ir] += s * 1e-3
        x[ip] += s * yaw
        outs.append(sy.native.force(CallSettings(50.0, 1), x, np.zeros_like(x))[1])
    a, b, c = outs
    np.testing.assert_allclose(a[0, :, 0], b[0, ::-1, 0], rtol=1e-9)  # Q
    np.testing.assert_allclose(a[1, :, 0], -b[1, ::-1, 0], rtol=1e-9)  # Y
    np.testing.assert_allclose(a[2, :, 0], b[2, ::-1, 0], rtol=1e-9, atol=1e-6)  # Fx
    assert np.abs(a[0, :, 0] - c[0, :, 0]).max() > 10.0


def test_bad_yaw(setup):
    from railvti.errors import InputError

    with pytest.raises(InputError, match="finite"):
        strip_wheel(setup[2], 0.0, 0.0, 0.0, np.inf)
