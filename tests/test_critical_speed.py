"""Critical speed: the nonlinear sweep never passes off its bottom as a result; the linear
method names the state of the dry-friction yaw damper."""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti import scenarios
from railvti.errors import InputError


def test_sweep_that_starts_too_high_says_so():
    """400-380 km/h holds a flange cycle; with the floor at 360 km/h the cycle never dies:
    the result must be NaN with 'below 360 km/h: no decay found', not 380 (its bottom)."""
    with pytest.warns(RuntimeWarning, match="below 360 km/h: no decay found"):
        cs = scenarios.critical_speed(
            method="nonlinear", speeds_kmh=[400.0, 380.0], duration=1.5, v_min_kmh=360.0, progress=False
        )
    b = cs.bifurcation
    assert math.isnan(cs.kmh) and cs.kmh != 380.0
    assert cs.no_decay_below_kmh == 360.0
    assert "below 360 km/h: no decay found" in cs.message
    # the sweep was extended (360 was not asked for) and the cycle is alive there
    assert 360.0 in b.extended_kmh and b.upper[b.speeds_kmh == 360.0][0] > b.threshold


def test_sweep_is_extended_down_to_decay_and_names_its_branch():
    """From 380-340 km/h the sweep goes down in 40 km/h steps until the cycle dies; the
    critical speed is the lowest living speed, below the requested bottom."""
    b = scenarios.bifurcation([380.0, 340.0], duration=2.0, progress=False)
    assert b.extended_kmh.size > 0 and math.isfinite(b.critical_kmh)
    assert b.critical_kmh < 340.0 and math.isnan(b.no_decay_below_kmh)
    below = b.speeds_kmh < b.critical_kmh
    assert below.any() and np.all(b.upper[below] <= b.threshold)  # dead one step lower
    k = int(np.flatnonzero(b.speeds_kmh == b.critical_kmh)[0])
    assert b.upper[k] > b.threshold
    # branch from the flange force; independently the amplitude against the 6.3 mm clearance
    if b.branch == "tread cycle":
        assert b.branch_amplitude < 6.3e-3 and b.branch_flange_force < 0.01 * 66e3
    else:
        assert b.branch == "flange cycle" and b.branch_flange_force > 0.0


def test_linear_method_reports_the_yaw_damper_state():
    """The stuck damper's steep slope locks the bogie yaw; sliding removes it and the bogie
    hunts at a lower speed."""
    stuck = scenarios.critical_speed(method="linear", tol_kmh=2.0)
    slide = scenarios.critical_speed(method="linear", tol_kmh=2.0, damper="sliding")
    assert "stuck" in stuck.damper_state and "sliding" in slide.damper_state
    assert slide.kmh < stuck.kmh - 20.0
    assert float(stuck) == stuck.kmh
    with pytest.raises(InputError, match="damper"):
        scenarios.linear_critical_speed_kmh(damper="locked")


def test_default_geometry_has_no_spurious_tread_cycle():
    """The defaults (Hertz + Kalker on the strip contact) at 250 km/h, below the nonlinear
    critical speed: hunting from 4 mm decays, as with the BEM (docs/vehicle.md "Strip
    contact": the BEM decays at 300 km/h); the table's contact-point jump keeps a tread
    cycle there (its artefact, the reason the strips are the default)."""
    assert scenarios.DEFAULT_GEOMETRY["hertz-kalker"] == "strip"
    strip = scenarios.hunting(250, duration=5.0, progress=False)
    table = scenarios.hunting(250, duration=5.0, progress=False, geometry="table")
    assert scenarios.amplitude(strip) < 0.1e-3
    assert scenarios.amplitude(table) > 0.5e-3


def test_default_geometry_follows_the_contact_model():
    assert scenarios.resolve_geometry("hertz-fastsim", None) == "strip"
    assert scenarios.resolve_geometry("bem", None) == "table"
    assert scenarios.resolve_geometry("hertz-kalker", "table") == "table"
    with pytest.raises(InputError, match="strip"):
        scenarios.resolve_geometry("bem", "strip")
    with pytest.raises(InputError, match="geometry"):
        scenarios.resolve_geometry("hertz-kalker", "points")
