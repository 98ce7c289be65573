"""Track irregularities as rail inputs under the wheels (railvti.vehicle.irregular_track,
fortran/vehicle/vehicle_irregularity.f90; docs/vehicle_irregularity.md): against theory (a
long wave is followed quasi-statically, delayed by the wheelsets' distance over the speed;
cross level rolls the wheelset by cross level / base), the symmetries (gauge alone, the mirror),
the run without irregularity (bit for bit) and the chunking."""

from __future__ import annotations

import functools
import os
import subprocess
import sys

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.track.irregularity import TrackIrregularity
from railvti.vehicle.irregular_track import (
    CROSS_LEVEL_BASE,
    node_slopes,
    on_track,
    rail_inputs,
)
from railvti.vehicle.simulate import simulate
from railvti.vehicle.systems import scenario_system, time_step

CHANNELS = ("vertical_level", "alignment", "cross_level", "gauge")


@functools.lru_cache(maxsize=None)
def _system(variant: str, speed: float):
    sy, _ = scenario_system(variant, None, speed, {})
    return sy, time_step(sy, None)


def _track(
    x0: float, x1: float, dx: float = 0.1, source: str = "test", ramp: tuple | None = None, **waves
) -> TrackIrregularity:
    """A track of sines: channel=(amplitude m, wavelength m[, phase rad]) each; ramp (xa, xb):
    zero before xa, faded in by a raised cosine up to xb (so that a coach starts on perfect
    track)."""
    x = np.arange(x0, x1 + dx, dx)
    ch = {c: np.zeros_like(x) for c in CHANNELS}
    for name, w in waves.items():
        a, lam = w[0], w[1]
        ph = w[2] if len(w) > 2 else 0.0
        ch[name] = ch[name] + a * np.sin(2 * np.pi * x / lam + ph)
    if ramp is not None:
        s = np.clip((x - ramp[0]) / (ramp[1] - ramp[0]), 0.0, 1.0)
        fade = 0.5 - 0.5 * np.cos(np.pi * s)
        ch = {c: v * fade for c, v in ch.items()}
    return TrackIrregularity(x, **ch, source=source)


def _fit(t: np.ndarray, s: np.ndarray, f: float, *others: float) -> tuple[float, float]:
    """Amplitude and phase of the part A sin(2 pi f t + phase) of s, fitted by least squares
    together with a constant and sines at the other frequencies."""
    cols = [np.ones_like(t)]
    for fk in (f, *others):
        w = 2 * np.pi * fk
        cols += [np.sin(w * t), np.cos(w * t)]
    c, *_ = np.linalg.lstsq(np.stack(cols, 1), s, rcond=None)
    return float(np.hypot(c[1], c[2])), float(np.arctan2(c[2], c[1]))


def _part(t: np.ndarray, s: np.ndarray, fs: list, others: list) -> np.ndarray:
    """The part of s at the frequencies fs, fitted by least squares with a constant and sines
    at the other frequencies."""
    cols = [np.ones_like(t)]
    for fk in (*fs, *others):
        cols += [np.sin(2 * np.pi * fk * t), np.cos(2 * np.pi * fk * t)]
    a = np.stack(cols, 1)
    c, *_ = np.linalg.lstsq(a, s, rcond=None)
    n = 1 + 2 * len(fs)
    return a[:, 1:n] @ c[1:n]


def _wrap(a: float) -> float:
    return float((a + np.pi) % (2 * np.pi) - np.pi)


# --- the inputs -----------------------------------------------------------------------------


def test_node_slopes_exact_for_a_parabola_on_uneven_nodes():
    """The slopes of the Hermite interpolant are those of a parabola through three nodes:
    exact for any quadratic, at the ends too."""
    x = np.array([0.0, 0.3, 1.0, 1.2, 2.5, 4.0])
    c = np.stack([2 * x**2 - x + 1, -0.5 * x**2 + 3 * x])
    d = node_slopes(x, c)
    assert np.allclose(d, np.stack([4 * x - 1, -x + 3]), rtol=0, atol=1e-12)


def test_rail_inputs_against_the_rails_positions():
    """The Fortran inputs under each wheel at time t equal the rails' positions of
    TrackIrregularity.rails() at x_start + v t + a_w (left rail at +0.75 m, the element's roll
    cross level / 1.5 m) to the interpolation's accuracy, their rates v d/dx to the same, and
    zero after the block."""
    sy, _ = _system("RR", 20.0)
    irr = _track(
        -40.0,
        120.0,
        dx=0.05,
        vertical_level=(0.004, 31.0),
        alignment=(0.003, 23.0, 0.4),
        cross_level=(0.002, 17.0, 1.0),
        gauge=(0.0015, 13.0, 2.0),
    )
    t = np.linspace(0.0, 3.0, 7)
    v, xs = 20.0, 5.0
    with on_track(sy, irr, v, xs):
        u = rail_inputs(sy, t)
    assert u.shape == (7, 7, 2, 4)
    yr, zr = irr.rails()
    fine = np.linspace(irr.x[0], irr.x[-1], 400001)
    for w, a in enumerate(sy.x_wheelsets):
        x = xs + v * t + a
        for k, sg in ((0, 1.0), (1, -1.0)):
            y = np.interp(x, irr.x, yr[k])
            z = np.interp(x, irr.x, zr[k])
            assert np.allclose(u[:, 0, k, w], y, rtol=0, atol=2e-7)
            assert np.allclose(u[:, 1, k, w] + sg * 0.5 * CROSS_LEVEL_BASE * u[:, 2, k, w], z, atol=2e-7)
            # rates: v times the slope of the positions (finite differences of the rails)
            dy = np.gradient(np.interp(fine, irr.x, yr[k]), fine)
            assert np.allclose(u[:, 3, k, w], v * np.interp(x, fine, dy), rtol=0, atol=5e-5 * v)
            assert np.allclose(u[:, 6, k, w], np.interp(x, fine, dy), rtol=0, atol=5e-5)
    u0 = rail_inputs(sy, t)
    assert not u0.any()


# --- bit for bit --------------------------------------------------------------------------


@pytest.mark.parametrize("variant", ["RR", "FR", "RF", "FF"])
def test_zero_irregularity_is_bit_identical(variant):
    """A track without irregularity gives the run without one, to the bit."""
    v = 100 / 3.6
    sy, h = _system(variant, v)
    irr = _track(-30.0, 60.0, dx=0.25)
    r0 = simulate(sy, v, 0.04, h=h, progress=False)
    r1 = simulate(sy, v, 0.04, h=h, progress=False, irregularity=irr, x_start=3.0)
    assert np.array_equal(r0.q, r1.q) and np.array_equal(r0.v, r1.v)
    assert np.array_equal(r0.wheel, r1.wheel)
    assert r0.irregularity == "" and r1.irregularity.startswith("test")
    assert r1.track_input.shape == (r1.t.size, 3, 2, 4) and not r1.track_input.any()


def _rough():
    return _track(
        -30.0,
        60.0,
        dx=0.1,
        vertical_level=(3e-4, 3.1),
        alignment=(5e-4, 7.3, 0.5),
        cross_level=(3e-4, 5.3, 1.0),
        gauge=(4e-4, 2.9, 2.0),
    )


def test_chunked_run_bit_identical():
    """A run in many Fortran calls (the time absolute across them) equals one call, to the bit."""
    v = 120 / 3.6
    sy, h = _system("RR", v)
    irr = _rough()
    one = simulate(sy, v, 0.3, h=h, progress=False, irregularity=irr)
    many = simulate(sy, v, 0.3, h=h, progress=True, chunk=0.02, irregularity=irr)
    assert np.array_equal(one.q, many.q) and np.array_equal(one.wheel, many.wheel)
    assert np.abs(one.Q - one.Q[0]).max() > 100.0  # the track moved the loads


_SCRIPT = """
import sys, numpy as np
from railvti.track.irregularity import TrackIrregularity
from railvti.vehicle.simulate import simulate
from railvti.vehicle.systems import scenario_system
x = np.arange(-30.0, 60.0, 0.1)
ch = dict(vertical_level=3e-4 * np.sin(x), alignment=5e-4 * np.sin(0.8 * x),
          cross_level=3e-4 * np.cos(1.2 * x), gauge=4e-4 * np.sin(2.1 * x))
sy, _ = scenario_system("RR", None, 30.0, {})
r = simulate(sy, 30.0, 0.1, progress=False, irregularity=TrackIrregularity(x, **ch))
np.savez(sys.argv[1], q=r.q, wheel=r.wheel)
"""


def test_independent_of_openblas_coretype(tmp_path):
    """The same numbers under two OpenBLAS kernel sets, to far below the response (the run
    without irregularity differs by rounding, too: the static solve's LAPACK)."""
    out = []
    for core in ("Haswell", "Sandybridge"):
        env = dict(os.environ, OPENBLAS_CORETYPE=core)
        path = tmp_path / f"{core}.npz"
        subprocess.run([sys.executable, "-c", _SCRIPT, str(path)], env=env, timeout=600, check=True)
        out.append(np.load(path))
    a, b = out
    assert np.ptp(a["q"][:, 18]) > 1e-4  # ws1_y moves
    assert np.abs(a["q"] - b["q"]).max() < 1e-10
    assert np.abs(a["wheel"] - b["wheel"]).max() < 1e-6 * np.abs(a["wheel"]).max()


# --- against theory -------------------------------------------------------------------------

#: The coach starts with its leading wheelset at -0.22 m, all on perfect track; the
#: irregularity fades in over the first RAMP metres.
X_START, RAMP = -11.0, (0.0, 10.0)


_TWO_WAVES = ((0.005, 50.0), (0.0005, 3.0))  # (amplitude m, wavelength m)


@functools.lru_cache(maxsize=None)
def _two_waves(variant: str):
    """A 50 m, 5 mm and a 3 m, 0.5 mm vertical level wave at 100 km/h."""
    v = 100 / 3.6
    sy, h = _system(variant, v)
    irr = _track(-30.0, 130.0, dx=0.05, vertical_level=_TWO_WAVES[0], ramp=RAMP)
    short = _track(-30.0, 130.0, dx=0.05, vertical_level=_TWO_WAVES[1], ramp=RAMP)
    irr = TrackIrregularity(
        irr.x, irr.vertical_level + short.vertical_level, irr.alignment, irr.cross_level, irr.gauge
    )
    r = simulate(sy, v, 3.4, h=h, output_dt=0.002, irregularity=irr, x_start=X_START, progress=False)
    return r, sy, v


@pytest.mark.parametrize("variant", ["RR", "RF"])
def test_vertical_level_followed_quasi_statically(variant):
    """The 50 m, 5 mm vertical level wave at 100 km/h (0.56 Hz): every wheelset follows it
    quasi-statically, z_w = A sin(2 pi (x_start + v t + a_w) / lambda) (amplitude within 0.5 %,
    phase within 0.005 rad: the delay a_w / v between wheelsets; measured 0.06 %, 2e-4 rad);
    the 3 m wave on top (9.3 Hz)
    moves the wheel loads at v / lambda by kN (the fitted sine carries > 80 % of their
    variance, on RF once the sleeper passing's own is taken out)."""
    r, sy, v = _two_waves(variant)
    k = r.t > 1.4
    (a1, l1), (_, l2) = _TWO_WAVES
    f1, f2, fs = v / l1, v / l2, v / 0.6
    for w, a_w in enumerate(sy.x_wheelsets):
        amp, ph = _fit(r.t[k], r.dof(f"ws{w + 1}_z")[k], f1, f2)
        assert abs(amp / a1 - 1.0) < 0.005
        assert abs(_wrap(ph - 2 * np.pi * (X_START + a_w) / l1)) < 0.005
        qa, _ = _fit(r.t[k], r.Q[k, 0, w], f2, f1)
        # on the ring the sleeper passing (v / 0.6 m = 46 Hz) moves the loads too: without it
        q = r.Q[k, 0, w] - _part(r.t[k], r.Q[k, 0, w], [fs, 2 * fs], [f1, f2])
        assert qa**2 / 2 > 0.8 * q.var()
        assert qa > 500.0


def test_ring_wheel_load_close_to_rigid_track_at_low_frequency():
    """The wheel loads of the 3 m wave (9.3 Hz, 0.9 and 1.9 kN) on the ring (RF) within 2 % of
    RR's, in phase within 0.01 rad: far below the ring's modes (50 Hz and up) both tracks
    respond statically (measured 0.6 %, 0.002 rad)."""
    (rr, _, v), (rf, _, _) = _two_waves("RR"), _two_waves("RF")
    f1, f2 = v / _TWO_WAVES[0][1], v / _TWO_WAVES[1][1]
    for w in range(4):
        for s in (0, 1):
            k = rr.t > 1.4
            a, pa = _fit(rr.t[k], rr.Q[k, s, w], f2, f1)
            k = rf.t > 1.4
            b, pb = _fit(rf.t[k], rf.Q[k, s, w], f2, f1)
            assert abs(b / a - 1.0) < 0.02 and abs(_wrap(pa - pb)) < 0.01


def test_short_wave_wheel_load_at_passing_frequency():
    """A 1 m, 0.1 mm vertical level wave at 100 km/h on RR: the wheel load oscillates at
    v / lambda = 27.8 Hz (the fitted sine carries > 95 % of its variance), by kN."""
    v = 100 / 3.6
    sy, h = _system("RR", v)
    irr = _track(-30.0, 60.0, dx=0.02, vertical_level=(1e-4, 1.0), ramp=RAMP)
    r = simulate(sy, v, 1.5, h=h, output_dt=h, irregularity=irr, x_start=X_START, progress=False)
    k = r.t > 1.2
    for w in range(4):
        q = r.Q[k, 0, w]
        amp, _ = _fit(r.t[k], q, v)
        assert amp > 1e3
        assert amp**2 / 2 > 0.95 * q.var()
        off, _ = _fit(r.t[k], q, 1.3 * v, v)
        assert off < 0.1 * amp


def test_alignment_followed_kinematically_with_the_delay():
    """A 150 m, 5 mm alignment wave at 50 km/h, far above the bogie's kinematic wavelength
    (about 16 m): each wheelset follows it laterally within 3 % and yaws with the rail (the
    rail's slope amplitude 2 pi A / lambda within 3 %); the leading wheelsets of the two
    bogies lag by their distance over the speed (phase within 0.02 rad)."""
    v = 50 / 3.6
    sy, h = _system("RR", v)
    a, lam = 0.005, 150.0
    irr = _track(-30.0, 250.0, alignment=(a, lam), ramp=RAMP)
    r = simulate(sy, v, 15.0, h=h, output_dt=0.01, irregularity=irr, x_start=X_START, progress=False)
    k = r.t > 4.0
    f = v / lam
    ph = []
    for w in range(4):
        amp, p = _fit(r.t[k], r.dof(f"ws{w + 1}_y")[k], f)
        assert abs(amp / a - 1.0) < 0.03
        yaw, _ = _fit(r.t[k], r.dof(f"ws{w + 1}_yaw")[k], f)
        assert abs(yaw / (2 * np.pi * a / lam) - 1.0) < 0.03
        ph.append(p)
    xw = sy.x_wheelsets
    for i, j in ((0, 2), (1, 3)):
        assert abs(_wrap(ph[i] - ph[j] - 2 * np.pi * (xw[i] - xw[j]) / lam)) < 0.02


def test_cross_level_rolls_the_wheelsets():
    """A 150 m, 6 mm cross-level wave at 50 km/h rolls each wheelset by cross level / 1.5 m
    (amplitude within 1 %, in phase with its own position: within 0.02 rad)."""
    v = 50 / 3.6
    sy, h = _system("RR", v)
    a, lam = 0.006, 150.0
    irr = _track(-30.0, 250.0, cross_level=(a, lam), ramp=RAMP)
    r = simulate(sy, v, 15.0, h=h, output_dt=0.01, irregularity=irr, x_start=X_START, progress=False)
    k = r.t > 4.0
    for w, a_w in enumerate(sy.x_wheelsets):
        amp, p = _fit(r.t[k], r.dof(f"ws{w + 1}_roll")[k], v / lam)
        assert abs(amp / (a / CROSS_LEVEL_BASE) - 1.0) < 0.01
        assert abs(_wrap(p - 2 * np.pi * (X_START + a_w) / lam)) < 0.02


def test_gauge_alone_is_symmetric():
    """A pure gauge wave (20 m, 3 mm) on the centred coach: the wheel's lateral forces change
    by hundreds of N, equal and opposite on the two wheels (sum below 1e-5 N), and no wheelset
    moves laterally or yaws (below 1e-12 m, rad)."""
    v = 50 / 3.6
    sy, h = _system("RR", v)
    irr = _track(-30.0, 100.0, gauge=(0.003, 20.0))
    r = simulate(sy, v, 3.0, h=h, output_dt=0.005, irregularity=irr, progress=False)
    assert np.ptp(r.Y[:, 0], axis=0).min() > 100.0
    assert np.abs(r.Y[:, 0] + r.Y[:, 1]).max() < 1e-5
    for w in range(4):
        assert np.abs(r.dof(f"ws{w + 1}_y")).max() < 1e-12
        assert np.abs(r.dof(f"ws{w + 1}_yaw")).max() < 1e-12


@pytest.mark.parametrize("variant", ["RR", "RF"])
def test_mirrored_track_gives_the_mirrored_run(variant):
    """The mirrored irregularity (all four channels) gives the mirrored run: y, roll, yaw of
    every body change sign, the rest stays, Q left <-> right, Y left <-> -right, to rounding
    (measured 1e-13 m RR, 1.5e-12 m RF; Q 5e-5 N, 5e-4 N). RF's wheel forces to Newton's
    tolerance: its stopping test from the contraction (vehicle_newmark) may stop the two runs
    one iteration apart, and the forces come from the iterate before the last correction (at
    most 10 tol behind, the creep forces through the step's velocity 2/h times that): Y 0.046 N
    measured (0.1 N allowed, of forces up to 1 kN), the DOFs still within 1e-10 m."""
    v = 50 / 3.6
    sy, h = _system(variant, v)
    irr = _track(
        -30.0,
        60.0,
        vertical_level=(3e-4, 3.1),
        alignment=(2e-3, 17.3, 0.5),
        cross_level=(1e-3, 5.3, 1.0),
        gauge=(4e-4, 2.9, 2.0),
        ramp=(0.0, 5.0),
    )
    kw = dict(h=h, irregularity=irr, x_start=X_START, progress=False)
    a = simulate(sy, v, 1.0, **kw)
    kw["irregularity"] = irr.mirrored()
    b = simulate(sy, v, 1.0, **kw)
    names = [n for n in a.dof_names if n.startswith(("ws", "carbody", "bogie", "bolster"))]
    for n in names:
        sg = -1.0 if n.rsplit("_", 1)[-1] in ("y", "roll", "yaw") else 1.0
        assert np.abs(a.dof(n) - sg * b.dof(n)).max() < 1e-10, n
    assert np.abs(a.dof("ws1_y")).max() > 1e-3
    force_tol = 0.01 if variant == "RR" else 0.1
    assert np.abs(a.Q - b.Q[:, ::-1]).max() < force_tol
    assert np.abs(a.Y + b.Y[:, ::-1]).max() < force_tol


# --- the scenario, the result, bad input ------------------------------------------------------


def test_scenario_and_saved_result(tmp_path):
    """scenarios.irregular_track: the coach from the irregularity's start to its end, the
    irregularity faded in over lead_in; the result file keeps the source and the inputs."""
    from railvti.runner.result_objects import load, save

    irr = _track(0.0, 60.0, alignment=(0.002, 12.0), source="a 12 m alignment sine")
    r = scenarios.irregular_track(80.0, irr, duration=0.3, lead_in=5.0)
    assert "a 12 m alignment sine" in r.irregularity and "lead-in" in r.irregularity
    assert np.ptp(r.track_input[:, 0, 0, 0]) > 0
    back = load(save(r, tmp_path / "r.h5"))
    assert back.irregularity == r.irregularity
    assert np.array_equal(back.track_input, r.track_input)
    data, scalars = r.case_data()
    assert scalars["irregularity"][0] == r.irregularity
    assert data["track_input"][0].shape == r.track_input.shape


def test_bad_input_named():
    v = 30.0
    sy, h = _system("RR", v)
    irr = _track(-30.0, 40.0)
    with pytest.raises(InputError, match="irregularity.*covers x = -30 .. 40 m"):
        simulate(sy, v, 1.0, h=h, irregularity=irr, progress=False)
    with pytest.raises(InputError, match="irregularity must be a railvti.track.TrackIrregularity.*ndarray"):
        simulate(sy, v, 0.1, h=h, irregularity=np.zeros((5, 100)), progress=False)
    with pytest.raises(InputError, match="x_start"):
        simulate(sy, v, 0.1, h=h, irregularity=irr, x_start=float("nan"), progress=False)
    with pytest.raises(InputError, match="integrator='energy'"):
        simulate(sy, v, 0.1, h=h, irregularity=irr, integrator="energy", progress=False)
    with pytest.raises(InputError, match="needs an irregularity"):
        scenarios.irregular_track(100.0)
    with pytest.raises(InputError, match="too short"):
        scenarios.irregular_track(100.0, _track(0.0, 15.0))


@pytest.mark.parametrize("flexible, rigid", [("FR", "RR"), ("FF", "RF")])
def test_flexible_wheelsets_follow_like_rigid_ones(flexible, rigid):
    """The flexible wheelsets (their rims on the irregular rails, FR on the track elements, FF
    on the ring) follow a track of long waves (40 m vertical level 4 mm, 60 m alignment 3 mm,
    45 m cross level 2 mm; 100 km/h, 2 s) as the rigid ones do: the leading wheelset's z and
    roll within 1 % of their range (measured 0.4 %, 0.5 %), its y within 10 % (6 %, 5 %:
    the wheelset's own lateral dynamics differ)."""
    v = 100 / 3.6
    irr = _track(
        -30.0,
        90.0,
        vertical_level=(0.004, 40.0),
        alignment=(0.003, 60.0, 0.7),
        cross_level=(0.002, 45.0),
        ramp=RAMP,
    )
    runs = {}
    for variant in (flexible, rigid):
        sy, h = _system(variant, v)
        runs[variant] = simulate(
            sy, v, 2.0, h=h, output_dt=0.01, irregularity=irr, x_start=X_START, progress=False
        )
    a, b = runs[flexible], runs[rigid]
    for c, tol in (("z", 0.01), ("roll", 0.01), ("y", 0.1)):
        rng = np.ptp(b.dof(f"ws1_{c}"))
        assert rng > 1e-3  # m or rad: the track moved it
        assert np.abs(a.dof(f"ws1_{c}") - b.dof(f"ws1_{c}")).max() < tol * rng, c


@pytest.mark.parametrize("variant", ["RR", "RF"])
def test_straight_track_at_an_angle_is_the_straight_run_turned(variant):
    """An alignment growing linearly, theta x (a straight track turned by theta = 1 mrad), and
    the coach turned with it (each body's y by theta (x_start + its x), yaw by theta, lateral
    velocity v theta) is the perfect track's run turned: Q and Y the same and each body's y the
    same plus theta (x_start + v t + its x), to rounding (measured 2e-15 m RR, 2e-14 m RF).
    Independent of the inputs' formulas: it holds only with the positions, the rates v dT/dx,
    the rail's yaw taken off the wheelset's and the wheelsets' positions a_w all right (without
    the yaw the creepage is off by theta: Y by kN)."""
    from railvti.vehicle.equilibrium import static_equilibrium
    from railvti.vehicle.params import Coach

    v, theta, xs = 100 / 3.6, 1e-3, 5.0
    sy, h = _system(variant, v)
    q0, v0, _ = static_equilibrium(sy, v, "hertz-kalker", return_velocity=True)
    xb = Coach().params["half_bogie_distance"]
    xpos = {"carbody": 0.0, "bogie1": xb, "bogie2": -xb, "bolster1": xb, "bolster2": -xb}
    xpos.update({f"ws{w + 1}": a for w, a in enumerate(sy.x_wheelsets)})
    dq, dv = np.zeros_like(q0), np.zeros_like(q0)
    for i, name in enumerate(sy.state_names):
        body, _, dof = name.rpartition("_")
        if body in xpos and dof == "y":
            dq[i], dv[i] = theta * (xs + xpos[body]), theta * v
        elif body in xpos and dof == "yaw":
            dq[i] = theta
    assert np.count_nonzero(dq) == 16  # 7 bodies' y, their 7 yaws and the 2 bolsters'
    x = np.arange(-20.0, 100.0, 0.5)
    z = np.zeros_like(x)
    irr = TrackIrregularity(x, z, theta * x, z, z)
    a = simulate(sy, v, 0.5, h=h, q0=q0, v0=v0, progress=False)
    b = simulate(sy, v, 0.5, h=h, q0=q0 + dq, v0=v0 + dv, irregularity=irr, x_start=xs, progress=False)
    assert np.abs(b.q - dq - np.outer(b.t, dv) - a.q).max() < 1e-12
    assert np.abs(a.Q - b.Q).max() < 1e-4
    assert np.abs(a.Y - b.Y).max() < 1e-4
