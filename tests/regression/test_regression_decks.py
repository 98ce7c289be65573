"""Deck regression tests: every deck's results against its stored reference (README.md here).

A failure names the deck, the case and each quantity that moved beyond its tolerance. If the
change is intended, re-make the reference (make_references.py) and say in the commit which
quantities moved and why.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import regression as R
from railvti.runner.deck import read_deck
from railvti.runner.deck_registry import case_types


@pytest.mark.parametrize("deck", R.DECKS, ids=[d.name for d in R.DECKS])
def test_deck_matches_its_reference(deck, tmp_path):
    if deck.slow and not R.full_run():
        also = f"; {deck.reduced_by} runs its case types" if deck.reduced_by else ""
        pytest.skip(f"slow deck{also}; set {R.FULL_ENV}=1 to run it")
    ref = R.read_reference(deck)
    new = R.run_deck(deck, tmp_path)
    diffs = R.compare(new, ref["cases"])
    assert not diffs, f"{deck.path.name}: results moved from {deck.reference.name}:\n  " + "\n  ".join(diffs)


def test_every_input_deck_and_case_type_is_covered():
    """Each inputs/ deck has a reference; each case type runs in the default suite."""
    inputs = {p.resolve() for pattern in ("*.nml", "*.inp") for p in R.INPUTS.glob(pattern)}
    assert inputs == {d.path.resolve() for d in R.DECKS if d.path.parent == R.INPUTS}
    fast_types = set()
    for d in R.DECKS:
        cases = read_deck(d.path)
        ref = R.read_reference(d)["cases"]
        # the reference holds the deck's cases, in order, with their types
        assert [(c.name, c.case_type.name) for c in cases] == [
            (k.split("_", 1)[1], v["type"]) for k, v in ref.items()
        ], d.name
        if not d.slow:
            fast_types |= {c.case_type.name for c in cases}
        elif d.reduced_by:
            assert {c.case_type.name for c in cases} <= {
                c.case_type.name for c in read_deck(R.deck(d.reduced_by).path)
            }
    assert fast_types == set(case_types())


def test_every_tolerance_states_its_reason():
    for rules in R.TOLERANCES.values():
        assert rules[-1][0] == "*"
        for _, tol in rules:
            assert tol.reason and tol.rtol >= 0 and tol.atol >= 0


def _perturbed(value, allowed: float, factor: float):
    """``value`` moved by ``factor * allowed`` (or by one step where nothing is allowed)."""
    if value is None or isinstance(value, str):  # a NaN element: make it a number
        return 0.0
    if isinstance(value, int) and not isinstance(value, bool):
        return value + max(1, math.ceil(factor * allowed))
    if allowed == 0.0:
        return float(np.nextafter(value, np.inf))
    return value + factor * allowed


def _compared_quantities():
    """(deck name, one-quantity reference) of every compared quantity of the default decks."""
    out = []
    for d in R.DECKS:
        if d.slow:
            continue
        for cname, case in R.read_reference(d)["cases"].items():
            for qname, rec in case["quantities"].items():
                tol = R.tolerance(
                    case["type"],
                    cname,
                    qname,
                    rec["kind"].startswith("integer"),
                    scenario=R.case_scenario(case),
                )
                if not math.isinf(tol.rtol):
                    out.append((d.name, {cname: {**case, "quantities": {qname: rec}}}))
    return out


def test_comparison_reports_a_perturbed_reference():
    """Each stored value moved by more than its tolerance is reported, naming case and
    quantity; moved by less, it is not. The run results are stood in for by the unperturbed
    reference."""
    checked = 0
    for dname, ref in _compared_quantities():
        cname = next(iter(ref))
        qname, rec = next(iter(ref[cname]["quantities"].items()))
        tol = R.tolerance(
            ref[cname]["type"],
            cname,
            qname,
            rec["kind"].startswith("integer"),
            scenario=R.case_scenario(ref[cname]),
        )
        keys: list[tuple[str, int | None]] = []
        if rec["kind"] in ("float", "integer"):
            keys = [("value", None)]
        elif rec["kind"] == "float_array":
            keys = [(k, None) for k in ("sum", "l1", "l2", "wsum", "min", "max")]
            keys += [("samples", 0), ("samples", len(rec["samples"]) - 1)]
        elif rec["kind"] == "integer_array":
            keys = [("sum", None), ("samples", 0)]
        for key, i in keys:
            value = rec[key] if i is None else rec[key][i]
            if rec["kind"] == "float_array":
                bounds = R.array_bounds(tol, rec)
                allowed = bounds[key] if key in bounds else tol.bound(R.stored_float(value), bounds["scale"])
            else:
                allowed = tol.bound(float(value))
            for factor, reported in ((1.5, True), (0.5, False)):
                if not reported and (allowed == 0.0 or value is None or isinstance(value, str)):
                    continue
                bad = copy.deepcopy(ref)
                target = bad[cname]["quantities"][qname]
                if i is None:
                    target[key] = _perturbed(value, allowed, factor)
                else:
                    target[key][i] = _perturbed(value, allowed, factor)
                diffs = R.compare(ref, bad)
                where = f"{dname} {cname} {qname} {key}{'' if i is None else f'[{i}]'} x{factor}"
                if reported:
                    assert any(m.startswith(f"{cname}: {qname}:") for m in diffs), where
                else:
                    assert not diffs, where
                checked += 1
        if rec["kind"] == "text":
            bad = copy.deepcopy(ref)
            bad[cname]["quantities"][qname]["value"] += "x"
            assert R.compare(ref, bad), f"{dname} {cname} {qname}"
            checked += 1
    assert checked > 1000


def test_comparison_reports_structure_changes():
    ref = R.read_reference(R.deck("normal_contact_example"))["cases"]
    case = next(iter(ref))
    for change, words in (
        (lambda r: r[case]["quantities"].pop("pressure"), "'pressure' is new"),
        (lambda r: r[case]["quantities"]["pressure"].update(shape=[1, 2]), "shape"),
        (lambda r: r[case]["quantities"]["pressure"].update(nonfinite=1), "NaN/inf"),
        (lambda r: r[case].update(status="error: X"), "status"),
        (lambda r: r.pop(case), "cases"),
    ):
        bad = copy.deepcopy(ref)
        change(bad)
        assert any(words in m for m in R.compare(ref, bad)), words
