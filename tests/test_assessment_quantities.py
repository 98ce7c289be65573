"""The assessment quantities (railvti.assessment) on synthetic runs with known forces and
motions: sliding means against a direct loop, Sigma Y and Y/Q against closed forms,
accelerations of body points against the rigid-body motion, Sperling's Wz of a sine
against the closed form (issue 34 acceptance), N_MV of a sine, the table's verdicts at the
limit, HDF5 storage, and bad input named."""

import math

import h5py
import numpy as np
import pytest

from railvti.assessment import (
    Assessment,
    Row,
    assess,
    derivative_error,
    n_mv,
    point_acceleration,
    sliding_mean,
    sperling_wz,
    sperling_wz_piecewise,
    sperling_wz_sine,
    weighting,
)
from railvti.errors import InputError
from railvti.runner.result_objects import load, save
from railvti.vehicle import DOF_NAMES, WHEEL_OUTPUTS, SimulationResult
from railvti.vehicle.params import DEFAULTS

DT = 0.002
Q0 = 50.0e3


def _result(duration=2.0, speed=50.0, Y=None, Q=None, q=None, v=None, **kw):
    """A SimulationResult of the coach's DOFs with the given wheel forces (nt, 2, 4) and
    motions (nt, n); zeros where not given."""
    t = np.arange(0.0, duration + 0.5 * DT, DT)
    nt, n = t.size, len(DOF_NAMES)
    wheel = np.zeros((nt, len(WHEEL_OUTPUTS), 2, 4))
    wheel[:, 0] = Q0 if Q is None else Q(t)
    if Y is not None:
        wheel[:, 1] = Y(t)
    return SimulationResult(
        t=t,
        q=np.zeros((nt, n)) if q is None else q(t),
        v=np.zeros((nt, n)) if v is None else v(t),
        wheel=wheel,
        dof_names=tuple(DOF_NAMES),
        speed=speed,
        contact="synthetic",
        h=DT,
        friction=0.3,
        flange_angle=math.radians(70.0),
        **kw,
    )


def _direct_mean(t, y, w):
    """The mean of the piecewise-linear y over [t_i - w, t_i], segment by segment."""
    out = []
    for ti in t[t >= t[0] + w - 1e-12]:
        a, b, s = ti - w, ti, 0.0
        for j in range(t.size - 1):
            u0, u1 = max(a, t[j]), min(b, t[j + 1])
            if u1 <= u0:
                continue
            y0 = y[j] + (y[j + 1] - y[j]) * (u0 - t[j]) / (t[j + 1] - t[j])
            y1 = y[j] + (y[j + 1] - y[j]) * (u1 - t[j]) / (t[j + 1] - t[j])
            s += 0.5 * (u1 - u0) * (y0 + y1)
        out.append(s / w)
    return np.array(out)


def test_sliding_mean_matches_a_direct_loop():
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.5, 1.5, 300)) * 0.01  # uneven on purpose
    y = rng.normal(size=t.size)
    w = 0.0537  # not a whole number of samples
    _, m = sliding_mean(t, y, w)
    ref = _direct_mean(t, y, w)
    assert m.shape == ref.shape
    assert np.max(np.abs(m - ref)) < 1e-12


def _sinc_amp(f, w):
    """Amplitude of the sliding mean over w of a unit sine of frequency f."""
    x = math.pi * f * w
    return math.sin(x) / x


def test_sum_y_and_its_2m_mean_on_known_forces():
    f, a, b1, b2, speed = 1.0, 12.0e3, 20.0e3, 5.0e3, 40.0

    def y(t):
        out = np.zeros((t.size, 2, 4))
        out[:, 0, 0] = b1 + a * np.sin(2 * np.pi * f * t)
        out[:, 1, 0] = b2
        return out

    r = assess(_result(duration=3.0, speed=speed, Y=y))
    row = r.row("sum_y_2m_prudhomme")
    expected = b1 + b2 + a * _sinc_amp(f, 2.0 / speed)  # 20 Hz low-pass: 1 - 2e-11 at 1 Hz
    assert row.where == "ws1"
    assert abs(row.value - expected) < 1e-4 * expected
    assert row.limit == pytest.approx(10e3 + 2 * Q0 / 3)  # P0 = 2 Q0
    assert r.row("sum_y_2m_en14363").limit == pytest.approx(0.85 * (10e3 + 2 * Q0 / 3))


def test_y_over_q_2m_on_known_forces():
    """The left wheel of wheelset 3 pushed outwards: the rail's Y on it is -0.3 Q (1 + 0.5
    sin): its flange-climb ratio is 0.3 (1 + 0.5 sin), 2 m sliding mean closed form."""
    f, speed = 2.0, 30.0

    def y(t):
        out = np.zeros((t.size, 2, 4))
        out[:, 0, 2] = -0.3 * Q0 * (1.0 + 0.5 * np.sin(2 * np.pi * f * t))
        return out

    r = assess(_result(duration=2.0, speed=speed, Y=y))
    row = r.row("yq_2m")
    assert row.where == "ws3 left"
    expected = 0.3 * (1.0 + 0.5 * _sinc_amp(f, 2.0 / speed))
    assert abs(row.value - expected) < 1e-4
    assert r.row("yq_max").value == pytest.approx(0.45, rel=1e-3)
    nadal = (math.tan(math.radians(70)) - 0.3) / (1 + 0.3 * math.tan(math.radians(70)))
    assert r.row("yq_max").limit == pytest.approx(nadal)


def test_q_max_is_the_99_85_percentile():
    """Q of one wheel a sine about Q0: its 99.85 % percentile is close to the crest (the
    percentile of a sine: Q0 + A sin(pi (0.9985 - 0.5)) ...), and dynamic Q = that - Q0."""
    amp = 20e3

    def q(t):
        out = np.full((t.size, 2, 4), Q0)
        out[:, 1, 0] += amp * np.sin(2 * np.pi * 1.0 * t)
        return out

    r = assess(_result(duration=4.0, Q=q))
    # the percentile of a sampled sine: crest times cos(pi (1 - 0.9985)) for a uniform phase
    expected = Q0 + amp * math.cos(math.pi * 0.0015)
    assert r.row("q_max").value == pytest.approx(expected, rel=2e-4)
    assert r.row("q_max").where == "ws1 right"
    assert r.row("q_dyn").value == pytest.approx(expected - Q0, rel=1e-3)
    assert r.row("q_max").limit == pytest.approx(90e3 + Q0)  # 180 km/h: below the 200 kN cap


def test_body_point_accelerations_follow_the_rigid_motion():
    """Carbody lateral, yaw and roll harmonics: the floor point above bogie 1 accelerates
    by -w^2 (A + B a - C (h_floor - h_cg)) sin(w t) laterally (small rotations about the
    track axes), to the central difference's error."""
    f, A, B, C = 3.0, 0.01, 0.001, 0.002
    w = 2 * np.pi * f
    names = list(DOF_NAMES)
    iy, iyaw, iroll = names.index("carbody_y"), names.index("carbody_yaw"), names.index("carbody_roll")

    def motion(t, rate):
        out = np.zeros((t.size, len(names)))
        s = w * np.cos(w * t) if rate else np.sin(w * t)
        out[:, iy], out[:, iyaw], out[:, iroll] = A * s, B * s, C * s
        return out

    r = _result(duration=1.0, q=lambda t: motion(t, False), v=lambda t: motion(t, True))
    a, hc, floor = DEFAULTS["half_bogie_distance"][0], DEFAULTS["carbody_cg_height"][0], 1.2
    ay, az = point_acceleration(r, "carbody", (0.0, 0.0, hc), (a, 0.0, floor))
    exact = -(w**2) * (A + B * a - C * (floor - hc)) * np.sin(w * r.t)
    amp = w**2 * abs(A + B * a - C * (floor - hc))
    err = np.max(np.abs(ay[1:-1] - exact[1:-1])) / amp
    assert err < 1.05 * derivative_error(f, DT) + 1e-9
    assert np.max(np.abs(az)) < 1e-9  # no vertical motion from lateral, yaw, roll at y = 0


@pytest.mark.parametrize("direction", ["vertical", "lateral"])
@pytest.mark.parametrize("f", [1.0, 2.0, 4.0, 8.0, 12.0])
def test_sperling_wz_of_a_sine_is_the_closed_form(direction, f):
    """A 0.3 m/s^2 sine: Wz from the filtered signal equals (100 a B(f))^0.3 within 0.5 %,
    and Sperling's original 0.896 (a^3 F(f)/f)^(1/10) (a in cm/s^2, piecewise F) within 3 %."""
    fs, amp = 500.0, 0.3
    t = np.arange(0.0, 65.0, 1.0 / fs)
    wz = sperling_wz(t, amp * np.sin(2 * np.pi * f * t), direction, discard=5.0)
    assert wz == pytest.approx(sperling_wz_sine(amp, f, direction), rel=5e-3)
    assert wz == pytest.approx(sperling_wz_piecewise(amp, f, direction), rel=3e-2)


def test_sperling_closed_form_value():
    """A worked value: 1 m/s^2 (100 cm/s^2) vertical at 2 Hz: B = 0.6101, Wz = 61.01^0.3."""
    assert sperling_wz_sine(1.0, 2.0, "vertical") == pytest.approx(61.008**0.3, rel=1e-4)


def test_n_mv_of_a_sine():
    """A lateral 1.5 Hz sine of 0.2 m/s^2 and a vertical 5 Hz one of 0.3 m/s^2: every 5 s
    block has the weighted rms a |W(f)| / sqrt 2, so N_MV = 6 sqrt(sum of their squares)."""
    fs = 100.0
    t = np.arange(0.0, 305.0, 1.0 / fs)
    ay, az = 0.2 * np.sin(2 * np.pi * 1.5 * t), 0.3 * np.sin(2 * np.pi * 5.0 * t)
    r = n_mv(t, None, ay, az, discard=5.0)
    wy = 0.2 * abs(weighting("Wd").response([1.5])[0]) / math.sqrt(2)
    wzz = 0.3 * abs(weighting("Wb").response([5.0])[0]) / math.sqrt(2)
    assert r.value == pytest.approx(6 * math.hypot(wy, wzz), rel=5e-3)
    assert r.blocks == 60 and not r.indicative
    short = n_mv(t[t < 60.0], None, ay[t < 60.0], az[t < 60.0], discard=5.0)
    assert short.indicative and short.blocks == 11
    assert short.value == pytest.approx(r.value, rel=1e-2)


def test_verdict_flips_at_the_limit():
    assert Row("a", "a", 1.0, "1", limit=1.0).verdict == "pass"
    assert Row("a", "a", 1.0 + 1e-12, "1", limit=1.0).verdict == "FAIL"
    assert Row("a", "a", 1.0, "1").verdict == "info"
    assert Row("a", "a", math.nan, "1", limit=1.0).verdict == "n/a"

    def y(t):
        out = np.zeros((t.size, 2, 4))
        out[:, 0, 1] = 30e3
        return out

    res = _result(duration=1.0, Y=y)
    value = assess(res).row("sum_y_2m_prudhomme").value
    # Prud'homme's limit 10 kN + 2 Q0 / 3 just above and just below the value
    above = assess(res, wheel_load=1.5 * (value * (1 + 1e-6) - 10e3))
    below = assess(res, wheel_load=1.5 * (value * (1 - 1e-6) - 10e3))
    assert above.row("sum_y_2m_prudhomme").verdict == "pass"
    assert below.row("sum_y_2m_prudhomme").verdict == "FAIL"
    assert not below.passed


def test_table_and_hdf5_round_trip(tmp_path):
    a = assess(_result(duration=1.0))
    text = a.table()
    assert len(text.splitlines()) < 50 and "overall:" in text
    assert str(a) == text
    with h5py.File(tmp_path / "a.h5", "w") as f:
        a.to_hdf5(f)
    with h5py.File(tmp_path / "a.h5", "r") as f:
        g = f["assessment"]
        assert g["sum_y_2m_prudhomme"].attrs["units"] == "N"
        assert g["carbody_ay_rms"].attrs["units"] == "m/s^2"
        b = Assessment.from_hdf5(g)
    assert [r.key for r in b.rows] == [r.key for r in a.rows]
    # the generic result file (railvti.runner.result_objects) holds it too
    c = load(save(a, tmp_path / "obj.h5"))
    assert c.table() == text
    with h5py.File(tmp_path / "obj.h5", "r") as f:
        assert f["result/rows/item2/value"].attrs["units"] == "per the row's unit field"
    for r, s in zip(a.rows, b.rows):
        assert r.verdict == s.verdict and r.unit == s.unit and r.limit_source == s.limit_source
        assert (math.isnan(r.value) and math.isnan(s.value)) or r.value == s.value


def test_windows_longer_than_the_run_are_named_rows():
    """0.03 s at 50 m/s is 1.5 m: no 2 m mean, no 100 m rms, no 5 s block: 'n/a' rows
    that say why; the rest is evaluated."""
    a = assess(_result(duration=0.03))
    for key in ("yq_2m", "sum_y_2m_prudhomme", "sum_y_rms", "n_mv"):
        assert a.row(key).verdict == "n/a" and "<" in a.row(key).note, key
    assert a.row("q_max").verdict == "pass"


def test_bad_input_is_named():
    r = _result(duration=1.0)
    with pytest.raises(InputError, match="no per-wheel outputs"):
        assess(SimulationResult(**{**r.__dict__, "wheel": np.zeros((r.t.size, 0, 2, 0))}))

    def y(t):
        out = np.zeros((t.size, 2, 4))
        out[100, 1, 2] = np.nan
        return out

    with pytest.raises(InputError, match=r"Y is NaN or inf at t = 0.2 s"):
        assess(_result(duration=1.0, Y=y))
    with pytest.raises(InputError, match="shorter than the 2 s window"):
        sliding_mean(r.t, r.t, 2.0, "Sigma Y")
    with pytest.raises(InputError, match="5 s block"):
        n_mv(r.t, None, np.zeros(r.t.size), np.zeros(r.t.size))
    with pytest.raises(InputError, match="streamed"):
        assess(SimulationResult(**{**r.__dict__, "streamed": "f.h5::g"}))
    with pytest.raises(InputError, match="discarding"):
        assess(r, discard=5.0)
    with pytest.raises(InputError, match="too few to filter"):
        assess(_result(duration=0.002))
