"""Vehicle deck case type: runs, records the contact model, plots, rejects bad keys."""

from pathlib import Path

import numpy as np
import pytest

from railvti.casetypes import REGISTRY
from railvti.runner.deck import parse_deck
from railvti.errors import InputError
import railvti.vehicle.cases  # noqa: F401  (registers the case type)

EXAMPLE = Path(__file__).resolve().parents[1] / "inputs" / "vehicle_example.nml"


def _params(**kw):
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(kw)
    return p


def test_centred_case_outputs(tmp_path):
    out = REGISTRY["vehicle"].run(
        _params(scenario="centred_running", speed_kmh=200.0, duration=0.1, contact="hertz-fastsim")
    )
    assert out.scalars["contact"][0] == "hertz-fastsim"
    assert out.scalars["max_Q_error"][0] < 1e-3
    assert out.datasets["Q_final"][0].shape == (2, 4)
    assert out.datasets["patch_pressure"][0].max() > 1e8  # Hertz p0 of a wheel load
    import h5py

    with h5py.File(tmp_path / "r.h5", "w") as f:
        g = f.create_group("results")
        for k, (a, _u) in out.datasets.items():
            g[k] = a
        paths = REGISTRY["vehicle"].plot(f, tmp_path, "c")
    assert all(p.exists() for p in paths)
    assert any(p.name == "c_wheels.png" for p in paths)  # all eight wheels
    assert out.datasets["wheel_YQ_max"][0].shape == (2, 4)
    assert "worst wheel: wheelset" in out.summary


def test_coach_parameter_through_deck():
    out = REGISTRY["vehicle"].run(
        _params(scenario="centred_running", duration=0.05, coach_carbody_mass=30000.0)
    )
    assert out.scalars["static_wheel_load"][0] == pytest.approx((30000 + 2 * 2615 + 4 * 1813) * 9.81 / 8)


def test_bad_scenario_and_negative_mass():
    with pytest.raises(InputError, match="scenario"):
        REGISTRY["vehicle"].run(_params(scenario="curving"))
    with pytest.raises(InputError, match="carbody_mass"):
        REGISTRY["vehicle"].run(_params(scenario="centred_running", coach_carbody_mass=-1.0))


def test_example_deck_parses_as_written_and_its_first_case_runs():
    """The example deck's cases carry the file's values, read here with f90nml directly
    (not through railvti.runner.deck), and the case type's defaults for the keys the file leaves
    out; the first case, centred running at 200 km/h, carries the coach's weight: Q on
    every wheel within 0.1 % of (carbody + 2 bogies + 4 wheelsets) g / 8 with the
    Manchester benchmark masses, and no net lateral force on any wheelset."""
    import f90nml

    raw = f90nml.read(EXAMPLE)["case"]
    cases = parse_deck(EXAMPLE.read_text())
    defaults = REGISTRY["vehicle"].defaults
    assert len(cases) == len(raw) == 2
    for case, group in zip(cases, raw):
        assert case.case_type.name == group["type"] == "vehicle"
        assert case.name == group["name"]
        given = {k: v for k, v in group.items() if k not in ("type", "name")}
        assert case.params["speed"] == pytest.approx(given.pop("speed_kmh") / 3.6, rel=1e-15)  # km/h alias
        assert {k: case.params[k] for k in given} == given
        assert all(case.params[k] == v for k, v in defaults.items() if k not in given and k != "speed")
    with pytest.raises(InputError, match="did you mean"):
        parse_deck("&case type='vehicle' speed_kmhh=200.0 /")
    first = cases[0]
    assert first.params["scenario"] == "centred_running"
    out = first.case_type.run(first.params)
    load = (32000.0 + 2 * 2615.0 + 4 * 1813.0) * 9.81 / 8
    np.testing.assert_allclose(out.datasets["Q_final"][0], load, rtol=1e-3)
    assert np.abs(out.datasets["Y_final"][0].sum(axis=0)).max() < 1e-6 * load
    assert out.scalars["contact"][0] == raw[0]["contact"]


def test_critical_speed_case_short_sweep(tmp_path):
    out = REGISTRY["vehicle"].run(
        _params(
            scenario="critical_speed",
            speeds_kmh_min=140.0,
            speeds_kmh_max=420.0,
            speeds_kmh_step=280.0,
            duration=1.5,
        )
    )
    up = out.datasets["upper_amplitude"][0]
    assert out.datasets["speeds_kmh"][0].tolist() == [140.0, 420.0]
    assert up[1] > 5e-3 and up[0] < 0.5e-3  # flange cycle at 420, decay at 140
    assert out.scalars["critical_speed_nonlinear"][0] == 420.0
    assert 250 < out.scalars["critical_speed_linear"][0] < 400
