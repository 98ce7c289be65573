"""The contact-model spec (railvti.vehicle.contact_models): one parse at the edge, the same
models as the Fortran core's CMODEL_* constants, and one BEM state per run."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from railvti import critical_search, scenarios
from railvti.errors import InputError
from railvti.vehicle import bem as bem_module
from railvti.vehicle.bifurcation import bifurcation_point, bifurcation_upper
from railvti.vehicle.contact_models import (
    BEM,
    CONTACT_MODELS,
    GEOMETRIES,
    HERTZ_FASTSIM,
    HERTZ_KALKER,
    ContactModel,
    contact_id,
    parse_contact_model,
)
from railvti.vehicle.equilibrium import eigenvalues
from railvti.vehicle.simulate import simulate

ROOT = Path(__file__).resolve().parents[1]
V = 200 / 3.6


def _fortran_constants() -> dict[str, int]:
    """The CMODEL_* parameters of fortran/vehicle/vehicle_contact.f90."""
    text = (ROOT / "fortran" / "vehicle" / "vehicle_contact.f90").read_text()
    decl = [
        ln for ln in text.splitlines() if re.match(r"\s*integer\s*,\s*parameter\s*::.*\bCMODEL_", ln, re.I)
    ]
    assert decl, "no CMODEL_* parameter in vehicle_contact.f90"
    return {
        m.group(1): int(m.group(2)) for ln in decl for m in re.finditer(r"\b(CMODEL_\w+)\s*=\s*(\d+)", ln)
    }


def test_every_spec_is_its_fortran_constant_and_every_constant_has_a_spec():
    consts = _fortran_constants()
    assert {m.fortran_name: m.fortran_id for m in CONTACT_MODELS.values()} == consts
    assert [m.fortran_id for m in CONTACT_MODELS.values()] == sorted(consts.values())
    # one name on both sides of f2py: 'hertz-fastsim' is CMODEL_HERTZ_FASTSIM
    assert all(
        m.fortran_name == "CMODEL_" + m.name.upper().replace("-", "_") for m in CONTACT_MODELS.values()
    )


def test_parse_returns_the_spec_and_names_the_allowed_values():
    assert parse_contact_model("hertz-kalker") is HERTZ_KALKER
    assert parse_contact_model("hertz-fastsim") is HERTZ_FASTSIM
    assert parse_contact_model("bem") is BEM
    assert parse_contact_model(BEM) is BEM
    assert contact_id("hertz-fastsim") == 2 and contact_id(BEM) == 3
    for bad in ("carter", "BEM", " bem", "", None, 3):
        with pytest.raises(
            InputError,
            match=r"unknown contact model .*'bem', 'hertz-fastsim', "
            r"'hertz-kalker'",
        ):
            parse_contact_model(bad)


def test_the_spec_holds_what_the_call_sites_checked():
    assert [m.name for m in CONTACT_MODELS.values() if m.needs_bem] == ["bem"]
    assert {n: m.newton_tol for n, m in CONTACT_MODELS.items()} == {
        "hertz-kalker": 1e-9,
        "hertz-fastsim": 1e-9,
        "bem": 1e-8,
    }
    assert {n for n, m in CONTACT_MODELS.items() if m.static_restart} == {"hertz-fastsim", "bem"}
    assert all(
        isinstance(m, ContactModel)
        and m.default_geometry in m.geometries
        and set(m.geometries) <= set(GEOMETRIES)
        for m in CONTACT_MODELS.values()
    )


@pytest.mark.parametrize("contact", sorted(CONTACT_MODELS))
@pytest.mark.parametrize("geometry", [None, "table", "strip", "points"])
def test_geometry_as_the_scenarios_resolve_it(contact, geometry):
    """The spec's geometries agree with railvti.scenarios.resolve_geometry (value and message),
    so the scenarios can call the spec."""
    try:
        want = scenarios.resolve_geometry(contact, geometry)
    except InputError as exc:
        with pytest.raises(InputError) as got:
            CONTACT_MODELS[contact].resolve_geometry(geometry)
        assert str(got.value) == str(exc)
    else:
        assert CONTACT_MODELS[contact].resolve_geometry(geometry) == want


# ---- one BEM state per run -------------------------------------------------------------------


@pytest.fixture
def opened(monkeypatch):
    """The BEM states opened while a test runs (BemState.__init__ counted)."""
    count = [0]
    init = bem_module.BemState.__init__

    def counting(self, *args, **kw):
        count[0] += 1
        init(self, *args, **kw)

    monkeypatch.setattr(bem_module.BemState, "__init__", counting)
    return count


@pytest.fixture(scope="module")
def coach():
    return scenarios.coach_system(geometry="table")


def test_a_bem_run_from_its_equilibrium_opens_one_state(coach, opened):
    run = simulate(coach, V, 0.003, contact="bem", h=1e-3, output_dt=1e-3, progress=False, threads=1)
    assert opened[0] == 1
    assert run.contact == "bem" and run.stats["bem_normal_solves"] > 0


def test_bem_eigenvalues_open_one_state(coach, opened):
    """The equilibrium and the linearisation about it share one BEM state (they opened one
    each)."""
    lam = eigenvalues(coach, V, contact="bem")
    assert opened[0] == 1
    assert np.isfinite(lam).all()


def test_hertz_runs_open_no_bem_state(coach, opened):
    simulate(coach, V, 0.002, contact="hertz-fastsim", h=1e-3, output_dt=1e-3, progress=False)
    assert opened[0] == 0


def test_a_bem_hunting_run_opens_one_state(opened):
    scenarios.hunting(300.0, contact="bem", duration=0.003, h=1e-3, output_dt=1e-3, progress=False, threads=1)
    assert opened[0] == 1


def test_a_bem_centred_run_opens_one_state(opened):
    scenarios.centred_running(
        200.0, contact="bem", duration=0.003, h=1e-3, output_dt=1e-3, progress=False, threads=1
    )
    assert opened[0] == 1


def test_a_bem_sweep_point_opens_one_state(opened):
    amp, _, _ = bifurcation_point(
        300.0 / 3.6,
        0.004,
        variant="RR",
        contact="bem",
        coach=None,
        h=1e-3,
        k_max=1,
        f_max=300.0,
        duration=0.003,
        output_dt=1e-3,
    )
    assert opened[0] == 1
    assert np.isfinite(amp)


def test_a_bem_continuation_opens_one_state_per_speed(opened):
    """The upper branch at two speeds: each speed's static solve (the top), carry and run share
    one state (the static solve and the run opened one each)."""
    out = bifurcation_upper(
        [310.0 / 3.6, 300.0 / 3.6],
        y_large=0.006,
        threshold=0.0,
        step=10.0 / 3.6,
        v_min=300.0 / 3.6,
        variant="RR",
        contact="bem",
        coach=None,
        h=1e-3,
        k_max=1,
        f_max=300.0,
        duration=0.003,
        output_dt=1e-3,
    )
    assert len(out["speeds"]) == 2 and opened[0] == 2


#: critical_search's settings for one short test point (the verdicts do not matter here).
SEARCH_CFG = dict(
    threshold=1e-3, rate_tol=0.1, window=0.002, duration=0.004, y_large=0.006, y_small=1e-4,
    collapse=0.5, max_extensions=0,
)  # fmt: skip


@pytest.mark.parametrize("test", ["fold", "decay"])
def test_a_bem_search_point_opens_one_state(opened, test):
    """A critical-speed search point runs in two segments after its static solve: one state
    for the three (each opened its own)."""
    runs = critical_search._Runs("RR", "bem", None, 1e-3, 1, 300.0, None, {}, 1e-3, 2)
    make = critical_search._upper_test if test == "fold" else critical_search._decay_test
    _, _, rec = make(runs, SEARCH_CFG, None)(300.0 / 3.6, None)
    assert opened[0] == 1
    assert np.isfinite(rec["amplitude"]) and "failed" not in rec
