"""railvti run never loses finished work, checks its output path first, and writes
self-describing results; result objects round-trip through HDF5 (issue 16, items 2-5)."""

from __future__ import annotations

import logging

import os
import stat

import h5py
import numpy as np
import pytest

from railvti import STEEL
from railvti.casetypes import REGISTRY, CaseOutput, CaseType
from railvti.runner.cli import main
from railvti.contact import Grid
from railvti.contact import normal as normal_mod
from railvti.contact.hertz import hertz_gap
from railvti.runner.deck import parse_deck
from railvti.runner.result_objects import load, save
from railvti.runner.results import case_deck

SMALL = """
&case
    name = '{name}', type = 'normal'
    gap_a = 1.0, gap_b = 1.0
    nx = 24, ny = 24, dx = 0.3e-3, dy = 0.3e-3
    fn = {fn}
/
"""


def _deck(tmp_path, text, name="deck.nml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _statuses(path):
    with h5py.File(path, "r") as f:
        return {k: str(g.attrs["status"]) for k, g in f.items()}


@pytest.fixture
def test_types(monkeypatch):
    """Two case types for the runner's own tests: 'boom' raises a non-railvti exception;
    'probe' returns the case groups it finds in the output file while it runs."""

    def boom(params):
        return {}["no such key"]  # KeyError: not a RailvtiError

    def probe(params):
        with h5py.File(params["path"], "r") as f:
            seen = sorted(f.keys())
        return CaseOutput(summary="probe", scalars={"seen": (",".join(seen), "text")})

    monkeypatch.setitem(REGISTRY, "boom", CaseType(name="boom", defaults={}, run=boom))
    monkeypatch.setitem(REGISTRY, "probe", CaseType(name="probe", defaults={"path": ""}, run=probe))


def test_any_exception_is_the_case_error_and_the_others_run(tmp_path, test_types, capsys, caplog):
    deck = _deck(
        tmp_path,
        SMALL.format(name="a", fn=1e4) + "&case name='b', type='boom' /\n" + SMALL.format(name="c", fn=5e3),
    )
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 1
    captured = capsys.readouterr()
    # one line on the console, saying it was unexpected and where the traceback is
    assert "case 2 'b': FAILED: KeyError: 'no such key' (unexpected: its traceback" in captured.out
    assert "Traceback" not in captured.out + captured.err + caplog.text
    # --debug: the traceback in the log (stderr)
    caplog.set_level(logging.DEBUG, logger="railvti.traceback")
    out.unlink()
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial", "--debug"]) == 1
    assert "Traceback" in caplog.text and "KeyError: 'no such key'" in caplog.text
    st = _statuses(out)
    assert st["001_a"] == "ok" and st["003_c"] == "ok"
    assert st["002_b"].startswith("error: KeyError")
    with h5py.File(out, "r") as f:
        assert "no such key" in f["002_b"].attrs["traceback"]
        assert f["003_c/fn"][()] == pytest.approx(5e3)


def test_each_finished_case_is_in_the_file_before_the_next_starts(tmp_path, test_types):
    out = tmp_path / "out.h5"
    deck = _deck(
        tmp_path,
        SMALL.format(name="a", fn=1e4)
        + SMALL.format(name="b", fn=1e4)
        + f"&case name='p', type='probe', path='{out}' /\n",
    )
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    with h5py.File(out, "r") as f:
        assert f["003_p/seen"][()].decode() == "001_a,002_b"


def test_resume_keeps_complete_cases_and_reruns_changed_ones(tmp_path, capsys):
    out = tmp_path / "out.h5"
    deck = _deck(tmp_path, SMALL.format(name="a", fn=1e4) + SMALL.format(name="b", fn=1e4))
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    with h5py.File(out, "r") as f:
        wall_a = f["001_a"].attrs["wall_time"]
    deck.write_text(SMALL.format(name="a", fn=1e4) + SMALL.format(name="b", fn=7e3))
    capsys.readouterr()
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial", "--resume"]) == 0
    text = capsys.readouterr().out
    assert "1 of 2 cases already complete" in text and "case 2 'b'" in text and "case 1 'a'" not in text
    with h5py.File(out, "r") as f:
        assert f["001_a"].attrs["wall_time"] == wall_a  # kept as it was
        assert f["002_b/fn"][()] == pytest.approx(7e3)  # re-run with the new value
        assert "fn = 7000.0" in f.attrs["deck"]


def test_output_path_is_checked_before_any_work(tmp_path, test_types, capsys):
    # the probe would fail if it ran: nothing may run before the output is refused
    deck = _deck(tmp_path, f"&case name='p', type='probe', path='{tmp_path / 'missing.h5'}' /\n")
    (tmp_path / "adir").mkdir()
    other = tmp_path / "notes.txt"
    other.write_text("my notes")
    for target, words in [
        (tmp_path / "adir", "is a directory"),
        (deck, "is the deck itself"),
        (other, "not a railvti results file"),
    ]:
        assert main(["run", str(deck), "-o", str(target), "-q", "--serial"]) == 2
        assert words in capsys.readouterr().err
    assert other.read_text() == "my notes" and deck.exists()
    if os.path.exists("/dev/full"):
        assert main(["run", str(deck), "-o", "/dev/full", "-q", "--serial"]) == 2
        assert "not a regular file" in capsys.readouterr().err
        assert stat.S_ISCHR(os.stat("/dev/full").st_mode)
    small = _deck(tmp_path, SMALL.format(name="a", fn=1e4), "small.nml")
    assert main(["run", str(small), "-o", str(other), "-q", "--force"]) == 0
    assert _statuses(other) == {"001_a": "ok"}


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_results_honour_the_umask(tmp_path, umask, mode):
    deck = _deck(tmp_path, SMALL.format(name="a", fn=1e4))
    old = os.umask(umask)
    try:
        assert main(["run", str(deck), "-o", str(tmp_path / "out.h5"), "-q", "--serial"]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(tmp_path / "out.h5").st_mode) == mode
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


def test_plot_into_an_existing_file_is_a_clear_error(tmp_path, capsys):
    deck = _deck(tmp_path, SMALL.format(name="a", fn=1e4))
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    capsys.readouterr()
    assert main(["plot", str(out), "-o", str(deck)]) == 2
    err = capsys.readouterr().err
    assert "existing file" in err and "Traceback" not in err


def test_memory_limit_refuses_before_running(tmp_path, test_types, capsys):
    deck = _deck(tmp_path, SMALL.format(name="a", fn=1e4))
    assert main(["run", str(deck), "-o", str(tmp_path / "o.h5"), "-q", "--serial", "--max-memory", "1k"]) == 2
    assert "more than the limit" in capsys.readouterr().err
    assert not (tmp_path / "o.h5").exists()
    assert (
        main(["run", str(deck), "-o", str(tmp_path / "o.h5"), "-q", "--serial", "--max-memory", "lots"]) == 2
    )
    assert "not a size" in capsys.readouterr().err


def test_a_case_is_remade_from_its_group_alone(tmp_path):
    deck = _deck(tmp_path, SMALL.format(name="a", fn=7.5e3))
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    text = case_deck(out, "001_a")
    case = parse_deck(text)[0]
    again = case.case_type.run(case.params)
    with h5py.File(out, "r") as f:
        assert np.array_equal(again.datasets["pressure"][0], f["001_a/pressure"][()])
        gi = f["001_a/inputs"]
        assert gi["fn"].attrs["units"] == "N" and gi["dx"].attrs["units"] == "m"
        assert gi["fn"][()] == 7.5e3


def test_gauss_seidel_in_slices_equals_one_call(monkeypatch):
    """The sliced solve (many Python round trips) against the one-call Fortran shim."""
    from railvti._native import core
    from railvti.contact.workspace import workspace

    g = Grid(40, 32, 0.2e-3, 0.2e-3)
    h = np.asfortranarray(hertz_gap(g, 1.087, 1.6667))
    p1 = np.zeros(g.shape, order="F")
    fn1, app1, it1, _, res1, info1 = core.normal_solve_c(
        workspace(g, STEEL), h, 1, 2, 1e-8, 20000, 1.0, 1e4, 0.0, p1
    )
    monkeypatch.setattr(normal_mod, "GS_SLICE_SECONDS", 1e-6)  # slices of ~1000 work units
    calls = []
    real = core.normal_gs_slice_c

    class Counting:
        def __getattr__(self, name):
            return getattr(core, name)

        def normal_gs_slice_c(self, *a):
            calls.append(1)
            return real(*a)

    monkeypatch.setattr(normal_mod, "core", Counting())
    r = normal_mod.solve_normal(h, g, STEEL, fn=1e4, method="gs")
    assert len(calls) > 50
    assert info1 == 0 and r.converged
    assert np.array_equal(r.pressure, p1)
    assert (r.approach, r.iterations, r.residual) == (app1, it1, res1)


def test_normal_result_round_trips(tmp_path):
    g = Grid(32, 32, 0.25e-3, 0.25e-3)
    r = normal_mod.solve_normal(hertz_gap(g, 1.0, 1.0), g, STEEL, fn=1e4)
    back = load(save(r, tmp_path / "n.h5"))
    assert type(back) is type(r) and back.grid == r.grid
    assert np.array_equal(back.pressure, r.pressure)
    assert (back.fn, back.approach, back.iterations, back.method) == (
        r.fn,
        r.approach,
        r.iterations,
        r.method,
    )
    with h5py.File(tmp_path / "n.h5", "r") as f:
        assert f["result/pressure"].attrs["units"] == "Pa"
        assert f["result/grid/dx"].attrs["units"] == "m"


def _all_datasets(node):
    out = {}
    node.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out


def test_vehicle_results_are_self_describing_and_round_trip(tmp_path):
    from railvti import scenarios as sc

    res = sc.hunting(300.0, duration=0.04)
    back = load(save(res, tmp_path / "sim.h5"))
    for k in ("t", "q", "v", "wheel"):
        assert np.array_equal(getattr(back, k), getattr(res, k))
    assert back.dof_names == res.dof_names and back.stats == res.stats
    assert back.wheels().line() == res.wheels().line()
    with h5py.File(tmp_path / "sim.h5", "r") as f:
        assert list(f["result/q"].attrs["dof_names"]) == list(res.dof_names)
        assert all(d.attrs.get("units") for d in _all_datasets(f).values())

    deck = _deck(
        tmp_path,
        "&case type='vehicle', name='v', scenario='centred_running', "
        "duration=0.04, contact='hertz-fastsim' /\n" + SMALL.format(name="n", fn=1e4),
    )
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    with h5py.File(out, "r") as f:
        for gname in ("001_v", "002_n"):
            ds = _all_datasets(f[gname])
            missing = [n for n, d in ds.items() if not d.attrs.get("units")]
            assert not missing, missing
            assert all(n.split("/")[0] != "inputs" or d.attrs.get("units") is not None for n, d in ds.items())
        g = f["001_v"]
        names = [s.decode() if isinstance(s, bytes) else s for s in g["q"].attrs["dof_names"]]
        assert len(names) == g["q"].shape[1] and names[names.index("ws1_y")] == "ws1_y"
        assert np.array_equal(g["q"][:, names.index("ws1_y")], g["y_ws1"][()])
        assert list(g["wheel_Q"].attrs["axes"]) == ["t", "wheel", "wheelset"]
        assert g["wheel_Q"].shape[1:] == (2, 4)
        assert g["stat_wall_time"].attrs["units"] == "s"
        assert list(f["002_n/pressure"].attrs["axes"]) == ["x", "y"]


def test_a_result_hdf5_cannot_store_is_that_case_error(tmp_path, monkeypatch):
    def odd(params):
        return CaseOutput(summary="odd", datasets={"bad": (np.array([{}, {}], dtype=object), "1")})

    monkeypatch.setitem(REGISTRY, "odd", CaseType(name="odd", defaults={}, run=odd))
    deck = _deck(tmp_path, "&case name='o', type='odd' /\n" + SMALL.format(name="a", fn=1e4))
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 1
    st = _statuses(out)
    assert st["001_o"].startswith("error: cannot store the results") and st["002_a"] == "ok"


def test_a_very_long_case_name_is_refused_before_anything_runs(tmp_path, capsys):
    """A 20,000-character case name: a clear error naming the key and its limit (the deck
    check), exit 2, no output file; a 64-character name runs and plots."""
    deck = _deck(tmp_path, SMALL.format(name="n" * 20000, fn=1e4))
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 2
    assert "key 'name' has 20000 characters; at most 64" in capsys.readouterr().err
    assert not out.exists()
    name = "n" * 64
    deck = _deck(tmp_path, SMALL.format(name=name, fn=1e4))
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    with h5py.File(out, "r") as f:
        (g,) = f.values()
        assert g.attrs["name"] == name
    assert main(["plot", str(out), "-o", str(tmp_path / "png")]) == 0
    assert len(list((tmp_path / "png").glob("*.png"))) == 1


def test_a_file_that_cannot_be_written_stops_with_status_3(tmp_path, monkeypatch, capsys):
    from railvti.runner import results

    real = results.ResultsWriter.write
    calls = []

    def failing(self, records):
        calls.append(1)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return real(self, records)

    monkeypatch.setattr(results.ResultsWriter, "write", failing)
    deck = _deck(
        tmp_path,
        SMALL.format(name="a", fn=1e4) + SMALL.format(name="b", fn=1e4) + SMALL.format(name="c", fn=1e4),
    )
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 3
    err = capsys.readouterr().err
    assert "No space left on device" in err and len(err.splitlines()) == 1
    assert _statuses(out) == {"001_a": "ok"}  # the last complete version
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


def test_file_attributes_hold_through_every_write_of_a_writer(tmp_path):
    """A writer sets the file's attributes on its first version and keeps them in every later
    one (copied, not written again); a writer continuing another run's file (--resume) sets
    its own."""
    from railvti.runner.results import LAYOUT, CaseRecord, ResultsWriter

    cases = parse_deck("".join(SMALL.format(name=n, fn=1e4) for n in "abc"))
    recs = [
        CaseRecord(c, output=CaseOutput(summary=c.name, scalars={"x": (1.0, "m")}), wall_time=0.1)
        for c in cases
    ]
    out = tmp_path / "out.h5"
    w = ResultsWriter(out, "deck one", deck_path="/decks/one.nml", cases=cases)
    for k, rec in enumerate(recs, 1):
        w.write([rec])
        with h5py.File(out, "r") as f:
            assert len(f) == k and f.attrs["deck"] == "deck one" and f.attrs["layout"] == LAYOUT
            assert f.attrs["deck_path"] == "/decks/one.nml" and len(f.attrs["deck_digest"]) == 64
            assert "railvti_version" in f.attrs
    # the file replaced behind the writer's back: checked again, its attributes set again
    other = tmp_path / "other.h5"
    ResultsWriter(other, "deck other", cases=cases[:1]).write([recs[0]])
    os.replace(other, out)
    w.write([recs[1]])
    with h5py.File(out, "r") as f:
        assert sorted(f) == ["001_a", "002_b"] and f.attrs["deck"] == "deck one"
    out.write_bytes(b"not HDF5")  # not a results file: started anew, as before
    w.write([recs[2]])
    with h5py.File(out, "r") as f:
        assert sorted(f) == ["003_c"] and f.attrs["deck"] == "deck one"
    w.write([recs[0]])
    w.write([recs[1]])
    w2 = ResultsWriter(out, "deck two", keep=True, deck_path="/decks/two.nml", cases=cases[:1])
    w2.write([recs[0]])
    w2.write([recs[1]])
    with h5py.File(out, "r") as f:
        assert len(f) == 3 and f.attrs["deck"] == "deck two" and f.attrs["deck_path"] == "/decks/two.nml"
