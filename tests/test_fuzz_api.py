"""Fuzz suite of bad Python API calls (issue 16): the case runners (what a deck case calls) and
the scenarios refuse what a deck refuses, with an InputError naming the argument and its
bound, before any computation; never a traceback of another kind, a NaN result or a run at
an implausible value. Every call here fails in its checks, so the suite is fast.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from railvti import scenarios
from railvti.casetypes import REGISTRY
from railvti.runner.deck_registry import case_types
from railvti.errors import InputError
from railvti.vehicle import Coach

case_types()

#: Complete parameters of a valid case of each type (the defaults and a few required keys).
REQUIRED = {
    "normal": dict(nx=16, ny=16, dx=4e-4, dy=4e-4, gap_a=1.0, gap_b=1.0, fn=1e3),
    "rolling": dict(nx=16, ny=16, dx=4e-4, dy=4e-4, gap_a=1.0, gap_b=1.0, fn=1e3, mu=0.3, speed=10.0),
    "track_receptance": dict(n_sleepers=16),
    "track_element": dict(n_sleepers=16),
}


def params(tname: str, **kw) -> dict:
    p = dict(REGISTRY[tname].defaults)
    p.update(REQUIRED.get(tname, {}))
    p.update(kw)
    return p


RUNNER_CASES = [
    # (id, type, overrides, words)
    ("rolling-mu-0", "rolling", dict(mu=0.0), ["mu", "(0, 1]"]),
    ("rolling-mu-2", "rolling", dict(mu=2.0), ["mu", "(0, 1]"]),
    ("rolling-mu-nan", "rolling", dict(mu=math.nan), ["mu", "finite"]),
    ("rolling-speed-negative", "rolling", dict(speed=-1.0), ["speed"]),
    ("rolling-both-gaps", "rolling", dict(semi_a=3e-3, semi_b=2e-3), ["not both"]),
    ("rolling-xi-text", "rolling", dict(xi="abc"), ["xi", "number"]),
    ("rolling-method", "rolling", dict(method="cg"), ["method", "one of"]),
    ("normal-nx-text", "normal", dict(nx="abc"), ["nx", "integer"]),
    ("normal-nx-float", "normal", dict(nx=16.5), ["nx", "integer"]),
    ("normal-nx-bool", "normal", dict(nx=True), ["nx", "integer"]),
    ("normal-fn-inf", "normal", dict(fn=math.inf), ["fn", "finite"]),
    ("normal-both-controls", "normal", dict(approach=1e-6), ["exactly one"]),
    ("normal-poisson", "normal", dict(poisson=0.5), ["poisson", "(-1, 0.5)"]),
    ("normal-unknown-key", "normal", dict(fm=1.0), ["unknown key 'fm'"]),
    ("normal-grid-huge", "normal", dict(nx=100000), ["nx", "2048"]),
    ("loaded-mu-nan", "loaded_wheelset", dict(mu=math.nan), ["mu", "finite"]),
    ("loaded-mu-negative", "loaded_wheelset", dict(mu=-0.3), ["mu", "[0, 1]"]),
    ("loaded-speed-negative", "loaded_wheelset", dict(speed=-2.0), ["speed", "[0, 166.667]"]),
    (
        "loaded-y-reversed",
        "loaded_wheelset",
        dict(y_min_mm=5.0, y_max_mm=0.0),
        ["y_min = 0.005", "y_max = 0"],
    ),
    ("loaded-old-and-new-name", "loaded_wheelset", dict(g=7e10, shear_modulus=8e10), ["give one"]),
    ("table-y-reversed", "geometry_table", dict(y_min_mm=10.0, y_max_mm=-10.0), ["y_min = 0.01"]),
    ("table-profile", "geometry_table", dict(rail="missing.prr"), ["rail", "missing.prr"]),
    ("wheel-rail-side", "wheel_rail", dict(side="middle"), ["side", "one of"]),
    ("wheel-rail-fz", "wheel_rail", dict(fz=0.0), ["fz", "(0, 1e+06]"]),
    ("ring-3", "track_receptance", dict(n_sleepers=3), ["n_sleepers", "[8, 1024]"]),
    ("ring-band", "track_receptance", dict(f_min=100.0, f_max=50.0), ["f_min"]),
    ("element-position", "track_element", dict(position="rail"), ["position", "one of"]),
    ("wheelset-speeds", "wheelset", dict(speeds_kmh=[0.0, 5000.0]), ["speeds_kmh", "600"]),
    ("wheelset-damping", "wheelset", dict(damping_ratio=1.5), ["damping_ratio"]),
    ("vehicle-5000-kmh", "vehicle", dict(speed_kmh=5000.0), ["speed", "166.667"]),
    ("vehicle-duration", "vehicle", dict(duration=1e6), ["max_duration"]),
    ("vehicle-scenario", "vehicle", dict(scenario="curving"), ["scenario", "one of"]),
    ("vehicle-contact", "vehicle", dict(contact="kalker"), ["contact", "one of"]),
    ("vehicle-y0", "vehicle", dict(y0=0.05), ["y0", "[-0.01, 0.01] m"]),
    ("vehicle-alpha", "vehicle", dict(alpha=0.5), ["alpha"]),
    ("vehicle-mass", "vehicle", dict(coach_carbody_mass=-1.0), ["carbody_mass"]),
]


@pytest.mark.parametrize("tname, kw, words", [c[1:] for c in RUNNER_CASES], ids=[c[0] for c in RUNNER_CASES])
def test_case_runner_refuses(tname, kw, words):
    with pytest.raises(InputError) as info:
        REGISTRY[tname].run(params(tname, **kw))
    for w in words:
        assert w in str(info.value), (w, str(info.value))


SCENARIO_CALLS = [
    ("hunting-5000", lambda: scenarios.hunting(5000.0, duration=0.01), ["5000", "(0, 600] km/h"]),
    ("hunting-nan", lambda: scenarios.hunting(math.nan, duration=0.01), ["speed_kmh", "finite"]),
    ("hunting-negative", lambda: scenarios.hunting(-100.0, duration=0.01), ["(0, 600] km/h"]),
    ("hunting-zero", lambda: scenarios.hunting(0.0, duration=0.01), ["(0, 600] km/h"]),
    ("hunting-text", lambda: scenarios.hunting("fast", duration=0.01), ["speed_kmh", "number"]),
    ("hunting-variant", lambda: scenarios.hunting(300.0, "XX", duration=0.01), ["variant"]),
    ("hunting-contact", lambda: scenarios.hunting(300.0, contact="x", duration=0.01), ["contact model"]),
    ("centred-5000", lambda: scenarios.centred_running(5000.0, duration=0.01), ["(0, 600] km/h"]),
    ("centred-inf", lambda: scenarios.centred_running(math.inf, duration=0.01), ["finite"]),
    ("bifurcation-5000", lambda: scenarios.bifurcation([300.0, 5000.0], duration=0.01), ["5000", "600"]),
    ("bifurcation-one-speed", lambda: scenarios.bifurcation([300.0], duration=0.01), ["at least two"]),
    ("bifurcation-negative", lambda: scenarios.bifurcation([-1.0, 300.0], duration=0.01), ["speeds > 0"]),
    ("conicity-negative", lambda: scenarios.equivalent_conicity(-1.0), ["amplitude"]),
    ("coach-negative-mass", lambda: Coach(carbody_mass=-5.0), ["carbody_mass"]),
    ("coach-unknown", lambda: Coach(carbody_mas=5.0), ["carbody_mas"]),
    (
        "bifurcation-fr-harmonic",
        lambda: scenarios.bifurcation([300.0, 280.0], "FR", duration=0.01, k_max=-1),
        ["k_max", "0..30"],
    ),
    ("linear-damper", lambda: scenarios.linear_critical_speed_kmh(damper="loose"), ["damper"]),
    ("critical-method", lambda: scenarios.critical_speed(method="guess"), ["method"]),
]


@pytest.mark.parametrize("call, words", [c[1:] for c in SCENARIO_CALLS], ids=[c[0] for c in SCENARIO_CALLS])
def test_scenario_refuses(call, words):
    with pytest.raises(InputError) as info:
        call()
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_runner_accepts_the_km_h_alias_and_old_names():
    """speed_kmh and g/nu given to a runner beside the defaults replace them (checked only)."""
    ct = REGISTRY["vehicle"]
    p = ct.validate(params("vehicle", speed_kmh=180.0))
    assert p["speed"] == pytest.approx(50.0) and "speed_kmh" not in p
    with pytest.warns(DeprecationWarning):
        p = REGISTRY["loaded_wheelset"].validate(params("loaded_wheelset", g=8.0e10, nu=0.25))
    assert p["shear_modulus"] == 8.0e10 and p["poisson"] == 0.25


def test_small_valid_rolling_case_is_finite():
    """The valid counterpart of the refused rolling calls: finite forces below mu Fn."""
    out = REGISTRY["rolling"].run(params("rolling", xi=1e-3))
    fx = out.scalars["fx"][0]
    assert np.isfinite(fx) and 0 < abs(fx) <= 0.3 * 1e3 * (1 + 1e-9)
    assert all(np.isfinite(a).all() for a, _ in out.datasets.values() if np.asarray(a).dtype.kind == "f")
