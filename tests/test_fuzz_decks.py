"""Fuzz suite of bad and hostile decks (issue 16): each runs through ``railvti run`` in-process
and must end in its outcome class, never in a traceback, a hang or a NaN with exit status 0:

- ``error``: exit status 2 before any case runs, one message on stderr naming the problem
  (the key, the bound, the line or the encoding), no output file;
- ``ok``: exit status 0 and a results file whose cases are all 'ok' with finite results.

The decks are generated: every bounded key of every case type just outside its bound and
with a value of the wrong type, every choice key with an unknown choice, and the hand-written
classes below (encodings, syntax, names, consistency between keys, every example of the
issue). Only the few 'ok' decks run a case, on a small grid.
"""

from __future__ import annotations

import codecs
import math
import random
import re

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.runner.deck_registry import case_types

case_types()

#: A cheap valid case of each type: keys that make it pass every check (not necessarily fast to run).
BASE = {
    "normal": "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3",
    "rolling": (
        "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3, "
        "mu = 0.3, speed = 10.0, xi = 1.0e-3"
    ),
    "dissimilar_rolling": (
        "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3, "
        "mu = 0.3, speed = 10.0, xi = 1.0e-3, wheel_shear_modulus = 23.0e9, wheel_poisson = 0.31"
    ),
    "subsurface": (
        "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3, "
        "z_min = 1.0e-4, z_max = 1.0e-3, nz = 3"
    ),
    "geometry_table": "n = 5",
    "viscoelastic_rolling": (
        "radius = 0.05, fn = 2.0e5, speed = 0.04, shear_modulus = 3.0e9, "
        "shear_modulus_relaxed = 1.0e9, relaxation_time = 0.01, n = 64"
    ),
    "loaded_wheelset": "n = 2, y_max_mm = 1.0",
    "wheel_rail": "y_mm = 1.0",
    "track_receptance": "n_sleepers = 16",
    "track_element": "n_sleepers = 16",
    "wheelset": "k_max = 1",
    "vehicle": "scenario = 'hunting', duration = 1.0",
    "line": "route_length = 200.0, curve_radius = 0.0",
    "transient": (
        "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3, mu = 0.3, "
        "kind = 'shift', fx = 100.0"
    ),
}
SMALL_NORMAL = "&case name = 'small', type = 'normal', " + BASE["normal"] + " /\n"


def deck(ctype: str, extra: str = "", name: str = "c1", duplicate: bool = False) -> str:
    """A one-case deck of type ``ctype``: the base keys (those not in ``extra``, unless
    ``duplicate``), then ``extra``."""
    given = set(re.findall(r"(\w+)\s*=", extra))
    base = ", ".join(a for a in BASE[ctype].split(", ") if duplicate or a.split("=")[0].strip() not in given)
    sep = ",\n    " if extra and base else ""
    return f"&case\n    name = '{name}', type = '{ctype}',\n    {base}{sep}{extra}\n/\n"


def run_deck(tmp_path, capsys, content: str | bytes) -> tuple[int, str, str, object]:
    path = tmp_path / "deck.nml"
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8")
    out = tmp_path / "out.h5"
    code = main(["run", str(path), "-o", str(out), "-q"])
    captured = capsys.readouterr()
    return code, captured.out, captured.err, out


def expect_error(tmp_path, capsys, content, *words: str) -> str:
    """Exit status 2, nothing written, and every word in the message (case-insensitive)."""
    code, _, err, out = run_deck(tmp_path, capsys, content)
    assert code == 2, err
    assert err.startswith("railvti: error: "), err
    assert "Traceback" not in err
    for w in words:
        assert w.lower() in err.lower(), (w, err)
    assert not out.exists()
    assert not list(tmp_path.glob("*.tmp"))
    return err


def expect_ok(tmp_path, capsys, content) -> None:
    """Exit status 0 and every case 'ok' with finite results."""
    code, _, err, out = run_deck(tmp_path, capsys, content)
    assert code == 0, err
    with h5py.File(out, "r") as f:
        assert len(f) >= 1
        for g in f.values():
            assert g.attrs["status"] == "ok"
            for d in g.values():
                if isinstance(d, h5py.Dataset) and d.dtype.kind == "f":
                    assert np.isfinite(d[()]).all(), d.name


# ------------------------------------------------------------------ generated: bounds and types


def _bound_cases():
    """(id, type, key, deck value, words in the message) for every bounded key outside its bound."""
    out = []
    for tname, ct in sorted(case_types().items()):
        for key, spec in ((k, ct.keys[k]) for k in ct.defaults if k in ct.keys):
            if spec.kind not in ("float", "int", "floats"):
                continue
            integer = spec.kind == "int"
            bounds = spec.bounds()
            if spec.hi is not None:
                v = spec.hi + (1 if integer else max(1.0, abs(spec.hi)))
                if spec.hi_open:
                    v = spec.hi
                out.append((f"{tname}-{key}-above", tname, key, repr(int(v) if integer else v), bounds))
            if spec.lo is not None:
                v = spec.lo - (1 if integer else max(1.0, abs(spec.lo)))
                if spec.lo_open:
                    v = spec.lo
                out.append((f"{tname}-{key}-below", tname, key, repr(int(v) if integer else v), bounds))
    return out


BOUNDS = _bound_cases()


@pytest.mark.parametrize("tname, key, value, bounds", [c[1:] for c in BOUNDS], ids=[c[0] for c in BOUNDS])
def test_value_outside_its_bound(tmp_path, capsys, tname, key, value, bounds):
    expect_error(tmp_path, capsys, deck(tname, f"{key} = {value}"), "case 1 'c1'", f"key '{key}'", bounds)


def _type_cases():
    """A text where a number belongs and a number where a text belongs, one key per type and kind,
    and NaN or infinity in every float key of the cheap case types."""
    out = []
    for tname, ct in sorted(case_types().items()):
        seen = set()
        for key, spec in ((k, ct.keys[k]) for k in ct.defaults if k in ct.keys):
            if spec.kind in seen and tname not in ("rolling", "loaded_wheelset"):
                continue
            seen.add(spec.kind)
            if spec.kind in ("float", "int", "flag", "floats"):
                out.append((f"{tname}-{key}-text", tname, key, "'abc'", "must be"))
            elif spec.kind == "str":
                out.append((f"{tname}-{key}-number", tname, key, "42", "must be a text"))
            if spec.kind == "float" and tname in ("rolling", "loaded_wheelset", "vehicle"):
                out.append((f"{tname}-{key}-nan", tname, key, "NaN", "finite"))
            if spec.choices:
                out.append((f"{tname}-{key}-choice", tname, key, "'bogus'", "one of"))
    return out


TYPES = _type_cases()


@pytest.mark.parametrize("tname, key, value, words", [c[1:] for c in TYPES], ids=[c[0] for c in TYPES])
def test_value_of_wrong_type(tmp_path, capsys, tname, key, value, words):
    expect_error(tmp_path, capsys, deck(tname, f"{key} = {value}"), "case 1 'c1'", f"key '{key}'", words)


# ------------------------------------------------------------------ the issue's examples

WHY = [
    # (id, deck, words)
    ("nx-abc", deck("normal", "nx = 'abc'").replace("nx = 16, ", ""), ["key 'nx'", "integer"]),
    (
        "hunting-5000-kmh",
        deck("vehicle", "speed_kmh = 5000.0"),
        ["key 'speed_kmh' = 5000.0 (speed = 1388.89 m/s)", "166.667"],
    ),
    ("friction-2", deck("rolling").replace("mu = 0.3", "mu = 2.0"), ["key 'mu'", "(0, 1]"]),
    ("ring-3-sleepers", deck("track_receptance").replace("16", "3"), ["key 'n_sleepers'", "[8, 1024]"]),
    (
        "ymin-above-ymax",
        deck("geometry_table", "y_min_mm = 5.0, y_max_mm = -5.0"),
        ["y_min = 0.005", "y_max = -0.005", "the case gave y_min_mm = 5.0, y_max_mm = -5.0"],
    ),
    (
        "ymin-above-ymax-loaded",
        deck("loaded_wheelset", "y_min_mm = 3.0").replace("y_max_mm = 1.0", "y_max_mm = 0.5"),
        ["y_min = 0.003", "< y_max", "y_min_mm = 3.0", "y_max_mm = 0.5"],
    ),
    (
        "curvatures-and-semiaxes",
        deck("rolling", "semi_a = 3e-3, semi_b = 2e-3"),
        ["gap_a, gap_b", "not both"],
    ),
    ("name-slash", deck("normal", name="a/b"), ["key 'name'", "'a/b'", "safe"]),
    ("name-20000", deck("normal", name="x" * 20000), ["key 'name'", "20000 characters", "at most 64"]),
    ("loaded-mu-nan", deck("loaded_wheelset", "mu = NaN"), ["key 'mu'", "finite"]),
    ("loaded-mu-negative", deck("loaded_wheelset", "mu = -0.1"), ["key 'mu'", "[0, 1]"]),
    ("loaded-speed-negative", deck("loaded_wheelset", "speed = -2.0"), ["key 'speed'", "[0, 166.667]"]),
    ("rolling-mu-0", deck("rolling").replace("mu = 0.3", "mu = 0.0"), ["key 'mu'", "(0, 1]"]),
    (
        "duration-1e6",
        deck("vehicle").replace("duration = 1.0", "duration = 1.0e6"),
        ["duration = 1e+06 s", "max_duration = 600 s"],
    ),
    ("unbalanced-quote", "&case name = 'x, type = 'normal' /\n", ["line 1", "unbalanced quote"]),
    ("duplicated-key", deck("normal", "fn = 2.0e3", duplicate=True), ["key 'fn'", "given 2 times", "lines"]),
    ("bom-then-error", codecs.BOM_UTF8 + deck("normal", "fm = 1.0").encode(), ["unknown key 'fm'", "'fn'"]),
    (
        "latin1",
        ("! Kraft in N, Gr\xf6\xdfe\n" + SMALL_NORMAL).encode("latin-1"),
        ["line 1", "0xF6", "not UTF-8"],
    ),
    ("nul-in-comment", b"! a comment \x00 with a NUL\n" + SMALL_NORMAL.encode(), ["line 1", "NUL byte"]),
]


@pytest.mark.parametrize("content, words", [c[1:] for c in WHY], ids=[c[0] for c in WHY])
def test_examples_of_the_issue(tmp_path, capsys, content, words):
    expect_error(tmp_path, capsys, content, *words)


# ------------------------------------------------------------------ encodings and bytes


def _random_binary(seed: int) -> bytes:
    rng = random.Random(seed)
    return bytes(rng.randrange(256) for _ in range(400))


ENCODING = [
    ("binary-1", _random_binary(1), ["deck.nml", "line"]),
    ("binary-2", _random_binary(2), ["deck.nml", "line"]),
    ("binary-3", _random_binary(3), ["deck.nml", "line"]),
    ("latin1-in-name", "&case name = 'gr\xfc\xdfe', type = 'normal' /".encode("latin-1"), ["line 1", "0xFC"]),
    ("latin1-line-3", ("\n\n" + "! \xe9\n" + SMALL_NORMAL).encode("latin-1"), ["line 3", "column 3", "0xE9"]),
    ("cp1252-quote", ("! \x93quoted\x94\n" + SMALL_NORMAL).encode("latin-1"), ["line 1", "0x93"]),
    ("utf16-no-bom", SMALL_NORMAL.encode("utf-16-le"), ["NUL byte", "UTF-16"]),
    ("nul-in-value", SMALL_NORMAL.replace("fn = 1.0e3", "fn = 1.0\x00e3").encode(), ["line 1", "NUL"]),
    ("control-char", ("! bell \x07\n" + SMALL_NORMAL).encode(), ["line 1", "0x07"]),
    ("escape-char", (SMALL_NORMAL + "\x1b[31m\n").encode(), ["line 2", "0x1B"]),
    ("gzip-magic", b"\x1f\x8b\x08\x00" + b"\x00" * 20, ["line 1"]),
    ("utf16-bad-after-bom", codecs.BOM_UTF16_LE + b"\x00\xd8", ["UTF-16"]),
    ("utf16-bom", SMALL_NORMAL.encode("utf-16"), ["line 1", "UTF-16", "save it as UTF-8"]),
    ("utf16-be-bom", codecs.BOM_UTF16_BE + SMALL_NORMAL.encode("utf-16-be"), ["UTF-16", "FE FF"]),
    ("utf32-bom", SMALL_NORMAL.encode("utf-32"), ["UTF-32"]),
    ("hdf5-file", b"\x89HDF\r\n\x1a\n" + b"\x00" * 32, ["line 1", "0x89"]),
]


@pytest.mark.parametrize("content, words", [c[1:] for c in ENCODING], ids=[c[0] for c in ENCODING])
def test_encoding_problems_name_the_line(tmp_path, capsys, content, words):
    expect_error(tmp_path, capsys, content, *words)


OK_TEXTS = [
    ("utf8-bom", codecs.BOM_UTF8 + SMALL_NORMAL.encode()),
    ("crlf", SMALL_NORMAL.replace("\n", "\r\n").encode()),
    ("utf8-comment", ("! Größe: Kraft in N, µm, \u2264 \u00b0C\n" + SMALL_NORMAL).encode()),
    (
        "tabs-and-case",
        SMALL_NORMAL.replace(", ", ",\t").replace("type = 'normal'", "TYPE = 'Normal'").encode(),
    ),
    ("quote-in-comment", ("! it's a comment with an unbalanced ' quote\n" + SMALL_NORMAL).encode()),
    ("doubled-quote-name", SMALL_NORMAL.replace("'small'", "'it''s'").replace("it''s", "its").encode()),
]


@pytest.mark.parametrize("content", [c[1] for c in OK_TEXTS], ids=[c[0] for c in OK_TEXTS])
def test_readable_decks_run(tmp_path, capsys, content):
    expect_ok(tmp_path, capsys, content)


# ------------------------------------------------------------------ syntax

SYNTAX = [
    ("empty", "", ["no '&case' group"]),
    ("comments-only", "! nothing here\n! at all\n", ["no '&case' group"]),
    ("whitespace-only", "   \n\t\n", ["no '&case' group"]),
    ("misspelt-group", SMALL_NORMAL.replace("&case", "&cases"), ["&cases", "only '&case'"]),
    ("other-group", SMALL_NORMAL + "&run x = 1 /\n", ["&run"]),
    ("quote-in-type", "&case name = 'x', type = 'normal /\n", ["line 1", "unbalanced quote", "column"]),
    ("double-quote-open", "&case name = \"x, type = 'normal' /\n", ["line 1", "unbalanced quote"]),
    ("quote-line-3", "&case\n name = 'x',\n type = 'normal\n/\n", ["line 3", "unbalanced quote"]),
    ("duplicate-nx", deck("normal", "nx = 32", duplicate=True), ["key 'nx'", "given 2 times"]),
    ("duplicate-name", deck("normal", "name = 'other'", duplicate=True), ["key 'name'", "given 2 times"]),
    ("duplicate-type", deck("normal", "type = 'rolling'", duplicate=True), ["key 'type'", "given 2 times"]),
    (
        "duplicate-across-lines",
        "&case name = 'x', type = 'normal'\n fn = 1.0\n fn = 2.0 /\n",
        ["key 'fn'", "lines 2, 3"],
    ),
    ("triplicate", deck("normal", "fn = 2.0, fn = 3.0", duplicate=True), ["key 'fn'", "given 3 times"]),
    ("element-assignment", deck("normal", "nx(2) = 3"), ["nx(2)", "element assignment"]),
    ("missing-type", "&case name = 'x', nx = 3 /\n", ["missing key 'type'"]),
    ("type-number", "&case name = 'x', type = 3 /\n", ["key 'type'", "text"]),
    ("unknown-type", "&case type = 'normall' /\n", ["unknown type 'normall'", "'normal'"]),
    ("unknown-key", deck("normal", "foo = 1"), ["unknown key 'foo'"]),
    ("key-without-value", deck("normal", "tol ="), ["'tol'", "no value"]),
    ("missing-required", deck("normal").replace("nx = 16, ", ""), ["required key 'nx'"]),
    ("no-slash", "&case name = 'x', type = 'normal', " + BASE["normal"] + "\n", ["namelist"]),
    ("garbage", "this is not a namelist at all\n", ["no '&case' group"]),
    ("stray-equals", "&case name = 'x', type = 'normal', = 3 /\n", ["line 1", "'=' without a key"]),
    ("double-equals", deck("normal", "tol == 1e-8"), ["line 4", "'=' without a key"]),
    ("list-for-integer", deck("normal").replace("nx = 16", "nx = 16, 32"), ["key 'nx'", "integer"]),
    ("logical-for-number", deck("normal").replace("fn = 1.0e3", "fn = .true."), ["key 'fn'", "number"]),
    ("fraction-for-integer", deck("normal").replace("nx = 16", "nx = 16.5"), ["key 'nx'", "integer"]),
    ("infinity", deck("normal").replace("fn = 1.0e3", "fn = 1e999"), ["key 'fn'", "finite"]),
    ("minus-infinity", deck("normal").replace("dx = 4.0e-4", "dx = -Infinity"), ["key 'dx'", "finite"]),
    ("too-many-cases", "&case /\n" * 1001, ["1001 groups", "at most 1000"]),
    (
        "many-stray-equals",
        "&case " + "= " * 5000 + "/",
        ["'=' without a key", "4999 problems", "and 4959 more"],
    ),
    ("unclosed-paren-long-line", "&case a" + " (b" * 5000 + " /", ["namelist"]),
    (
        "long-duplicate-list",
        "&case name = 'x', type = 'normal'\n" + " fn = 1.0\n" * 300 + "/",
        ["key 'fn'", "given 300 times", "..."],
    ),
]


@pytest.mark.parametrize("content, words", [c[1:] for c in SYNTAX], ids=[c[0] for c in SYNTAX])
def test_syntax_problems_are_named(tmp_path, capsys, content, words):
    expect_error(tmp_path, capsys, content, *words)


# ------------------------------------------------------------------ names

NAMES = [
    ("slash", "a/b"),
    ("leading-slash", "/root"),
    ("dot", "."),
    ("dotdot", ".."),
    ("hidden", ".x"),
    ("space", "a b"),
    ("tab", "a\tb"),
    ("umlaut", "gr\u00fc\u00dfe"),
    ("emoji", "car\U0001f683"),
    ("backslash", "a\\b"),
    ("colon", "c:x"),
    ("star", "a*"),
    ("long-65", "x" * 65),
    ("dash-first", "-x"),
]


@pytest.mark.parametrize("name", [n[1] for n in NAMES], ids=[n[0] for n in NAMES])
def test_unsafe_case_names(tmp_path, capsys, name):
    expect_error(tmp_path, capsys, deck("normal", name=name), "key 'name'")


# ------------------------------------------------------------------ consistency between keys

CONSISTENCY = [
    ("normal-fn-and-approach", deck("normal", "approach = 1e-6"), ["exactly one of fn", "approach"]),
    ("normal-neither", deck("normal").replace(", fn = 1.0e3", ""), ["exactly one of fn"]),
    ("two-bumps-no-separation", deck("normal", "gap = 'two_bumps'"), ["bump_separation > 0"]),
    (
        "rolling-half-semiaxes",
        deck("rolling", "semi_a = 3e-3").replace("gap_a = 1.0, gap_b = 1.0, ", ""),
        ["semi_a, semi_b"],
    ),
    ("rolling-no-gap", deck("rolling").replace("gap_a = 1.0, gap_b = 1.0, ", ""), ["gap_a, gap_b"]),
    (
        "rolling-semiaxes-two-bumps",
        deck("rolling", "semi_a = 3e-3, semi_b = 2e-3, gap = 'two_bumps', bump_separation = 1e-3").replace(
            "gap_a = 1.0, gap_b = 1.0, ", ""
        ),
        ["'hertz' gap only"],
    ),
    (
        "table-equal-ends",
        deck("geometry_table", "y_min_mm = 1.0, y_max_mm = 1.0"),
        ["y_min = 0.001", "or n = 1"],
    ),
    (
        "loaded-field-outside",
        deck("loaded_wheelset", "field_at_mm = 5.0"),
        ["field_at = 0.005", "[y_min, y_max]"],
    ),
    (
        "profile-missing",
        deck("geometry_table", "wheel = 'no_such_profile.prw'"),
        ["key 'wheel'", "no_such_profile.prw", "neither 's1002'"],
    ),
    ("rail-profile-missing", deck("loaded_wheelset", "rail = 'nope.txt'"), ["key 'rail'", "nope.txt"]),
    ("half-wheelset-no-roll", deck("wheel_rail", "side = 'left'"), ["side = 'left'", "roll_mrad"]),
    (
        "half-wheelset-free-rolling",
        deck("wheel_rail", "side = 'right', roll_mrad = 0.0"),
        ["side = 'right'", "omega > 0"],
    ),
    (
        "track-f-min-above-max",
        deck("track_receptance", "f_min = 500.0, f_max = 100.0"),
        ["f_min = 500", "f_max = 100"],
    ),
    ("wheelset-band", deck("wheelset", "f_lo = 900.0, f_hi = 100.0"), ["f_lo = 900", "f_hi = 100"]),
    ("wheelset-geometry", deck("wheelset", "seat_radius = 0.5"), ["wheelset geometry"]),
    ("vehicle-rr-modes", deck("vehicle", "k_max = 1"), ["k_max", "model 'RR' has rigid wheelsets"]),
    (
        "vehicle-sweep-reversed",
        deck(
            "vehicle", "scenario = 'critical_speed', speeds_kmh_min = 400.0, speeds_kmh_max = 300.0"
        ).replace("scenario = 'hunting', ", ""),
        ["speeds_kmh_min = 400", "speeds_kmh_max = 300"],
    ),
    (
        "vehicle-sweep-too-fine",
        deck("vehicle", "speeds_kmh_step = 0.01").replace("'hunting'", "'critical_speed'"),
        ["speeds_kmh_step", "at most 201"],
    ),
    (
        "vehicle-h-above-duration",
        deck("vehicle", "h = 0.005").replace("duration = 1.0", "duration = 0.001"),
        ["h = 0.005 s", "duration"],
    ),
    ("vehicle-negative-mass", deck("vehicle", "coach_carbody_mass = -1.0"), ["coach", "carbody_mass"]),
    (
        "vehicle-duration-over-own-max",
        deck("vehicle", "max_duration = 10.0").replace("duration = 1.0", "duration = 20.0"),
        ["duration = 20 s", "max_duration = 10 s"],
    ),
    (
        "speed-and-speed-kmh",
        deck("vehicle", "speed = 50.0, speed_kmh = 180.0"),
        ["'speed_kmh'", "'speed'", "give one"],
    ),
    (
        "g-and-shear-modulus",
        deck("loaded_wheelset", "g = 8.0e10, shear_modulus = 8.2e10"),
        ["'g'", "'shear_modulus'", "give one"],
    ),
    (
        "nu-out-of-range-old-name",
        deck("wheel_rail", "nu = 0.7"),
        ["key 'nu' = 0.7 (poisson = 0.7)", "(-1, 0.5)"],
    ),
]


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize("content, words", [c[1:] for c in CONSISTENCY], ids=[c[0] for c in CONSISTENCY])
def test_inconsistent_keys_are_named(tmp_path, capsys, content, words):
    expect_error(tmp_path, capsys, content, *words)


# ------------------------------------------------------------------ the whole deck first


def test_every_problem_of_every_case_at_once(tmp_path, capsys):
    """Three cases, problems in the first and the third: both named, the second not run."""
    text = (
        deck("normal", "fn = -1.0", name="first")
        + SMALL_NORMAL
        + deck("rolling", "xi = 'abc', nx = 0", name="third")
    )
    text = text.replace("fn = 1.0e3, fn = -1.0", "fn = -1.0")
    err = expect_error(
        tmp_path,
        capsys,
        text,
        "3 problems",
        "case 1 'first'",
        "case 3 'third'",
        "key 'fn'",
        "key 'xi'",
        "key 'nx'",
    )
    assert "case 2" not in err


def test_key_and_value_problems_of_one_case_together(tmp_path, capsys):
    text = deck("normal", "foo = 1, nx = 'abc'").replace("dy = 4.0e-4, ", "")
    expect_error(
        tmp_path,
        capsys,
        text,
        "3 problems",
        "unknown key 'foo'",
        "key 'nx' must be an integer",
        "required key 'dy'",
    )


def test_problem_in_last_case_stops_before_the_first_runs(tmp_path, capsys):
    """A deck whose expensive first case would run for minutes fails at once on its last case."""
    text = deck("vehicle", "duration = 60.0").replace("duration = 1.0, ", "") + deck(
        "normal", "nx = 'abc'", "bad"
    )
    text = text.replace(
        "nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3,\n    nx = 'abc'",
        "nx = 'abc', ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0, fn = 1.0e3",
    )
    expect_error(tmp_path, capsys, text, "case 2 'bad'", "key 'nx'")


def test_deprecated_material_names_still_work(tmp_path, capsys):
    from railvti.runner.deck import parse_deck

    with pytest.warns(DeprecationWarning) as record:
        cases = parse_deck(deck("loaded_wheelset", "g = 8.0e10, nu = 0.25"))
    messages = " ".join(str(w.message) for w in record)
    assert (
        "'g'" in messages and "'shear_modulus'" in messages and "'nu'" in messages and "'poisson'" in messages
    )
    assert cases[0].params["shear_modulus"] == 8.0e10 and cases[0].params["poisson"] == 0.25
    assert "g" not in cases[0].params


def test_speed_kmh_alias_converts_to_si():
    from railvti.runner.deck import parse_deck

    (case,) = parse_deck(deck("vehicle", "speed_kmh = 252.0"))
    assert case.params["speed"] == pytest.approx(70.0, rel=1e-15)
    assert "speed_kmh" not in case.params


def test_mm_aliases_of_si_keys():
    """The mm / mrad aliases convert to the SI keys (m, rad, rad/m); the case holds the keys."""
    from railvti.runner.deck import parse_deck

    (case,) = parse_deck(
        deck(
            "loaded_wheelset", "y_min_mm = -2.0, y_max_mm = 4.0, dx_mm = 0.5, yaw_mrad_per_mm = 2.4"
        ).replace(", y_max_mm = 1.0", "")
    )
    p = case.params
    assert (p["y_min"], p["y_max"], p["dx"], p["yaw_per_y"]) == pytest.approx((-2e-3, 4e-3, 5e-4, 2.4))
    assert not [k for k in p if k.endswith("_mm")]
    (case,) = parse_deck(
        deck("wheel_rail", "y = 0.003, yaw_mrad = -2.0, gauge_mm = 1435.0").replace("y_mm = 1.0,", "")
    )
    assert (case.params["y"], case.params["yaw"], case.params["gauge"]) == pytest.approx((3e-3, -2e-3, 1.435))


def test_mm_alias_beside_its_si_key(tmp_path, capsys):
    expect_error(
        tmp_path,
        capsys,
        deck("geometry_table", "y_min = -0.01, y_min_mm = -10.0"),
        "'y_min'",
        "'y_min_mm'",
        "give one",
    )


def test_mm_alias_out_of_range_names_the_key_and_bound(tmp_path, capsys):
    expect_error(
        tmp_path,
        capsys,
        deck("geometry_table", "y_max_mm = 200.0"),
        "key 'y_max_mm' = 200.0 (y_max = 0.2 m)",
        "[-0.05, 0.05] m",
    )


@pytest.mark.parametrize("seed", range(12))
def test_random_mutations_of_a_valid_deck(tmp_path, capsys, seed):
    """Random byte-level mutations of a valid deck (deleted, doubled or replaced characters):
    either a named error or a valid run, never a traceback."""
    rng = random.Random(seed)
    chars = list(SMALL_NORMAL)
    for _ in range(3):
        i = rng.randrange(len(chars))
        op = rng.choice(("del", "dup", "sub"))
        if op == "del":
            del chars[i]
        elif op == "dup":
            chars.insert(i, chars[i])
        else:
            chars[i] = rng.choice("'\"=,/&!x9.-( \n")
    text = "".join(chars)
    path = tmp_path / "deck.nml"
    path.write_text(text)
    out = tmp_path / "out.h5"
    code = main(["run", str(path), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert code in (0, 1, 2), text
    if code == 2:
        assert err.startswith("railvti: error: ") and len(err.strip()) > len("railvti: error: ") + 5, (
            text,
            err,
        )
        assert not out.exists()
    else:
        with h5py.File(out, "r") as f:
            for g in f.values():
                if g.attrs["status"] == "ok":
                    assert all(
                        np.isfinite(d[()]).all()
                        for d in g.values()
                        if isinstance(d, h5py.Dataset) and d.dtype.kind == "f"
                    )


def test_fuzz_suite_size():
    n = (
        len(BOUNDS)
        + len(TYPES)
        + len(WHY)
        + len(ENCODING)
        + len(OK_TEXTS)
        + len(SYNTAX)
        + len(NAMES)
        + len(CONSISTENCY)
        + 12
        + 8
    )
    assert n >= 150, n
    assert math.isfinite(n)
