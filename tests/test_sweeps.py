"""Sweeps (railvti.runner.sweeps, docs/sweeps.md): the deck declaration, and the same numbers bit for
bit serial, on a LocalCluster and through a scheduler address (a scheduler and two worker
processes started here on 127.0.0.1); a failing point is recorded and the others finish;
``--resume`` after SIGINT runs only the missing points; ``import railvti`` imports no dask."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from railvti.runner.cli import main
from railvti.runner.deck import parse_deck
from railvti.errors import InputError

#: Run statistics that are wall-clock times (not results).
TIMING = {"stat_wall_time", "stat_real_time_factor"}

# Normal contact over fn (the 3rd point's area overflows the grid: GridTooSmallError), and a
# short RR hunting run (Hertz + FASTSIM; each new worker process first builds its contact
# table, a few seconds).
DECK = """
&case
    name = 'hz', type = 'normal'
    gap_a = 1.0, gap_b = 1.5, nx = 24, ny = 24, dx = 0.3e-3, dy = 0.3e-3
    sweep_fn = 1.0e3, 3.0e3, 3.0e4
/
&case
    name = 'hunt', type = 'vehicle', scenario = 'hunting', contact = 'hertz-fastsim'
    duration = 0.3, output_dt = 0.01
    sweep_speed_kmh = 420.0
/
"""


def _dump(path: Path) -> dict:
    """Every dataset and case attribute of a results file but the wall-clock ones."""
    out = {}
    with h5py.File(path, "r") as f:

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and name.rsplit("/", 1)[-1] not in TIMING:
                out[name] = obj[()]

        f.visititems(visit)
        for k, g in f.items():
            for a in ("status", "params_digest", "sweep", "sweep_point"):
                out[f"{k}@{a}"] = g.attrs.get(a)
    return out


def _same(a: dict, b: dict) -> list[str]:
    """Names whose values differ (bit for bit; NaN equal to NaN)."""
    bad = sorted(set(a) ^ set(b))
    for k in set(a) & set(b):
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if x.dtype.kind == "f":
            same = x.shape == y.shape and x.tobytes() == y.tobytes()
        else:
            same = x.shape == y.shape and bool(np.all(x == y))
        if not same:
            bad.append(k)
    return bad


def test_a_sweep_expands_in_deck_order_with_converted_values():
    cases = parse_deck("""
&case
    name = 'p', type = 'vehicle', scenario = 'hunting'
    sweep_range_speed_kmh = 300, 340, 20
    sweep_y0 = 0.006, 0.0005
/
&case
    name = 'z', type = 'normal', gap_a = 1.0, gap_b = 1.0, nx = 8, ny = 8, dx = 1e-3, dy = 1e-3
    sweep = 'zip', sweep_fn = 1e3, 2e3, sweep_tol = 1e-6, 1e-8
/
""")
    assert [c.name for c in cases] == [
        "p.speed_kmh_300.y0_0.006",
        "p.speed_kmh_300.y0_0.0005",
        "p.speed_kmh_320.y0_0.006",
        "p.speed_kmh_320.y0_0.0005",
        "p.speed_kmh_340.y0_0.006",
        "p.speed_kmh_340.y0_0.0005",
        "z.fn_1000.tol_1e-06",
        "z.fn_2000.tol_1e-08",
    ]
    assert [c.index for c in cases] == list(range(1, 9))
    assert cases[2].params["speed"] == pytest.approx(320 / 3.6, rel=1e-15)  # km/h alias -> m/s
    assert cases[2].params["y0"] == 0.006
    assert dict(cases[7].point) == {"fn": 2000.0, "tol": 1e-8} and cases[7].sweep == "z"
    assert cases[7].params["fn"] == 2000.0 and cases[7].params["tol"] == 1e-8


@pytest.mark.parametrize(
    "body, message",
    [
        ("speed_kmh = 300, sweep_speed_kmh = 300, 320", "key 'speed_kmh' is both given and swept"),
        ("sweep = 'zip', sweep_speed_kmh = 300, 320, sweep_y0 = 0.001", "lists of equal length"),
        ("sweep_speeed = 1, 2", "unknown key 'speeed'"),
        ("sweep_range_speed_kmh = 300, 200, 20", "go from start towards stop"),
        ("sweep = 'cross', sweep_y0 = 0.001", "must be one of 'product', 'zip'"),
        ("sweep_speed_kmh = 300, 700", "case 2 'v.speed_kmh_700': key 'speed' = 194.4"),
    ],
)
def test_bad_sweeps_are_refused_before_anything_runs(body, message):
    with pytest.raises(InputError, match=None) as err:
        parse_deck(f"&case name = 'v', type = 'vehicle', {body} /\n")
    assert message in str(err.value)


def test_import_railvti_and_the_serial_path_import_no_dask(tmp_path):
    deck = tmp_path / "d.nml"
    deck.write_text(DECK.split("&case", 2)[1].join(["&case", ""]).replace("3.0e4", "2.0e3"))
    code = f"""
import sys, railvti
from railvti.runner.cli import main
assert main(["run", {str(deck)!r}, "-o", {str(tmp_path / "o.h5")!r}, "-q", "--serial"]) == 0
from railvti import scenarios
from railvti.runner import sweeps
cases = sweeps.sweep("normal", dict(gap_a=1.0, gap_b=1.0, nx=16, ny=16, dx=3e-4, dy=3e-4),
                     {{"fn": [1e3, 2e3]}})
recs = sweeps.run(cases)
assert [r.status for r in recs] == ["ok", "ok"], [r.status for r in recs]
bad = sorted(m for m in sys.modules if m.split(".")[0] in ("dask", "distributed"))
assert not bad, bad
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """A Dask scheduler on 127.0.0.1 and two single-threaded worker processes (the way a
    cluster of machines is started: docs/sweeps.md); yields its address."""
    folder = tmp_path_factory.mktemp("dask")
    sfile = folder / "scheduler.json"
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", TQDM_DISABLE="1")
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "dask",
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(sfile),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    ]
    try:
        t0 = time.monotonic()
        while not sfile.exists() and time.monotonic() - t0 < 60:
            time.sleep(0.1)
        address = json.loads(sfile.read_text())["address"]
        procs.append(
            subprocess.Popen(
                [
                    sys.executable,
                    "-m",
                    "dask",
                    "worker",
                    address,
                    "--nworkers",
                    "2",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                ],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                env=env,
                cwd=folder,
            )
        )
        from distributed import Client

        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=60)
        yield address
        from distributed import Client

        with Client(address, timeout=10) as c:
            c.shutdown()  # the scheduler closes its workers, then itself
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


@pytest.mark.slow
def test_serial_local_cluster_and_scheduler_give_the_same_bits(tmp_path, scheduler, capsys):
    deck = tmp_path / "sweep.nml"
    deck.write_text(DECK)
    runs = {"serial": ["--serial"], "local": ["--workers", "2"], "scheduler": ["--scheduler", scheduler]}
    files = {}
    for what, opts in runs.items():
        files[what] = tmp_path / f"{what}.h5"
        # the failing point is recorded, the others finish: exit status 1 (some failed)
        assert main(["run", str(deck), "-o", str(files[what]), "-q", *opts]) == 1, what
    out = capsys.readouterr().out
    assert "LocalCluster of 2 worker processes" in out and f"scheduler {scheduler} with 2 workers" in out
    ref = _dump(files["serial"])
    assert ref["003_hz.fn_30000@status"].startswith("error: GridTooSmallError")
    ok = [k for k in ref if k.endswith("@status") and ref[k] == "ok"]
    assert len(ok) == 3 and "004_hunt.speed_kmh_420/y_ws1" in ref
    for what in ("local", "scheduler"):
        assert _same(ref, _dump(files[what])) == [], what
    with h5py.File(files["scheduler"], "r") as f:
        assert "GridTooSmallError" in f["003_hz.fn_30000"].attrs["traceback"]
        assert json.loads(f["004_hunt.speed_kmh_420"].attrs["sweep_point"]) == {"speed_kmh": 420.0}
    # railvti plot: each point of these small sweeps, and one summary plot per sweep
    png = tmp_path / "png"
    assert main(["plot", str(files["scheduler"]), "-o", str(png)]) == 0
    names = {p.name for p in png.iterdir()}
    assert {
        "scheduler_hz_sweep.png",
        "scheduler_hunt_phase.png",
        "scheduler_001_hz.fn_1000_pressure.png",
    } <= names, names
    assert not any(n.startswith("scheduler_003_") for n in names)  # the failed point
    capsys.readouterr()
    assert main(["summary", str(files["scheduler"]), "--plots", str(png)]) == 0
    text = capsys.readouterr().out
    assert "4 cases, 3 ok, 1 not" in text and "*_sweep.png (1)" in text and "*_pressure.png (2)" in text


@pytest.mark.filterwarnings("ignore:bifurcation. below:RuntimeWarning")
def test_bifurcation_on_a_client_equals_its_serial_independent_sweep(scheduler):
    from railvti import scenarios

    kw = dict(contact="hertz-kalker", duration=1.2, v_min_kmh=300.0, progress=False)
    serial = scenarios.bifurcation([340.0, 300.0], independent=True, **kw)
    dist = scenarios.bifurcation([340.0, 300.0], client=scheduler, independent=True, **kw)
    for name in ("speeds_kmh", "upper", "decay"):
        assert np.array_equal(getattr(serial, name), getattr(dist, name)), name
    assert serial.details["flange_force"].tobytes() == dist.details["flange_force"].tobytes()
    assert serial.upper[0] > 0 and serial.speeds_kmh.tolist() == [300.0, 340.0]


# Two CG points (fast) and two Gauss-Seidel points (2-3 s each on a fast machine, where 100 x
# 100 elements took 0.75 s and both finished before the signal) on a 140 x 140 grid.
DX, DY = 0.09e-3, 0.072e-3
SLOW = f"""
&case
    name = 'gs', type = 'normal', gap_a = 1.087, gap_b = 1.6667
    nx = 140, ny = 140, dx = {DX}, dy = {DY}, tol = 1e-9
    sweep = 'zip', sweep_method = 'cg', 'cg', 'gs', 'gs', sweep_fn = 1.0e4, 1.1e4, 1.2e4, 1.3e4
/
"""


def _statuses(path: Path) -> dict[str, str]:
    try:
        with h5py.File(path, "r") as f:
            return {k: str(g.attrs["status"]) for k, g in f.items()}
    except OSError:
        return {}


def test_resume_after_sigint_on_the_cluster_runs_only_the_missing_points(tmp_path):
    deck = tmp_path / "slow.nml"
    deck.write_text(SLOW)
    out = tmp_path / "out.h5"
    cmd = [
        sys.executable,
        "-m",
        "railvti.runner.cli",
        "run",
        str(deck),
        "-o",
        str(out),
        "-q",
        "--workers",
        "2",
    ]
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    fast = {"001_gs.method_cg.fn_10000", "002_gs.method_cg.fn_11000"}
    t0 = time.monotonic()
    while time.monotonic() - t0 < 90 and not fast <= set(_statuses(out)):
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    time.sleep(0.3)
    t_sig = time.monotonic()
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    stopped = time.monotonic() - t_sig
    assert proc.returncode == 130, stdout + stderr
    assert "--resume" in stdout
    st = _statuses(out)
    assert {k: st[k] for k in fast} == {k: "ok" for k in fast}
    # the points the workers were running are marked, as the serial path marks its case (a
    # Gauss-Seidel point may end before the signal on a quiet machine: it is then complete)
    running = {k: v for k, v in st.items() if k not in fast}
    interrupted = {k for k, v in running.items() if v.startswith("interrupted: SIGINT")}
    assert interrupted and all(v == "ok" for k, v in running.items() if k not in interrupted), st
    assert stopped < 3.0  # the workers are killed, not waited for (about 0.9 s here)
    done = {k for k, v in st.items() if v == "ok"}
    with h5py.File(out, "r") as f:
        walls = {k: f[k].attrs["wall_time"] for k in done}
    r = subprocess.run(cmd + ["--resume"], capture_output=True, text=True, timeout=180)
    assert r.returncode == 0, r.stdout + r.stderr
    assert f"resume: {len(done)} of 4 cases already complete" in r.stdout
    for k in sorted(st):
        ran = f"case {int(k[:3])} 'gs." in r.stdout
        assert ran == (k in interrupted), (k, r.stdout)
    st = _statuses(out)
    assert st == {k: "ok" for k in fast | {"003_gs.method_gs.fn_12000", "004_gs.method_gs.fn_13000"}}
    with h5py.File(out, "r") as f:
        assert {k: f[k].attrs["wall_time"] for k in done} == walls  # kept, not re-run
        p = f["004_gs.method_gs.fn_13000/pressure"][()]
        assert p.sum() * DX * DY == pytest.approx(1.3e4, rel=1e-9)
    assert not [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


def _profiler_enabled() -> bool:
    import dask

    return bool(dask.config.get("distributed.worker.profile.enabled"))


@pytest.mark.filterwarnings("ignore:bifurcation. below:RuntimeWarning")
def test_a_client_never_changes_the_bifurcation():
    """The same call with and without a LocalCluster returns the same bits: the
    continuation (its upper branch one sequential task, here extended below the sweep from
    340 to 300 km/h because the cycle lives at 340) and the independent sweep alike. The
    independent upper branch differs from the continuation's (a coexisting cycle): the
    client does not imply it. The table geometry keeps the workers' set-up short; the code
    path is the strip's too."""
    from railvti import scenarios
    from railvti.runner.sweeps import local_client

    kw = dict(contact="hertz-kalker", geometry="table", duration=0.3, v_min_kmh=300.0, progress=False)
    serial = {ind: scenarios.bifurcation([380.0, 340.0], independent=ind, **kw) for ind in (False, True)}
    import dask

    mine = dask.config.get("distributed.worker.profile.enabled", None)
    with local_client(2) as c:
        dist = {
            ind: scenarios.bifurcation([380.0, 340.0], independent=ind, client=c, **kw)
            for ind in (False, True)
        }
        # the workers run without Dask's statistical profiler (WORKER_CONFIG); this process's
        # settings are its own
        assert list(c.run(_profiler_enabled).values()) == [False, False]
    assert dask.config.get("distributed.worker.profile.enabled", None) == mine
    for ind in (False, True):
        a, b = serial[ind], dist[ind]
        for name in ("speeds_kmh", "upper", "decay"):
            assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), (ind, name)
        assert a.details["flange_force"].tobytes() == b.details["flange_force"].tobytes()
        assert a.speeds_kmh.tolist() == [300.0, 340.0, 380.0]  # 300: the extension
    assert serial[False].upper[0] > 0 and serial[False].upper[0] != serial[True].upper[0]


@pytest.mark.parametrize(
    "address, message",
    [
        ("tcp://127.0.0.1:1", r"'tcp://127.0.0.1:1': no Dask scheduler reachable at 127.0.0.1:1"),
        ("tcp://127.0.0.1", r"'tcp://127.0.0.1': malformed scheduler address"),
        ("http://127.0.0.1:8786", r"'http://127.0.0.1:8786': malformed scheduler address"),
    ],
)
def test_an_unreachable_client_is_an_input_error_within_seconds(address, message):
    from railvti import scenarios

    t0 = time.monotonic()
    with pytest.raises(InputError, match=message):
        scenarios.bifurcation([380.0, 340.0], client=address, progress=False)
    assert time.monotonic() - t0 < 5.0
    with pytest.raises(InputError, match="client must be a distributed.Client"):
        scenarios.critical_speed(method="nonlinear", speeds_kmh=[380.0, 340.0], client=42)
