"""The stiff limit of model FR (issue 30, item 2): the FE wheelset with Young's modulus times
``wheelset_stiffness_scale`` must reproduce model RR (the same wheelset body and gyroscopic
moments, railvti.vehicle.wheelset_body), the independent reference; and bad scales are refused
before any run. The full check (linear critical speed within 0.5 %, hunting at 400 km/h within
1 %) is validation/vehicle_stiff_limit.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from railvti import scenarios
from railvti.vehicle import systems
from railvti.errors import InputError
from railvti.vehicle.flexible import build_fr
from railvti.vehicle.flexible_linear import eigenvalues as fr_eigenvalues
from railvti.vehicle.params import Coach
from railvti.vehicle.equilibrium import eigenvalues
from railvti.vehicle.table import linearised_table

SMALL = {"k_max": 1, "f_max": 300.0}


def _hunting(ev: np.ndarray) -> complex:
    """The least damped oscillatory eigenvalue between 1 and 20 Hz."""
    band = ev[(ev.imag > 2 * np.pi * 1.0) & (ev.imag < 2 * np.pi * 20.0)]
    return band[np.argmax(band.real)]


def test_stiff_wheelset_linearises_as_rr():
    """At 300 km/h the hunting eigenvalue of FR x 1e3 equals RR's (measured: within 1e-4 of
    |lambda|), while the real FR's lies visibly apart (its wheelset's flexibility lowers the
    critical speed by about 3.5 %)."""
    lam = scenarios.equivalent_conicity(0.003)
    v = 300.0 / 3.6
    table = linearised_table(scenarios.wheel_table(), lam)
    er = _hunting(eigenvalues(scenarios.coach_system("RR", linear_conicity=lam), v))
    built = {
        scale: build_fr(
            Coach(wheelset_stiffness_scale=scale), table, v, wheelset=systems.fr_wheelset(), **SMALL
        )
        for scale in (1.0, 1e3)
    }
    out = {scale: _hunting(fr_eigenvalues(sy, v)) for scale, (sy, _) in built.items()}
    assert abs(out[1e3] - er) < 1e-3 * abs(er)
    assert abs(out[1.0] - er) > 5 * abs(out[1e3] - er)
    # the scaled modes: the same ones, sqrt(1e3) times higher
    l1, l3 = built[1.0][1][0], built[1e3][1][0]
    assert l1.labels == l3.labels
    np.testing.assert_allclose(l3.freq_hz, np.sqrt(1e3) * l1.freq_hz, rtol=1e-6)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), "x"])
def test_bad_scale_is_refused_naming_the_key(bad):
    with pytest.raises(InputError, match="wheelset_stiffness_scale"):
        Coach(wheelset_stiffness_scale=bad)


def test_scale_too_stiff_for_any_step_is_refused_before_a_run():
    with pytest.raises(InputError, match="wheelset_stiffness_scale = 1e\\+09.*time step"):
        scenarios.fr_system(Coach(wheelset_stiffness_scale=1e9), speed_kmh=300.0, **SMALL)


def test_deck_key_is_checked_before_a_run(tmp_path):
    from railvti.runner.deck import read_deck

    deck = tmp_path / "d.nml"
    deck.write_text(
        "&case\n  type = 'vehicle'\n  scenario = 'hunting'\n  model = 'FR'\n"
        "  speed_kmh = 300.0\n  coach_wheelset_stiffness_scale = -2.0\n/\n"
    )
    with pytest.raises(InputError, match="wheelset_stiffness_scale"):
        read_deck(deck)
