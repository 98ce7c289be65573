"""Deck case type 'dissimilar_rolling': run, the equal-materials limit against 'rolling',
the bad material keys named, the plot."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import railvti.contact.cases  # noqa: F401  (registers 'rolling')
import railvti.contact.dissimilar_cases  # noqa: F401  (registers 'dissimilar_rolling')
from railvti.casetypes import REGISTRY, REQUIRED, validate
from railvti.errors import InputError


def _params(case: str = "dissimilar_rolling", **kw):
    p = {k: (None if v is REQUIRED else v) for k, v in REGISTRY[case].defaults.items()}
    p.update(
        nx=40, ny=32, dx=0.2e-3, dy=0.2e-3, gap_a=1.087, gap_b=1.6667, fn=10e3, mu=0.3, xi=1e-3, speed=30.0
    )
    p.update(kw)
    return p


def test_equal_materials_give_the_rolling_case():
    out = REGISTRY["dissimilar_rolling"].run(_params())
    ref = REGISTRY["rolling"].run(_params("rolling"))
    assert out.scalars["fx"][0] == ref.scalars["fx"][0]
    assert np.array_equal(out.datasets["tx"][0], ref.datasets["tx"][0])
    assert out.scalars["beta"][0] == 0.0 and out.scalars["outer_iterations"][0] == 1


def test_plane_strain_free_rolling_case(tmp_path: Path):
    """The example deck's Bentall-Johnson case: |xi| near CONTACT's 4.29e-4 (100 elements
    across, 10 mm rows: within 1.5 %), Fx = 0, and its plot."""
    p = _params(
        nx=108, ny=4, dx=2.0e-6, dy=0.01, gap_a=20.0, gap_b=0.0, fn=324.0, mu=0.05, free_rolling=1,
        wheel_shear_modulus=23e9, wheel_poisson=0.31, rail_shear_modulus=82e9, rail_poisson=0.28,
    )  # fmt: skip
    ct = REGISTRY["dissimilar_rolling"]
    out = ct.run(p)
    assert abs(out.scalars["xi"][0]) == pytest.approx(4.29e-4, rel=0.015)
    assert abs(out.scalars["fx"][0]) < 1e-9 * 0.05 * 324.0
    with h5py.File(tmp_path / "d.h5", "w") as f:
        g = f.create_group("001_bj")
        g.attrs["name"] = "bj"
        for k, (v, _) in {**out.datasets, **out.scalars}.items():
            g.create_dataset(k, data=np.asarray(v))
        paths = ct.plot(g, tmp_path, "bj")
    assert paths and paths[0].stat().st_size > 10_000


@pytest.mark.parametrize(
    "key, value",
    [
        ("wheel_shear_modulus", 0.0),
        ("rail_shear_modulus", -82e9),
        ("wheel_poisson", 0.5),
        ("rail_poisson", -1.0),
        ("rail_poisson", 0.7),
    ],
)
def test_bad_material_keys_are_named(key, value):
    with pytest.raises(InputError, match=key):
        validate("dissimilar_rolling", _params(**{key: value}))


def test_plane_strain_needs_the_outer_rows():
    with pytest.raises(InputError, match="ny >= 4"):
        REGISTRY["dissimilar_rolling"].run(_params(ny=3, gap_b=0.0))


_RUN = """
import numpy as np, sys
import railvti.contact.dissimilar_cases  # noqa
from railvti.casetypes import REGISTRY, REQUIRED
p = {k: (None if v is REQUIRED else v) for k, v in REGISTRY["dissimilar_rolling"].defaults.items()}
p.update(nx=40, ny=32, dx=0.3e-3, dy=0.3e-3, gap_a=1.087, gap_b=1.6667, fn=5e3, mu=0.3, xi=1e-3,
         speed=30.0, wheel_shear_modulus=23e9, wheel_poisson=0.31)
ct = REGISTRY["dissimilar_rolling"]
a = ct.run(dict(p))
b = ct.run(dict(p))  # the workspace cached now
np.save(sys.argv[1], np.stack([a.datasets["tx"][0], a.datasets["pressure"][0], b.datasets["tx"][0]]))
"""


@pytest.mark.parametrize("env", [{"OMP_NUM_THREADS": "2"}, {"OPENBLAS_CORETYPE": "Prescott"}])
def test_results_do_not_depend_on_threads_kernels_or_the_cache(tmp_path, env):
    """One thread against two, the default OpenBLAS kernels against Prescott's, and a first
    solve against one on the cached workspace: the same tractions to far below the tolerances."""
    import os
    import subprocess
    import sys

    out = []
    for i, extra in enumerate(({"OMP_NUM_THREADS": "1"}, env)):
        e = dict(os.environ, **extra)
        path = tmp_path / f"r{i}.npy"
        subprocess.run([sys.executable, "-c", _RUN, str(path)], env=e, check=True)
        out.append(np.load(path))
    scale = np.abs(out[0][0]).max()
    assert np.abs(out[0][0] - out[1][0]).max() <= 1e-9 * scale  # threads / kernels
    assert np.abs(out[0][1] - out[1][1]).max() <= 1e-9 * np.abs(out[0][1]).max()
    assert np.abs(out[0][0] - out[0][2]).max() <= 1e-9 * scale  # the cache
