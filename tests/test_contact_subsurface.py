"""Subsurface stresses (railvti.contact.subsurface) against theory.

References: Hertz's field on the axis of a circular contact (Johnson 1985, eq. 3.45);
Hamilton (1983), "Explicit equations for the stresses beneath a sliding spherical contact",
Proc. IMechE 197C, 53-59, for the normal load off the axis; the Boussinesq and Cerruti
point-force solutions (Johnson 1985, sect. 3.2-3.3) integrated numerically (scipy) over the
Hertz pressure and the sliding traction mu p, an integration independent of the corner
functions; equilibrium of a slab between the surface and a plane at depth z.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate, optimize

from railvti.contact import Grid, hertz, solve_normal, hertz_gap
from railvti.contact.subsurface import subsurface_stress, subsurface_stress_fields
from railvti.errors import InputError
from railvti.material import Material

NU = 0.3
A = 1.0e-3  # contact radius, m
P0 = 1.0e9  # Pa
MAT = Material(shear_modulus=80e9, poisson=NU)


def axis_closed_form(s, nu=NU):
    """(sigma_r, sigma_z) / p0 on the axis at z = s a (Johnson 1985, eq. 3.45)."""
    s = np.asarray(s, dtype=float)
    sz = -1.0 / (1.0 + s * s)
    sr = -(1.0 + nu) * (1.0 - s * np.arctan(1.0 / s)) + 0.5 / (1.0 + s * s)
    return sr, sz


def hamilton_normal(x, y, z, a=1.0, nu=NU):
    """Hamilton (1983), the normal-load stresses (xx, yy, zz, yz, xz, xy) / p0 off the axis."""
    r2 = x * x + y * y
    aa = r2 + z * z - a * a
    s = np.sqrt(aa * aa + 4.0 * a * a * z * z)
    m = np.sqrt(0.5 * (s + aa))
    n = np.sqrt(0.5 * (s - aa))
    phi = np.arctan(a / m)
    g = m * m - n * n + z * m - a * n
    h = 2.0 * m * n + a * m + z * n
    k = 1.0 / a  # 3 P / (2 pi a^3) = p0 / a
    common = (1.0 - nu) * n * z * z - (1.0 - 2.0 * nu) / 3.0 * (n * s + 2.0 * aa * n + a**3) - nu * m * z * a

    def direct(u, v):
        return k * (
            (1.0 + nu) * z * phi
            + ((v * v - u * u) / r2 * common - n * (u * u + 2.0 * nu * v * v) - m * u * u * z * a / s) / r2
        )

    sxx, syy = direct(x, y), direct(y, x)
    szz = k * (-n + a * z * m / s)
    sxy = k * (
        x
        * y
        * (1.0 - 2.0 * nu)
        / r2**2
        * (-n * r2 + 2.0 / 3.0 * n * (s + 2.0 * aa) - z * (z * n + a * m) + 2.0 / 3.0 * a**3)
        + x * y * z / r2**2 * (-a * m * r2 / s - z * n + a * m)
    )
    sxz = -k * z * (x * n / s - x * z * h / (g * g + h * h))
    syz = -k * z * (y * n / s - y * z * h / (g * g + h * h))
    return np.array([sxx, syy, szz, syz, sxz, sxy])


def point_force(x, y, z, nu=NU):
    """Stresses (xx, yy, zz, yz, xz, xy) of unit point forces at the origin: (Boussinesq
    along +z into the body, Cerruti along +x), Johnson 1985 sect. 3.2-3.3."""
    r = np.sqrt(x * x + y * y + z * z)
    r2 = x * x + y * y
    t = 1.0 - 2.0 * nu
    b = np.array(
        [
            (t / r2 * ((1 - z / r) * (x * x - y * y) / r2 + z * y * y / r**3) - 3 * z * x * x / r**5),
            (t / r2 * ((1 - z / r) * (y * y - x * x) / r2 + z * x * x / r**3) - 3 * z * y * y / r**5),
            -3 * z**3 / r**5,
            -3 * y * z * z / r**5,
            -3 * x * z * z / r**5,
            x * y * (t * (2 * r + z) / (r**3 * (r + z) ** 2) - 3 * z / r**5),
        ]
    ) / (2 * np.pi)
    rz = r + z
    c = np.array(
        [
            -x / r**3 * (3 * x * x / r**2 - t / rz**2 * (r * r - y * y - 2 * r * y * y / rz)),
            -x / r**3 * (3 * y * y / r**2 - t / rz**2 * (3 * r * r - x * x - 2 * r * x * x / rz)),
            -3 * x * z * z / r**5,
            -3 * x * y * z / r**5,
            -3 * x * x * z / r**5,
            -y / r**3 * (3 * x * x / r**2 + t / rz**2 * (r * r - x * x - 2 * r * x * x / rz)),
        ]
    ) / (2 * np.pi)
    return b, c


def hertz_quadrature(x, y, z, mu, a=1.0, nu=NU):
    """Stresses / p0 at (x, y, z) of the Hertz pressure and the traction mu p along +x, by
    adaptive quadrature of the point-force solutions over the disc (polar coordinates)."""
    out = np.zeros(6)
    for k in range(6):

        def f(rho, th, k=k):
            xi, eta = rho * np.cos(th), rho * np.sin(th)
            pr = np.sqrt(max(1.0 - rho * rho / (a * a), 0.0))
            b, c = point_force(x - xi, y - eta, z, nu)
            return (b[k] + mu * c[k]) * pr * rho

        out[k] = integrate.dblquad(f, 0.0, 2 * np.pi, 0.0, a, epsabs=1e-8, epsrel=1e-8)[0]
    return out


def hertz_grid(n_per_a=30):
    g = Grid.covering(A, A, n_per_semiaxis=n_per_a, margin=1.1)
    x, y = g.mesh()
    p = P0 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))
    return g, p


@pytest.fixture(scope="module")
def axis_field():
    g, p = hertz_grid(40)
    # an odd grid has an element centred on the axis
    g = Grid(g.nx + 1, g.ny + 1, g.dx, g.dy)
    x, y = g.mesh()
    p = P0 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))
    s = np.linspace(0.02, 4.0, 120)
    r = subsurface_stress_fields(g, p, poisson=NU, z=s * A, x=[0.0], y=[0.0], method="direct")
    return s, r


def test_hertz_axis_against_closed_form(axis_field):
    s, r = axis_field
    sr, sz = axis_closed_form(s)
    assert np.max(np.abs(r.component("zz")[0, 0] / P0 - sz)) < 2e-3
    assert np.max(np.abs(r.component("xx")[0, 0] / P0 - sr)) < 2e-3
    assert np.max(np.abs(r.component("yy")[0, 0] / P0 - sr)) < 2e-3
    assert np.max(np.abs(r.stress[0, 0, :, 3:])) < 1e-3 * P0  # no shear on the axis
    assert np.max(np.abs(r.von_mises[0, 0] / P0 - np.abs(sz - sr))) < 2e-3


def test_hertz_max_von_mises_and_depth():
    """Closed form (Johnson 1985, eq. 3.45, nu = 0.3): max |sigma_z - sigma_r| = 0.6200 p0 at
    z = 0.4809 a; the BEM field's 3-D maximum within 1 % of both."""
    f = lambda s: -abs(np.subtract(*axis_closed_form(s)))  # noqa: E731
    best = optimize.minimize_scalar(f, bounds=(0.2, 1.0), method="bounded", options={"xatol": 1e-10})
    vm_th, s_th = -best.fun, best.x
    assert vm_th == pytest.approx(0.6200, abs=1e-4) and s_th == pytest.approx(0.4809, abs=1e-4)
    g, p = hertz_grid(30)
    g = Grid(g.nx + 1, g.ny + 1, g.dx, g.dy)
    x, y = g.mesh()
    p = P0 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))
    z = np.linspace(0.40, 0.56, 33) * A
    r = subsurface_stress_fields(g, p, poisson=NU, z=z, method="fft")
    xm, ym, zm = r.max_von_mises_at
    assert r.max_von_mises / P0 == pytest.approx(vm_th, rel=0.01)
    assert zm / A == pytest.approx(s_th, rel=0.01)
    assert abs(xm) < 1e-9 and abs(ym) < 1e-9


def test_bem_pressure_max_von_mises():
    """The same from the BEM normal solution of a sphere (gap x^2 + y^2 over 2R)."""
    mat = Material(shear_modulus=80e9, poisson=NU)
    R = 0.05
    h = hertz(1 / (2 * R), 1 / (2 * R), 1.0e4, mat)
    g = Grid.covering(h.a, h.b, n_per_semiaxis=24, margin=1.2)
    g = Grid(g.nx + 1, g.ny + 1, g.dx, g.dy)
    nr = solve_normal(hertz_gap(g, 1 / (2 * R), 1 / (2 * R)), g, mat, fn=1.0e4)
    r = subsurface_stress(nr, mat, z=np.linspace(0.40, 0.56, 17) * h.a, x=[0.0], y=[0.0])
    assert r.max_von_mises / h.p0 == pytest.approx(0.6200, rel=0.01)
    assert r.max_von_mises_at[2] / h.a == pytest.approx(0.4809, rel=0.01)


def _inner_fraction(L, z, k):
    """Part of a point force's sigma_zz (k = 2, normal force) or sigma_xz (k = 4, Cerruti)
    integral that falls inside the square |x|, |y| < L at depth z (the tail outside decays
    slowly for sigma_xz, ~ z / L)."""

    def f(y, x):
        r5 = (x * x + y * y + z * z) ** 2.5
        return 3.0 * z * (z * z if k == 2 else x * x) / (2.0 * np.pi * r5)

    return integrate.dblquad(f, -L, L, -L, L, epsabs=1e-12, epsrel=1e-10)[0]


def test_far_field_vanishes_and_equilibrium():
    """The slab above z carries the applied load: the integral of sigma_zz over the plane z
    equals -Fn and that of sigma_xz equals -Fx (less the point-force tail beyond the
    integration square, computed by quadrature); the field decays far from the patch."""
    n_per_a, L = 8, 12.0
    h = A / n_per_a
    nx = int(2 * L * n_per_a)
    g = Grid(nx, nx, h, h)
    x, y = g.mesh()
    p = P0 * np.sqrt(np.maximum(1.0 - (x * x + y * y) / A**2, 0.0))
    q = 0.3 * p
    fn = p.sum() * g.element_area
    fx = q.sum() * g.element_area
    z = np.array([0.5, 1.0])
    r = subsurface_stress_fields(g, p, q, poisson=NU, z=z * A, method="fft")
    for k, zk in enumerate(z):
        fz_int = r.component("zz")[:, :, k].sum() * h * h
        fx_int = r.component("xz")[:, :, k].sum() * h * h
        assert fz_int == pytest.approx(-fn * _inner_fraction(L, zk, 2), rel=1e-3)
        assert fx_int == pytest.approx(-fx * _inner_fraction(L, zk, 4), rel=1e-3)
    far = subsurface_stress_fields(
        g, p, q, poisson=NU, z=[50 * A, 200 * A], x=[0.0], y=[0.0], method="direct"
    )
    assert far.max_von_mises < 1e-3 * P0
    assert far.von_mises[0, 0, 1] < far.von_mises[0, 0, 0] / 10  # ~ 1/z^2 decay


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_hamilton_field_off_axis(mu):
    """Off-axis points of the sliding sphere: the BEM field of the Hertz pressure and the
    traction mu p (full sliding, acting along +x on the body) against Hamilton's explicit
    normal-load equations and, for the whole field, the quadrature of the point forces."""
    g, p = hertz_grid(40)
    pts = [
        (0.3, 0.2, 0.5),
        (-0.6, 0.1, 0.3),
        (0.5, -0.5, 0.8),
        (1.2, 0.4, 0.6),
        (0.0, 0.7, 0.25),
        (0.32, 0.01, 0.43),
    ]
    x = np.array([t[0] for t in pts]) * A
    y = np.array([t[1] for t in pts]) * A
    z = np.array([t[2] for t in pts]) * A
    for k in range(len(pts)):
        r = subsurface_stress_fields(g, p, mu * p, poisson=NU, z=[z[k]], x=[x[k]], y=[y[k]])
        got = r.stress[0, 0, 0] / P0
        if mu == 0.0:
            ref = hamilton_normal(*pts[k])
            if k < 2:  # the transcription of Hamilton's equations against the quadrature
                assert np.max(np.abs(hertz_quadrature(*pts[k], mu) - ref)) < 1e-7
        else:
            ref = hertz_quadrature(*pts[k], mu)
        assert np.max(np.abs(got - ref)) < 2e-3, (pts[k], got, ref)


def test_sliding_maximum_moves_to_surface():
    """Full sliding (traction mu p along +x on the body, nu = 0.3): the largest von Mises
    stress rises and moves up and forward with mu: at mu = 0.3 it is 0.660 p0 at
    z = 0.43 a, x = +0.32 a (0.620 p0 at 0.48 a without friction); by mu = 0.4 it has
    reached the surface, at the trailing half of the patch. (This field's crossing lies
    between mu = 0.35 and 0.4; the off-axis values are checked against the quadrature of
    the point forces in test_hamilton_field_off_axis.)"""
    g, p = hertz_grid(30)
    z = np.concatenate(([0.005], np.linspace(0.02, 0.7, 69))) * A
    res = {}
    for mu in (0.0, 0.3, 0.4):
        r = subsurface_stress_fields(g, p, mu * p, poisson=NU, z=z, y=[g.y[g.ny // 2]], method="fft")
        res[mu] = (r.max_von_mises / P0, np.array(r.max_von_mises_at) / A)
    assert res[0.0][1][2] == pytest.approx(0.48, abs=0.015)
    assert res[0.3][0] == pytest.approx(0.660, abs=0.005)
    assert res[0.3][1][2] == pytest.approx(0.43, abs=0.015)
    assert res[0.3][1][0] == pytest.approx(0.32, abs=0.04)
    assert res[0.4][1][2] < 0.01 and res[0.4][1][0] < 0.0


def test_methods_agree_and_thread_independent():
    g, p = hertz_grid(8)
    q = 0.25 * p
    qy = -0.1 * p
    z = [0.1 * A, 0.6 * A]
    a = subsurface_stress_fields(g, p, q, qy, poisson=0.28, z=z, method="fft")
    b = subsurface_stress_fields(g, p, q, qy, poisson=0.28, z=z, method="direct")
    assert np.max(np.abs(a.stress - b.stress)) < 1e-9 * P0
    sub = subsurface_stress_fields(g, p, q, qy, poisson=0.28, z=z, x=g.x[3:9], y=g.y[::2])
    assert np.array_equal(sub.x, g.x[3:9])
    assert np.max(np.abs(sub.stress - a.stress[3:9][:, ::2])) < 1e-9 * P0


def test_invariants_against_numpy():
    g, p = hertz_grid(8)
    r = subsurface_stress_fields(g, p, 0.3 * p, 0.1 * p, poisson=NU, z=[0.2 * A, 0.5 * A])
    s = r.stress
    t = np.empty(s.shape[:3] + (3, 3))
    t[..., 0, 0], t[..., 1, 1], t[..., 2, 2] = s[..., 0], s[..., 1], s[..., 2]
    t[..., 1, 2] = t[..., 2, 1] = s[..., 3]
    t[..., 0, 2] = t[..., 2, 0] = s[..., 4]
    t[..., 0, 1] = t[..., 1, 0] = s[..., 5]
    ev = np.linalg.eigvalsh(t)[..., ::-1]
    assert np.max(np.abs(ev - r.principal)) < 1e-9 * P0
    assert np.max(np.abs(r.tresca - (ev[..., 0] - ev[..., 2]))) < 1e-9 * P0
    vm = np.sqrt(
        0.5
        * ((ev[..., 0] - ev[..., 1]) ** 2 + (ev[..., 1] - ev[..., 2]) ** 2 + (ev[..., 2] - ev[..., 0]) ** 2)
    )
    assert np.max(np.abs(r.von_mises - vm)) < 1e-9 * P0


@pytest.mark.parametrize("z", [[0.0], [-1e-4], [1e-4, -2e-4], [np.nan]])
def test_depth_outside_half_space(z):
    g, p = hertz_grid(6)
    with pytest.raises(InputError, match="subsurface z"):
        subsurface_stress_fields(g, p, poisson=NU, z=z)


def test_bad_inputs():
    g, p = hertz_grid(6)
    with pytest.raises(InputError, match="poisson"):
        subsurface_stress_fields(g, p, poisson=0.5, z=[1e-4])
    with pytest.raises(InputError, match="qx"):
        subsurface_stress_fields(g, p, p[:-1], poisson=NU, z=[1e-4])
    with pytest.raises(InputError, match="method"):
        subsurface_stress_fields(g, p, poisson=NU, z=[1e-4], x=[1e-5], method="fft")
    with pytest.raises(InputError, match="fewer depths"):
        subsurface_stress_fields(
            g,
            p,
            poisson=NU,
            z=np.linspace(1e-5, 1e-3, 10),
            x=np.linspace(0, 1e-3, 3000),
            y=np.linspace(0, 1e-3, 3000),
        )
    with pytest.raises(InputError, match="body"):
        subsurface_stress(solve_normal(hertz_gap(g, 100.0, 100.0), g, MAT, fn=1e3), MAT, [1e-4], body="axle")


_THREAD_SCRIPT = """
import numpy as np, sys
from railvti.contact import Grid
from railvti.contact.subsurface import subsurface_stress_fields
g = Grid.covering(1e-3, 1e-3, n_per_semiaxis=10, margin=1.1)
x, y = g.mesh()
p = 1e9 * np.sqrt(np.maximum(1 - (x * x + y * y) / 1e-6, 0))
z = np.linspace(0.05e-3, 1e-3, 7)
a = subsurface_stress_fields(g, p, 0.3 * p, -0.1 * p, poisson=0.3, z=z, method="fft").stress
b = subsurface_stress_fields(g, p, 0.3 * p, -0.1 * p, poisson=0.3, z=z, method="direct").stress
np.save(sys.argv[1], np.stack([a, b]))
"""


def test_results_independent_of_thread_count(tmp_path):
    """OMP_NUM_THREADS = 1 and 2 give the same bits on both paths (each value is summed by one
    thread in a fixed order)."""
    import os
    import subprocess
    import sys

    out = []
    for n in (1, 2):
        f = tmp_path / f"t{n}.npy"
        env = dict(os.environ, OMP_NUM_THREADS=str(n))
        subprocess.run([sys.executable, "-c", _THREAD_SCRIPT, str(f)], env=env, check=True)
        out.append(np.load(f))
    assert np.array_equal(out[0], out[1])
