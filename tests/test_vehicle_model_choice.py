"""contact='auto' (railvti.vehicle.model_choice): the cheapest measured model within the
tolerance, the scenes' tables, the hunting scene's classification, the choice stored with
the run, and bad input. validation/vehicle_auto_contact.py measures the chosen models' real
errors against the 0.5 mm BEM."""

from __future__ import annotations

import itertools

import pytest

from railvti import scenarios
from railvti.errors import InputError
from railvti.track import TrackCurve
from railvti.vehicle.model_choice import (
    _VARIANT_TABLES,
    SCENES,
    VARIANT_SCENES,
    choose_contact,
    choose_variant,
    flange_scene,
    measured,
)


@pytest.mark.parametrize("scene", SCENES)
def test_the_cheapest_model_within_the_tolerance(scene) -> None:
    """For every tolerance and set of quantities: the choice meets the tolerance on each, and
    no cheaper measured model does (brute force over the table)."""
    cands = measured(scene)
    qs = tuple(cands[0].errors)
    for tol, n in itertools.product((0.001, 0.005, 0.01, 0.03, 0.1, 0.5, 5.0), range(1, len(qs) + 1)):
        ask = qs[:n]
        ok = [m for m in cands if all(m.errors[q] <= tol for q in ask)]
        if not ok:
            with pytest.raises(InputError, match="smallest errors measured"):
                choose_contact(scene, tol, ask)
            continue
        c = choose_contact(scene, tol, ask)
        assert all(c.errors[q] <= tol for q in ask)
        assert c.rtf == min(m.rtf for m in ok)
        assert c.quantities == ask and c.scene == scene


def test_documented_choices() -> None:
    """The speed-against-accuracy chart's advice (docs/speed_accuracy.md) is what the chooser
    gives: tread-cycle amplitudes need the BEM, flange-cycle amplitudes any model, tread Q max
    the strip contact."""
    assert choose_contact("hunting-tread", 0.05, ["amplitude"]).label == "bem 0.75 mm"
    assert choose_contact("hunting-tread", 0.1, ["amplitude"]).label == "bem 1.0 mm"
    assert choose_contact("hunting-flange", 0.01, ["amplitude"]).label == "hertz-kalker (table)"
    assert choose_contact("hunting-tread", 0.01, ["q_max"]).label == "hertz-fastsim (strip)"
    assert choose_contact("hunting-flange", 0.05, ["q_max", "y_max"]).label == "bem 1.5 mm"
    assert "expected error" in choose_contact("curve", 0.01, ["sum_y"]).line()


def test_flange_scene() -> None:
    assert flange_scene(0.0, 50e3) == "hunting-tread"
    assert flange_scene(2e3, 50e3) == "hunting-tread"  # a flange-root touch
    assert flange_scene(30e3, 50e3) == "hunting-flange"


def test_auto_curving_records_its_choice() -> None:
    """A scenario run with contact='auto' runs the chosen model and carries the choice into
    its result and its results-file scalars."""
    c = TrackCurve(radius=1200.0, cant=0.15, transition_in=100.0, arc_length=1000.0, transition_out=100.0)
    cr = scenarios.curving(
        160,
        c,
        "RR",
        "auto",
        tolerance=0.01,
        quantities=("sum_y",),
        x_start=500.0,
        duration=0.05,
        progress=False,
    )
    mc = cr.run.model_choice
    assert mc.label == "hertz-kalker (table)" and cr.run.contact == "hertz-kalker"
    _, scalars = cr.run.case_data()
    assert scalars["auto_contact"][0] == "hertz-kalker (table)"
    assert scalars["auto_expected_error_sum_y"][0] == pytest.approx(0.0088)


def test_bad_input() -> None:
    with pytest.raises(InputError, match="scenes are"):
        choose_contact("tunnel", 0.05)
    with pytest.raises(InputError, match="measured errors of"):
        choose_contact("curve", 0.05, ["amplitude"])
    with pytest.raises(InputError, match="tolerance"):
        choose_contact("curve", -0.05)
    with pytest.raises(InputError, match="drop"):
        scenarios.hunting(300, "RR", "auto", duration=0.01, geometry="strip", progress=False)


@pytest.mark.parametrize("scene", VARIANT_SCENES)
def test_the_cheapest_variant_within_the_tolerance(scene) -> None:
    """As for the contact models: brute force over each scene's variant table."""
    for tol in (0.001, 0.005, 0.01, 0.03, 0.1, 2.0):
        c = choose_variant(scene, tol)
        _, table = _VARIANT_TABLES[scene]
        ok = [v for v, (rtf, e) in table.items() if all(x <= tol for x in e.values())]
        assert c.variant in ok and c.rtf == min(table[v][0] for v in ok)


def test_variant_choices_follow_the_physics() -> None:
    """The sleeper passing's dynamic wheel load needs the ring track (RF: within 0.2 % of FF,
    RR has none); a critical speed within 1 % needs the flexible wheelsets (FR)."""
    assert choose_variant("centred", 0.05, ["dynamic_q"]).variant == "RF"
    assert choose_variant("centred", 0.03, ["q_max"]).variant == "RF"
    assert choose_variant("centred", 0.041, ["q_max"]).variant == "RR"  # 4.07 % without the ring
    assert choose_variant("critical-speed", 0.05).variant == "RR"
    assert choose_variant("critical-speed", 0.01).variant == "FR"
    assert choose_variant("critical-speed", 0.005).variant == "FF"


def test_auto_variant_in_a_scenario() -> None:
    c = scenarios.centred_running(
        200, "auto", "hertz-kalker", duration=0.002, variant_tolerance=0.05, variant_quantities=("q_max",)
    )
    assert c.variant == "RR" and c.run.variant_choice.variant == "RR"
    _, scalars = c.run.case_data()
    assert scalars["auto_variant"][0] == "RR"
