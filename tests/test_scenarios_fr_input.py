"""Model FR: bad input gives a clear InputError naming the problem (issue 14, acceptance
'Bad input'), before any run."""

from __future__ import annotations

import importlib

import pytest

from railvti import scenarios
from railvti.casetypes import REGISTRY
from railvti.errors import InputError
from railvti.vehicle.flexible import mode_index, mode_labels
import railvti.vehicle.cases  # noqa: F401  (registers the case type)

SIM = importlib.import_module("railvti.vehicle.simulate")  # the module (the package exports the function)


def _deck(**kw):
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(kw)
    return p


@pytest.mark.parametrize(
    "call",
    [
        lambda: scenarios.centred_running(200.0, variant="FX", duration=0.01),
        lambda: scenarios.hunting(300.0, variant="fr", duration=0.01),
        lambda: scenarios.bifurcation([300.0, 280.0], variant="FQ", progress=False),
        lambda: scenarios.linear_critical_speed_kmh("XR"),
        lambda: scenarios.critical_speed("ring", method="linear"),
        lambda: scenarios.coach_system("XX"),
    ],
)
def test_unknown_variant(call):
    with pytest.raises(InputError, match="unknown variant"):
        call()


def test_unknown_model_in_a_deck():
    with pytest.raises(InputError, match="model"):
        REGISTRY["vehicle"].run(_deck(model="XR"))


@pytest.mark.parametrize("k_max", [-1, 31, 1.5, "two", True])
def test_unknown_harmonic(k_max):
    with pytest.raises(InputError, match="k_max"):
        scenarios.fr_system(speed_kmh=300.0, k_max=k_max)
    with pytest.raises(InputError, match="k_max"):
        scenarios.bifurcation([300.0, 280.0], "FR", k_max=k_max, progress=False)


def test_unknown_harmonic_in_a_deck():
    with pytest.raises(InputError, match="k_max"):
        REGISTRY["vehicle"].run(_deck(model="FR", scenario="centred_running", k_max=31))


@pytest.mark.parametrize("f_max", [0.0, -100.0, float("nan"), float("inf")])
def test_bad_f_max(f_max):
    with pytest.raises(InputError, match="f_max"):
        scenarios.fr_system(speed_kmh=300.0, f_max=f_max)
    with pytest.raises(InputError, match="f_max"):
        scenarios.centred_running(200.0, "FR", f_max=f_max, duration=0.01)
    with pytest.raises(InputError, match="f_max"):
        scenarios.linear_critical_speed_kmh("FR", f_max=f_max)
    with pytest.raises(InputError, match="f_max"):
        REGISTRY["vehicle"].run(_deck(model="FR", scenario="centred_running", f_max=f_max))


def test_f_max_below_every_mode():
    with pytest.raises(InputError, match="no elastic mode below f_max"):
        scenarios.fr_system(speed_kmh=300.0, k_max=1, f_max=10.0)


def test_unknown_mode_label():
    sy, lay = scenarios.fr_system(speed_kmh=300.0, k_max=1, f_max=300.0)
    labels = mode_labels(sy, lay)
    assert "ws2_k1A_1" in labels and "ws1_residual_1" in labels
    assert mode_index(sy, lay, "ws2_k1A_1") == sy.n + labels.index("ws2_k1A_1")
    for bad in ("ws2_k2A_1", "ws5_k0_1", "k1A_1", "ws1_k1C_1"):
        with pytest.raises(InputError, match="unknown mode label"):
            mode_index(sy, lay, bad)


def test_step_too_large_for_the_kept_modes(monkeypatch):
    """With the trapezoidal modal step (FR's default before issue 33; FR's default now, the exact
    step, has no step limit) the step is refused before any work (static equilibrium, runs) in
    every FR entry point: 2 ms against the 561 Hz mode of the default selection (h omega = 7)."""
    monkeypatch.setattr(SIM, "EXACT_BY_DEFAULT", ())
    for call in (
        lambda: scenarios.centred_running(200.0, "FR", h=2e-3),
        lambda: scenarios.hunting(300.0, "FR", h=2e-3),
        lambda: scenarios.bifurcation([300.0, 280.0], "FR", h=2e-3, progress=False),
        lambda: scenarios.critical_speed("FR", h=2e-3, speeds_kmh=[300.0, 280.0], progress=False),
    ):
        with pytest.raises(InputError, match="too large for the highest mode"):
            call()
    # the deck check refuses it with the rest of the case's problems
    with pytest.raises(InputError, match="too large for the highest mode"):
        REGISTRY["vehicle"].validate(_deck(model="FR", scenario="hunting", h=2e-3))
    # a step the modes take passes the check (k <= 1 up to 300 Hz: 293 Hz, h omega = 1.8)
    REGISTRY["vehicle"].validate(_deck(model="FR", scenario="hunting", h=1e-3, k_max=1, f_max=300.0))


def test_mode_selection_given_to_rr():
    with pytest.raises(InputError, match="k_max"):
        scenarios.centred_running(200.0, "RR", k_max=1, duration=0.01)
    with pytest.raises(InputError, match="f_max"):
        scenarios.bifurcation([300.0, 280.0], "RR", f_max=300.0, progress=False)
    with pytest.raises(InputError, match="k_max"):
        REGISTRY["vehicle"].validate(_deck(model="RR", k_max=1))


def test_sweep_speeds_once_and_in_range():
    with pytest.raises(InputError, match="not both"):
        scenarios.bifurcation([300.0, 280.0], speeds=[80.0, 70.0], progress=False)
    with pytest.raises(InputError, match="m/s"):
        scenarios.bifurcation(speeds=[300.0, 280.0], progress=False)  # km/h given as m/s
    with pytest.raises(InputError, match="two speeds"):
        scenarios.bifurcation(speeds=[80.0], progress=False)
    with pytest.raises(InputError, match="not both"):
        scenarios.bifurcation([300.0, 280.0], v_min=10.0, v_min_kmh=30.0, progress=False)
