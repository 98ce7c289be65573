"""Input decks, the railvti command and the HDF5 results file."""

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.runner.deck import parse_deck
from railvti.errors import InputError

CASE = """
&case
    name = 'small', type = 'normal'
    gap_a = 1.0, gap_b = 1.0
    nx = 32, ny = 32, dx = 0.25e-3, dy = 0.25e-3
    fn = 1.0e4
/
"""
TOO_SMALL = """
&case
    name = 'cramped', type = 'normal'
    gap_a = 0.5, gap_b = 0.5
    nx = 10, ny = 10, dx = 0.2e-3, dy = 0.2e-3
    fn = 1.0e4
/
"""


def test_parse_fills_defaults():
    cases = parse_deck(CASE + CASE.replace("'small'", "'second'"))
    assert [c.name for c in cases] == ["small", "second"]
    assert cases[0].params["method"] == "cg"
    assert cases[0].params["fn"] == 1.0e4
    assert cases[0].params["approach"] is None


@pytest.mark.parametrize(
    "text, words",
    [
        (CASE.replace("fn = 1.0e4", "fm = 1.0e4"), "unknown key 'fm'.*did you mean 'fn'"),
        (CASE.replace("nx = 32, ", ""), "missing value for required key 'nx'"),
        (CASE.replace("type = 'normal'", "type = 'norml'"), "unknown type 'norml'.*did you mean 'normal'"),
        (CASE.replace("&case", "&cases"), "unknown namelist group '&cases'"),
        (CASE.replace("fn = 1.0e4", "fn = "), "key 'fn' has no value"),
        (CASE.replace("type = 'normal'", ""), "missing key 'type'"),
        ("", "no '&case' group"),
        ("&case name = 'x' fn = 1.0e4 / &case = /", "valid Fortran namelist|unknown|no value|missing"),
    ],
)
def test_bad_decks_name_the_problem(text, words):
    with pytest.raises(InputError, match=words):
        parse_deck(text)


def test_run_writes_hdf5_and_plots(tmp_path):
    deck = tmp_path / "deck.nml"
    deck.write_text(CASE)
    out = tmp_path / "res.h5"
    assert main(["run", str(deck), "-o", str(out), "-q"]) == 0
    with h5py.File(out, "r") as f:
        g = f["001_small"]
        assert g.attrs["status"] == "ok"
        assert g["pressure"].shape == (32, 32)
        assert g["pressure"].attrs["units"] == "Pa"
        assert g["inputs"].attrs["fn"] == 1.0e4
        p = g["pressure"][()]
        assert p.sum() * 0.25e-3**2 == pytest.approx(1.0e4, rel=1e-8)
        assert g["fn"][()] == pytest.approx(1.0e4)
        assert np.isfinite(p).all()
    assert main(["plot", str(out), "-o", str(tmp_path / "png")]) == 0
    pngs = list((tmp_path / "png").glob("*.png"))
    assert len(pngs) == 1 and pngs[0].stat().st_size > 1000


def test_failing_case_is_recorded_and_others_run(tmp_path, capsys):
    deck = tmp_path / "deck.nml"
    deck.write_text(TOO_SMALL + CASE)
    out = tmp_path / "res.h5"
    assert main(["run", str(deck), "-o", str(out), "-q"]) == 1
    assert "GridTooSmallError" in capsys.readouterr().out
    with h5py.File(out, "r") as f:
        assert f["001_cramped"].attrs["status"].startswith("error: GridTooSmallError")
        assert "pressure" not in f["001_cramped"]
        assert f["002_small"].attrs["status"] == "ok"


def test_bad_deck_writes_nothing(tmp_path, capsys):
    deck = tmp_path / "deck.nml"
    deck.write_text(CASE.replace("gap_a", "gapa"))
    out = tmp_path / "res.h5"
    assert main(["run", str(deck), "-o", str(out)]) == 2
    assert "unknown key 'gapa'" in capsys.readouterr().err
    assert not out.exists()
    assert not list(tmp_path.glob("*.tmp"))


def test_missing_deck_file(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.nml")]) == 2
    assert "cannot read deck" in capsys.readouterr().err


def test_cases_lists_keys(capsys):
    assert main(["cases"]) == 0
    assert "type = 'normal'" in capsys.readouterr().out
