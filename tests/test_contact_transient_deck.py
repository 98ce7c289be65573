"""Deck case type 'transient' (kinds shift, rolling, load): runs, theory beside, plot, bad keys."""

from __future__ import annotations

from pathlib import Path

import h5py
import pytest

import railvti.contact.transient_cases  # noqa: F401  (registers the case type)
from railvti.casetypes import REGISTRY, REQUIRED, validate
from railvti.errors import InputError


def _params(**kw):
    ct = REGISTRY["transient"]
    p = {k: (None if v is REQUIRED else v) for k, v in ct.defaults.items()}
    p.update(
        {
            "nx": 28,
            "ny": 24,
            "dx": 0.15e-3,
            "dy": 0.15e-3,
            "gap_a": 10.0,
            "gap_b": 10.0,
            "fn": 10e3,
            "mu": 0.3,
        }
    )
    p.update(kw)
    return p


def test_shift_case_beside_cattaneo_mindlin(tmp_path: Path):
    out = REGISTRY["transient"].run(_params(kind="shift", fx=0.875 * 0.3 * 10e3, steps=2))
    s = out.scalars
    assert s["fx"][0] == pytest.approx(0.875 * 3e3, rel=1e-5)
    assert abs(s["shift_x_total"][0]) == pytest.approx(s["shift_theory"][0], rel=0.01)
    assert s["stick_radius"][0] == pytest.approx(s["stick_radius_theory"][0], rel=0.05)
    _plot(out, tmp_path)


def test_rolling_and_load_cases(tmp_path: Path):
    ct = REGISTRY["transient"]
    a = 1.4877e-3
    out = ct.run(_params(kind="rolling", nx=32, xi=-0.002, speed=30.0, distance=12 * a))
    assert out.scalars["fx"][0] == pytest.approx(out.scalars["steady_fx"][0], rel=1e-4)
    assert 2 * a < out.scalars["distance_99"][0] < 8 * a
    out = ct.run(
        _params(kind="load", nx=32, xi=-0.002, speed=55.0, distance=8 * a, frequency=2000.0, quasi_steady=1)
    )
    assert out.datasets["fx_quasi_steady"][0].shape == out.datasets["fx_history"][0].shape
    assert out.scalars["fx_max_difference"][0] > 0.0
    _plot(out, tmp_path)


def _plot(out, tmp_path):
    with h5py.File(tmp_path / "r.h5", "w") as f:
        g = f.create_group("001_case")
        g.attrs["name"] = "case"
        for k, (v, _) in out.datasets.items():
            g[k] = v
        for k, (v, _) in out.scalars.items():  # the runner stores scalars as datasets
            g[k] = v
        paths = REGISTRY["transient"].plot(g, tmp_path, "case")
    assert all(Path(p).stat().st_size > 1000 for p in paths)


@pytest.mark.parametrize(
    "kw, key",
    [
        (dict(kind="shift", fx=3e3), "fx"),  # mu fn: full sliding
        (dict(kind="rolling", speed=30.0), "distance"),
        (dict(kind="sideways"), "kind"),
        (dict(kind="rolling", distance=0.01, theta=2.0), "theta"),
    ],
)
def test_bad_keys(kw, key):
    with pytest.raises(InputError, match=key):
        validate("transient", _params(**kw))


def test_step_that_skips_the_patch_names_dt():
    with pytest.raises(InputError, match="dt"):
        REGISTRY["transient"].run(
            _params(kind="rolling", nx=32, speed=30.0, distance=0.01, dt=20 * 0.15e-3 / 30)
        )
