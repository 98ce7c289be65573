"""The scenarios take the speed in SI (speed, m/s) or by its suffixed alias (speed_kmh)."""

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError


def test_speed_in_m_s_and_km_h_give_the_same_run():
    a = scenarios.centred_running(speed_kmh=180.0, duration=0.02)
    b = scenarios.centred_running(speed=50.0, duration=0.02)
    assert a.speed_kmh == pytest.approx(180.0) and b.speed_kmh == pytest.approx(180.0)
    np.testing.assert_allclose(b.Q, a.Q, rtol=1e-12)
    np.testing.assert_allclose(b.Y, a.Y, rtol=1e-9, atol=1e-9)


def test_speed_errors_name_the_argument_and_unit():
    with pytest.raises(InputError, match="not both"):
        scenarios.centred_running(200.0, speed=50.0)
    with pytest.raises(InputError, match="required"):
        scenarios.hunting(duration=0.01)
    with pytest.raises(InputError, match="m/s"):
        scenarios.hunting(speed=-3.0, duration=0.01)
    with pytest.raises(InputError, match="m/s"):
        scenarios.hunting(speed=400.0, duration=0.01)
