"""Deck keys of the friction laws on the 'rolling' case type: a Polach case runs and equals
the Python API's answer, full slip under the jump law gives mu_kinetic Fn, no friction key
leaves today's case bit for bit, and inconsistent coefficients are refused naming the key."""

from __future__ import annotations

import numpy as np
import pytest

import railvti.contact.cases  # noqa: F401  (registers the case types)
from railvti.casetypes import REGISTRY, REQUIRED
from railvti.contact import Grid, hertz_gap, solve_normal, solve_rolling
from railvti.contact.friction import FrictionLaw, solve_tangential_friction
from railvti.errors import InputError
from railvti.material import Material


def _params(**kw):
    ct = REGISTRY["rolling"]
    p = {k: (None if v is REQUIRED else v) for k, v in ct.defaults.items()}
    p.update(
        dict(
            nx=24,
            ny=24,
            dx=1.0e-3,
            dy=0.5e-3,
            gap_a=0.8,
            gap_b=1 / 0.6,
            fn=100e3,
            mu=0.55,
            xi=4e-3,
            speed=11.0,
        )
    )
    p.update(kw)
    return p


def test_polach_case_matches_the_api():
    out = REGISTRY["rolling"].run(_params(friction_law="polach", polach_a=0.4, friction_decay_s_m=0.6))
    mat = Material(shear_modulus=82e9, poisson=0.28)
    grid = Grid(24, 24, 1.0e-3, 0.5e-3, None, None)
    normal = solve_normal(hertz_gap(grid, 0.8, 1 / 0.6), grid, mat, fn=100e3)
    ref = solve_tangential_friction(
        normal.pressure, grid, mat, FrictionLaw.polach(0.55, 0.4, 0.6), (4e-3, 0, 0), 11.0
    )
    assert out.scalars["fx"][0] == pytest.approx(ref.fx, rel=1e-9)
    assert out.scalars["n_multiple"][0] == 0
    # below the constant-mu force (the law has fallen in the slip area)
    const = REGISTRY["rolling"].run(_params())
    assert abs(out.scalars["fx"][0]) < abs(const.scalars["fx"][0])


def test_jump_law_full_slip():
    out = REGISTRY["rolling"].run(_params(friction_law="coulomb", mu_kinetic=0.4, xi=0.05))
    assert -out.scalars["fx"][0] / out.scalars["fn"][0] == pytest.approx(0.4, rel=2e-3)


def test_no_friction_key_is_todays_case():
    out = REGISTRY["rolling"].run(_params())
    mat = Material(shear_modulus=82e9, poisson=0.28)
    grid = Grid(24, 24, 1.0e-3, 0.5e-3, None, None)
    r = solve_rolling(hertz_gap(grid, 0.8, 1 / 0.6), grid, mat, 0.55, 100e3, (4e-3, 0, 0), 11.0)
    np.testing.assert_array_equal(out.datasets["tx"][0], r.tx)
    assert "n_multiple" not in out.scalars


@pytest.mark.parametrize(
    ("kw", "key"),
    [
        (dict(friction_law="linear", mu_kinetic=0.6, friction_halving_speed_m_s=1.0), "mu_kinetic"),
        (dict(friction_law="polach", polach_a=1.5, friction_decay_s_m=0.6), "polach_a"),
        (dict(friction_law="polach", polach_a=0.4, friction_decay_s_m=-0.6), "friction_decay_s_m"),
        (dict(friction_law="rational", mu_kinetic=0.2), "friction_halving_speed_m_s"),
        (dict(mu_kinetic=0.2), "mu_kinetic"),
        (dict(friction_law="coulomb", mu_kinetic=0.2, polach_a=0.3), "polach_a"),
    ],
)
def test_inconsistent_coefficients_name_the_key(kw, key):
    ct = REGISTRY["rolling"]
    msgs = ct.check(_params(**kw))
    assert any(key in m for m in msgs), msgs
    with pytest.raises(InputError, match=key):
        ct.run(_params(**kw))
