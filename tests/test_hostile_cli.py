"""Hostile uses of the ``railvti`` command (issue 31, items 3 and 5, share of item 9).

Outcome classes, by group (the counts are the parametrized cases):

* **refused clearly** (exit 2 or argparse's usage error, one line naming the option, file
  or address and what is expected, no traceback, nothing written): bad ``--workers``,
  ``--max-memory`` sizes, unknown or clashing options, a missing / directory / empty /
  binary / non-deck deck, malformed ``--scheduler`` addresses (refused at once, before Dask
  is imported), unreachable or non-Dask schedulers (within 5 s).
* **one-line failure** (a case that fails with each railvti.errors class, or with an
  unexpected exception: one console line with class, case and message, exit 1, the other
  cases run, the traceback in the results file; the traceback on the console only with
  ``--debug``), and errors raised outside the cases (exit 2 for railvti's, 1 plus a hint for
  others).
* **handled edge case** (a closed stdout for each subcommand: exit 0 or 141, no traceback,
  no "Exception ignored"; ``run`` completes its file).
* **stopped by signal** (SIGINT / SIGTERM while the deck is read, the output is checked or
  the cluster starts: exit 130 / 143, one line saying nothing ran, the output untouched).

Most cases run ``railvti.runner.cli.main`` in this process; the broken pipes run a few child
processes (a real pipe is needed).
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import h5py
import pytest

from railvti import errors
from railvti.runner import cli
from railvti.runner.deck_registry import case_types
from railvti.casetypes import REGISTRY, CaseOutput, CaseType
from railvti.runner.cli import main
from railvti.errors import InputError
from railvti.runner.sweeps import scheduler_address

CASE = """
&case
    name = '{name}', type = 'normal'
    gap_a = 1.0, gap_b = 1.0
    nx = 32, ny = 32, dx = 0.25e-3, dy = 0.25e-3
    fn = 1.0e4
/
"""


def _deck(tmp_path: Path, text: str | None = None) -> Path:
    deck = tmp_path / "deck.nml"
    deck.write_text(CASE.format(name="a") + CASE.format(name="b") if text is None else text)
    return deck


def _no_traceback(captured) -> str:
    text = captured.out + captured.err
    assert "Traceback" not in text and "Exception ignored" not in text, text
    return text


# ---------------------------------------------------------------------------------------------
# refused clearly: options


@pytest.mark.parametrize("workers", ["0", "-1", "-100"])
def test_workers_below_one_are_refused_before_the_deck_is_read(tmp_path, capsys, workers):
    out = tmp_path / "out.h5"
    missing = tmp_path / "missing.nml"  # not read: the option is refused first
    assert main(["run", str(missing), "-o", str(out), "--workers", workers]) == 2
    err = _no_traceback(capsys.readouterr())
    assert f"--workers must be at least 1, got {workers}" in err
    assert not out.exists()


@pytest.mark.parametrize("workers", ["two", "1.5", "", "2x", "1e3"])
def test_workers_not_an_integer_is_a_usage_error(tmp_path, capsys, workers):
    with pytest.raises(SystemExit) as exc:
        main(["run", str(_deck(tmp_path)), "--workers", workers])
    assert exc.value.code == 2
    err = _no_traceback(capsys.readouterr())
    assert "--workers" in err and "invalid int value" in err


@pytest.mark.parametrize(
    "size", ["lots", "-1G", "0", "1e400", "nan", "5Q", "", "  ", "8 GB extra", "-inf", "0.0M", "G"]
)
def test_bad_memory_sizes_are_refused(tmp_path, capsys, size):
    out = tmp_path / "out.h5"
    assert main(["run", str(_deck(tmp_path)), "-o", str(out), "--serial", f"--max-memory={size}"]) == 2
    err = _no_traceback(capsys.readouterr())
    assert "--max-memory" in err or "memory size" in err, err
    assert not out.exists()
    assert os.environ.get("RAILVTI_MAX_MEMORY") is None  # restored


@pytest.mark.parametrize("size", ["8G", "none", "512M", "1e12", "inf"])
def test_good_memory_sizes_run(tmp_path, capsys, size):
    out = tmp_path / "out.h5"
    assert main(["run", str(_deck(tmp_path)), "-o", str(out), "-q", "--serial", f"--max-memory={size}"]) == 0
    _no_traceback(capsys.readouterr())
    with h5py.File(out, "r") as f:
        assert sorted(f) == ["001_a", "002_b"]


@pytest.mark.parametrize(
    "argv, words",
    [
        (["run", "DECK", "--wrokers", "2"], "unrecognized arguments: --wrokers"),
        (["run", "DECK", "--frobnicate"], "unrecognized arguments: --frobnicate"),
        (["run", "DECK", "-x"], "unrecognized arguments: -x"),
        (["run", "DECK", "--serial", "--workers", "2"], "not allowed with argument"),
        (["run", "DECK", "--scheduler", "tcp://h:1", "--workers", "2"], "not allowed with argument"),
        (["run", "DECK", "--serial", "--scheduler", "tcp://h:1"], "not allowed with argument"),
        (["run"], "the following arguments are required: deck"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
        ([], "the following arguments are required"),
        (["run", "DECK", "--workers"], "expected one argument"),
        (["run", "DECK", "--max-memory"], "expected one argument"),
        (["cases", "normal", "extra"], "unrecognized arguments: extra"),
    ],
)
def test_unknown_or_clashing_options_are_usage_errors(tmp_path, capsys, argv, words):
    deck = str(_deck(tmp_path))
    with pytest.raises(SystemExit) as exc:
        main([deck if a == "DECK" else a for a in argv])
    assert exc.value.code == 2
    err = _no_traceback(capsys.readouterr())
    assert words in err and "usage:" in err


# ---------------------------------------------------------------------------------------------
# refused clearly: decks


def _bad_deck(tmp_path: Path, kind: str) -> tuple[Path, str]:
    p = tmp_path / "deck.nml"
    if kind == "missing":
        return p, "cannot read deck"
    if kind == "directory":
        p.mkdir()
        return p, "cannot read deck"
    if kind == "empty":
        p.write_bytes(b"")
    elif kind == "binary":
        p.write_bytes(bytes(range(256)) * 8)
    elif kind == "nul bytes":
        p.write_bytes(CASE.format(name="a").encode() + b"\0\0\0")
    elif kind == "hdf5 file":
        with h5py.File(p, "w") as f:
            f["x"] = 1.0
    elif kind == "comments only":
        p.write_text("! nothing here\n! at all\n")
    elif kind == "truncated":
        p.write_text(CASE.format(name="a")[:60])
    elif kind == "latin-1 garbage":
        p.write_bytes("&case name='\xe9\xe8', type='normal' /\n".encode("latin-1"))
    return p, ""


@pytest.mark.parametrize(
    "kind",
    [
        "missing",
        "directory",
        "empty",
        "binary",
        "nul bytes",
        "hdf5 file",
        "comments only",
        "truncated",
        "latin-1 garbage",
    ],
)
def test_a_bad_deck_file_is_one_line_and_nothing_written(tmp_path, capsys, kind):
    deck, words = _bad_deck(tmp_path, kind)
    out = tmp_path / "out.h5"
    assert main(["run", str(deck), "-o", str(out), "--serial"]) == 2
    err = _no_traceback(capsys.readouterr())
    assert err.startswith("railvti: error:") and "deck" in err, err
    assert words in err
    assert not out.exists()
    assert not list(tmp_path.glob("*.tmp"))


# ---------------------------------------------------------------------------------------------
# refused clearly: scheduler addresses (at once, before Dask)

MALFORMED = [
    "notanaddress",
    "tcp://",
    "tcp://host",
    "tcp://:8786",
    "tcp://host:port",
    "tcp://host:0",
    "tcp://host:65536",
    "tcp://host:-1",
    "http://host:8786",
    "tcp://a b:8786",
    "tcp://host:8786/path",
    "tcp://[::1",
    "tcp://::1:8786",
    "",
    " ",
    "tcp://host:8786?x=1",
    "udp://h:1",
    "tcp://h:1.5",
    "ftp://h:21",
    "host:",
    ":8786",
    "tcp://h:\uff18\uff17\uff18\uff16",
    "tcp://h\u00e9:8786",
    "tcp://[zz]:8786",
    "inproc://",
]


@pytest.mark.parametrize("address", MALFORMED)
def test_a_malformed_scheduler_is_refused_at_once_naming_it(tmp_path, capsys, address):
    out = tmp_path / "out.h5"
    t0 = time.monotonic()
    assert main(["run", str(_deck(tmp_path)), "-o", str(out), "--scheduler", address]) == 2
    assert time.monotonic() - t0 < 1.0
    err = _no_traceback(capsys.readouterr())
    assert f"--scheduler {address!r}: malformed scheduler address" in err
    assert "tcp://host:port" in err and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize(
    "address, parsed",
    [
        ("tcp://10.0.0.5:8786", ("tcp", "10.0.0.5", 8786)),
        ("h:1", ("tcp", "h", 1)),
        ("TLS://node-1.cluster:443", ("tls", "node-1.cluster", 443)),
        ("tcp://[::1]:8786", ("tcp", "::1", 8786)),
        ("inproc://10.0.0.1/1234/1", ("inproc", "10.0.0.1/1234/1", 0)),
    ],
)
def test_well_formed_addresses_parse(address, parsed):
    assert scheduler_address(address) == parsed


def test_a_scheduler_address_that_is_not_a_text_is_refused():
    with pytest.raises(InputError, match="a int, not a text"):
        scheduler_address(8786)


@contextlib.contextmanager
def _listener(reply: bytes | None):
    """A TCP port on 127.0.0.1 that accepts and then says ``reply`` (None: nothing, ever)."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(16)
    stop = threading.Event()

    def serve() -> None:
        srv.settimeout(0.1)
        conns = []
        while not stop.is_set():
            try:
                c, _ = srv.accept()
            except OSError:
                continue
            conns.append(c)
            if reply is not None:
                c.sendall(reply)
                c.close()
        for c in conns:
            c.close()

    t = threading.Thread(target=serve, daemon=True)
    t.start()
    try:
        yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    finally:
        stop.set()
        t.join(2)
        srv.close()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("kind", ["refused", "silent", "http", "garbage", "unknown host"])
def test_an_unreachable_or_foreign_scheduler_fails_within_5_s_naming_it(tmp_path, capsys, kind):
    replies = {
        "silent": None,
        "http": b"HTTP/1.1 400 Bad Request\r\ncontent-length: 0\r\n\r\n",
        "garbage": os.urandom(64),
    }
    with contextlib.ExitStack() as stack:
        if kind in replies:
            address = stack.enter_context(_listener(replies[kind]))
        elif kind == "refused":
            address = f"tcp://127.0.0.1:{_free_port()}"
        else:
            address = "tcp://no-such-host.invalid:8786"
        out = tmp_path / "out.h5"
        t0 = time.monotonic()
        assert main(["run", str(_deck(tmp_path)), "-o", str(out), "-q", "--scheduler", address]) == 2
        took = time.monotonic() - t0
    err = _no_traceback(capsys.readouterr())
    assert took < 5.0, took
    assert f"--scheduler {address!r}: no Dask scheduler" in err and err.count("\n") == 1, err
    assert not out.exists()


# ---------------------------------------------------------------------------------------------
# one-line failures: each railvti.errors class in a case, and unexpected ones


def _error_classes() -> list[type]:
    case_types()  # every case type's module loaded: all their error classes
    import railvti.contact.kalker  # noqa: F401

    out, todo = [], [errors.RailvtiError]
    while todo:
        cls = todo.pop()
        out.append(cls)
        todo.extend(cls.__subclasses__())
    return sorted(set(out), key=lambda c: c.__name__)


EXPECTED = _error_classes()
UNEXPECTED = [KeyError, ZeroDivisionError, MemoryError, RuntimeError, TypeError, AssertionError]


@pytest.fixture
def raising_type(monkeypatch):
    """A case type 'raises' whose run raises the class named by its key 'what', with a
    two-line message (only the first may reach the console for an unexpected one)."""
    classes = {c.__name__: c for c in EXPECTED + UNEXPECTED}

    def run(params):
        cls = classes[params["what"]]
        if params["what"] == "KeyError":
            raise KeyError("no such key")
        raise cls(f"{params['what']} in key 'fn' = 3\nsecond line")

    def ok(params):
        return CaseOutput(summary="fine", scalars={"x": (1.0, "1")})

    monkeypatch.setitem(REGISTRY, "raises", CaseType(name="raises", defaults={"what": ""}, run=run))
    monkeypatch.setitem(REGISTRY, "fine", CaseType(name="fine", defaults={}, run=ok))


def _failing_deck(tmp_path: Path, what: str) -> Path:
    return _deck(
        tmp_path, f"&case name='bad', type='raises', what='{what}' /\n&case name='good', type='fine' /\n"
    )


def _run_failing(tmp_path: Path, capsys, caplog, cls: type, debug: bool) -> tuple[Path, str, list[str]]:
    """Run the deck whose first case raises ``cls``: the file, the console's text, its FAILED lines."""
    caplog.set_level(logging.DEBUG if debug else logging.WARNING, logger="railvti.traceback")
    out = tmp_path / "out.h5"
    argv = ["run", str(_failing_deck(tmp_path, cls.__name__)), "-o", str(out), "-q", "--serial"]
    assert main(argv + (["--debug"] if debug else [])) == 1
    captured = capsys.readouterr()
    text = captured.out + captured.err
    return out, text, [ln for ln in text.splitlines() if "FAILED" in ln]


@pytest.mark.parametrize("debug", [False, True], ids=["plain", "debug"])
@pytest.mark.parametrize("cls", EXPECTED, ids=lambda c: c.__name__)
def test_an_expected_failure_is_one_line_and_the_traceback_only_with_debug(
    tmp_path, capsys, caplog, raising_type, cls, debug
):
    out, text, lines = _run_failing(tmp_path, capsys, caplog, cls, debug)
    assert lines == [f"case 1 'bad': FAILED: {cls.__name__}: {cls.__name__} in key 'fn' = 3; second line"], (
        text
    )
    assert "\nsecond line" not in text
    assert "unexpected" not in text
    assert ("Traceback" in caplog.text) == debug and "Traceback" not in text
    with h5py.File(out, "r") as f:
        assert f["002_good"].attrs["status"] == "ok"
        assert "Traceback" in f["001_bad"].attrs["traceback"]  # always in the file


@pytest.mark.parametrize("debug", [False, True], ids=["plain", "debug"])
@pytest.mark.parametrize("cls", UNEXPECTED, ids=lambda c: c.__name__)
def test_an_unexpected_failure_is_one_line_with_a_hint(tmp_path, capsys, caplog, raising_type, cls, debug):
    out, text, lines = _run_failing(tmp_path, capsys, caplog, cls, debug)
    assert len(lines) == 1 and lines[0].startswith(f"case 1 'bad': FAILED: {cls.__name__}: "), text
    assert "unexpected" in lines[0] and "--debug" in lines[0]
    assert ("Traceback" in caplog.text) == debug and "Traceback" not in text
    with h5py.File(out, "r") as f:
        assert "Traceback" in f["001_bad"].attrs["traceback"]


@pytest.mark.parametrize("debug", [False, True], ids=["plain", "debug"])
@pytest.mark.parametrize(
    "exc, code, words",
    [
        (InputError("deck 'x': key 'fn' = -1 is outside (0, inf)"), 2, "railvti: error: deck 'x': key 'fn'"),
        (errors.GridTooSmallError("grid too small\nsecond line"), 2, "railvti: error: grid too small"),
        (KeyError("boom"), 1, "railvti: unexpected error: KeyError: 'boom' (a bug; run again with --debug"),
        (RuntimeError("first\nsecond"), 1, "railvti: unexpected error: RuntimeError: first (a bug"),
    ],
)
def test_an_error_outside_the_cases_is_one_line(
    tmp_path, capsys, caplog, monkeypatch, exc, code, words, debug
):
    caplog.set_level(logging.DEBUG if debug else logging.WARNING, logger="railvti.traceback")
    import railvti.runner.deck

    def read_deck(path):
        raise exc

    monkeypatch.setattr(railvti.runner.deck, "read_deck", read_deck)
    assert main(["run", str(_deck(tmp_path)), "--serial"] + (["--debug"] if debug else [])) == code
    err = _no_traceback(capsys.readouterr())
    assert err.startswith(words), err
    assert "second" not in err or isinstance(exc, InputError)
    assert ("Traceback" in caplog.text) == debug


# ---------------------------------------------------------------------------------------------
# handled edge case: a closed stdout


class _ClosedPipe:
    """A stdout whose reader went away."""

    def write(self, text: str) -> int:
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self) -> None:
        raise BrokenPipeError(32, "Broken pipe")

    def fileno(self) -> int:
        raise OSError("no descriptor")


@pytest.mark.parametrize("argv", [["cases"], ["cases", "vehicle"], ["summary", "OUT"], ["plot", "OUT"]])
def test_a_closed_stdout_in_process_is_quiet(tmp_path, capsys, monkeypatch, argv):
    out = tmp_path / "res.h5"
    if "OUT" in argv:
        assert main(["run", str(_deck(tmp_path)), "-o", str(out), "-q", "--serial"]) == 0
        capsys.readouterr()
    monkeypatch.setattr(sys, "stdout", _ClosedPipe())
    code = main([str(out) if a == "OUT" else a for a in argv])
    monkeypatch.undo()
    assert code == cli.EXIT_SIGPIPE
    _no_traceback(capsys.readouterr())


def test_a_run_with_a_closed_stdout_completes_its_file(tmp_path, capsys, monkeypatch):
    out = tmp_path / "res.h5"
    monkeypatch.setattr(sys, "stdout", _ClosedPipe())
    code = main(["run", str(_deck(tmp_path)), "-o", str(out), "-q", "--serial"])
    monkeypatch.undo()
    assert code == 0
    _no_traceback(capsys.readouterr())
    with h5py.File(out, "r") as f:
        assert [f[k].attrs["status"] for k in sorted(f)] == ["ok", "ok"]


@pytest.mark.parametrize(
    "argv", [["cases"], ["cases", "normal"], ["--help"], ["run", "--help"], ["run", "DECK", "--serial"]]
)
def test_a_closed_pipe_for_a_real_process_is_quiet(tmp_path, argv):
    """``railvti ... | head -1``: the reader closes after one line."""
    deck = _deck(tmp_path)
    cmd = [sys.executable, "-m", "railvti.runner.cli", *[str(deck) if a == "DECK" else a for a in argv]]
    if "run" in argv and "--help" not in argv:
        cmd += ["-o", str(tmp_path / "res.h5")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.readline()
    proc.stdout.close()
    err = proc.stderr.read()
    code = proc.wait(timeout=60)
    assert code in (0, cli.EXIT_SIGPIPE), err
    assert "Traceback" not in err and "Exception ignored" not in err and "BrokenPipe" not in err, err
    if "run" in argv and "--help" not in argv:
        assert code == 0
        with h5py.File(tmp_path / "res.h5", "r") as f:
            assert sorted(f) == ["001_a", "002_b"]


# ---------------------------------------------------------------------------------------------
# stopped by signal, before any case


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize(
    "where",
    [
        "reading the deck",
        "checking the output",
        "starting the cluster",
        "an import (as ImportError)",
        "the cluster's imports (as ImportError)",
    ],
)
def test_a_signal_before_any_case_stops_with_one_line(tmp_path, capsys, monkeypatch, sig, where):
    import railvti.runner.batch
    import railvti.runner.deck
    from railvti.runner import sweeps

    out = tmp_path / "out.h5"
    deck = _deck(tmp_path)
    fired = []

    def send() -> None:
        fired.append(True)
        try:
            os.kill(os.getpid(), sig)
            time.sleep(1.0)  # the handler raises here, within the first tick
        except KeyboardInterrupt:
            if "ImportError" in where:  # as a C extension's module init reports it
                raise ImportError("initialization failed") from None
            raise
        pytest.fail("the signal did not stop the start-up")

    if where in ("reading the deck", "an import (as ImportError)"):
        real = railvti.runner.deck.read_deck
        monkeypatch.setattr(railvti.runner.deck, "read_deck", lambda p: (send(), real(p))[1])
    elif where == "checking the output":
        monkeypatch.setattr(railvti.runner.batch, "check_output", lambda *a, **k: send())
    else:

        @contextlib.contextmanager
        def local_client(n):
            send()
            yield None

        monkeypatch.setattr(sweeps, "local_client", local_client)
    t0 = time.monotonic()
    code = main(["run", str(deck), "-o", str(out), "-q", "--workers", "2"])
    assert time.monotonic() - t0 < 1.0
    assert fired and code == 128 + sig
    err = _no_traceback(capsys.readouterr())
    name = signal.Signals(sig).name
    assert err.count("\n") == 1 and f"stopped by {name}" in err
    assert "no case ran" in err or "before any case ran" in err
    assert not out.exists()
    assert signal.getsignal(signal.SIGINT) is not cli._raise_signal  # handlers restored


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_at_cluster_start_leaves_an_existing_file_unchanged(tmp_path, capsys, monkeypatch, sig):
    from railvti.runner import sweeps

    out = tmp_path / "out.h5"
    deck = _deck(tmp_path)
    assert main(["run", str(deck), "-o", str(out), "-q", "--serial"]) == 0
    before = out.read_bytes()
    capsys.readouterr()

    @contextlib.contextmanager
    def local_client(n):
        os.kill(os.getpid(), sig)
        time.sleep(1.0)
        yield None

    monkeypatch.setattr(sweeps, "local_client", local_client)
    assert main(["run", str(deck), "-o", str(out), "-q", "--workers", "2", "--resume"]) == 128 + sig
    err = _no_traceback(capsys.readouterr())
    assert f"stopped by {signal.Signals(sig).name} while the Dask cluster started" in err
    assert f"{out} is unchanged" in err
    assert out.read_bytes() == before
