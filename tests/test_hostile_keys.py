"""Hostile suite of keys, API numbers, consistency between keys and malformed decks (issue 31,
items 6 and 7): every case runs in-process (parse_deck, CaseType.validate, API calls), no
subprocess, and ends in one outcome class:

- **refused clearly** (groups ``coach``, ``upper``, ``types``, ``api-text``, ``api-nan``,
  ``cross``, ``sweep-dup``, ``truncated``, ``contact-deck``, ``env``, ``handle``): an
  InputError whose message names the key (or the line, the variable, the handle) and the
  allowed range; never another exception, never a traceback of f90nml or scipy;
- **handled edge case** (groups ``at-bound``, ``shipped``, ``sweep-ok``, ``labels``): accepted
  and correct: a value at its bound is allowed, the shipped decks pass every bound, a sweep
  of distinct points expands, "none found" NaN and an interrupted stream's axes are labelled.

The counts per class are printed by ``pytest -q tests/test_hostile_keys.py`` as the ids'
prefixes.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from railvti import _checks, scenarios
from railvti.casetypes import REGISTRY
from railvti.runner.deck import parse_deck, read_deck
from railvti.runner.deck_registry import case_types
from railvti.errors import InputError
from railvti.vehicle import Coach
from railvti.vehicle.params import BOUNDS as COACH_BOUNDS
from railvti.vehicle.params import DEFAULTS as COACH_DEFAULTS

case_types()
ROOT = Path(__file__).resolve().parents[1]

#: Keys that make a case of each type pass every check.
REQUIRED = {
    "normal": dict(nx=16, ny=16, dx=4e-4, dy=4e-4, gap_a=1.0, gap_b=1.0, fn=1e3),
    "rolling": dict(nx=16, ny=16, dx=4e-4, dy=4e-4, gap_a=1.0, gap_b=1.0, fn=1e3, mu=0.3, speed=10.0),
    "subsurface": dict(
        nx=16, ny=16, dx=4e-4, dy=4e-4, gap_a=1.0, gap_b=1.0, fn=1e3, z_min=1e-4, z_max=1e-3, nz=3
    ),
    "track_receptance": dict(n_sleepers=16),
    "track_element": dict(n_sleepers=16),
    "vehicle": dict(duration=2.0),
}


def params(tname: str, **kw) -> dict:
    p = dict(REGISTRY[tname].defaults)
    p.update(REQUIRED.get(tname, {}))
    p.update(kw)
    return p


def refused(call, *words: str) -> str:
    """Run ``call``; it must raise InputError whose message holds every word (any case)."""
    with pytest.raises(InputError) as info:
        call()
    msg = str(info.value)
    assert "Traceback" not in msg and "AssertionError" not in msg and "f(a)" not in msg
    for w in words:
        assert w.lower() in msg.lower(), (w, msg)
    return msg


def vehicle_deck(extra: str) -> str:
    return f"&case\n  name = 'v', type = 'vehicle', scenario = 'hunting', duration = 2.0,\n  {extra}\n/\n"


# --- refused clearly: every coach_* key above its bound, in a deck --------------------------

COACH_HIGH = [(k, COACH_BOUNDS[k][1] * 10.0 + 1.0) for k in COACH_DEFAULTS]


@pytest.mark.parametrize("key, value", COACH_HIGH, ids=[f"coach-high-{k}" for k, _ in COACH_HIGH])
def test_coach_key_above_its_bound_is_refused_naming_key_and_range(key, value):
    spec = REGISTRY["vehicle"].keys[f"coach_{key}"]
    refused(
        lambda: parse_deck(vehicle_deck(f"coach_{key} = {value!r}")),
        f"key 'coach_{key}'",
        spec.bounds(),
        "case 1 'v'",
    )


COACH_LOW = [(k, lo) for k, (lo, _, _) in COACH_BOUNDS.items() if lo > 0.0]


@pytest.mark.parametrize("key, lo", COACH_LOW, ids=[f"coach-low-{k}" for k, _ in COACH_LOW])
def test_coach_key_below_its_bound_is_refused(key, lo):
    spec = REGISTRY["vehicle"].keys[f"coach_{key}"]
    refused(
        lambda: REGISTRY["vehicle"].validate(params("vehicle", **{f"coach_{key}": lo / 2.0})),
        f"key 'coach_{key}'",
        spec.bounds(),
    )


ISSUE_COACH = [
    ("coach-friction-5", "coach_friction = 5.0", ["coach_friction", "(0, 1]", "0.6"]),
    ("coach-primary-ky-1e30", "coach_primary_ky = 1e30", ["coach_primary_ky", "[38840, 3.884e+08] N/m"]),
    ("coach-wheel-radius-0.01", "coach_wheel_radius = 0.01", ["coach_wheel_radius", "[0.2, 0.8] m"]),
    ("coach-friction-0", "coach_friction = 0.0", ["coach_friction", "(0, 1]"]),
    ("coach-gravity-moon", "coach_gravity = 1.62", ["coach_gravity", "[9.7, 9.9]"]),
    ("coach-text", "coach_carbody_mass = 'heavy'", ["coach_carbody_mass", "number"]),
    ("coach-negative-damper", "coach_primary_cy = -1.0", ["coach_primary_cy", "[0, 200000]"]),
]


@pytest.mark.parametrize("extra, words", [c[1:] for c in ISSUE_COACH], ids=[c[0] for c in ISSUE_COACH])
def test_examples_of_the_issue_are_refused(extra, words):
    refused(lambda: parse_deck(vehicle_deck(extra)), *words)


# --- refused clearly: the new upper bounds of the other case types ---------------------------

UPPER = [
    (t, k)
    for t in ("track_receptance", "wheelset", "vehicle")
    for k, s in REGISTRY[t].keys.items()
    if s.kind == "float"
    and s.hi is not None
    and not k.startswith("coach_")
    and ("stiffness" in k or "damping" in k or t == "wheelset" or k in ("max_duration", "h"))
]


@pytest.mark.parametrize("tname, key", UPPER, ids=[f"upper-{t}-{k}" for t, k in UPPER])
def test_key_above_its_upper_bound_is_refused(tname, key):
    spec = REGISTRY[tname].keys[key]
    refused(
        lambda: REGISTRY[tname].validate(params(tname, **{key: spec.hi * 10.0 + 1.0})),
        f"key '{key}'",
        spec.bounds(),
    )


def test_every_key_of_every_case_type_has_a_range():
    """Item 6: no numeric key without both bounds (a lower and an upper or a cross-key one)."""
    open_keys = {("vehicle", "duration")}  # bounded above by max_duration (cross-key)
    missing = [
        (t, k)
        for t, ct in case_types().items()
        for k in ct.defaults
        if k in ct.keys
        and ct.keys[k].kind in ("float", "int", "floats")
        and (ct.keys[k].lo is None or ct.keys[k].hi is None)
        and (t, k) not in open_keys
    ]
    assert not missing, missing
    assert all(k in ct.keys for ct in case_types().values() for k in ct.defaults)


# --- refused clearly: wrong types, NaN and inf in the API -------------------------------------

TYPES = [
    ("types-nan-friction", "vehicle", dict(coach_friction=math.nan), ["coach_friction", "finite"]),
    ("types-inf-ky", "vehicle", dict(coach_primary_ky=math.inf), ["coach_primary_ky", "finite"]),
    ("types-text-duration", "vehicle", dict(duration="2"), ["duration", "number"]),
    ("types-bool-mass", "vehicle", dict(coach_carbody_mass=True), ["coach_carbody_mass", "number"]),
    ("types-list-speed", "vehicle", dict(speed=[80.0]), ["speed", "number"]),
    ("types-text-fn", "normal", dict(fn="1e4"), ["fn", "number"]),
    ("types-nan-dx", "normal", dict(dx=math.nan), ["dx", "finite"]),
    ("types-text-n-sleepers", "track_receptance", dict(n_sleepers="16"), ["n_sleepers", "integer"]),
    ("types-float-web-steps", "wheelset", dict(web_steps=2.5), ["web_steps", "integer"]),
    ("types-inf-pad", "track_receptance", dict(pad_stiffness_vertical=math.inf), ["pad_stiffness_vertical"]),
]


@pytest.mark.parametrize("tname, kw, words", [c[1:] for c in TYPES], ids=[c[0] for c in TYPES])
def test_wrong_types_are_refused(tname, kw, words):
    refused(lambda: REGISTRY[tname].validate(params(tname, **kw)), *words)


def _normal(**kw):
    from railvti import STEEL
    from railvti.contact import Grid, hertz_gap, solve_normal

    g = Grid(16, 16, 4e-4, 4e-4)
    args = dict(fn=1e3)
    args.update(kw)
    return solve_normal(hertz_gap(g, 1.0, 1.0), g, STEEL, **args)


def _hertz(**kw):
    from railvti import STEEL
    from railvti.contact import hertz

    args = dict(A=1.0, B=1.0, fn=1e3, material=STEEL)
    args.update(kw)
    return hertz(**args)


API_TEXT = [
    ("api-text-fn", lambda: _normal(fn="1e4"), ["fn", "'1e4'", "text"]),
    ("api-text-approach", lambda: _normal(fn=None, approach="1e-6"), ["approach", "text"]),
    ("api-text-hertz-fn", lambda: _hertz(fn="1e3"), ["fn", "text"]),
    ("api-text-hertz-A", lambda: _hertz(A="1.0"), ["A", "text"]),
    ("api-bytes-hertz-B", lambda: _hertz(B=b"1.0"), ["B", "text"]),
    ("api-text-coach", lambda: Coach(friction="0.3"), ["friction", "text"]),
    ("api-text-coach-mass", lambda: Coach(carbody_mass="32000"), ["carbody_mass", "text"]),
    ("api-text-speed", lambda: scenarios.hunting("300"), ["speed", "text"]),
    ("api-text-duration", lambda: scenarios.hunting(300.0, duration="1.0"), ["duration", "text"]),
    ("api-text-array", lambda: _checks.finite_array("q0", ["1.0", "2.0"]), ["q0", "text"]),
    ("api-text-int", lambda: _checks.positive_int("n", "3"), ["n", "text"]),
    ("api-text-friction", lambda: _checks.friction("mu", "0.3"), ["mu", "text"]),
    (
        "api-text-grid",
        lambda: __import__("railvti.contact", fromlist=["Grid"]).Grid("16", 16, 1e-4, 1e-4),
        ["nx", "give nx=16, not nx='16'"],
    ),
    (
        "api-text-sweep-speeds",
        lambda: scenarios.bifurcation(["300", "320"], progress=False),
        ["speeds_kmh", "texts"],
    ),
    (
        "api-text-sweep-speeds-ms",
        lambda: scenarios.bifurcation(speeds=["80", "90"], progress=False),
        ["speeds", "texts"],
    ),
]


@pytest.mark.parametrize("call, words", [c[1:] for c in API_TEXT], ids=[c[0] for c in API_TEXT])
def test_api_refuses_texts_for_numbers(call, words):
    refused(call, *words)


API_NAN = [
    ("api-nan-fn", lambda: _normal(fn=math.nan), ["fn", "finite"]),
    ("api-inf-hertz", lambda: _hertz(A=math.inf), ["A", "finite"]),
    ("api-nan-coach", lambda: Coach(primary_kx=math.nan), ["primary_kx", "finite"]),
    ("api-coach-friction-5", lambda: Coach(friction=5.0), ["friction = 5", "[0, 1]", "0.3-0.6"]),
    ("api-nan-speed", lambda: scenarios.hunting(math.nan), ["speed", "finite"]),
    (
        "api-h-1e-9",
        lambda: scenarios.hunting(300.0, duration=0.01, h=1e-9, progress=False),
        ["h = 1e-09 s", "below 1e-06 s", "round-off"],
    ),
]


@pytest.mark.parametrize("call, words", [c[1:] for c in API_NAN], ids=[c[0] for c in API_NAN])
def test_api_refuses_nan_inf_and_implausible(call, words):
    refused(call, *words)


# --- refused clearly: consistency between keys -------------------------------------------------

CROSS = [
    (
        "cross-output-dt",
        "vehicle",
        dict(output_dt=0.5, duration=0.2),
        ["output_dt = 0.5 s", "duration = 0.2 s"],
    ),
    ("cross-duration-1e-9", "vehicle", dict(duration=1e-9), ["duration", "[0.001, inf) s"]),
    (
        "cross-critical-window",
        "vehicle",
        dict(scenario="critical_speed", duration=0.5),
        ["duration = 0.5 s", "> 1 s", "critical_speed", "amplitude"],
    ),
    (
        "cross-critical-window-equal",
        "vehicle",
        dict(scenario="critical_speed", duration=1.0),
        ["duration = 1 s", "window"],
    ),
    ("cross-h-above-duration", "vehicle", dict(h=0.005, duration=0.002), ["h = 0.005 s", "duration"]),
    ("cross-h-1e-9", "vehicle", dict(h=1e-9), ["key 'h'", "[1e-06, 0.01] s", "round-off"]),
    (
        "cross-duration-over-max",
        "vehicle",
        dict(duration=20.0, max_duration=10.0),
        ["duration = 20 s", "max_duration = 10 s"],
    ),
    (
        "cross-speeds-reversed",
        "vehicle",
        dict(scenario="critical_speed", speeds_kmh_min=400.0, speeds_kmh_max=300.0),
        ["speeds_kmh_min = 400"],
    ),
    (
        "cross-semi-axes-ratio",
        "rolling",
        dict(gap_a=None, gap_b=None, semi_a=0.05, semi_b=1e-6),
        ["semi_a = 0.05 m", "semi_b = 1e-06 m", "<= 1000"],
    ),
    (
        "cross-hertz-unresolved",
        "normal",
        dict(fn=1e-9),
        ["Hertz patch", "fn = 1e-09 N", "dx = 0.0004 m", "make dx, dy smaller"],
    ),
    ("cross-hertz-coarse", "rolling", dict(dx=0.01, dy=0.01, nx=4, ny=4), ["Hertz patch", "elements"]),
    (
        "cross-semi-coarse",
        "rolling",
        dict(gap_a=None, gap_b=None, semi_a=1e-4, semi_b=1e-4),
        ["Hertz patch of semi_a, semi_b", "elements"],
    ),
    (
        "cross-table-back-to-back",
        "geometry_table",
        dict(back_to_back=1.6),
        ["back_to_back = 1.6 m", "radius = 0.46 m", "journal_spacing 2 m", "up to about 1.55"],
    ),
    ("cross-table-radius", "geometry_table", dict(radius=0.16), ["radius = 0.16 m", "from about 0.22"]),
    ("cross-loaded-back-to-back", "loaded_wheelset", dict(back_to_back=1.62), ["back_to_back = 1.62 m"]),
    ("cross-wheel-rail-radius", "wheel_rail", dict(radius=0.16), ["radius = 0.16 m", "contact_offset"]),
    ("cross-fr-keys-on-rr", "vehicle", dict(k_max=2), ["k_max", "models FR and FF"]),
    ("cross-ring-keys-on-rr", "vehicle", dict(n_sleepers=40), ["n_sleepers", "ring track"]),
]


@pytest.mark.parametrize("tname, kw, words", [c[1:] for c in CROSS], ids=[c[0] for c in CROSS])
def test_inconsistent_keys_are_refused_naming_both(tname, kw, words):
    refused(lambda: REGISTRY[tname].validate(params(tname, **kw)), *words)


def test_output_dt_beyond_duration_in_a_deck_names_the_case():
    text = "&case\n  name = 'v', type = 'vehicle', duration = 0.5, output_dt = 0.8\n/\n"
    refused(lambda: parse_deck(text), "case 1 'v'", "output_dt = 0.8 s", "duration = 0.5 s")


# --- refused clearly: duplicate sweep points ---------------------------------------------------

SWEEP_DUP = [
    ("sweep-dup-product", "sweep_speed_kmh = 300.0, 200.0, 300.0", ["points 1 and 3", "speed_kmh = 300"]),
    (
        "sweep-dup-zip",
        "sweep = 'zip', sweep_speed_kmh = 300.0, 300.0, sweep_y0 = 0.001, 0.001",
        ["points 1 and 2", "y0 = 0.001"],
    ),
    ("sweep-dup-int-float", "sweep_speed_kmh = 300, 300.0", ["same point twice"]),
    (
        "sweep-dup-two-keys",
        "sweep_speed_kmh = 300.0, 300.0, sweep_y0 = 0.001, 0.002",
        ["points 1 and 3", "give each point once"],
    ),
    ("sweep-dup-choice-case", "sweep_contact = 'hertz-kalker', 'HERTZ-KALKER'", ["same point twice"]),
]


@pytest.mark.parametrize("extra, words", [c[1:] for c in SWEEP_DUP], ids=[c[0] for c in SWEEP_DUP])
def test_a_sweep_with_the_same_point_twice_is_refused(extra, words):
    refused(lambda: parse_deck(vehicle_deck(extra)), *words)


def test_python_sweep_with_the_same_point_twice_is_refused():
    from railvti.runner.sweeps import sweep

    refused(lambda: sweep("vehicle", {"duration": 2.0}, {"speed_kmh": [300.0, 300.0]}), "same point twice")


# --- refused clearly: truncated and malformed namelist decks -----------------------------------


def _truncations():
    out = []
    for name in (
        "vehicle_example.nml",
        "rolling_example.nml",
        "geometry_example.nml",
        "track_example.nml",
        "default.nml",
    ):
        text = (ROOT / "inputs" / name).read_text()
        # cut inside a value ('82.0e', '-'), after '&', inside a group, before its '/'
        for cut in sorted(
            {
                text.find("e", text.find("= ", text.find("&case")) + 2),
                text.find("&") + 1,
                text.find("&") + 6,
                text.rfind("/"),
                text.rfind("= ") + 2,
            }
        ):
            out.append((f"truncated-{name.split('.')[0]}-{cut}", text[:cut]))
    return out


@pytest.mark.parametrize("text", [t for _, t in _truncations()], ids=[i for i, _ in _truncations()])
def test_a_truncated_deck_names_a_line(text):
    msg = refused(lambda: parse_deck(text))
    assert msg.startswith(("line ", "lines ", "case ", "the deck has")), msg


MALFORMED = [
    (
        "malformed-cut-exponent",
        "&case\n type = 'normal'\n nx = 16, ny = 16, dx = 4e-4, dy = 4e-4,\n"
        " gap_a = 1.0, gap_b = 1.0\n fn = 1.0e\n/\n",
        ["line 5", "not a number", "fn = 1.0e"],
    ),
    ("malformed-lone-minus", "&case\n type = 'vehicle'\n y0 = -\n/\n", ["line 3", "'-'"]),
    (
        "malformed-no-slash",
        "&case\n type = 'vehicle'\n duration = 2.0\n",
        ["line 3", "opened at line 1", "'/'"],
    ),
    ("malformed-lone-ampersand", "! a deck\n&", ["line 2", "truncated"]),
    (
        "malformed-second-group-cut",
        "&case type = 'vehicle', duration = 2.0 /\n&case\n type = 've",
        ["line 3", "unbalanced quote"],
    ),
]


@pytest.mark.parametrize(
    "tname",
    ["geometry_table", "loaded_wheelset", "wheel_rail"],
    ids=lambda t: f"cross-no-journal-spacing-{t}",
)
def test_a_wheelset_that_does_not_fit_names_no_key_of_another_type(tname):
    msg = refused(lambda: REGISTRY[tname].validate(params(tname, back_to_back=1.6)), "back_to_back = 1.6 m")
    assert "increase journal_spacing" not in msg


@pytest.mark.parametrize("text, words", [c[1:] for c in MALFORMED], ids=[c[0] for c in MALFORMED])
def test_a_malformed_deck_names_the_line(text, words):
    refused(lambda: parse_deck(text), *words)


# --- refused clearly: CONTACT decks ----------------------------------------------------------

A22 = (ROOT / "inputs" / "mbench_a22_left.inp").read_text()


def _contact(tmp_path, text: str) -> Path:
    path = tmp_path / "deck.inp"
    path.write_text(text.replace("'../python", f"'{ROOT}/python"))
    return path


CONTACT = [
    (
        "contact-8-digit-word",
        lambda t: t.replace("  0203100 ", "  02203100", 1),
        ["C-P-B-T-N-F-S has 8 digits", "02203100", "at most 7"],
    ),
    (
        "contact-8-digit-second",
        lambda t: t.replace("  0022033 ", "  00022033", 1),
        ["V-L-D-C-M-Z-E has 8 digits"],
    ),
    (
        "contact-9-digit-third",
        lambda t: t.replace("  0001321 ", "  000001321", 1),
        ["H-G-I-A-O-W-R has 9 digits"],
    ),
    ("contact-truncated", lambda t: t[: t.find("MAXGS") - 5], ["deck.inp"]),
    ("contact-module-3", lambda t: t.replace("  1  MODULE", "  3  MODULE", 1), ["MODULE 3", "not supported"]),
    ("contact-text-number", lambda t: t.replace("0.30  0.30 ", "abc  0.30 ", 1), ["deck.inp"]),
]


@pytest.mark.parametrize("edit, words", [c[1:] for c in CONTACT], ids=[c[0] for c in CONTACT])
def test_a_malformed_contact_deck_is_refused_naming_the_line(tmp_path, edit, words):
    path = _contact(tmp_path, edit(A22))
    refused(lambda: read_deck(path), *words)


# --- refused clearly: environment variables, handles ------------------------------------------


def test_bad_memory_limit_names_the_variable(monkeypatch):
    from railvti import resources

    monkeypatch.setenv("RAILVTI_MAX_MEMORY", "lots")
    refused(resources.memory_limit, "RAILVTI_MAX_MEMORY", "'lots'", "8G")


def test_bad_stream_threshold_names_the_variable(monkeypatch):
    from railvti.runner.stream import stream_threshold

    monkeypatch.setenv("RAILVTI_STREAM_ABOVE", "-3")
    refused(stream_threshold, "RAILVTI_STREAM_ABOVE", "'-3'")


@pytest.mark.parametrize(
    "value", ["two", "0", "2.5"], ids=["env-threads-text", "env-threads-0", "env-threads-float"]
)
def test_bad_thread_count_names_the_variable(monkeypatch, value):
    from railvti.vehicle.simulate import bem_threads

    monkeypatch.setenv("RAILVTI_THREADS", value)
    refused(lambda: bem_threads(object()), "RAILVTI_THREADS")


def test_bad_interrupted_copy_size_warns_naming_the_variable(monkeypatch, caplog, tmp_path):
    import h5py

    from railvti.casetypes import CaseOutput, Streamed
    from railvti.runner.results import _interrupted_rows

    monkeypatch.setenv("RAILVTI_INTERRUPTED_COPY_MB", "much")
    src = tmp_path / "s.h5"
    with h5py.File(src, "w") as f:
        f["h/t"] = np.arange(10.0)
    out = CaseOutput("", datasets={"t": (Streamed(str(src), "h/t"), "s")})
    with h5py.File(tmp_path / "r.h5", "w") as f, caplog.at_level("WARNING", logger="railvti"):
        assert _interrupted_rows(f.create_group("g"), out) is None  # all 10 rows fit
    assert "RAILVTI_INTERRUPTED_COPY_MB" in caplog.text and "'much'" in caplog.text


@pytest.mark.parametrize(
    "handle", [12345, -1, "1", 2.5], ids=["handle-bogus", "handle-negative", "handle-text", "handle-float"]
)
def test_freeing_a_bogus_workspace_handle_is_refused(handle):
    from railvti.contact import workspace

    refused(lambda: workspace._free(handle), "not a live workspace", repr(handle))


# --- handled edge cases -------------------------------------------------------------------------

AT_BOUND = [
    (k, COACH_BOUNDS[k][i])
    for k in ("friction", "wheel_radius", "primary_ky", "gravity", "bumpstop_clearance", "half_wheelbase")
    for i in (0, 1)
    if not (k == "friction" and i == 0)
]


@pytest.mark.parametrize("key, value", AT_BOUND, ids=[f"at-bound-{k}-{v:g}" for k, v in AT_BOUND])
def test_a_coach_value_at_its_bound_is_accepted(key, value):
    p = REGISTRY["vehicle"].validate(params("vehicle", **{f"coach_{key}": value}))
    assert p[f"coach_{key}"] == value


@pytest.mark.parametrize(
    "name",
    sorted(p.name for p in (ROOT / "inputs").iterdir() if p.suffix in (".nml", ".inp")),
    ids=lambda n: f"shipped-{n}",
)
def test_the_shipped_decks_pass_every_bound(name):
    cases = read_deck(ROOT / "inputs" / name)
    assert cases and all(not c.case_type.problems(c.params, c.written) for c in cases)


def test_sweep_ok_distinct_points_expand_in_order():
    cases = parse_deck(vehicle_deck("sweep_speed_kmh = 300.0, 200.0, 250.0"))
    assert [round(c.params["speed"] * 3.6, 9) for c in cases] == [300.0, 200.0, 250.0]


def test_sweep_ok_zip_with_a_repeated_value_on_one_axis():
    cases = parse_deck(vehicle_deck("sweep = 'zip', sweep_speed_kmh = 300.0, 300.0, sweep_y0 = 0.001, 0.002"))
    assert len(cases) == 2


def test_labels_nan_meanings_are_written_for_none_found():
    from railvti.contact.wheelset_cases import wheel_nan_labels
    from railvti.vehicle.cases import NAN_MEANINGS

    assert {
        "critical_speed_nonlinear",
        "no_decay_below_kmh",
        "flange_hunting_speed",
        "critical_speed_linear",
    } <= set(NAN_MEANINGS)
    assert all(m.startswith(("NaN:", "inf:")) for m in NAN_MEANINGS.values())
    labels = wheel_nan_labels(["wheel"])
    assert set(labels) == {"fz", "sinks"} and "not solved" in labels["fz"]["nan"]


def test_labels_an_interrupted_stream_keeps_its_axes(tmp_path):
    """batch._streamed_partial labels t, y_ws1, vy_ws1 as a finished case does."""
    from railvti.runner.batch import _streamed_partial
    from railvti.runner.stream import HistoryStream

    class Part:
        wheel = np.zeros((3, 15, 2, 4))

        @staticmethod
        def _save_attrs():
            return {"q": {"axes": ["t", "state"]}, "t": {"axes": ["t"]}}

    hs = HistoryStream(tmp_path / "s.h5", store=("t", "q"))
    hs.append({"t": np.arange(3.0), "q": np.zeros((3, 2)), "y_ws1": np.zeros(3), "vy_ws1": np.zeros(3)})
    hs.close()
    data, labels = _streamed_partial(Part(), hs)
    assert {"t", "q"} <= set(data)
    assert all(labels[k]["axes"][0] == "t" for k in data)


def test_labels_hunting_summary_says_the_window_of_a_short_run():
    """A hunting run shorter than the 1 s window says its amplitude is over the whole run."""
    from railvti.vehicle.cases import AMPLITUDE_WINDOW

    assert AMPLITUDE_WINDOW == scenarios.AMPLITUDE_WINDOW == 1.0


def test_labels_rf_critical_speed_is_accepted_up_front():
    """Model RF runs every scenario (README, scenarios.RF_SCENARIOS): its critical_speed deck
    case passes the checks (measured: the nonlinear sweep 300/340 km/h, 1.2 s, 260 km/h tread
    cycle in 113 s; the linear method 314.95 km/h in 530 s)."""
    (case,) = parse_deck(vehicle_deck("model = 'RF'").replace("'hunting'", "'critical_speed'"))
    assert case.params["model"] == "RF" and case.params["scenario"] == "critical_speed"
