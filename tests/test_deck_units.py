"""Self-describing results (issue 16, Deliver 5 and its acceptance): a walk over every
dataset of a results file with a vehicle, contact and track case, and over files written by
``save()`` from the API. It fails on any dataset without a units attribute (or with an empty
one), on an input attribute with no input dataset carrying its units and meaning, on a
multi-dimensional array without a label per axis, on NaN without a note on the empty slots,
and on a vehicle state without DOF names."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.runner.result_objects import load, save

DECK = """
&case name = 'vh', type = 'vehicle', scenario = 'hunting', duration = 0.04 /
&case name = 'n', type = 'normal', nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4,
      gap_a = 1.0, gap_b = 1.0, fn = 1.0e3 /
&case name = 'r', type = 'rolling', nx = 16, ny = 16, dx = 4.0e-4, dy = 4.0e-4, gap_a = 1.0, gap_b = 1.0,
      fn = 1.0e3, mu = 0.3, speed = 10.0, xi = 1.0e-3 /
&case name = 'lw', type = 'loaded_wheelset', n = 2, y_max_mm = 1.0 /
&case name = 'wr', type = 'wheel_rail', y_mm = 1.0 /
&case name = 'g', type = 'geometry_table', n = 5 /
&case name = 'te', type = 'track_element', n_sleepers = 8, kappa_max = 30.0, mesh_max_area = 4e-4,
      arc_step = 0.012 /
"""


def _datasets(node: h5py.Group) -> dict[str, h5py.Dataset]:
    out: dict[str, h5py.Dataset] = {}
    node.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out


def _text(v) -> str:
    return v.decode() if isinstance(v, bytes) else str(v)


def _problems(group: h5py.Group) -> list[str]:
    """What makes ``group`` not self-describing, one line per dataset or attribute."""
    out = []
    for name, d in _datasets(group).items():
        units = _text(d.attrs.get("units", "")).strip()
        if not units:
            out.append(f"{name}: no units")
        if d.ndim >= 2 and name.split("/")[0] != "inputs":
            axes = d.attrs.get("axes")
            if axes is None or len(axes) != d.ndim:
                out.append(f"{name}: {d.ndim}-D without one label per axis")
        if (
            d.dtype.kind == "f"
            and d.size
            and np.isnan(d[()]).any()
            and not ("empty_slots" in d.attrs or "note" in d.attrs)
        ):
            out.append(f"{name}: NaN without a note on empty slots")
    inputs = group.get("inputs")
    if inputs is not None:
        for key in inputs.attrs:
            d = inputs.get(key)
            if d is None or not _text(d.attrs.get("units", "")).strip() or not d.attrs.get("meaning"):
                out.append(f"inputs attribute {key}: no dataset with its units and meaning")
    return out


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> h5py.File:
    folder = tmp_path_factory.mktemp("units")
    deck = folder / "deck.nml"
    deck.write_text(DECK)
    out = folder / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "-q"]) == 0
    with h5py.File(out, "r") as f:
        yield f


def test_every_dataset_and_input_of_every_case_has_units(results):
    assert len(results) == 7
    problems = {g: _problems(results[g]) for g in results}
    assert not any(problems.values()), {g: p for g, p in problems.items() if p}
    for g in results.values():  # the inputs are there to be checked
        assert len(g["inputs"].attrs) >= 5 and len(_datasets(g["inputs"])) == len(g["inputs"].attrs)


def test_vehicle_states_carry_dof_names_and_column_units(results):
    g = results["001_vh"]
    for k, length, angle in (("q", "m", "rad"), ("v", "m/s", "rad/s")):
        names = [_text(s) for s in g[k].attrs["dof_names"]]
        cols = [_text(s) for s in g[k].attrs["column_units"]]
        assert len(names) == len(cols) == g[k].shape[1] == 53
        assert len(set(names)) == len(names) and set(cols) == {length, angle}
        assert cols[names.index("ws1_y")] == length and cols[names.index("ws1_yaw")] == angle
        assert np.array_equal(g[k][:, names.index("ws1_y")], g["y_ws1" if k == "q" else "vy_ws1"][()])


def test_the_walk_fails_on_a_dataset_without_units(tmp_path):
    """The check itself: a dataset without units, a 2-D one without axes, an undocumented NaN
    and an input attribute without its dataset are each reported."""
    with h5py.File(tmp_path / "bad.h5", "w") as f:
        g = f.create_group("case")
        g["a"] = np.ones(3)
        g["b"] = np.ones((2, 2))
        g["b"].attrs["units"] = "m"
        g["c"] = np.array([1.0, np.nan])
        g["c"].attrs["units"] = "N"
        g.create_group("inputs").attrs["speed"] = 10.0
        p = _problems(g)
    assert p == [
        "a: no units",
        "b: 2-D without one label per axis",
        "c: NaN without a note on empty slots",
        "inputs attribute speed: no dataset with its units and meaning",
    ]


def test_results_saved_from_the_api_have_units(tmp_path):
    """save() of a vehicle run, a rolling result and a ring track element round-trips and
    every dataset it writes has units."""
    from railvti import STEEL, scenarios
    from railvti.contact import Grid
    from railvti.contact.hertz import hertz_gap
    from railvti.contact.normal import solve_normal
    from railvti.contact.rolling import solve_rolling

    g = Grid(16, 16, 4e-4, 4e-4, -3.2e-3, -3.2e-3)
    gap = hertz_gap(g, 1.0, 1.0)
    solve_normal(gap, g, STEEL, fn=1e3)
    objs = {
        "sim": scenarios.hunting(300.0, duration=0.02),
        "rolling": solve_rolling(gap, g, STEEL, 0.3, 1e3, (1e-3, 0.0, 0.0), 10.0),
    }
    for name, obj in objs.items():
        path = save(obj, tmp_path / f"{name}.h5")
        with h5py.File(path, "r") as f:
            missing = [n for n, d in _datasets(f).items() if not _text(d.attrs.get("units", "")).strip()]
        assert not missing, (name, missing)
        assert type(load(path)) is type(obj)


def test_vehicle_charts_name_the_run_and_draw_noise_flat(results):
    """Plots an engineer can read (Deliver 7): the title names scenario, speed, model and
    contact (read back from the stored case), and a history that varies by round-off only is
    drawn flat over at least MIN_SPAN with its value written, without an axis offset."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from railvti.vehicle import cases as vcases
    from railvti.vehicle import plots as vplots

    assert vcases._run_title(results["001_vh"]) == "hunting, 300 km/h, model RR, hertz-kalker on the strips"
    fig, ax = plt.subplots()
    q = 54.546 + 1e-11 * np.sin(np.arange(50))  # kN: a static load with round-off on it
    ax.plot(q)
    vplots._readable(ax, q, "kN")
    lo, hi = ax.get_ylim()
    assert hi - lo >= 2 * vplots.MIN_SPAN["kN"] and lo < 54.546 < hi
    assert ax.yaxis.get_major_formatter().get_useOffset() is False
    assert any("flat y: 54.546 kN" in t.get_text() for t in ax.texts)
    fig2, ax2 = plt.subplots()
    ax2.plot(np.linspace(0, 3, 50))  # a real signal keeps its autoscaled range
    vplots._readable(ax2, np.linspace(0, 3, 50), "mm")
    assert not ax2.texts and ax2.get_ylim()[1] - ax2.get_ylim()[0] < 4
    plt.close("all")
