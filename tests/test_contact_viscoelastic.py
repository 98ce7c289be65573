"""Viscoelastic steady rolling (issue 35, Deliver 3): the filtered kernels against quadrature,
the elastic limits (Hertz), Hunter's cylinder (Hunter 1961) against his reduction solved by
quadrature, the 3-D grid against solve_normal, the deck case type and bad input."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import quad

import railvti.contact.viscoelastic_cases  # noqa: F401  (registers the case type)
from railvti import Material
from railvti.casetypes import REGISTRY, REQUIRED
from railvti.contact import Grid, hertz, hertz_gap, solve_normal, solve_rolling
from railvti.contact.viscoelastic import (
    ViscoelasticMaterial,
    grid_coefficients,
    line_hertz_half_width,
    line_kernel,
    solve_viscoelastic,
    solve_viscoelastic_line,
)
from railvti.contact.viscoelastic_hunter import hunter_cylinder
from railvti.contact.viscoelastic_rolling import solve_viscoelastic_rolling
from railvti.errors import InputError

#: A polymer: glassy G0 three times the relaxed Ginf (J0 / Jinf = 1/3), nu = 0.4.
POLY = ViscoelasticMaterial(
    shear_modulus=3.0e9, shear_modulus_relaxed=1.0e9, relaxation_time=0.01, poisson=0.4
)
R, FN = 0.05, 2.0e5  # m, N/m


def _quad_filtered(fun, r, el, breaks):
    """Int_0^inf (1/L) exp(-s/L) fun(r + s) ds by adaptive quadrature split at the kinks."""
    pts = sorted({0.0, *[b for b in breaks if b > 0.0], 40.0 * el})
    total = sum(
        quad(lambda s: math.exp(-s / el) / el * fun(r + s), a, b, limit=400, epsrel=1e-12, epsabs=0.0)[0]
        for a, b in zip(pts, pts[1:])
    )
    return (
        total + quad(lambda s: math.exp(-s / el) / el * fun(r + s), pts[-1], np.inf, limit=200, epsabs=0.0)[0]
    )


def test_line_kernel_is_the_filtered_elastic_kernel():
    """k(m) = J0 Ke + (Jinf - J0) F[Ke] against adaptive quadrature of the filter integral."""
    n, d, speed, ell = 30, 1e-4, 0.05, 1.0
    k = line_kernel(n, d, speed, POLY, None, reference_length=ell)
    j0, jinf, el = POLY.compliance_instant, POLY.compliance_relaxed, speed * POLY.creep_time

    def phi(t):
        return 0.0 if t == 0.0 else t * math.log(abs(t) / ell) - t

    def ke(r):
        return -(2.0 / math.pi) * (phi(r + d / 2) - phi(r - d / 2))

    for m in (-29, -5, -1, 0, 1, 4, 29):
        r = m * d
        ref = j0 * ke(r) + (jinf - j0) * _quad_filtered(ke, r, el, [-r - d / 2, -r + d / 2])
        assert k[m + n - 1] == pytest.approx(ref, rel=1e-9, abs=1e-12 * abs(ref))


def test_grid_coefficients_are_the_filtered_boussinesq_field():
    """The 3-D field against quadrature of the filter over the element integral of 1/r."""
    grid = Grid(16, 12, 1e-4, 1.5e-4)
    speed = 0.033
    c = grid_coefficients(grid, speed, POLY)
    j0, jinf, el = POLY.compliance_instant, POLY.compliance_relaxed, speed * POLY.creep_time
    dx, dy = grid.dx, grid.dy

    def blog(a, b):
        if b == 0.0:
            return 0.0
        r = math.hypot(a, b)
        return b * math.log(a + r) if a > 0 else b * math.log(b * b / (r - a))

    def ce(x, y):
        f = [
            blog(yy, xx) + blog(xx, yy) for xx in (x + dx / 2, x - dx / 2) for yy in (y + dy / 2, y - dy / 2)
        ]
        return (f[0] - f[1] - f[2] + f[3]) / math.pi

    for k, l in ((0, 0), (-3, 0), (5, 1), (-15, 2), (7, -4), (15, 11)):
        x, y = k * dx, l * dy
        ref = j0 * ce(x, y) + (jinf - j0) * _quad_filtered(
            lambda t: ce(t, y), x, el, [-x - dx / 2, -x + dx / 2]
        )
        assert c[k % 32, l % 24] == pytest.approx(ref, rel=3e-6)


@pytest.mark.parametrize("tau, compliance", [(1e-12, "relaxed"), (1e6, "instant")])
def test_line_limits_of_the_relaxation_time_are_hertz(tau, compliance):
    """tau -> 0: the relaxed response (Jinf); tau -> inf: the glassy one (J0); both symmetric
    Hertz line contacts (Johnson 1985, eq. 4.43: a^2 = 4 P R / (pi E*), p0 = 2 P / (pi a))."""
    mat = ViscoelasticMaterial(3.0e9, 1.0e9, tau, 0.4)
    j = mat.compliance_relaxed if compliance == "relaxed" else mat.compliance_instant
    a = line_hertz_half_width(R, FN, j)
    r = solve_viscoelastic_line(R, FN, 1.0, mat, n=600, half_length=2.0 * a)
    d = 4.0 * a / 600
    assert (r.x_leading - r.x_trailing) / 2 == pytest.approx(a, abs=d)
    assert abs(r.centroid) < 1e-6 * a
    assert r.pmax == pytest.approx(2.0 * FN / (math.pi * a), rel=3e-3)


@pytest.mark.parametrize("ratio", [0.3, 1.0, 3.0])
def test_hunter_cylinder(ratio):
    """Rigid cylinder on a standard linear solid (Hunter 1961): the BEM against Hunter's
    reduction (airfoil inversion + first-order equation, viscoelastic_hunter) at L / a_inf =
    0.3, 1, 3: pressure centroid within 0.005 %, contact edges within one strip, pressure
    profile within 0.3 % (L2; pointwise the strip cut by the leading edge differs by ~2 %)."""
    a = line_hertz_half_width(R, FN, POLY.compliance_relaxed)
    speed = ratio * a / POLY.creep_time
    n = 800
    r = solve_viscoelastic_line(R, FN, speed, POLY, n=n, half_length=1.25 * a)
    h = hunter_cylinder(R, FN, POLY.compliance_instant, POLY.compliance_relaxed, speed * POLY.creep_time)
    d = 2.5 * a / n
    assert r.centroid == pytest.approx(h.centroid, rel=5e-5)
    assert r.resistance_coefficient == pytest.approx(h.resistance_coefficient, rel=5e-5)
    assert r.x_leading == pytest.approx(h.x_leading, abs=d)
    assert r.x_trailing == pytest.approx(h.x_trailing, abs=d)
    assert h.x_leading + h.x_trailing > 0.05 * a  # the contact moves forward
    ph = np.interp(r.x, h.x[::-1], h.pressure[::-1], left=0.0, right=0.0)
    assert np.linalg.norm(r.pressure - ph) < 3e-3 * np.linalg.norm(ph)


def test_resistance_peaks_at_an_intermediate_speed():
    """Hunter: the resistance tends to zero for small and large V tc / a and has one maximum."""
    a = line_hertz_half_width(R, FN, POLY.compliance_relaxed)
    ratios = [0.01, 0.1, 0.3, 1.0, 3.0, 10.0, 100.0]
    mu = [
        solve_viscoelastic_line(R, FN, q * a / POLY.creep_time, POLY, n=400).resistance_coefficient
        for q in ratios
    ]
    k = int(np.argmax(mu))
    assert 0 < k < len(ratios) - 1
    assert all(np.diff(mu[: k + 1]) > 0) and all(np.diff(mu[k:]) < 0)
    assert mu[0] < 0.1 * mu[k] and mu[-1] < 0.1 * mu[k]


def test_two_elastic_bodies_on_the_grid_match_solve_normal():
    """Two elastic bodies of one material: the same problem as solve_normal (another solver)."""
    mat = Material(shear_modulus=82e9, poisson=0.28)
    A = B = 1.0 / (2 * 0.46)
    hz = hertz(A, B, 1e5, mat)
    grid = Grid.covering(hz.a, hz.b, n_per_semiaxis=14)
    gap = hertz_gap(grid, A, B)
    ref = solve_normal(gap, grid, mat, fn=1e5, tol=1e-11)
    r = solve_viscoelastic(gap, grid, 1e5, 30.0, mat, mat)
    assert np.abs(r.pressure - ref.pressure).max() < 1e-7 * ref.pmax
    assert r.approach == pytest.approx(ref.approach, rel=1e-8)
    assert abs(r.centroid) < 1e-9 * hz.a


@pytest.mark.parametrize("speed, compliance", [(0.0, "relaxed"), (1e5, "instant")])
def test_grid_speed_limits_are_hertz(speed, compliance):
    """A sphere on a standard linear solid: V = 0 the relaxed Hertz contact, V tc >> a the
    glassy one (p0 = 3 fn / (2 pi a^2) with 1/E* = J the body's compliance)."""
    j = POLY.compliance_relaxed if compliance == "relaxed" else POLY.compliance_instant
    Rs, fn = 0.02, 50.0
    a = (3 * fn * Rs * j / 4) ** (1 / 3)
    grid = Grid.covering(a, a, n_per_semiaxis=16, margin=1.3)
    x, y = grid.mesh()
    r = solve_viscoelastic((x * x + y * y) / (2 * Rs), grid, fn, speed, POLY)
    assert r.pmax == pytest.approx(3 * fn / (2 * math.pi * a * a), rel=0.01)
    assert abs(r.centroid) < 1e-3 * a


def test_grid_sphere_rolls_with_resistance():
    """A sphere at V tc = a_inf: contact and centroid moved forward, resistance > 0, peaked."""
    Rs, fn = 0.02, 50.0
    a = (3 * fn * Rs * POLY.compliance_relaxed / 4) ** (1 / 3)
    grid = Grid.covering(a, a, n_per_semiaxis=12, margin=1.3)
    x, y = grid.mesh()
    gap = (x * x + y * y) / (2 * Rs)
    mus = [
        solve_viscoelastic(gap, grid, fn, q * a / POLY.creep_time, POLY).resistance_coefficient
        for q in (0.05, 1.0, 30.0)
    ]
    assert mus[1] > 3 * max(mus[0], mus[2]) > 0
    r = solve_viscoelastic(gap, grid, fn, a / POLY.creep_time, POLY)
    assert r.resistance_force == pytest.approx(fn * r.centroid / Rs, rel=1e-2)


def test_result_independent_of_blas_threads_and_kernels():
    """The dense LU (line) and the GMRES/FFT solve (grid) give the same answer with 1 and 2
    OpenBLAS threads and with OpenBLAS's Sandybridge kernels (rtol 1e-12)."""
    code = (
        "import json, numpy as np; from railvti.contact import Grid;"
        "from railvti.contact.viscoelastic import *;"
        "m = ViscoelasticMaterial(3e9, 1e9, 0.01, 0.4);"
        "r = solve_viscoelastic_line(0.05, 2e5, 0.04, m, n=500);"
        "g = Grid.covering(6.1e-4, 6.1e-4, 10, 1.3); x, y = g.mesh();"
        "q = solve_viscoelastic((x * x + y * y) / 0.04, g, 50.0, 0.01, m);"
        "print(json.dumps([r.centroid, float(r.pressure.max()), q.centroid, float(q.pressure.max())]))"
    )
    out = []
    for threads, core_type in (("1", None), ("2", None), ("1", "Sandybridge")):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS=threads)
        env.pop("OPENBLAS_CORETYPE", None)
        if core_type:
            env["OPENBLAS_CORETYPE"] = core_type
        res = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        )
        out.append(json.loads(res.stdout))
    np.testing.assert_allclose(out[1], out[0], rtol=1e-12)
    np.testing.assert_allclose(out[2], out[0], rtol=1e-12)


@pytest.mark.parametrize(
    "kw, key",
    [
        ({"shear_modulus": 0.0}, "shear_modulus"),
        ({"shear_modulus": -1e9}, "shear_modulus"),
        ({"shear_modulus_relaxed": 0.0}, "shear_modulus_relaxed"),
        ({"relaxation_time": 0.0}, "relaxation_time"),
        ({"relaxation_time": -1.0}, "relaxation_time"),
        ({"poisson": 0.5}, "poisson"),
        ({"poisson": -1.0}, "poisson"),
        ({"poisson": float("nan")}, "poisson"),
        ({"shear_modulus_relaxed": 4e9}, "shear_modulus_relaxed"),
    ],
)
def test_bad_material_names_the_key(kw, key):
    args = {"shear_modulus": 3e9, "shear_modulus_relaxed": 1e9, "relaxation_time": 0.01, "poisson": 0.4}
    args.update(kw)
    with pytest.raises(InputError, match=key):
        ViscoelasticMaterial(**args)


def test_bad_solver_input_names_the_argument():
    with pytest.raises(InputError, match="speed"):
        solve_viscoelastic_line(R, FN, -1.0, POLY)
    with pytest.raises(InputError, match="radius"):
        solve_viscoelastic_line(0.0, FN, 1.0, POLY)
    with pytest.raises(InputError, match="rigid"):
        solve_viscoelastic_line(R, FN, 1.0, None, None)
    with pytest.raises(InputError, match="body2"):
        solve_viscoelastic_line(R, FN, 1.0, POLY, "steel")


def _deck(**kw):
    ct = REGISTRY["viscoelastic_rolling"]
    p = {k: (None if v is REQUIRED else v) for k, v in ct.defaults.items()}
    p.update(
        {
            "radius": R,
            "fn": FN,
            "speed": 0.04,
            "shear_modulus": 3e9,
            "shear_modulus_relaxed": 1e9,
            "relaxation_time": 0.01,
        }
    )
    p.update(kw)
    return p


def test_deck_case_line_and_point(tmp_path):
    import h5py

    ct = REGISTRY["viscoelastic_rolling"]
    out = ct.run(_deck())
    r = solve_viscoelastic_line(R, FN, 0.04, POLY)
    assert out.scalars["centroid"][0] == r.centroid
    with h5py.File(tmp_path / "v.h5", "w") as f:
        g = f.create_group("001_case")
        g.attrs["name"] = "case"
        for k, (v, _) in out.datasets.items():
            g.create_dataset(k, data=np.asarray(v))
        assert ct.plot(g, tmp_path, "v")[0].stat().st_size > 10_000
    tg = ct.run(_deck(geometry="point", fn=50.0, radius=0.02, n_per_semiaxis=8, mu=0.3, xi=-1e-3))
    assert 0 < tg.scalars["fx"][0] < 0.3 * 50.0
    pt = ct.run(
        _deck(
            geometry="point",
            fn=50.0,
            radius=0.02,
            n_per_semiaxis=8,
            body2="elastic",
            body2_shear_modulus=82e9,
            body2_poisson=0.28,
        )
    )
    assert pt.scalars["resistance_coefficient"][0] > 0
    assert pt.datasets["pressure"][0].ndim == 2


@pytest.mark.parametrize(
    "kw, key",
    [
        ({"shear_modulus": 0.0}, "shear_modulus"),
        ({"relaxation_time": 0.0}, "relaxation_time"),
        ({"poisson": 0.5}, "poisson"),
        ({"shear_modulus_relaxed": 5e9}, "shear_modulus_relaxed"),
        ({"body2": "elastic"}, "body2_shear_modulus"),
    ],
)
def test_deck_bad_keys_are_named(kw, key):
    problems = REGISTRY["viscoelastic_rolling"].problems(_deck(**kw))
    assert problems and any(key in m for m in problems)


@pytest.mark.parametrize("ratio", [0.3, 3.0])
def test_grid_strip_emulates_the_line_contact(ratio):
    """Two rows of length 2000 a on the 3-D grid (plane strain emulated, as for Carter in
    validation/contact_carter.py): the quadrature-filtered Boussinesq field gives the line
    contact's closed-form solution (centroid and pressure within 1e-5)."""
    a = line_hertz_half_width(R, FN, POLY.compliance_relaxed)
    speed = ratio * a / POLY.creep_time
    n = 200
    line = solve_viscoelastic_line(R, FN, speed, POLY, n=n, half_length=1.25 * a)
    dy = 2000.0 * a
    grid = Grid(n, 2, 2.5 * a / n, dy)
    x, _ = grid.mesh()
    r = solve_viscoelastic(x * x / (2 * R), grid, FN * 2 * dy, speed, POLY, strip=True)
    assert r.centroid == pytest.approx(line.centroid, rel=1e-5)
    assert np.linalg.norm(r.pressure[:, 0] - line.pressure) < 1e-5 * np.linalg.norm(line.pressure)


@pytest.mark.parametrize("speed, modulus", [(1e-6, "relaxed"), (1e5, "instant")])
def test_tangential_limits_are_elastic_rolling(speed, modulus):
    """Two PA6 rollers (one material: no coupling): V -> 0 and V tc >> a give solve_rolling's
    creep force and tractions with the relaxed and the glassy modulus (another kernel path)."""
    pa6 = ViscoelasticMaterial(1143e6, 571.5e6, 0.0045, 0.4)
    rs, fn, mu = 0.05, 200.0, 0.3
    a = (3 * fn * rs * 2 * pa6.compliance_relaxed / 4) ** (1 / 3)
    grid = Grid.covering(a, a, n_per_semiaxis=10, margin=1.3)
    x, y = grid.mesh()
    gap = np.asfortranarray((x * x + y * y) / (2 * rs))
    r = solve_viscoelastic_rolling(gap, grid, fn, speed, (-2e-3, 1e-3, 0.5), mu, pa6, pa6)
    g = pa6.shear_modulus_relaxed if modulus == "relaxed" else pa6.shear_modulus
    ref = solve_rolling(gap, grid, Material(g, 0.4), mu, fn, (-2e-3, 1e-3, 0.5), speed)
    assert r.fx == pytest.approx(ref.fx, rel=1e-5)
    assert r.fy == pytest.approx(ref.fy, rel=1e-5)
    assert np.abs(r.tx - ref.tx).max() < 1e-4 * mu * ref.pmax


def test_tangential_creep_force_saturates_and_moves_with_speed():
    """A large creepage saturates at mu Fn; at a small one the force grows from the relaxed
    to the glassy contact as Kalker's linear theory says (G0 / Ginf = 2)."""
    pa6 = ViscoelasticMaterial(1143e6, 571.5e6, 0.0045, 0.4)
    rs, fn, mu = 0.05, 200.0, 0.3
    a = (3 * fn * rs * 2 * pa6.compliance_relaxed / 4) ** (1 / 3)
    grid = Grid.covering(a, a, n_per_semiaxis=10, margin=1.3)
    x, y = grid.mesh()
    gap = np.asfortranarray((x * x + y * y) / (2 * rs))
    sat = solve_viscoelastic_rolling(gap, grid, fn, a / pa6.creep_time, (-0.1, 0, 0), mu, pa6, pa6)
    assert sat.fx == pytest.approx(mu * fn, rel=1e-4)
    f = [
        solve_viscoelastic_rolling(gap, grid, fn, q * a / pa6.creep_time, (-5e-4, 0, 0), mu, pa6, pa6).fx
        for q in (1e-4, 1e4)
    ]
    # nearly linear (Kalker): F = G a^2 C11 xi with a ~ G^(-1/3), so F ~ G^(1/3)
    assert f[1] / f[0] == pytest.approx(2.0 ** (1.0 / 3.0), rel=0.05)
