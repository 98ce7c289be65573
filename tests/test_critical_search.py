"""The fold and the decay boundary by path-following (railvti.critical_search): bad input,
the criteria on signals with a known envelope, the bracketing on stand-ins with a known
answer, and one short RR search across two speeds far from the fold."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from railvti.critical_search import (
    bracket_down,
    cycle_verdict,
    envelope,
    growth_rate,
    nonlinear_critical_speed,
)
from railvti.errors import InputError


# ---- bad input: an InputError naming the key, before any run -------------------------------


@pytest.mark.parametrize(
    "kw, key",
    [
        (dict(resolution_kmh=0.0), "resolution_kmh"),
        (dict(resolution_kmh=float("nan")), "resolution_kmh"),
        (dict(resolution=-1.0), "resolution"),
        (dict(resolution_kmh=30.0), "resolution"),  # wider than the 20 km/h step
        (dict(speed_top_kmh=140.0), "speed_top"),  # below the 150 km/h floor
        (dict(speed_top_kmh=400.0, speed_top=100.0), "speed_top"),
        (dict(speed_top_kmh=900.0), "speed_top_kmh"),
        (dict(step_kmh=float("inf")), "step_kmh"),
        (dict(duration=float("nan")), "duration"),
        (dict(duration=0.6), "window"),  # fewer than two windows
        (dict(threshold=0.0), "threshold"),
        (dict(rate_tol=-0.1), "rate_tol"),
        (dict(collapse=1.0), "collapse"),
        (dict(segments=0), "segments"),
        (dict(max_extensions=1.5), "max_extensions"),
        (dict(h=float("nan")), "h"),
        (dict(y_large=-0.006), "y_large"),
        (dict(n_sleepers=40), "n_sleepers"),  # a ring key for RR
        (dict(k_max=3), "k_max"),
    ],
)
def test_bad_input_names_the_key(kw, key):
    with pytest.raises(InputError, match=key):
        nonlinear_critical_speed("RR", **kw)


def test_unknown_variant_and_contact():
    with pytest.raises(InputError, match="unknown variant"):
        nonlinear_critical_speed("XX")
    with pytest.raises(InputError, match="contact"):
        nonlinear_critical_speed("RR", contact="coulomb")


def test_scenarios_and_vehicle_do_not_import_it():
    code = (
        "import sys, railvti.scenarios, railvti.vehicle.simulate; "
        "print('railvti.critical_search' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# ---- the criteria on signals with a known envelope -----------------------------------------


def _signal(rate: float, a0: float = 5e-3, f: float = 6.0, T: float = 4.0):
    t = np.arange(1, int(T / 0.002) + 1) * 0.002
    return t, a0 * np.exp(rate * t) * np.sin(2 * np.pi * f * t + 0.3)


def test_envelope_and_growth_rate_against_the_exact_envelope():
    for rate in (-1.0, -0.2, 0.0, 0.3):
        t, y = _signal(rate)
        tc, a = envelope(t, y, 0.5)
        assert tc.size == 8
        # half the peak-to-peak lies between the true envelope's extremes in the window
        # (less a little: the sampled peaks of a 6 Hz sine within a window)
        ends = 5e-3 * np.exp(rate * np.stack([tc - 0.25, tc + 0.25]))
        assert np.all(a <= ends.max(axis=0) * (1 + 1e-9))
        assert np.all(a >= 0.9 * ends.min(axis=0))
        assert growth_rate(t, y, 0.5) == pytest.approx(rate, abs=0.02)
    # grows, then saturates on a cycle: the sign stays positive however long the run
    t, _ = _signal(0.0, T=8.0)
    y = 0.5e-3 * np.minimum(np.exp(2.0 * t), 10.0) * np.sin(2 * np.pi * 6.0 * t)
    assert growth_rate(t, y, 0.5) > 0.0


def test_cycle_verdict():
    t, y = _signal(0.0)
    v, amp, rate = cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.05)
    assert v == "alive" and amp == pytest.approx(5e-3, rel=0.01) and abs(rate) < 0.01
    t, y = _signal(-0.2)  # still a large motion, but dying
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.05)[0] == "decaying"
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.5)[0] == "alive"
    t, y = _signal(-0.2, a0=0.2e-3)  # below the floor
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.5)[0] == "dead"
    # a cycle settling onto a smaller one (the envelope falls, then levels) is alive
    t, _ = _signal(0.0)
    a = 4e-3 + 2e-3 * np.exp(-3.0 * t)
    y = a * np.sin(2 * np.pi * 6.0 * t)
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.05, collapse=0.5)[0] == "alive"
    # a carried cycle that collapses onto a slowly decaying remnant has left its branch
    a = 0.3e-3 * np.exp(-0.02 * t) + 7e-3 * np.exp(-4.0 * t)
    y = a * np.sin(2 * np.pi * 6.0 * t)
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.05)[0] == "alive"
    assert cycle_verdict(t, y, threshold=0.25e-3, rate_tol=0.05, collapse=0.5)[0] == "dead"


# ---- the bracketing on stand-ins with a known answer ---------------------------------------


def test_bracket_of_a_step_contains_it_to_the_resolution():
    fold = 287.3

    def test(s, state):
        return s >= fold, state, None

    b = bracket_down(test, 420.0, 20.0, 150.0, 2.5)
    assert b.lo < fold <= b.hi and b.hi - b.lo <= 2.5
    walk = [s for s, _, _ in b.visited[:8]]
    assert walk == [420.0, 400.0, 380.0, 360.0, 340.0, 320.0, 300.0, 280.0]
    assert len(b.visited) == 8 + 3  # 20 -> 10 -> 5 -> 2.5 km/h
    b = bracket_down(test, 420.0, 20.0, 150.0, 0.1)
    assert b.hi - b.lo <= 0.1 and b.lo < fold <= b.hi


def test_bracket_carries_the_living_state_down():
    """A hysteretic stand-in: a fresh start has a cycle only at >= 330; a cycle carried from
    a living state lives down to 287.3 if the step from that state is at most 25 (larger
    jumps knock it off). The walk and every bisection test must start from the state of the
    current lowest living speed."""
    seen = []

    def test(s, state):
        seen.append((s, state))
        if state is None:
            ok = s >= 330.0
        else:
            ok = s >= 287.3 and state - s <= 25.0
        return ok, (s if ok else None), None

    b = bracket_down(test, 420.0, 20.0, 150.0, 2.5)
    assert b.lo < 287.3 <= b.hi and b.hi - b.lo <= 2.5  # not the fresh start's 330
    for s, state in seen[1:]:
        assert state is not None and state > s  # from a living state above
    # each bisection test starts from the lowest living speed found so far
    living = [s for s, ok, _ in b.visited if ok]
    for k, (_s, state) in enumerate(seen[1:], start=1):
        assert state == min(x for x, ok, _ in b.visited[:k] if ok)
    assert b.hi == min(living)


def test_bracket_edges():
    b = bracket_down(lambda s, st: (False, st, None), 420.0, 20.0, 150.0, 2.5)
    assert math.isnan(b.hi) and b.lo == 420.0 and len(b.visited) == 1
    b = bracket_down(lambda s, st: (True, st, None), 420.0, 20.0, 150.0, 2.5)
    assert math.isnan(b.lo) and b.hi == 160.0


def test_a_failed_run_stops_the_search_and_keeps_what_it_had():
    """A run that cannot be completed (Newton, a BEM patch at its grid's edge) is neither a
    living nor a dead cycle: the walk stops with the fold unknown below the last living
    speed, the bisection with the bracket as it stood; the reason is kept."""

    def walk(s, st):
        return (True, st, {}) if s > 370.0 else (False, st, {"failed": "Newton"})

    b = bracket_down(walk, 420.0, 20.0, 150.0, 2.5)
    assert b.hi == 380.0 and math.isnan(b.lo)
    assert [s for s, _, _ in b.visited] == [420.0, 400.0, 380.0, 360.0]
    assert "360" in b.failure and "Newton" in b.failure

    def bisect(s, st):
        if s == 290.0:
            return False, st, {"failed": "grid edge"}
        return s > 285.0, st, {}

    b = bracket_down(bisect, 420.0, 20.0, 150.0, 2.5)
    assert (b.lo, b.hi) == (280.0, 300.0) and "290" in b.failure


# ---- RR at two speeds far from the fold ----------------------------------------------------


def test_rr_lives_at_420_and_dies_at_250():
    """Carried from a 6 mm start at 420 km/h (a flange cycle of ~9.7 mm, the 6.3 mm flange
    clearance exceeded), the cycle dies at 250 km/h, far below the fold (docs/vehicle.md:
    RR's cycle dies between 260 and 300 km/h); from 0.5 mm the motion grows at 420 and
    decays at 250 (the linear critical speed is 317.5 km/h)."""
    c = nonlinear_critical_speed(
        "RR", speed_top_kmh=420.0, speed_floor_kmh=250.0, step_kmh=170.0, resolution_kmh=170.0, duration=2.0
    )
    assert c.fold_bracket_kmh == pytest.approx((250.0, 420.0))
    assert c.fold_kmh == pytest.approx(420.0) and c.fold == pytest.approx(420.0 / 3.6)
    assert list(c.path_alive) == [True, False]
    assert c.path_amplitudes[0] > 6.3e-3 and c.fold_branch == "flange cycle"
    assert c.path_amplitudes[1] < 0.25e-3
    assert c.decay_bracket_kmh == pytest.approx((250.0, 420.0))
    assert c.decay_rates[0] > 0.0 > c.decay_rates[1]
    assert "fold" in c.message and "decay boundary" in c.message
