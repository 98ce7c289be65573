"""Decks with model = 'FR' (issue 14 item 5): every vehicle scenario takes it, with k_max and
f_max; the HDF5 results hold the modal coordinates with their mode labels and the rims'
deformation at the contact points, each with a units attribute."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from railvti import scenarios
from railvti.runner.cli import main
from railvti.vehicle.flexible_points import rim_deformation

DECK = """
&case
    type = 'vehicle'
    name = 'fr_hunting'
    scenario = 'hunting'
    model = 'FR'
    k_max = 1
    f_max = 300.0
    speed_kmh = 300.0
    duration = 0.04
    output_dt = 0.002
/
&case
    type = 'vehicle'
    name = 'fr_sweep'
    scenario = 'critical_speed'
    model = 'FR'
    k_max = 0
    f_max = 300.0
    speeds_kmh_min = 220.0
    speeds_kmh_max = 380.0
    speeds_kmh_step = 160.0
    duration = 1.1
/
"""


def _group(f, name):
    return next(g for g in f.values() if g.attrs["name"] == name)


def _text(x):
    x = x[()] if hasattr(x, "shape") else x
    return x.decode() if isinstance(x, bytes) else str(x)


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    d = tmp_path_factory.mktemp("frdeck")
    deck = d / "fr.nml"
    deck.write_text(DECK)
    out = d / "fr.h5"
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    return out


def test_hunting_case_stores_labelled_modes_and_rim_deformation(results):
    with h5py.File(results, "r") as f:
        g = _group(f, "fr_hunting")
        assert g["modal_q"].attrs["units"].startswith("kg^0.5 m")
        labels = [x.decode() if isinstance(x, bytes) else str(x) for x in g["mode_label"][()]]
        k, fam = (
            g["mode_k"][()],
            [x.decode() if isinstance(x, bytes) else str(x) for x in g["mode_family"][()]],
        )
        freq = g["mode_frequency"][()]
        assert g["mode_frequency"].attrs["units"] == "Hz" and g["mode_k"].attrs["units"] == "1"
        modal_q, q, t = g["modal_q"][()], g["q"][()], g["t"][()]
        rim = g["rim_deformation"][()]
        angle = g["rim_rail_angle_change"][()]
        camber = g["rim_camber_change"][()]
        assert "rail_head_roll" not in g  # FR: the rigid track's head does not roll
        assert g["rim_deformation"].attrs["units"] and g["rim_rail_angle_change"].attrs["units"] == "rad"
        dof_names = [x.decode() if isinstance(x, bytes) else str(x) for x in g["q"].attrs["dof_names"]]
    # the labels: the mode set of the FR system at 300 km/h with k <= 1 up to 300 Hz
    sy, lay = scenarios.fr_system(speed_kmh=300.0, k_max=1, f_max=300.0)
    assert modal_q.shape == (t.size, sy.modal.n_modes) and len(labels) == sy.modal.n_modes
    assert dof_names[sy.n :] == list(sy.modal.names)
    np.testing.assert_array_equal(modal_q, q[:, sy.n :])
    for j, lab in enumerate(labels):
        if k[j] < 0:
            assert "residual" in lab and fam[j] == "residual" and np.isnan(freq[j])
        else:
            assert lab.split("_")[1].startswith(f"k{k[j]}{'' if fam[j] == '0' else fam[j]}")
            assert 60.0 < freq[j] <= 300.0
    assert set(np.unique(k)) == {-1, 0, 1}
    # the stored rim deformation is the modal state through the rim rows (u = Phi Q)
    np.testing.assert_allclose(rim, rim_deformation(sy, q), rtol=1e-12, atol=1e-15)
    # statically loaded rims: camber raises each tread's inner edge by 0.3-2 mrad
    assert np.all(angle[0] > 3e-4) and np.all(angle[0] < 2e-3)
    # FR's rigid rail: the relative angle is the camber, -drx left and +drx right
    np.testing.assert_array_equal(angle, camber)
    np.testing.assert_allclose(camber, rim[:, 2] * np.array([-1.0, 1.0])[:, None], rtol=1e-12)


def test_sweep_case_runs_fr_with_its_steps(results):
    with h5py.File(results, "r") as f:
        g = _group(f, "fr_sweep")
        kmh, step = g["speeds_kmh"][()], g["step"][()]
        assert g["speeds_kmh"].attrs["units"] == "km/h" and g["step"].attrs["units"] == "s"
        lin = float(g["critical_speed_linear"][()])
        model = _text(g["model"])
        assert int(g["k_max"][()]) == 0 and float(g["f_max"][()]) == 300.0
    assert kmh.tolist()[-2:] == [220.0, 380.0]
    sy, _ = scenarios.fr_system(speed_kmh=380.0, k_max=0, f_max=300.0)
    assert step.shape == kmh.shape and np.all(step * sy.modal.max_frequency() <= 2.0 + 1e-9)
    assert model == "FR"
    assert 250.0 < lin < 400.0
