"""Track deck case types and the rigid track element."""
import numpy as np
import pytest

from railvti.casetypes import REGISTRY, REQUIRED
from railvti.errors import InputError
from railvti.track import RingTrack, TrackElement
import railvti.track.cases  # noqa: F401  (registers the case types)

from test_track_ring import COARSE


def _params(name, **kw):
    p = {k: v for k, v in REGISTRY[name].defaults.items()}
    p.update(n_sleepers=8, **COARSE)
    p.update(kw)
    assert all(v is not REQUIRED for v in p.values())
    return p


def test_receptance_case_runs_and_matches_api():
    out = REGISTRY["track_receptance"].run(_params("track_receptance", f_max=1500.0, n_freq=50))
    f = out.datasets["freq"][0]
    h = out.datasets["vertical_midspan_re"][0] + 1j * out.datasets["vertical_midspan_im"][0]
    ref = RingTrack(8, f_max=1500.0, **COARSE).receptance(f, "vertical", "midspan")
    assert np.allclose(h, ref, rtol=1e-10)
    assert out.scalars["static_vertical_midspan"][0] > 0


def test_receptance_case_rejects_bad_n_freq():
    with pytest.raises(InputError, match="n_freq"):
        REGISTRY["track_receptance"].run(_params("track_receptance", n_freq=1))


def test_track_element_reproduces_static_receptance():
    tr = RingTrack(8, **COARSE)
    e = TrackElement.from_ring(tr)
    for d in ("vertical", "lateral_inphase", "vertical_opposite"):
        assert e.receptance(np.array([0.0]), d)[0].real == pytest.approx(tr.static_modal(d), rel=1e-9)
    # its resonance sits at the ring's first resonance of that pattern
    f = np.linspace(20.0, 400.0, 800)
    fz = np.sqrt(e.stiffness[1] / e.inertia[1]) / (2 * np.pi)
    assert fz == pytest.approx(f[np.argmax(np.abs(tr.receptance(f, "vertical")))], abs=1.0)


def test_track_element_bad_input():
    with pytest.raises(InputError, match="inertia"):
        TrackElement(inertia=(-1.0, 1.0, 1.0), stiffness=(1.0, 1.0, 1.0), damping=(0, 0, 0))
    with pytest.raises(InputError, match="stiffness"):
        TrackElement(inertia=(1.0, 1.0, 1.0), stiffness=(1.0, -1.0, 1.0), damping=(0, 0, 0))


def test_example_deck_keys_are_known():
    from pathlib import Path

    import f90nml

    deck = Path(__file__).resolve().parents[1] / "inputs" / "track_example.nml"
    groups = f90nml.read(deck)["case"]
    groups = groups if isinstance(groups, list) else [groups]
    assert len(groups) == 2
    for g in groups:
        ct = REGISTRY[g["type"]]
        unknown = set(g) - set(ct.defaults) - {"type", "name"}
        assert not unknown, unknown
        missing = [k for k, v in ct.defaults.items() if v is REQUIRED and k not in g]
        assert not missing, missing
