"""Deck case type 'rolling': run, HDF5 datasets, plot, semi-axes input, errors."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import railvti.contact.cases  # noqa: F401  (registers the case types)
from railvti.casetypes import REGISTRY, REQUIRED
from railvti.errors import InputError


def _params(**kw):
    ct = REGISTRY["rolling"]
    p = {k: (None if v is REQUIRED else v) for k, v in ct.defaults.items()}
    p.update(
        {
            "nx": 40,
            "ny": 32,
            "dx": 0.2e-3,
            "dy": 0.2e-3,
            "gap_a": 1.087,
            "gap_b": 1.6667,
            "fn": 10e3,
            "mu": 0.3,
            "xi": 1e-3,
            "phi": 0.3,
            "speed": 30.0,
        }
    )
    p.update(kw)
    return p


def test_rolling_case_runs_and_plots(tmp_path: Path):
    ct = REGISTRY["rolling"]
    out = ct.run(_params())
    for name in ("tx", "ty", "slip", "slip_velocity", "power_density", "status", "pressure"):
        assert out.datasets[name][0].shape == (40, 32)
    fx = out.scalars["fx"][0]
    da = 0.2e-3**2
    assert fx == pytest.approx(out.datasets["tx"][0].sum() * da, rel=1e-12)
    assert out.scalars["power"][0] == pytest.approx(out.datasets["power_density"][0].sum() * da, rel=1e-12)
    with h5py.File(tmp_path / "r.h5", "w") as f:
        g = f.create_group("001_case")
        g.attrs["name"] = "case"
        for k, (v, _) in out.datasets.items():
            g.create_dataset(k, data=np.asarray(v))
        for k, (v, _) in out.scalars.items():
            g.create_dataset(k, data=v)
        paths = ct.plot(g, tmp_path, "r")
    assert len(paths) == 1 and paths[0].stat().st_size > 10_000


def test_rolling_case_from_semiaxes():
    out = REGISTRY["rolling"].run(_params(gap_a=None, gap_b=None, semi_a=2.5e-3, semi_b=2.0e-3, xi=0.05))
    p = out.datasets["pressure"][0]
    x = out.datasets["x"][0]
    y = out.datasets["y"][0]
    ii, jj = np.nonzero(p > 0)
    # the contact patch spans about 2a x 2b
    assert (x[ii.max()] - x[ii.min()] + 0.2e-3) == pytest.approx(5.0e-3, rel=0.1)
    assert (y[jj.max()] - y[jj.min()] + 0.2e-3) == pytest.approx(4.0e-3, rel=0.1)
    assert abs(out.scalars["fx"][0]) == pytest.approx(0.3 * 10e3, rel=5e-3)


def test_rolling_case_needs_gap():
    with pytest.raises(InputError, match="semi"):
        REGISTRY["rolling"].run(_params(gap_a=None, gap_b=None))


def test_example_deck_keys():
    import f90nml

    deck = Path(__file__).resolve().parent.parent / "inputs" / "rolling_example.nml"
    groups = f90nml.read(deck)["case"]
    allowed = set(REGISTRY["rolling"].defaults) | {"type", "name"}
    for g in groups:
        assert g["type"] == "rolling"
        assert set(g.keys()) <= allowed
