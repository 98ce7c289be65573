"""railvti.contact.wear: T gamma against the BEM's frictional power, Archard wear against
the power identity of the slip zone, Jendel's map bands, Ekberg's surface fatigue index at
Johnson's shakedown limit, and the vehicle's per-wheel T gamma output."""

from __future__ import annotations

import numpy as np
import pytest

from railvti.contact import Grid, hertz, hertz_gap, solve_rolling
from railvti.contact.wear import JENDEL_K, archard_wear, jendel_coefficient, surface_fatigue_index, t_gamma
from railvti.errors import InputError
from railvti.material import Material

MAT = Material(shear_modulus=82e9, poisson=0.28)
FN, MU, V = 80e3, 0.3, 30.0
A_GAP, B_GAP = 0.5 / 0.46, 0.5 / 0.3


def _rolling(creepage: tuple[float, float, float], n: int = 30):
    h = hertz(A_GAP, B_GAP, FN, MAT)
    grid = Grid.covering(h.a, h.b, n, 1.3)
    return solve_rolling(hertz_gap(grid, A_GAP, B_GAP), grid, MAT, MU, FN, creepage, V, tol=1e-9), h


@pytest.mark.parametrize("creepage", [(1e-3, 0.0, 0.0), (0.0, 1.5e-3, 0.0), (2e-3, -1e-3, 0.0)])
def test_t_gamma_is_the_frictional_power_per_speed(creepage) -> None:
    """Without spin, T gamma V equals the frictional power sum |tau| |s| dA in the continuum
    (steady rolling: the elastic part of the slip does no net work on a symmetric kernel).
    The BEM's discrete slip (upwind differences) converges to it at first order: measured
    2.2 / 1.6 / 1.0 % on 30 x 30 elements and half that on 60 x 60."""
    err = []
    for n in (30, 60):
        r, _ = _rolling(creepage, n)
        tg = t_gamma(r.fx, r.fy, creepage[0], creepage[1])
        assert tg > 0.0
        err.append(tg * V / r.power - 1.0)
    assert abs(err[1]) < 0.012
    assert 1.7 < err[0] / err[1] < 2.4  # first order in the element size


def test_archard_volume_from_the_power_identity() -> None:
    """With a constant k, the worn volume rate k/H sum p |s| dA equals k P / (mu H): in the slip
    zone |tau| = mu p, in adhesion s = 0 (P: the BEM's own frictional power)."""
    r, _ = _rolling((2e-3, 1e-3, 0.0))
    hard, k = 2.4e9, 1e-3
    w = archard_wear(r, hard, coefficient=k)
    assert w.volume_rate == pytest.approx(k * r.power / (MU * hard), rel=1e-6)
    # the depth per pass summed across the track is the volume per metre rolled
    assert w.depth_per_pass.sum() * r.grid.dy == pytest.approx(w.volume_per_distance, rel=1e-12)
    assert w.volume_per_distance == pytest.approx(w.volume_rate / V, rel=1e-12)
    assert np.all(w.depth_rate >= 0.0) and np.all(w.depth_rate[r.status != 2] == 0.0)


def test_jendel_bands() -> None:
    h = 2.4e9
    p = np.array([1e9, 1e9, 1e9, 1e9, 0.81 * h])
    s = np.array([0.1, 0.2, 0.7, 0.71, 0.1])
    np.testing.assert_array_equal(
        jendel_coefficient(p, s, h), [JENDEL_K[1], JENDEL_K[2], JENDEL_K[2], JENDEL_K[3], JENDEL_K[0]]
    )
    r, _ = _rolling((2e-3, 0.0, 0.0), n=16)
    w = archard_wear(r, h)
    assert set(np.unique(w.coefficient)) <= set(JENDEL_K)


def test_surface_fatigue_index_at_the_shakedown_limit() -> None:
    """FI_surf = f - k / p0 for a Hertz patch (p0 = 3 Fn / (2 pi a b), Hertz's own maximum
    pressure): zero where the traction coefficient reaches k / p0."""
    h = hertz(A_GAP, B_GAP, FN, MAT)
    k = 300e6
    f = k / h.p0
    assert surface_fatigue_index(f * FN, FN, h.a, h.b, k) == pytest.approx(0.0, abs=1e-12)
    fi = surface_fatigue_index(np.array([0.0, 0.3 * FN]), np.array([FN, FN]), h.a, h.b, k)
    np.testing.assert_allclose(fi, [-k / h.p0, 0.3 - k / h.p0], rtol=1e-12)
    assert surface_fatigue_index(0.0, 0.0, 0.0, 0.0, k) == -np.inf


def test_bad_input_named() -> None:
    r, _ = _rolling((1e-3, 0.0, 0.0), n=12)
    with pytest.raises(InputError, match="hardness"):
        archard_wear(r, -1.0)
    with pytest.raises(InputError, match="coefficient"):
        archard_wear(r, 2.4e9, coefficient=0.0)
    with pytest.raises(InputError, match="shear_yield"):
        surface_fatigue_index(1.0, 1.0, 1e-3, 1e-3, float("nan"))


def test_vehicle_t_gamma_is_dissipative_and_bounded() -> None:
    """The time loop's per-wheel T gamma (summed over the wheel's points): where the wheel has
    one point, |T gamma| <= |F_t| |(xi, eta)| (Cauchy-Schwarz on -(Fx xi + Fy eta)), and the
    work on the creepages is positive overall."""
    from railvti import scenarios

    res = scenarios.hunting(360.0, variant="RR", contact="hertz-fastsim", duration=0.5, progress=False)
    tg, ft = res.wheel_output("T_gamma"), res.wheel_output("F_t")
    xi, eta = res.wheel_output("xi"), res.wheel_output("eta")
    one = res.wheel_output("N_flange") == 0.0
    assert np.all(np.abs(tg[one]) <= ft[one] * np.hypot(xi[one], eta[one]) * (1 + 1e-9) + 1e-9)
    # spin's share of Fy can make a point's T gamma slightly negative where eta is near 0;
    # the wheelsets' mean work on the creepages is positive and far larger
    assert tg.mean() > 0.0 and tg.max() > 1.0 and tg.min() > -0.01 * tg.max()
