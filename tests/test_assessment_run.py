"""The assessment of a real short run (hunting, RR, Hertz + FASTSIM, 1 s) and of a vehicle
deck case, which stores it with units."""

import math

import numpy as np
import pytest

from railvti import scenarios
from railvti.assessment import assess, butterworth_lowpass
from railvti.assessment.table import VERDICTS
from railvti.casetypes import REGISTRY
import railvti.vehicle.cases  # noqa: F401  (registers the case type)
from railvti.runner.stream import HistoryStream


@pytest.fixture(scope="module")
def run():
    return scenarios.hunting(300, variant="RR", contact="hertz-fastsim", duration=1.0)


def _direct_mean(t, y, w):
    """Mean of the piecewise-linear y over [t_i - w, t_i] by a loop over the segments."""
    out = []
    for ti in t[t >= t[0] + w - 1e-12]:
        a, s = ti - w, 0.0
        for j in range(t.size - 1):
            u0, u1 = max(a, t[j]), min(ti, t[j + 1])
            if u1 > u0:
                y0 = y[j] + (y[j + 1] - y[j]) * (u0 - t[j]) / (t[j + 1] - t[j])
                y1 = y[j] + (y[j + 1] - y[j]) * (u1 - t[j]) / (t[j + 1] - t[j])
                s += 0.5 * (u1 - u0) * (y0 + y1)
        out.append(s / w)
    return np.array(out)


def test_hunting_run_sum_y_is_the_sum_of_the_wheels_2m_means(run):
    """Sigma Y_2m of every wheelset = the sum of its two wheels' (20 Hz filtered) Y 2 m
    means, each by a direct loop; the row holds the largest |.| over the wheelsets."""
    a = assess(run)
    fs = 1.0 / (run.t[1] - run.t[0])
    yf = butterworth_lowpass(20.0).apply(run.Y, fs)
    w = 2.0 / run.speed
    per_ws = [
        np.abs(_direct_mean(run.t, yf[:, 0, ws], w) + _direct_mean(run.t, yf[:, 1, ws], w)).max()
        for ws in range(4)
    ]
    row = a.row("sum_y_2m_prudhomme")
    assert row.value == pytest.approx(max(per_ws), rel=1e-9)
    assert row.where == f"ws{int(np.argmax(per_ws)) + 1}"
    assert row.value > 5e3  # hunting from a 4 mm kick pushes the track: a real signal
    for r in a.rows:
        assert r.verdict in VERDICTS
        assert r.verdict == "n/a" or math.isfinite(r.value)
    assert "Sigma Y" in a.table()


def test_vehicle_case_stores_the_assessment():
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(scenario="hunting", speed_kmh=300.0, duration=0.3, contact="hertz-fastsim")
    out = REGISTRY["vehicle"].run(p)
    value, unit = out.datasets["assess_sum_y_2m_prudhomme"]
    assert unit == "N" and np.isfinite(value)
    labels = out.attrs["assess_sum_y_2m_prudhomme"]
    assert labels["verdict"] in VERDICTS and "Prud'homme" in labels["limit_source"]
    assert out.datasets["assess_carbody_ay_rms"][1] == "m/s^2"
    assert "overall:" in out.attrs["assessment_passed"]["table"]
    assert out.datasets["assessment_passed"][0] in (0, 1)


def test_a_case_too_short_to_assess_says_why_and_stands():
    """5 ms of centred running at the 10 ms output interval: two output times, too few to
    filter; the case keeps its results and says why it has no assessment."""
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(scenario="centred_running", speed_kmh=200.0, duration=0.005, contact="hertz-kalker")
    out = REGISTRY["vehicle"].run(p)
    assert "too few to filter" in out.scalars["assessment"][0]
    assert not any(k.startswith("assess_") for k in out.datasets)
    assert "Q_final" in out.datasets


def test_a_stream_reads_back_its_history_and_columns(tmp_path):
    """HistoryStream.read (the sink's whole history, for the assessment of a streamed run):
    the appended rows, and the columns asked for in the order asked."""
    rng = np.random.default_rng(1)
    blocks = [rng.normal(size=(n, 5)) for n in (3, 4)]
    with HistoryStream(tmp_path / "s.h5") as s:
        for b in blocks:
            s.append({"v": b})
        full = np.vstack(blocks)
        assert np.array_equal(s.read("v"), full)
        assert np.array_equal(s.read("v", [3, 0, 2]), full[:, [3, 0, 2]])
