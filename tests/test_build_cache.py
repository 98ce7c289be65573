"""The ring track's and the FE wheelset's builds on disk (railvti._cache.Recorder; issue 33,
docs/vehicle_contact.md "FF with the BEM: the whole call").

Checked against the builds with the cache off (``RAILVTI_CACHE_DIR=""``): a replayed ring
track (rail reduced basis, wave bases, every cyclic group's eigenvectors, degenerate pairs
included) and a replayed flexible wheelset (each harmonic's ARPACK modes, the FE statics'
terms) are the built ones bit for bit, every array and number of the objects, while the
eigen-solvers are not called at all; a call whose inputs differ from the recorded ones runs,
and the entry is rewritten.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from railvti import _cache
from railvti.track import ring as ring_mod
from railvti.track.ring import RingTrack
from coarse_ring import COARSE_SECTION as COARSE

V = 300.0 / 3.6


def _same(a, b, path="obj", depth=0):
    """Assert a and b hold the same values bit for bit (arrays: dtype, shape, strides, bytes)."""
    assert type(a) is type(b), path
    if isinstance(a, np.ndarray):
        assert (a.dtype, a.shape, a.strides) == (b.dtype, b.shape, b.strides), path
        assert a.tobytes() == b.tobytes(), path
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]", depth)
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            _same(a[k], b[k], f"{path}[{k!r}]", depth)
    elif isinstance(a, (bool, int, float, str, complex, np.generic)) or a is None:
        assert repr(a) == repr(b), path
    elif depth < 3 and hasattr(a, "__dict__"):
        fields = (
            {f.name for f in dataclasses.fields(a)} if dataclasses.is_dataclass(a) else set(vars(a))
        ) - {"build_time"}
        for k in sorted(fields):
            _same(getattr(a, k), getattr(b, k), f"{path}.{k}", depth + 1)


def _refuse(*args, **kwargs):
    raise AssertionError("an eigen-solve ran although the cache holds it")


class _NoSolve:
    """railvti's core with the ring's eigen-solvers refused (the section matrices allowed)."""

    def __getattr__(self, name):
        if name in ("track_reduced_basis_c", "track_wave_basis_c", "track_group_modes_c"):
            return _refuse
        return getattr(ring_mod._native_core, name)


def test_replayed_ring_is_the_built_one_bit_for_bit(tmp_path, monkeypatch):
    monkeypatch.setenv(_cache.ENV, "")
    off = RingTrack(8, **COARSE)
    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    first = RingTrack(8, **COARSE)  # built and stored
    assert len(list(tmp_path.glob("ring-*.npz"))) == 1
    monkeypatch.setattr(ring_mod, "_native_core", ring_mod.core, raising=False)
    monkeypatch.setattr(ring_mod, "core", _NoSolve())
    loaded = RingTrack(8, **COARSE)
    # the groups hold degenerate pairs (families 1 and 2 of one wave number): their
    # eigenvectors are whatever the solver returned, replayed exactly
    assert np.any(np.isclose(np.diff(np.sort(loaded.lam)), 0.0, atol=1e-9 * loaded.lam.max()))
    _same(off, first, "built")
    _same(off, loaded, "loaded")
    # another input: built (the refusing core raises), not replayed
    with pytest.raises(AssertionError, match="eigen-solve ran"):
        RingTrack(8, pad_stiffness_vertical=250e6, **COARSE)


#: A fresh process: a flexible wheelset built (or replayed) at a speed, the sha256 over
#: every array and number it holds, and how many ARPACK solves and FE statics ran.
CHILD = textwrap.dedent(
    """
    import dataclasses, hashlib, json, sys
    import numpy as np
    from railvti.wheelset import fe, flexible, statics
    from railvti.wheelset.model import Wheelset
    n = {"modes": 0, "statics": 0}
    def counted(name, f):
        def g(*a, **k):
            n[name] += 1
            return f(*a, **k)
        return g
    fe._modes_call = counted("modes", fe._modes_call)
    flexible.harmonic_statics = counted("statics", flexible.harmonic_statics)
    h = hashlib.sha256()
    def feed(x, depth=0):
        if isinstance(x, np.ndarray):
            h.update(repr((x.dtype.str, x.shape, x.strides)).encode() + x.tobytes())
        elif isinstance(x, (list, tuple)):
            for y in x:
                feed(y, depth)
        elif dataclasses.is_dataclass(x) and depth < 3:
            for f in dataclasses.fields(x):
                feed(getattr(x, f.name), depth + 1)
        else:
            h.update(repr(x).encode())
    feed(Wheelset().flexible_body(float(sys.argv[1]), k_max=1, f_max=300.0))
    print(json.dumps({"sha": h.hexdigest(), **n}))
    """
)


def _child(cache: str, speed: float = V) -> dict:
    env = dict(os.environ, **{_cache.ENV: cache})
    p = subprocess.run([sys.executable, "-c", CHILD, repr(speed)], capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_replayed_wheelset_is_the_built_one_bit_for_bit(tmp_path):
    # each build in a fresh process, as a new user's run (a harmonic solved twice in one
    # process is the same bit for bit: test_wheelset_model.py)
    off = _child("")
    first = _child(str(tmp_path))  # built and stored
    assert len(list(tmp_path.glob("wheelset-modes-*.npz"))) == 2  # harmonics 0 and 1
    assert len(list(tmp_path.glob("wheelset-statics-*.npz"))) == 1
    loaded = _child(str(tmp_path))
    assert off["modes"] >= 2 and first["modes"] == off["modes"] and off["statics"] > 0
    assert (loaded["modes"], loaded["statics"]) == (0, 0)  # nothing solved
    assert off["sha"] == first["sha"] == loaded["sha"]
    # another speed: the modes and statics do not depend on it, replayed as well
    fast = _child(str(tmp_path), 1.5 * V)
    assert (fast["modes"], fast["statics"]) == (0, 0) and fast["sha"] == _child("", 1.5 * V)["sha"]


def test_recorder_runs_a_call_whose_inputs_changed(tmp_path, monkeypatch):
    monkeypatch.setenv(_cache.ENV, str(tmp_path))
    ran = []

    def f(x):
        ran.append(x)
        return np.arange(3.0) * x, int(x), float(x) / 3

    rec = _cache.Recorder("test-rec", "k")
    a = [rec.call("f", f, 1.0), rec.call("f", f, 2.0)]
    rec.finish()
    rec = _cache.Recorder("test-rec", "k")
    b = [rec.call("f", f, 1.0), rec.call("f", f, 5.0)]  # the second call's input changed
    rec.finish()
    assert ran == [1.0, 2.0, 5.0] and (rec.replayed, rec.ran) == (1, 1)
    _same(a[0], b[0])
    assert b[1][1] == 5 and type(b[1][1]) is int and b[1][2] == 5.0 / 3
    rec = _cache.Recorder("test-rec", "k")  # the rewritten entry: both replayed
    c = [rec.call("f", f, 1.0), rec.call("f", f, 5.0)]
    assert ran == [1.0, 2.0, 5.0] and rec.replayed == 2
    _same(b, c)
    monkeypatch.setenv(_cache.ENV, "")  # off: every call runs, nothing is written
    rec = _cache.Recorder("test-rec", "k")
    rec.call("f", f, 1.0)
    rec.finish()
    assert ran[-1] == 1.0 and len(ran) == 4
