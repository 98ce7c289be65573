"""The disk cache of built tables (railvti._cache; issue 33, docs/sweeps.md "Scaling").

Checked against the tables built without the cache: a loaded contact table, strip geometry
and conicity are the built ones bit for bit, and so is a run on them; a damaged or foreign
entry is ignored (a warning) and rebuilt; writers racing on one entry leave a whole file;
``RAILVTI_CACHE_DIR=""`` turns the cache off. The session's cache folder is a temporary one
(tests/conftest.py).
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from railvti import _cache
from railvti.vehicle import strip as strip_mod
from railvti.vehicle import systems
from railvti.vehicle import table as table_mod

#: A small table (81 positions, 3 roll rows: ~0.2 s) for the cache's paths.
SMALL = dict(y_max=0.002, roll_max=0.00125)
TABLE_ARRAYS = ("y", "data", "s_wheel", "s_own", "roll", "data_roll")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh cache folder of the test's own; the in-memory caches emptied."""
    folder = tmp_path / "cache"
    monkeypatch.setenv(_cache.ENV, str(folder))
    monkeypatch.setattr(table_mod, "_CACHE", {})
    return folder


def _built(monkeypatch, **kw):
    """The small table built with the cache off."""
    monkeypatch.setenv(_cache.ENV, "")
    table_mod._CACHE.clear()
    w, r = systems.profiles()
    out = table_mod.wheel_table(w, r, **kw)
    table_mod._CACHE.clear()
    return out


def _assert_same_table(a, b):
    for name in TABLE_ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert (x.dtype, x.shape, x.strides) == (y.dtype, y.shape, y.strides), name
        assert x.tobytes() == y.tobytes(), name
    for name in ("r0", "n_clipped", "r_nominal", "split"):
        assert repr(getattr(a, name)) == repr(getattr(b, name)), name
    assert a.material == b.material and a.wheel is b.wheel and a.rail is b.rail


def _entries(folder: Path, kind: str) -> list[Path]:
    return sorted(folder.glob(f"{kind}-*.npz"))


def _no_build(*args, **kwargs):
    raise AssertionError("built although the cache holds it")


def test_loaded_table_is_the_built_one_bit_for_bit(cache, monkeypatch):
    built = _built(monkeypatch, **SMALL)
    monkeypatch.setenv(_cache.ENV, str(cache))
    w, r = systems.profiles()
    first = table_mod.wheel_table(w, r, **SMALL)  # built and stored
    assert len(_entries(cache, "wheel_table")) == 1
    table_mod._CACHE.clear()
    monkeypatch.setattr(table_mod, "_build", _no_build)
    loaded = table_mod.wheel_table(w, r, **SMALL)
    assert loaded is not first
    _assert_same_table(built, first)
    _assert_same_table(built, loaded)


def test_key_follows_every_input(cache, monkeypatch):
    w, r = systems.profiles()
    table_mod.wheel_table(w, r, **SMALL)
    table_mod.wheel_table(w, r, y_max=SMALL["y_max"], roll_max=SMALL["roll_max"], step=1e-4)
    other = type(w)(w.y, w.z + 1e-6, kind=w.kind, name=w.name)  # the wheel worn by 1 um
    table_mod.wheel_table(other, r, **SMALL)
    assert len(_entries(cache, "wheel_table")) == 3
    base = _cache.digest("k", w, r, 0.002)
    assert base == _cache.digest("k", w, r, 0.002)
    assert base != _cache.digest("k", w, r, np.nextafter(0.002, 1.0))
    assert base != _cache.digest("k", other, r, 0.002)
    assert base != _cache.digest("k2", w, r, 0.002)
    with pytest.raises(TypeError):
        _cache.digest("k", object())


def _damage(path: Path, how: str) -> None:
    good = path.read_bytes()
    if how == "truncated":
        path.write_bytes(good[: len(good) // 2])
    elif how == "garbage":
        path.write_bytes(b"not an npz file at all" * 100)
    elif how == "flipped":  # one byte of the arrays: the zip's CRC or the checksum sees it
        b = bytearray(good)
        b[len(b) // 2] ^= 0xFF
        path.write_bytes(bytes(b))
    elif how == "pickled":  # this entry's key and format, an object array (a pickle)
        with np.load(path) as z:
            meta = {k: z[k] for k in ("_key", "_format", "_sum")}
        with open(path, "wb") as f:
            np.savez(f, a_y=np.array([object()], dtype=object), **meta)
    elif how == "tampered":  # a valid npz under this key, an array changed, the checksum not
        with np.load(path) as z:
            d = {k: z[k] for k in z.files}
        d["a_data"] = d["a_data"].copy()
        d["a_data"].flat[0] += 1.0
        with open(path, "wb") as f:
            np.savez(f, **d)
    elif how == "foreign":  # a whole entry of another key under this name
        d = {"a_value": np.array(1.0), "_key": np.array("0" * 64), "_format": np.array(1)}
        d["_sum"] = np.array(_cache._checksum({"value": d["a_value"]}))
        with open(path, "wb") as f:
            np.savez(f, **d)


@pytest.mark.parametrize("how", ["truncated", "garbage", "flipped", "pickled", "tampered", "foreign"])
def test_damaged_entry_is_ignored_and_rebuilt(cache, monkeypatch, caplog, how):
    built = _built(monkeypatch, **SMALL)
    monkeypatch.setenv(_cache.ENV, str(cache))
    w, r = systems.profiles()
    table_mod.wheel_table(w, r, **SMALL)
    (path,) = _entries(cache, "wheel_table")
    _damage(path, how)
    table_mod._CACHE.clear()
    with caplog.at_level(logging.WARNING, logger="railvti"):
        again = table_mod.wheel_table(w, r, **SMALL)
    assert any("railvti cache: ignored" in m for m in caplog.messages), caplog.messages
    _assert_same_table(built, again)
    # rewritten whole: the next process loads it
    table_mod._CACHE.clear()
    monkeypatch.setattr(table_mod, "_build", _no_build)
    _assert_same_table(built, table_mod.wheel_table(w, r, **SMALL))


def test_cache_off_and_unwritable(tmp_path, monkeypatch, caplog):
    monkeypatch.setattr(table_mod, "_CACHE", {})
    monkeypatch.setenv(_cache.ENV, "")
    assert _cache.cache_dir() is None
    assert _cache.store("k", "0" * 64, {"x": np.ones(2)}) is None
    assert _cache.load("k", "0" * 64) is None
    blocker = tmp_path / "file"
    blocker.write_text("a file where the folder should be")
    monkeypatch.setenv(_cache.ENV, str(blocker / "cache"))
    w, r = systems.profiles()
    with caplog.at_level(logging.WARNING, logger="railvti"):
        t = table_mod.wheel_table(w, r, **SMALL)
    assert t.data_roll.shape[-1] == 3
    assert any("cannot write" in m for m in caplog.messages)


def test_default_folder_is_the_users_cache(monkeypatch, tmp_path):
    monkeypatch.delenv(_cache.ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    if sys.platform.startswith("linux"):
        assert _cache.cache_dir() == tmp_path / "railvti"
    monkeypatch.setenv(_cache.ENV, "~/elsewhere")
    assert _cache.cache_dir() == Path.home() / "elsewhere"


_WRITER = textwrap.dedent(
    """
    import sys
    import numpy as np
    from railvti import _cache
    key, n = sys.argv[1], int(sys.argv[2])
    payload = {"x": np.arange(1_000_000, dtype=float), "y": np.asfortranarray(np.ones((300, 200)))}
    for _ in range(n):
        assert _cache.store("race", key, payload) is not None
    """
)


def test_concurrent_writers_leave_a_whole_entry(cache, caplog):
    """Two processes write one 8.5 MB entry 15 times each while this one reads it: every read
    is the whole entry or none, never a damaged file."""
    key = "1" * 64
    procs = [
        subprocess.Popen([sys.executable, "-c", _WRITER, key, "15"], env=dict(os.environ)) for _ in range(2)
    ]
    reads = 0
    x = np.arange(1_000_000, dtype=float)
    with caplog.at_level(logging.WARNING, logger="railvti"):
        while any(p.poll() is None for p in procs):
            got = _cache.load("race", key)
            if got is not None:
                reads += 1
                assert np.array_equal(got["x"], x) and got["y"].flags.f_contiguous
    assert all(p.wait(timeout=60) == 0 for p in procs)
    assert not [m for m in caplog.messages if "ignored" in m], caplog.messages
    assert _cache.load("race", key) is not None
    assert not list(cache.glob(".*.tmp"))  # no writer's temporary file left behind


def test_strip_geometry_and_conicity_loaded_bit_for_bit(cache, monkeypatch):
    w, r = systems.profiles()
    monkeypatch.setenv(_cache.ENV, "")
    built = strip_mod.strip_geometry(w, r)
    monkeypatch.setenv(_cache.ENV, str(cache))
    strip_mod.strip_geometry(w, r)
    monkeypatch.setattr(strip_mod, "_build", _no_build)
    loaded = strip_mod.strip_geometry(w, r)
    for name, kind in strip_mod._DISK_FIELDS.items():
        a, b = getattr(built, name), getattr(loaded, name)
        if kind is float:
            assert float(a).hex() == b.hex(), name
        else:
            assert (a.dtype, a.shape, a.strides) == (b.dtype, b.shape, b.strides), name
            assert a.tobytes() == b.tobytes(), name
    monkeypatch.setattr(systems, "_PROFILES", dict(systems._PROFILES))
    systems._PROFILES.pop("conicity", None)
    value = systems.hunting_conicity()  # from the session's cache or built; stored here
    systems._PROFILES.pop("conicity")
    monkeypatch.setattr(systems, "equivalent_conicity", _no_build)
    assert systems.hunting_conicity().hex() == value.hex()
    monkeypatch.undo()
    assert systems.equivalent_conicity(0.003).hex() == value.hex()


_RUN = textwrap.dedent(
    """
    import hashlib, sys, warnings
    from railvti import scenarios
    from railvti.vehicle import strip, systems, table
    if sys.argv[1] == "load":  # a build would fail: the run must read the cache
        def fail(*a, **k):
            raise AssertionError("built although cached")
        table._build = strip._build = systems.equivalent_conicity = fail
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = scenarios.hunting(speed_kmh=400, contact="hertz-fastsim", duration=0.3, y0=0.006)
    h = hashlib.sha256()
    for a in (r.t, r.q, r.v, r.wheel):
        h.update(a.tobytes())
    print(h.hexdigest())
    """
)


@pytest.mark.slow
def test_run_on_a_loaded_table_is_the_built_run_bit_for_bit(tmp_path):
    """A hunting run in a fresh process: without the cache, on a cold cache (built, stored) and
    on the stored tables (nothing built): the same trajectory bit for bit."""

    def run(mode: str, folder: str) -> str:
        env = dict(os.environ, **{_cache.ENV: folder})
        out = subprocess.run(
            [sys.executable, "-c", _RUN, mode], env=env, capture_output=True, text=True, timeout=300
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return out.stdout.strip().splitlines()[-1]

    folder = str(tmp_path / "cache")
    off = run("build", "")
    cold = run("build", folder)
    warm = run("load", folder)
    assert off == cold == warm
    assert {p.name.split("-")[0] for p in Path(folder).glob("*.npz")} == {
        "wheel_table",
        "strip_geometry",
        "conicity",
    }


def test_pruning_keeps_the_newest_entries_within_count_and_bytes(cache, monkeypatch):
    """A kind keeps its most recently written entries, at most MAX_ENTRIES of them and at most
    MAX_BYTES together, the newest always (a ring entry is ~31 MB: a few, not sixteen);
    other kinds are untouched."""
    monkeypatch.setattr(_cache, "MAX_ENTRIES", 3)
    big = np.zeros(40_000)  # 320 kB an entry
    monkeypatch.setattr(_cache, "MAX_BYTES", 700_000)  # two big entries
    _cache.store("other", _cache.digest("other", 0), {"a": np.zeros(3)})
    for i in range(4):
        path = _cache.store("big", _cache.digest("big", i), {"a": big + i})
        os.utime(path, (1e9 + i, 1e9 + i))  # written in order, whatever the clock's resolution
    kept = {
        int(_cache.load("big", _cache.digest("big", i))["a"][0])
        for i in range(4)
        if _cache.load("big", _cache.digest("big", i))
    }
    assert kept == {2, 3}
    monkeypatch.setattr(_cache, "MAX_BYTES", 1 << 40)
    for i in range(4, 8):
        path = _cache.store("small", _cache.digest("small", i), {"a": np.full(3, i)})
        os.utime(path, (1e9 + i, 1e9 + i))
    assert len(_entries(cache, "small")) == 3
    monkeypatch.setattr(_cache, "MAX_BYTES", 1)  # smaller than any entry: the newest stays
    path = _cache.store("big", _cache.digest("big", 9), {"a": big + 9})
    assert _entries(cache, "big") == [path]
    assert len(_entries(cache, "other")) == 1
