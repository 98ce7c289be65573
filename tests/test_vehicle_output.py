"""The output interval (railvti.vehicle.output): by default the stored history resolves the
sleeper passing on the ring track, checked against its known frequency v / sleeper spacing;
an output_dt that aliases a known excitation warns, naming the key."""

from __future__ import annotations

import logging
import warnings

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import AliasingWarning, InputError
from railvti.vehicle import output
from railvti.casetypes import REGISTRY
import railvti.vehicle.cases  # noqa: F401  (registers the case type)


def _dominant(t: np.ndarray, x: np.ndarray) -> float:
    """Frequency of the largest peak of the detrended, Hann-windowed signal (zero-padded
    64x, so the peak is read to a small fraction of the 1 / T bin), Hz."""
    x = x - np.polyval(np.polyfit(t, x, 1), t)
    n = 64 * x.size
    spec = np.abs(np.fft.rfft(x * np.hanning(x.size), n))
    f = np.fft.rfftfreq(n, t[1] - t[0])
    return float(f[1 + np.argmax(spec[1:])])


def test_rf_default_output_shows_the_sleeper_passing_frequency():
    """RF at 200 km/h on 0.6 m sleepers: the wheel load's dominant frequency in the default
    history is the sleeper passing, 92.6 Hz, within 1 % (after a 50 ms transient); every
    10th sample of it (the old 10 ms interval) puts the peak far from it."""
    f_sleeper = 200.0 / 3.6 / 0.6
    with warnings.catch_warnings():
        warnings.simplefilter("error", AliasingWarning)  # the default never aliases
        c = scenarios.centred_running(200.0, "RF", duration=0.2, progress=False)
    t, q = c.run.t, c.run.Q[:, 1, 0]  # right wheel, leading wheelset
    k = t >= 0.05
    assert 1.0 / (t[1] - t[0]) > 5 * f_sleeper  # samples per sleeper period
    assert _dominant(t[k], q[k]) == pytest.approx(f_sleeper, rel=0.01)
    coarse = np.flatnonzero(k)[:: max(1, int(round(0.01 / (t[1] - t[0]))))]
    assert abs(_dominant(t[coarse], q[coarse]) - f_sleeper) > 0.5 * f_sleeper


def test_an_aliasing_output_dt_warns_naming_the_key_and_the_bound():
    """The rule itself: 10 ms at 92.6 Hz aliases (Nyquist 5.4 ms); 5 ms does not."""
    e = output.sleeper_passing(200.0 / 3.6, 0.6)
    with pytest.warns(
        AliasingWarning,
        match=r"output_dt = 0.01 s.*sleeper passing.*92.59 Hz"
        r".*at most 0.005 s",
    ):
        output.check_interval(0.01, 5e-4, [e])
    with warnings.catch_warnings():
        warnings.simplefilter("error", AliasingWarning)
        output.check_interval(0.005, 5e-4, [e])
    assert output.default_interval([e], 5e-4, 0.01) == pytest.approx(1e-3)  # 10.8 / period


def test_rr_hunting_with_a_coarse_output_dt_warns_and_bad_values_are_refused(caplog):
    """RR hunting at 300 km/h (Klingel's frequency about 9.5 Hz): 0.2 s aliases it; a deck
    run warns and logs it too; a negative output_dt is an InputError naming the key."""
    with pytest.warns(AliasingWarning, match="output_dt = 0.2 s.*hunting"):
        scenarios.hunting(300.0, duration=0.4, output_dt=0.2, progress=False)
    with caplog.at_level(logging.WARNING), pytest.warns(AliasingWarning, match="output_dt"):
        REGISTRY["vehicle"].run(
            {
                **REGISTRY["vehicle"].defaults,
                "scenario": "hunting",
                "speed_kmh": 300.0,
                "duration": 0.4,
                "output_dt": 0.2,
            }
        )
    assert any("output_dt" in r.getMessage() and "aliases" in r.getMessage() for r in caplog.records)
    with pytest.raises(InputError, match="output_dt"):
        scenarios.hunting(300.0, duration=0.1, output_dt=-1e-3, progress=False)
