"""The default modal step per variant (issue 33; simulate.default_modal_step): FR's is the exact
step with sub-steps in flange contact ('exact-flange') at 1 ms (the plain exact step at 1 ms
was not adopted: its flange cycles, docs/speed_accuracy.md "FR at RR's 1 ms"), the other
variants' the trapezoidal step; the opt-in path a variant takes by joining
simulate.EXACT_BY_DEFAULT: simulate, the scenarios' default step, the deck check and the cost
estimate follow it, and modal_step='trapezoidal' keeps the trapezoidal run bit for bit."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from railvti import scenarios
from railvti.casetypes import REGISTRY
from railvti.errors import InputError
from railvti.runner.cost import estimate_params
from railvti.vehicle.simulate import MODAL_STEP_LIMIT, default_modal_step, exact_modal, system_variant
from railvti.vehicle.systems import default_step, time_step
import railvti.vehicle.cases  # noqa: F401  (registers the case type)

SIM = importlib.import_module("railvti.vehicle.simulate")  # the module (the package exports the function)
V_KMH = 300.0


@pytest.fixture(scope="module")
def fr():
    return scenarios.coach_system("FR", speed_kmh=V_KMH)


@pytest.fixture
def fr_opted_in(monkeypatch):
    """Variant FR's modal blocks stepped exactly by default (as today)."""
    monkeypatch.setattr(SIM, "EXACT_BY_DEFAULT", ("FR",))


@pytest.fixture
def fr_opted_out(monkeypatch):
    """No variant stepped exactly by default (FR's default before issue 33)."""
    monkeypatch.setattr(SIM, "EXACT_BY_DEFAULT", ())


def _hunting(duration: float = 0.3, **kw):
    return scenarios.hunting(V_KMH, variant="FR", duration=duration, y0=0.006, progress=False, **kw)


def test_default_modal_step_per_variant(fr):
    """'exact-flange' for FR, 'trapezoidal' for the others; the FR system is recognised as FR."""
    assert SIM.EXACT_BY_DEFAULT == ("FR",)
    assert default_modal_step("FR") == "exact-flange"
    for v in ("RR", "RF", "FF", ""):
        assert default_modal_step(v) == "trapezoidal"
    assert system_variant(fr) == "FR" and exact_modal(fr)


def test_opted_out_default_step(fr, fr_opted_out):
    """Opted out, the FR system's default step is 1 ms halved for the rims' modes
    (h omega_max <= 2), and 1 ms is refused."""
    assert default_modal_step("FR") == "trapezoidal" and not exact_modal(fr)
    assert default_step(fr) == 5e-4 and default_step(fr) * fr.modal.max_frequency() <= MODAL_STEP_LIMIT
    with pytest.raises(InputError, match="too large"):
        time_step(fr, 1e-3)


def test_opt_in_settings(fr, fr_opted_in):
    """Opted in: 'exact-flange' with the trapezoidal rule's settings only (hht, alpha = 0); the
    FR system's default step is 1 ms, which the trapezoidal modal step refuses."""
    assert default_modal_step("FR") == "exact-flange"
    for v in ("RR", "RF", "FF", ""):
        assert default_modal_step(v) == "trapezoidal"
    assert default_modal_step("FR", alpha=-0.05) == "trapezoidal"
    assert default_modal_step("FR", integrator="energy") == "trapezoidal"
    assert (
        exact_modal(fr) and not exact_modal(fr, alpha=-0.05) and not exact_modal(fr, modal_step="trapezoidal")
    )
    assert default_step(fr) == 1e-3 and time_step(fr, None) == 1e-3 and time_step(fr, 1e-3) == 1e-3
    assert 1e-3 * fr.modal.max_frequency() > MODAL_STEP_LIMIT  # the rims' ~560 Hz modes
    assert default_step(fr, exact=False) == 5e-4
    with pytest.raises(InputError, match="too large"):
        time_step(fr, 1e-3, exact=False)


def test_opt_in_runs_and_the_trapezoidal_run_on_request(fr_opted_in):
    """Opted in, the default run is the exact step with flange sub-steps at 1 ms bit for bit;
    modal_step='trapezoidal' takes the trapezoidal default step (0.5 ms) bit for bit as given
    explicitly."""
    a = _hunting(0.1)
    b = _hunting(0.1, h=1e-3, modal_step="exact-flange")
    np.testing.assert_array_equal(a.q, b.q)
    assert a.stats["steps"] == 100
    c = _hunting(0.1, modal_step="trapezoidal")
    d = _hunting(0.1, h=5e-4, modal_step="trapezoidal")
    np.testing.assert_array_equal(c.q, d.q)
    assert c.stats["steps"] == 200
    assert not np.array_equal(a.q, c.q)


def test_exact_1ms_closer_in_tread_q_than_trapezoidal_half_ms():
    """Tread hunting (300 km/h from 6 mm, 0.3 s) against the trapezoidal step at 1/8 ms (the
    exact step at 1/16 ms is within 1.6 % of its Q max; validation/vehicle_fr_rr_like_for_like.py):
    the exact step at 1 ms has the closer largest wheel load (measured 0.34 against 5.3 kN: the
    trapezoidal rule runs the rims' modes slow) and its lateral motion within 0.5 % of the
    amplitude (measured 0.19 %, the rigid DOFs' 1 ms error; the trapezoidal 0.5 ms 0.11 %). Not
    so in a flange cycle (the validation script's 'cycle420': why FR's default adds the sub-steps
    in flange contact, test_vehicle_fr_flange_step)."""
    new = _hunting(h=1e-3, modal_step="exact")
    old = _hunting(modal_step="trapezoidal")
    ref = _hunting(h=1.25e-4, modal_step="trapezoidal")
    err_new = abs(new.Q.max() - ref.Q.max())
    err_old = abs(old.Q.max() - ref.Q.max())
    assert err_new < 0.5 * err_old, (err_new, err_old)
    amp = np.abs(ref.y_ws1).max()
    assert np.abs(new.y_ws1 - ref.y_ws1).max() < 5e-3 * amp


def _deck(**kw):
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(model="FR", scenario="hunting", duration=2.0)
    p.update(kw)
    return p


def test_deck_check_follows_the_default(fr_opted_in):
    """Opted in, a deck's h = 1 ms for model FR passes the check (the exact step has no step
    limit); with alpha /= 0 (the trapezoidal modal step) it is refused, as by default."""
    REGISTRY["vehicle"].validate(_deck(h=1e-3))
    with pytest.raises(InputError, match="too large for the highest mode"):
        REGISTRY["vehicle"].validate(_deck(h=1e-3, alpha=-0.05))


def test_deck_check_opted_out_refuses_fr_at_1ms(fr_opted_out):
    with pytest.raises(InputError, match="too large for the highest mode"):
        REGISTRY["vehicle"].validate(_deck(h=1e-3))


def test_cost_estimate_follows_the_default(monkeypatch):
    """The estimate of an FR case: opted out the trapezoidal step's; opted in (the default), 1 ms
    steps (a third of the estimate's 1/3 ms ones) at the exact step's measured cost, so between
    a third and the whole; RF does not move."""
    monkeypatch.setattr(SIM, "EXACT_BY_DEFAULT", ())
    before = estimate_params("vehicle", _deck())
    rf_before = estimate_params("vehicle", _deck(model="RF"))
    monkeypatch.setattr(SIM, "EXACT_BY_DEFAULT", ("FR",))
    after = estimate_params("vehicle", _deck())
    assert 1.0 / 3.0 < after.seconds / before.seconds < 1.0, (after, before)
    assert "h = 0.001 s" in after.size
    assert estimate_params("vehicle", _deck(alpha=-0.05)).seconds == before.seconds
    assert estimate_params("vehicle", _deck(model="RF")).seconds == rf_before.seconds
