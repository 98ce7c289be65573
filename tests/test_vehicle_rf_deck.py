"""Model RF in decks and results (issue 15, deliverable 4): the 'vehicle' case type takes
model = 'RF' with n_sleepers, f_limit, x_offset and the ring's parameters (track_*); the HDF5
results hold the ring's modal coordinates with their labels and the rail's motion under each
wheel, with units; SimulationResult.save / result_objects.load carry the same. A tiny case (coarse
40-sleeper ring, 20 ms) run end to end through `railvti run` and read back."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from railvti import scenarios
from railvti.casetypes import REGISTRY
from railvti.runner.cli import main
from railvti.errors import InputError
from railvti.runner.result_objects import load, save
from railvti.vehicle import cases as vehicle_cases  # registers the case type "vehicle"
from railvti.vehicle import systems
from coarse_ring import COARSE

RING = dict(n_sleepers=40, f_limit=300.0, x_offset=0.1, **{f"track_{k}": v for k, v in COARSE.items()})
DECK = """
&case
    type = 'vehicle'
    name = 'rf_centred'
    scenario = 'centred_running'
    model = 'RF'
    speed_kmh = 200.0
    duration = 0.02
    n_sleepers = 40
    f_limit = 300.0
    x_offset = 0.1
    track_kappa_max = 30.0
    track_mesh_max_area = 4e-4
    track_arc_step = 0.012
    track_f_max = 500.0
/
"""
FF = DECK.replace("rf_centred", "ff_centred").replace(
    "model = 'RF'", "model = 'FF'\n    k_max = 1\n    f_max = 300.0"
)
HUNTING = """
&case
    type = 'vehicle'
    name = 'rf_hunting'
    scenario = 'hunting'
    model = 'RF'
    speed_kmh = 300.0
    duration = 0.02
    output_dt = 0.002
    y0 = 0.003
    n_sleepers = 40
    f_limit = 300.0
    track_kappa_max = 30.0
    track_mesh_max_area = 4e-4
    track_arc_step = 0.012
    track_f_max = 500.0
/
"""


def _deck(**kw):
    p = dict(REGISTRY["vehicle"].defaults)
    p.update(kw)
    return p


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    d = tmp_path_factory.mktemp("rfdeck")
    (d / "rf.nml").write_text(DECK + HUNTING + FF)
    out = d / "rf.h5"
    assert main(["run", str(d / "rf.nml"), "-o", str(out), "-q", "--serial"]) == 0
    return out


def test_deck_case_stores_ring_modes_and_rail_deflection(results):
    """The ring's modal coordinates with the system's labels (the kept modes <= f_limit, then
    24 residual coordinates), and the rail deflection under each wheel: the same as
    RingSystem.rail_deflection of the stored states (computed here from the Python API's
    system), the crown under every wheel pressed down by a few tenths of a mm."""
    sy = scenarios.rf_system(speed_kmh=200.0, n_sleepers=40, f_limit=300.0, x_offset=0.1, track_params=COARSE)
    n0 = sy.n_state - sy.ring.n_modes - sy.ring.n_residual
    with h5py.File(results, "r") as f:
        g = f["001_rf_centred"]
        assert str(g.attrs["status"]) == "ok"
        r = g["results"] if "results" in g else g
        labels = [x.decode() if isinstance(x, bytes) else str(x) for x in r["mode_label"][()]]
        assert labels == list(sy.state_names[n0:])
        assert list(r["modal_q"].attrs["mode_label"]) == labels
        mq = r["modal_q"][()]
        freq = r["mode_frequency"][()]
        nk = sy.ring.n_modes
        assert r["mode_frequency"].attrs["units"] == "Hz"
        assert np.all(freq[:nk] <= 300.0) and np.all(np.isnan(freq[nk:]))
        assert int(np.asarray(r["n_ring_modes"]) if "n_ring_modes" in r else r.attrs["n_ring_modes"]) == nk
        assert np.all(r["mode_group"][()][:nk] >= 0) and np.all(r["mode_group"][()][nk:] == -1)
        t, q = r["t"][()], r["q"][()]
        np.testing.assert_array_equal(mq, q[:, n0:])
        rail = r["rail_deflection"][()]
        assert rail.shape == (t.size, 3, 2, 4)
        assert list(r["rail_deflection"].attrs["column_units"]) == ["m", "m", "rad"]
        crown = r["rail_crown_z"][()]
        assert r["rail_crown_z"].attrs["units"] == "m"
    np.testing.assert_allclose(rail, sy.rail_deflection(t, q), rtol=1e-10, atol=1e-15)
    assert np.all(crown < -1e-4) and np.all(crown > -2e-3)
    np.testing.assert_allclose(crown[:, 0], crown[:, 1], rtol=1e-6)  # mirror symmetry


def test_hunting_deck_case_on_the_ring(results):
    """The hunting scenario with model RF from a deck: the leading wheelset shifted by y0 on
    the ring, the rail under its wheels pushed laterally (not mirror-symmetric), datasets
    labelled as in centred running."""
    with h5py.File(results, "r") as f:
        g = f["002_rf_hunting"]
        assert str(g.attrs["status"]) == "ok"
        r = g["results"] if "results" in g else g
        rail = r["rail_deflection"][()]
        crown = r["rail_crown_z"][()]
        y = r["ws_y"][()]
        assert r["modal_q"].shape[0] == rail.shape[0] == y.shape[0] == crown.shape[0]
    assert abs(y[0, 0] - 0.003) < 2e-4
    assert np.all(crown < 0)  # pressed down
    assert np.max(np.abs(rail[:, 0, 0] + rail[:, 0, 1])) > 1e-8  # no longer a mirror image


def test_simulation_result_saves_and_loads_the_rail(tmp_path):
    """SimulationResult of model RF: ``rail`` is RingSystem.rail_deflection of its states;
    save / load returns it equal, with the ring coordinates' names in dof_names."""
    c = scenarios.centred_running(
        200.0, variant="RF", duration=0.01, n_sleepers=40, f_limit=300.0, track_params=COARSE, progress=False
    )
    run = c.run
    assert run.rail is not None and run.rail.shape == (run.t.size, 3, 2, 4)
    np.testing.assert_allclose(run.rail, c.rail, rtol=1e-12, atol=0)
    back = load(save(run, tmp_path / "rf.h5"))
    np.testing.assert_array_equal(back.rail, run.rail)
    assert back.dof_names == run.dof_names and any(n.startswith("ring_g") for n in back.dof_names)
    with h5py.File(tmp_path / "rf.h5", "r") as f:
        assert list(f["result/rail"].attrs["component"]) == ["y", "z", "roll"]
        assert "m, m, rad" in f["result/rail"].attrs["units"]


def test_rr_result_has_no_rail():
    run = scenarios.centred_running(200.0, duration=0.005, progress=False).run
    assert run.rail is None


def test_model_choices_follow_scenarios():
    assert REGISTRY["vehicle"].keys["model"].choices == scenarios.VARIANTS


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(n_sleepers=30), "n_sleepers = 30.*too short for the coach"),
        (dict(track_pad_stiffness_vertical=-2e8), "track_pad_stiffness_vertical"),
        (dict(f_limit=-5.0), "f_limit"),
        (dict(model="FR"), "keys of the ring track"),
        (dict(model="RR"), "keys of the ring track"),
    ],
)
def test_bad_ring_keys_refused_before_running(kw, match):
    """Checked with the deck, before any ring is built."""
    p = _deck(model="RF", scenario="centred_running", duration=0.01, **RING)
    p.update(kw)
    with pytest.raises(InputError, match=match):
        REGISTRY["vehicle"].validate(p)


def test_bad_ring_deck_exits_2_naming_the_problem(tmp_path, capsys):
    deck = tmp_path / "bad.nml"
    deck.write_text(
        DECK.replace("n_sleepers = 40", "n_sleepers = 30")
        + DECK.replace("rf_centred", "rf_pad").replace(
            "track_f_max = 500.0", "track_f_max = 500.0\n    track_pad_stiffness_vertical = -1e8"
        )
    )
    assert main(["run", str(deck), "-o", str(tmp_path / "o.h5"), "-q", "--serial"]) == 2
    err = capsys.readouterr().err
    assert "case 1 'rf_centred'" in err and "too short for the coach" in err
    assert "case 2 'rf_pad'" in err and "track_pad_stiffness_vertical" in err


def test_truncation_without_track_modes_in_a_deck(tmp_path, capsys):
    """f_limit below the ring's lowest mode: the case fails with the InputError that says so
    (it needs the ring's modes, so it is found when the case runs)."""
    deck = tmp_path / "low.nml"
    deck.write_text(DECK.replace("f_limit = 300.0", "f_limit = 1.0"))
    out = tmp_path / "o.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 1
    assert "no ring mode at or below f_limit = 1.0 Hz" in capsys.readouterr().out
    with h5py.File(out, "r") as f:
        assert str(next(iter(f.values())).attrs["status"]).startswith("error: InputError")


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: scenarios.rf_system(speed_kmh=200.0, n_sleepers=30), "too short for the coach"),
        (
            lambda: scenarios.rf_system(speed_kmh=200.0, n_sleepers=40, f_limit=1.0, track_params=COARSE),
            "no ring mode at or below f_limit",
        ),
        (
            lambda: scenarios.rf_system(speed_kmh=200.0, n_sleepers=40, f_limit=0.0, track_params=COARSE),
            "f_limit",
        ),
        (
            lambda: scenarios.centred_running(
                200.0,
                variant="RF",
                n_sleepers=40,
                duration=0.01,
                track_params={**COARSE, "pad_stiffness_vertical": -2e8},
            ),
            "pad_stiffness_vertical",
        ),
        (
            lambda: scenarios.centred_running(
                200.0,
                variant="RF",
                n_sleepers=40,
                duration=0.01,
                track_params={**COARSE, "pad_stiffness_lateral": -1.0},
            ),
            "pad_stiffness_lateral",
        ),
    ],
)
def test_bad_ring_input_from_the_api(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_ff_deck_case_stores_wheelset_and_ring_modes(results):
    """Model FF from a deck: the wheelsets' modal coordinates (labels 'ws<i>_k...', the rims'
    camber) and the ring's (prefixed 'ring_', labels 'ring_g...'), split where the system's
    state splits; the rails pressed down under every wheel, the rims' camber positive."""
    sy, _ = scenarios.ff_system(
        speed_kmh=200.0, k_max=1, f_max=300.0, n_sleepers=40, f_limit=300.0, x_offset=0.1, track_params=COARSE
    )
    nr = sy.ring.n_modes + sy.ring.n_residual
    with h5py.File(results, "r") as f:
        grp = f["003_ff_centred"]
        assert str(grp.attrs["status"]) == "ok", grp.attrs.get("error")
        g = grp["results"] if "results" in grp else grp
        wl = [x.decode() if isinstance(x, bytes) else x for x in g["mode_label"][()]]
        rl = [x.decode() if isinstance(x, bytes) else x for x in g["ring_mode_label"][()]]
        assert len(rl) == nr and all(x.startswith("ring_") for x in rl)
        assert len(wl) == sy.n_state - sy.n - nr and wl[0].startswith("ws1_k")
        assert g["modal_q"].shape[1] == len(wl) and g["ring_modal_q"].shape[1] == nr
        assert np.all(g["rail_crown_z"][-1] < 0)
        assert np.all(g["rim_camber_change"][-1] > 0)
        # the relative angle: the camber minus the rail head's roll, read from the ring's
        # rail_deflection (-roll left, +roll right: the inner edge rising)
        roll = g["rail_deflection"][-1, 2] * np.array([-1.0, 1.0])[:, None]
        np.testing.assert_allclose(g["rail_head_roll"][-1], roll, rtol=0, atol=1e-15)
        np.testing.assert_allclose(
            g["rim_rail_angle_change"][-1], g["rim_camber_change"][-1] - roll, rtol=0, atol=1e-15
        )
        assert g["rim_rail_angle_change"].attrs["units"] == "rad"


def test_a_deck_run_labels_its_modes_with_the_system_it_ran(monkeypatch):
    """The run hands back its system: a ring hunting case builds the RF system once (the run
    itself), not again to label the ring's modes (counted at the builder)."""
    built = []
    build_rf = systems.build_rf

    def counting(*args, **kw):
        built.append(args[3] if len(args) > 3 else kw.get("v"))
        return build_rf(*args, **kw)

    monkeypatch.setattr(systems, "build_rf", counting)
    out = vehicle_cases.run(
        _deck(
            scenario="hunting",
            model="RF",
            speed=300.0 / 3.6,
            duration=0.02,
            output_dt=0.002,
            y0=0.003,
            n_sleepers=40,
            f_limit=300.0,
            **{f"track_{k}": v for k, v in COARSE.items()},
        )
    )
    assert len(built) == 1
    assert "ring_modal_q" in out.datasets or "modal_q" in out.datasets
    assert out.scalars["speed_kmh"][0] == 300.0
