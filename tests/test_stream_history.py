"""Long time histories streamed to HDF5 as the time loop runs (railvti.runner.stream, issue 16 item 4):
a streamed run stores exactly the numbers of a run kept in memory, keeps only its tail in
memory, and a streamed case interrupted (SIGINT) or killed (SIGKILL) under ``railvti run``
leaves a valid results file."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from railvti import scenarios as sc
from railvti.casetypes import HistorySink
from railvti.errors import InputError
from railvti.runner.cli import main
from railvti.runner.stream import STREAM_ENV, HistoryStream

STAT_TIMES = {"stat_wall_time", "stat_real_time_factor"}


def test_a_streamed_run_stores_the_numbers_of_the_run_kept_in_memory(tmp_path):
    full = sc.hunting(300.0, duration=1.0, progress=False)
    path = tmp_path / "stream.h5"
    with HistoryStream(path) as sink:  # the caller's sink, closed by its owner
        tail = sc.hunting(
            300.0, duration=1.0, progress=True, stream_to=sink, stream_tail=0.05, chunk=0.1
        )  # 0.1 s per Fortran call, the tail two calls
    with h5py.File(path, "r") as f:
        g = f["history"]
        for name in ("t", "q", "v", "wheel"):
            assert np.array_equal(g[name][()], getattr(full, name)), name
        assert g.attrs["rows"] == len(full.t)
        assert list(g["q"].attrs["dof_names"]) == list(full.dof_names)
        assert g["t"].attrs["units"] == "s" and g["q"].maxshape[0] is None
    # memory holds only the tail (at least stream_tail seconds), the end of the full run
    n = len(tail.t)
    assert 0.05 <= tail.t[-1] - tail.t[0] and n < len(full.t) // 2
    assert np.array_equal(tail.q, full.q[-n:]) and np.array_equal(tail.wheel, full.wheel[-n:])
    assert tail.streamed == f"{path}::history"
    same = {k: v for k, v in full.stats.items() if k not in ("wall_time", "real_time_factor")}
    assert {k: tail.stats[k] for k in same} == same


def test_a_block_cut_short_leaves_only_whole_rows(tmp_path):
    """A signal between the datasets of one block (here: raised by a derived dataset after
    't' was written): close() cuts every dataset to the rows of the complete blocks."""
    calls = []

    def second(block, attrs):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return 2.0 * block["x"]

    with HistoryStream(tmp_path / "s.h5", store=("t", "x"), derived={"y": second}) as s:
        for k in range(3):
            try:
                s.append({"t": np.arange(k * 5, k * 5 + 5.0), "x": np.ones((5, 3)) * k})
            except KeyboardInterrupt:
                pass
    with h5py.File(tmp_path / "s.h5", "r") as f:
        assert {k: f["history"][k].shape[0] for k in f["history"]} == {"t": 10, "x": 10, "y": 10}
        assert np.array_equal(f["history/y"][()], 2.0 * f["history/x"][()])
        assert np.array_equal(f["history/t"][()], np.arange(10.0))


def _datasets(group: h5py.Group) -> dict[str, h5py.Dataset]:
    out = {}
    group.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out


VEHICLE = """
&case
    name = 'hunt', type = 'vehicle', scenario = 'hunting', duration = 0.6
/
&case
    name = 'run2', type = 'vehicle', scenario = 'centred_running', duration = 0.3
/
"""


def test_a_streamed_deck_case_equals_the_case_kept_in_memory(tmp_path, monkeypatch):
    deck = tmp_path / "deck.nml"
    deck.write_text(VEHICLE)
    import railvti.runner.results as results_mod

    copied = []
    real_copy = results_mod._copy_streamed
    monkeypatch.setattr(
        results_mod, "_copy_streamed", lambda g, n, r, *a: copied.append(n) or real_copy(g, n, r, *a)
    )
    files = {}
    for mode, threshold in (("memory", "none"), ("stream", "0")):
        monkeypatch.setenv(STREAM_ENV, threshold)
        files[mode] = tmp_path / f"{mode}.h5"
        assert main(["run", str(deck), "-o", str(files[mode]), "-q", "--serial"]) == 0
        assert bool(copied) == (mode == "stream")  # the second run streamed
    assert {"t", "q", "v", "y_ws1", "ws_y", "wheel_Q"} <= set(copied)
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    with h5py.File(files["memory"], "r") as a, h5py.File(files["stream"], "r") as b:
        assert set(a) == set(b) == {"001_hunt", "002_run2"}
        for g in a:
            da, db = _datasets(a[g]), _datasets(b[g])
            assert set(da) == set(db)
            for name, d in da.items():
                assert dict(d.attrs).keys() == dict(db[name].attrs).keys(), name
                if name in STAT_TIMES:
                    continue
                assert np.array_equal(d[()], db[name][()], equal_nan=d.dtype.kind == "f"), (g, name)
                for k, v in d.attrs.items():
                    assert np.array_equal(np.asarray(v), np.asarray(db[name].attrs[k])), (g, name, k)


LONG = """
&case
    name = 'first', type = 'normal', gap_a = 1.0, gap_b = 1.0
    nx = 24, ny = 24, dx = 0.3e-3, dy = 0.3e-3, fn = 1.0e4
/
&case
    name = 'long', type = 'vehicle', scenario = 'hunting', duration = 120.0, output_dt = 0.001
/
"""


def _start(tmp_path: Path, **extra_env: str) -> tuple[subprocess.Popen, Path]:
    deck = tmp_path / "deck.nml"
    deck.write_text(LONG)
    out = tmp_path / "out.h5"
    env = dict(os.environ, **{STREAM_ENV: "1M"}, **extra_env)
    proc = subprocess.Popen(
        [sys.executable, "-m", "railvti.runner.cli", "run", str(deck), "-o", str(out), "-q", "--serial"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    return proc, out


def _wait_for_stream(proc: subprocess.Popen, folder: Path, out: Path, timeout: float = 90.0) -> None:
    """Until case 1 is in the file and case 2 has streamed its first blocks."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        tmp = [p for p in folder.iterdir() if p.name.endswith(".tmp")]
        if out.exists() and tmp and tmp[0].stat().st_size > 0:  # the first block is written
            time.sleep(1.0)
            return
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.1)
    proc.kill()
    pytest.fail("the streamed case did not start in time")


def test_an_interrupted_streamed_case_leaves_a_valid_file(tmp_path):
    proc, out = _start(tmp_path)
    _wait_for_stream(proc, tmp_path, out)
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    stopped = time.monotonic() - t0
    assert proc.returncode == 130, (stdout, stderr)
    assert "Traceback" not in stderr
    assert stopped < 5.0
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    with h5py.File(out, "r") as f:
        assert f["001_first"].attrs["status"] == "ok"
        g = f["002_long"]
        assert str(g.attrs["status"]).startswith("interrupted: SIGINT")
        t = g["t"][()]
        assert len(t) > 200 and np.all(np.diff(t) > 0)
        assert t[-1] == pytest.approx(g["stat_interrupted_at"][()])
        for name in ("q", "v", "y_ws1", "wheel_Q"):
            assert g[name].shape[0] == len(t), name
        names = [s.decode() if isinstance(s, bytes) else s for s in g["q"].attrs["dof_names"]]
        assert np.array_equal(g["q"][:, names.index("ws1_y")], g["y_ws1"][()])
        assert g["wheel_Q"].attrs["units"] == "N"
        assert g["q"].compression is None  # copied uncompressed: a prompt stop
    # the kept history is the start of the same run kept in memory
    full = sc.hunting(300.0, duration=float(t[200]) + 1e-9, output_dt=0.001, progress=False)
    with h5py.File(out, "r") as f:
        assert np.array_equal(f["002_long/q"][:201], full.q[:201])


def test_an_interrupted_long_history_keeps_its_first_rows(tmp_path):
    """Beyond the copy budget (here 0.05 MB) an interrupted case keeps the first rows of its
    streamed history, says so, and every streamed dataset keeps the same rows: the stop does
    not wait for a long copy."""
    proc, out = _start(tmp_path, RAILVTI_INTERRUPTED_COPY_MB="0.05")
    _wait_for_stream(proc, tmp_path, out)
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, (stdout, stderr)
    with h5py.File(out, "r") as f:
        g = f["002_long"]
        assert str(g.attrs["status"]).startswith("interrupted: SIGINT")
        kept = str(g.attrs["history_rows_kept"])
        n_kept, n_all = (int(w) for w in re.match(r"(\d+) of (\d+):", kept).groups())
        t = g["t"][()]
        assert len(t) == n_kept < n_all
        assert t[0] <= 0.001 + 1e-12 and np.all(np.diff(t) > 0)  # from the first output on
        assert g["stat_interrupted_at"][()] > t[-1]
        assert g["q"].shape[0] == g["v"].shape[0] == n_kept
        assert g["q"].nbytes + g["v"].nbytes + g["t"].nbytes <= 0.05 * 2**20


def test_sigkill_in_a_streamed_case_leaves_the_previous_valid_file(tmp_path):
    proc, out = _start(tmp_path)
    _wait_for_stream(proc, tmp_path, out)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=30)
    with h5py.File(out, "r") as f:
        assert {k: str(g.attrs["status"]) for k, g in f.items()} == {"001_first": "ok"}
    # the stream file, and at most one file of a write cut short
    assert 1 <= len([p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]) <= 2


def test_a_path_as_stream_to_is_refused_with_the_sink_to_use(tmp_path):
    """The simulation writes to a sink its caller hands in (railvti.casetypes.HistorySink):
    it makes no file itself."""
    with pytest.raises(InputError, match=r"HistoryStream\(path\)"):
        sc.hunting(300.0, duration=0.01, progress=False, stream_to=tmp_path / "s.h5")
    assert not (tmp_path / "s.h5").exists()
    with HistoryStream(tmp_path / "s.h5") as sink:
        assert isinstance(sink, HistorySink)
