"""Deck case type 'subsurface': run, HDF5 datasets, plot, the depth grid's bad input."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import railvti.contact.subsurface_cases  # noqa: F401  (registers the case type)
from railvti.casetypes import REGISTRY, REQUIRED
from railvti.errors import InputError


def _params(**kw):
    ct = REGISTRY["subsurface"]
    p = {k: (None if v is REQUIRED else v) for k, v in ct.defaults.items()}
    # a sphere of R = 50 mm on a flat (gap (x^2 + y^2) / 2R), 2 kN: a = 0.86 mm
    p.update({"nx": 41, "ny": 41, "dx": 0.06e-3, "dy": 0.06e-3, "gap_a": 10.0, "gap_b": 10.0, "fn": 2e3})
    p.update({"poisson": 0.3, "z_min": 0.04e-3, "z_max": 0.64e-3, "nz": 16})
    p.update(kw)
    return p


def test_subsurface_case_runs_writes_and_plots(tmp_path: Path):
    ct = REGISTRY["subsurface"]
    out = ct.run(_params())
    assert out.datasets["stress"][0].shape == (41, 41, 16, 6)
    assert out.datasets["von_mises"][0].shape == (41, 41, 16)
    p0, a = out.scalars["hertz_p0"][0], out.scalars["hertz_a"][0]
    # Hertz (Johnson 1985, eq. 3.45): 0.620 p0 at 0.481 a; depth steps of 0.04 mm
    assert out.scalars["max_von_mises"][0] / p0 == pytest.approx(0.620, rel=0.01)
    assert out.scalars["max_von_mises_z"][0] / a == pytest.approx(0.481, abs=0.05)
    with h5py.File(tmp_path / "r.h5", "w") as f:
        g = f.create_group("001_case")
        g.attrs["name"] = "case"
        for k, (v, _) in out.datasets.items():
            g.create_dataset(k, data=np.asarray(v))
        paths = ct.plot(g, tmp_path, "r")
    assert len(paths) == 1 and paths[0].stat().st_size > 10_000


def test_sliding_and_rolling_tractions():
    ct = REGISTRY["subsurface"]
    base = ct.run(_params(nz=6))
    slid = ct.run(_params(nz=6, traction="sliding", mu=0.3))
    assert slid.scalars["max_von_mises"][0] > base.scalars["max_von_mises"][0]
    roll = ct.run(_params(nz=6, traction="rolling", mu=0.3, xi=-2e-3, speed=20.0))
    rail = roll.scalars["max_von_mises"][0]
    wheel = ct.run(_params(nz=6, traction="rolling", mu=0.3, xi=-2e-3, speed=20.0, body="wheel"))
    # the rail carries -(tx, ty), the wheel (tx, ty): not mirror images (the traction of
    # rolling is not symmetric in x), both above the frictionless maximum
    assert wheel.scalars["max_von_mises"][0] > base.scalars["max_von_mises"][0]
    assert rail > base.scalars["max_von_mises"][0]
    assert wheel.scalars["max_von_mises"][0] != pytest.approx(rail, rel=1e-3)


@pytest.mark.parametrize(
    "kw, key", [({"z_min": 0.0}, "z_min"), ({"z_min": -1e-4}, "z_min"), ({"z_max": -1e-3}, "z_max")]
)
def test_depth_grid_outside_half_space_names_the_key(kw, key):
    with pytest.raises(InputError, match=key):
        REGISTRY["subsurface"].run(_params(**kw))


def test_depth_grid_inverted():
    with pytest.raises(InputError, match="z_max"):
        REGISTRY["subsurface"].run(_params(z_min=0.5e-3, z_max=0.1e-3))
