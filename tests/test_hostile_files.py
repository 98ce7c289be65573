"""Hostile files, disks and locks for ``railvti run`` (issue 31, items 1, 2 and 9).

Outcome classes of the cases (121 in all), counted in the closing note of issue 31:

* refused clearly (InputError / exit 2, naming the file or the other run, nothing written),
  39: ``test_output_path_refused`` (17 output paths of every kind),
  ``test_output_in_a_read_only_folder_is_refused``, ``test_other_deck_refused`` (8: another
  deck's file, plain and --resume), ``test_other_deck_of_another_type_refused``,
  ``test_damaged_results_file_refused`` (4), ``test_live_lock_refused`` (5: a second
  concurrent writer), ``test_lock_cannot_be_created``,
  ``test_two_concurrent_cli_runs_the_second_refused``, ``test_sweeps_run_refused_by_a_live_lock``;
* handled edge cases (exit 0 / the documented behaviour), 55: ``test_output_path_handled``
  (8), the symlinked output, the default output beside a stale .tmp,
  ``test_force_replaces_other_deck`` (2), ``test_same_deck_accepted`` (14), the deck digest,
  ``test_damaged_results_file_forced`` (8), ``test_stale_lock_taken_over`` (6), a killed
  holder's lock, ``test_lock_behaviour`` (6), the lock held while cases run, a stream copied,
  ``test_guarded_file`` (4), HDF5 through a GuardedFile;
* stopped by a signal (raised after HDF5 returns, the file sound), 4:
  ``test_signal_inside_a_stream_write`` (3), ``test_signal_inside_save``;
* exit 3 (the file cannot be written: one line, the cases written before kept and exactly
  the ones reported, no ``.tmp``, no lock, no traceback, no "Exception ignored"), 23:
  ``test_write_error_exit_3`` (9: ENOSPC, EDQUOT, EIO, EFBIG, EROFS at the first, second and
  third case, short writes), ``test_write_error_exit_3_os_calls`` (5: fsync, rename, temp
  file creation, the --resume copy, truncate), ``test_stream_write_error_exit_3`` (4: the
  stream file's first and later blocks, its close, its copy), ``test_api_write_error`` (2),
  ``test_sweeps_run_raises_on_a_write_error`` (2), a record refused twice.

Every case also asserts: no "Traceback" in the output, no NaN in a result of exit 0, no
temporary file left, subprocesses under a timeout.
"""

from __future__ import annotations

import errno
import json
import os
import shutil
import socket
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pytest

from railvti.runner import guarded_io, result_objects, results
from railvti.runner.batch import check_deck, check_output
from railvti.casetypes import REGISTRY, CaseOutput, CaseType
from railvti.runner.cli import main
from railvti.runner.deck import parse_deck
from railvti.errors import InputError
from railvti.runner.guarded_io import GuardedFile, WriteFailed, open_h5
from railvti.runner.output_lock import OutputLock, lock_path
from railvti.runner.stream import STREAM_ENV, HistoryStream, case_stream

SMALL = """
&case
    name = '{name}', type = '{type}'
    gap_a = 1.0, gap_b = 1.0
    nx = 24, ny = 24, dx = 0.3e-3, dy = 0.3e-3
    fn = 1e4
/
"""


def deck_text(*names: str, type_: str = "normal") -> str:
    return "".join(SMALL.format(name=n, type=type_) for n in names)


def write_deck(folder: Path, *names: str, fname: str = "deck.nml") -> Path:
    p = folder / fname
    p.write_text(deck_text(*names))
    return p


def side_files(folder: Path) -> list[str]:
    """Temporary and lock files left in a folder."""
    return sorted(p.name for p in folder.iterdir() if p.name.endswith((".tmp", ".lock")))


def run(capfd, *args: str) -> tuple[int, str, str]:
    rc = main(["run", *args, "-q", "--serial"])
    cap = capfd.readouterr()
    assert "Traceback" not in cap.out + cap.err
    assert "Exception ignored" not in cap.err
    return rc, cap.out, cap.err


def groups(path: Path) -> dict[str, str]:
    with h5py.File(path, "r") as f:
        return {k: str(g.attrs["status"]) for k, g in f.items()}


def no_nan(path: Path) -> None:
    with h5py.File(path, "r") as f:
        for g in f.values():
            for d in g.values():
                if isinstance(d, h5py.Dataset) and d.dtype.kind == "f":
                    assert np.all(np.isfinite(d[()])), d.name


@pytest.fixture
def readonly_dir(tmp_path):
    """A folder no file can be created in: chmod 555 for a user, a read-only tmpfs for root."""
    d = tmp_path / "ro"
    d.mkdir()
    if os.geteuid() != 0:
        d.chmod(0o555)
        yield d
        d.chmod(0o755)
        return
    r = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(d)],
        capture_output=True,
        text=True,
        timeout=30,
    )
    if r.returncode != 0:
        pytest.skip(f"no read-only folder for root here (mount: {r.stderr.strip()})")
    try:
        yield d
    finally:
        subprocess.run(["umount", "-l", str(d)], capture_output=True, timeout=30)


# ---------------------------------------------------------------------------------------------
# Output paths: refused clearly (InputError, before any work)


def _path_case(kind: str, tmp: Path, deck: Path) -> tuple[Path, str]:
    """An output path of a hostile kind and the words its refusal must contain."""
    if kind == "directory":
        (tmp / "adir").mkdir()
        return tmp / "adir", "is a directory"
    if kind == "empty_name":
        return Path(""), "is a directory"
    if kind == "dev_null":
        return Path("/dev/null"), "not a regular file"
    if kind == "dev_full":
        return Path("/dev/full"), "not a regular file"
    if kind == "fifo":
        os.mkfifo(tmp / "pipe")
        return tmp / "pipe", "not a regular file"
    if kind == "socket":
        s = socket.socket(socket.AF_UNIX)
        s.bind(str(tmp / "sock"))
        s.close()
        return tmp / "sock", "not a regular file"
    if kind == "the_deck":
        return deck, "is the deck itself"
    if kind == "symlink_to_deck":
        (tmp / "link.h5").symlink_to(deck)
        return tmp / "link.h5", "is the deck itself"
    if kind == "text_file":
        (tmp / "notes.h5").write_text("my notes")
        return tmp / "notes.h5", "not a railvti results file"
    if kind == "empty_file":
        (tmp / "empty.h5").write_bytes(b"")
        return tmp / "empty.h5", "not a railvti results file"
    if kind == "foreign_hdf5":
        with h5py.File(tmp / "foreign.h5", "w") as f:
            f["x"] = np.arange(3)
        return tmp / "foreign.h5", "not a railvti results file"
    if kind == "random_bytes":
        (tmp / "noise.h5").write_bytes(os.urandom(4096))
        return tmp / "noise.h5", "not a railvti results file"
    if kind == "dangling_symlink":
        (tmp / "dangling.h5").symlink_to(tmp / "nowhere" / "x.h5")
        return tmp / "dangling.h5", "which does not exist"
    if kind == "symlink_loop":
        (tmp / "loop1.h5").symlink_to(tmp / "loop2.h5")
        (tmp / "loop2.h5").symlink_to(tmp / "loop1.h5")
        return tmp / "loop1.h5", "symbolic links"
    if kind == "parent_is_a_file":
        (tmp / "afile").write_text("x")
        return tmp / "afile" / "out.h5", "output folder"
    if kind == "name_too_long":
        return tmp / ("x" * 300 + ".h5"), "name too long"
    if kind == "proc_file":
        return Path("/proc/self/status"), "not a railvti results file"
    raise AssertionError(kind)


PATH_KINDS = [
    "directory",
    "empty_name",
    "dev_null",
    "dev_full",
    "fifo",
    "socket",
    "the_deck",
    "symlink_to_deck",
    "text_file",
    "empty_file",
    "foreign_hdf5",
    "random_bytes",
    "dangling_symlink",
    "symlink_loop",
    "parent_is_a_file",
    "name_too_long",
    "proc_file",
]


@pytest.mark.parametrize("kind", PATH_KINDS)
def test_output_path_refused(tmp_path, kind, capfd):
    deck = write_deck(tmp_path, "a")
    out, words = _path_case(kind, tmp_path, deck)
    before = (
        out.read_bytes() if kind != "proc_file" and not kind.startswith("name") and out.is_file() else None
    )
    with pytest.raises(InputError) as exc:
        check_output(out, deck)
    assert words.lower() in str(exc.value).lower()
    rc, _, err = run(capfd, str(deck), "-o", str(out))  # the same through the CLI
    assert rc == 2 and words.lower() in err.lower() and len(err.splitlines()) == 1
    if before is not None:
        assert out.read_bytes() == before  # untouched
    assert deck.read_text() == deck_text("a")
    assert side_files(tmp_path) == []


def test_output_in_a_read_only_folder_is_refused(readonly_dir, tmp_path, capfd):
    deck = write_deck(tmp_path, "a")
    rc, _, err = run(capfd, str(deck), "-o", str(readonly_dir / "out.h5"))
    assert rc == 2 and "cannot write in the output folder" in err
    assert list(readonly_dir.iterdir()) == []


# ---------------------------------------------------------------------------------------------
# Output paths: handled edge cases (exit 0, the file where it should be)

HANDLED = {
    "nested_new_folders": "a/b/c/out.h5",
    "unicode_name": "résultats_ß_列车.h5",
    "spaces_in_name": "my results file.h5",
    "name_250_chars": "r" * 246 + ".h5",
    "newline_in_name": "two\nlines.h5",
    "dotdot_path": "sub/../out.h5",
    "no_suffix": "results",
    "looks_like_a_temp_file": ".out.h5.123.abcdef01.tmp.h5",
}


@pytest.mark.parametrize("kind", sorted(HANDLED))
def test_output_path_handled(tmp_path, kind, capfd):
    deck = write_deck(tmp_path, "a", "b")
    out = tmp_path / HANDLED[kind]
    rc, text, _ = run(capfd, str(deck), "-o", str(out))
    assert rc == 0 and "2 of 2 cases ok" in text
    assert groups(out) == {"001_a": "ok", "002_b": "ok"}
    no_nan(out)
    assert side_files(out.parent) == []


def test_symlink_to_a_results_file_writes_its_target(tmp_path, capfd):
    deck = write_deck(tmp_path, "a")
    target = tmp_path / "real" / "out.h5"
    target.parent.mkdir()
    assert run(capfd, str(deck), "-o", str(target))[0] == 0
    link = tmp_path / "link.h5"
    link.symlink_to(target)
    deck.write_text(deck_text("a", "b"))
    assert (
        run(
            capfd,
            str(deck),
            "-o",
            str(link),
        )[0]
        == 0
    )
    assert link.is_symlink() and set(groups(target)) == {"001_a", "002_b"}
    assert side_files(tmp_path) == [] and side_files(target.parent) == []


def test_default_output_and_a_stale_temp_file_beside_it(tmp_path, capfd):
    """No -o: DECK.h5; a .tmp left by an earlier SIGKILL is left alone and does not matter."""
    deck = write_deck(tmp_path, "a")
    stale = tmp_path / ".deck.h5.999999.deadbeef.tmp"
    stale.write_bytes(b"garbage")
    assert run(capfd, str(deck))[0] == 0
    assert groups(tmp_path / "deck.h5") == {"001_a": "ok"} and stale.read_bytes() == b"garbage"


# ---------------------------------------------------------------------------------------------
# Another deck's file (railvti.runner.results.deck_owner, railvti.runner.batch.check_deck)


def _results_of(
    tmp: Path, capfd, *names: str, fname: str = "first.nml", out: str = "out.h5", type_: str = "normal"
) -> Path:
    d = tmp / fname
    d.write_text(deck_text(*names, type_=type_))
    assert run(capfd, str(d), "-o", str(tmp / out))[0] == 0
    return tmp / out


OTHER = {  # the first deck's cases, the second deck's cases
    "no_case_shared": (("a", "b"), ("x", "y")),
    "one_of_three_shared": (("a", "b", "c"), ("a", "y", "z")),
    "same_names_other_positions": (("a", "b"), ("b", "a")),
    "one_vs_many": (("a",), ("x", "y", "z", "w")),
}


@pytest.mark.parametrize("resume", [False, True], ids=["plain", "resume"])
@pytest.mark.parametrize("kind", sorted(OTHER))
def test_other_deck_refused(tmp_path, capfd, kind, resume):
    first, second = OTHER[kind]
    out = _results_of(tmp_path, capfd, *first)
    before = out.read_bytes()
    deck = write_deck(tmp_path, *second, fname="second.nml")
    rc, _, err = run(capfd, str(deck), "-o", str(out), *(["--resume"] if resume else []))
    assert rc == 2 and "first.nml" in err and "--force" in err and len(err.splitlines()) == 1
    assert ("mix two decks" in err) == resume
    assert out.read_bytes() == before and side_files(tmp_path) == []


def test_other_deck_of_another_type_refused(tmp_path, capfd):
    """The same case names, another case type: not the same deck."""
    out = _results_of(tmp_path, capfd, "a", "b")
    with h5py.File(out, "r+") as f:
        for g in f.values():
            g.attrs["type"] = "rolling"
        del f.attrs["deck_path"]
        del f.attrs["deck_digest"]
    deck = write_deck(tmp_path, "a", "b", fname="second.nml")
    with pytest.raises(InputError, match="written from another deck"):
        check_deck(out, deck, parse_deck(deck.read_text()))


@pytest.mark.parametrize("resume", [False, True], ids=["plain", "resume"])
def test_force_replaces_other_deck(tmp_path, capfd, resume):
    out = _results_of(tmp_path, capfd, "a", "b")
    deck = write_deck(tmp_path, "x", fname="second.nml")
    rc, text, err = run(capfd, str(deck), "-o", str(out), "--force", *(["--resume"] if resume else []))
    assert rc == 0 and "--force: it is replaced" in err
    assert groups(out) == {"001_x": "ok"}  # nothing mixed in
    with h5py.File(out, "r") as f:
        assert f.attrs["deck_path"] == str(deck.resolve())
    assert side_files(tmp_path) == []


SAME = {
    # how the second run's deck relates to the first's: (deck text, file name, folder)
    "same_file_params_edited": ("edit", "first.nml", ""),
    "same_file_case_added": ("add", "first.nml", ""),
    "same_file_all_cases_renamed": ("rename", "first.nml", ""),
    "renamed_deck": ("same", "renamed.nml", ""),
    "moved_deck": ("same", "first.nml", "moved"),
    "half_the_cases_shared": ("half", "other.nml", ""),
    "older_file_without_deck_path": ("same", "other.nml", "strip"),
}


@pytest.mark.parametrize("resume", [False, True], ids=["plain", "resume"])
@pytest.mark.parametrize("kind", sorted(SAME))
def test_same_deck_accepted(tmp_path, capfd, kind, resume):
    out = _results_of(tmp_path, capfd, "a", "b")
    text, fname, where = SAME[kind]
    if where == "strip":
        with h5py.File(out, "r+") as f:
            del f.attrs["deck_path"], f.attrs["deck_digest"]
    folder = tmp_path / where if where and where != "strip" else tmp_path
    folder.mkdir(exist_ok=True)
    body = {
        "same": deck_text("a", "b"),
        "add": deck_text("a", "b", "c"),
        "rename": deck_text("p", "q"),
        "half": deck_text("a", "z"),
        "edit": deck_text("a", "b").replace("fn = 1e4", "fn = 8e3", 1),
    }[text]
    if where == "moved":
        (tmp_path / "first.nml").unlink()
    deck = folder / fname
    deck.write_text(body)
    rc, out_text, err = run(capfd, str(deck), "-o", str(out), *(["--resume"] if resume else []))
    assert rc == 0 and "railvti: error" not in err
    names = set(groups(out))
    expect = {
        "same": {"001_a", "002_b"},
        "add": {"001_a", "002_b", "003_c"},
        "rename": {"001_p", "002_q"} | ({"001_a", "002_b"} if resume else set()),
        "half": {"001_a", "002_z"} | ({"002_b"} if resume else set()),
        "edit": {"001_a", "002_b"},
    }[text]
    assert names == expect
    no_nan(out)


def test_deck_digest_ignores_parameters():
    a = parse_deck(deck_text("a", "b"))
    b = parse_deck(deck_text("a", "b").replace("fn = 1e4", "fn = 3e3"))
    c = parse_deck(deck_text("a", "c"))
    assert results.deck_digest(a) == results.deck_digest(b) != results.deck_digest(c)


# ---------------------------------------------------------------------------------------------
# Damaged results files


def _damage(path: Path, how: str) -> None:
    data = bytearray(path.read_bytes())
    if how == "truncated_half":
        path.write_bytes(bytes(data[: len(data) // 2]))
    elif how == "truncated_to_superblock":
        path.write_bytes(bytes(data[:96]))
    elif how == "zeroed_tail":
        path.write_bytes(bytes(data[: len(data) // 3]) + bytes(len(data) - len(data) // 3))
    elif how == "noise_in_the_middle":
        mid = len(data) // 2
        data[mid : mid + 2048] = os.urandom(2048)
        path.write_bytes(bytes(data))
    else:
        raise AssertionError(how)


DAMAGE = ["truncated_half", "truncated_to_superblock", "zeroed_tail", "noise_in_the_middle"]


@pytest.mark.parametrize("how", DAMAGE)
def test_damaged_results_file_refused(tmp_path, capfd, how):
    out = _results_of(tmp_path, capfd, "a", "b", "c")
    _damage(out, how)
    before = out.read_bytes()
    deck = write_deck(tmp_path, "a", "b", "c", fname="first.nml")
    rc, text, err = run(capfd, str(deck), "-o", str(out), "--resume")
    # refused, naming the file (each of these damages reaches the metadata resume reads)
    assert rc == 2 and str(out) in err and "--force" in err and len(err.splitlines()) == 1
    assert out.read_bytes() == before
    assert side_files(tmp_path) == []


@pytest.mark.parametrize("resume", [False, True], ids=["plain", "resume"])
@pytest.mark.parametrize("how", DAMAGE)
def test_damaged_results_file_forced(tmp_path, capfd, how, resume):
    out = _results_of(tmp_path, capfd, "a", "b")
    _damage(out, how)
    deck = write_deck(tmp_path, "a", "b", fname="first.nml")
    rc, text, _ = run(capfd, str(deck), "-o", str(out), "--force", *(["--resume"] if resume else []))
    assert rc == 0 and groups(out) == {"001_a": "ok", "002_b": "ok"}
    assert "2 of 2 cases ok" in text and "kept from before" not in text  # both ran again
    no_nan(out)


# ---------------------------------------------------------------------------------------------
# Locks (railvti.runner.output_lock)

HOLDER = textwrap.dedent("""
    import fcntl, json, os, socket, sys, time
    fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT, 0o666)
    fcntl.flock(fd, fcntl.LOCK_EX)
    os.write(fd, json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                             "started": "2026-01-01T00:00:00", "deck": "/decks/other.nml"}).encode())
    print("locked", flush=True)
    time.sleep(60)
""")


@pytest.fixture
def holder(tmp_path):
    """Another live process holding the lock of tmp_path/out.h5."""
    out = tmp_path / "out.h5"
    p = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(lock_path(out))], stdout=subprocess.PIPE, text=True
    )
    try:
        assert p.stdout.readline().strip() == "locked"
        yield out, p
    finally:
        p.kill()
        p.wait(timeout=10)


@pytest.mark.parametrize("via", ["api", "cli", "cli_resume", "cli_force", "other_deck"])
def test_live_lock_refused(holder, tmp_path, capfd, via):
    out, proc = holder
    deck = write_deck(tmp_path, "a")
    if via == "api":
        with pytest.raises(InputError) as exc:
            with OutputLock(out, "mine"):
                pass
        err = str(exc.value)
    else:
        extra = {"cli": [], "cli_resume": ["--resume"], "cli_force": ["--force"], "other_deck": []}[via]
        if via == "other_deck":
            deck = write_deck(tmp_path, "x", fname="other.nml")
        rc, _, err = run(capfd, str(deck), "-o", str(out), *extra)
        assert rc == 2 and len(err.splitlines()) == 1
    assert f"PID {proc.pid}" in err and "/decks/other.nml" in err and "being written" in err
    assert not out.exists() and lock_path(out).exists()  # the holder's lock stays


STALE = {
    "dead_pid": {
        "pid": 2**22 + 12345,
        "host": socket.gethostname(),
        "deck": "/d/old.nml",
        "started": "2026-01-01T00:00:00",
    },
    "other_host": {"pid": 1, "host": "elsewhere.example", "deck": "/d/old.nml"},
    "garbage": "{{{ not json",
    "empty": "",
    "json_list": "[1, 2, 3]",
    "binary": "\x00\xff\x00",
}


@pytest.mark.parametrize("kind", sorted(STALE))
def test_stale_lock_taken_over(tmp_path, capfd, kind):
    deck = write_deck(tmp_path, "a")
    out = tmp_path / "out.h5"
    rec = STALE[kind]
    lock_path(out).write_text(json.dumps(rec) if isinstance(rec, dict) else rec)
    rc, text, err = run(capfd, str(deck), "-o", str(out))
    assert rc == 0 and groups(out) == {"001_a": "ok"}
    if isinstance(rec, dict):
        assert "took over the lock" in err and f"PID {rec['pid']}" in err
    else:
        assert "took over" not in err
    assert not lock_path(out).exists()


def test_lock_of_a_killed_holder_taken_over(tmp_path, capfd):
    out = tmp_path / "out.h5"
    p = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(lock_path(out))], stdout=subprocess.PIPE, text=True
    )
    assert p.stdout.readline().strip() == "locked"
    p.kill()
    p.wait(timeout=10)
    notes = []
    with OutputLock(out, "mine", note=notes.append) as lock:
        assert lock.took_over["pid"] == p.pid
    assert len(notes) == 1 and f"PID {p.pid}" in notes[0] and not lock_path(out).exists()


LOCK_CASES = [
    "reentrant",
    "released_after_exception",
    "record_while_held",
    "two_outputs",
    "long_output_name",
    "released_after_run_error",
]


@pytest.mark.parametrize("kind", LOCK_CASES)
def test_lock_behaviour(tmp_path, kind, capfd, monkeypatch):
    out = tmp_path / "out.h5"
    if kind == "reentrant":
        with OutputLock(out, "d1"):
            with OutputLock(out, "d1"):
                assert lock_path(out).exists()
            assert lock_path(out).exists()
        assert not lock_path(out).exists()
    elif kind == "released_after_exception":
        with pytest.raises(RuntimeError):
            with OutputLock(out, "d1"):
                raise RuntimeError("boom")
        assert not lock_path(out).exists()
        with OutputLock(out, "d2"):
            pass
    elif kind == "record_while_held":
        with OutputLock(out, "/x/deck.nml"):
            rec = json.loads(lock_path(out).read_text())
        assert rec["pid"] == os.getpid() and rec["deck"] == "/x/deck.nml"
        assert rec["host"] == socket.gethostname() and rec["started"][:2] == "20"
    elif kind == "two_outputs":
        with OutputLock(out, "d"), OutputLock(tmp_path / "other.h5", "d"):
            assert lock_path(out).exists() and lock_path(tmp_path / "other.h5").exists()
        assert side_files(tmp_path) == []
    elif kind == "long_output_name":
        long_out = tmp_path / ("n" * 250 + ".h5")
        assert len(lock_path(long_out).name) < 255
        with OutputLock(long_out, "d"):
            assert lock_path(long_out).exists()
    elif kind == "released_after_run_error":

        def boom(params):
            raise KeyError("x")

        monkeypatch.setitem(REGISTRY, "boom", CaseType(name="boom", defaults={}, run=boom))
        deck = tmp_path / "deck.nml"
        deck.write_text("&case name='b', type='boom' /\n")
        rc, _, _ = run(capfd, str(deck), "-o", str(out))
        assert rc == 1 and not lock_path(out).exists()


def test_lock_is_held_while_the_cases_run(tmp_path, monkeypatch, capfd):
    out = tmp_path / "out.h5"
    seen = []

    def probe(params):
        seen.append(json.loads(lock_path(out).read_text()))
        return CaseOutput(summary="probe", scalars={"x": (1.0, "1")})

    monkeypatch.setitem(REGISTRY, "probe", CaseType(name="probe", defaults={}, run=probe))
    deck = tmp_path / "deck.nml"
    deck.write_text("&case name='p', type='probe' /\n")
    assert run(capfd, str(deck), "-o", str(out))[0] == 0
    assert seen[0]["pid"] == os.getpid() and seen[0]["deck"] == str(deck.resolve())


def test_lock_cannot_be_created(readonly_dir):
    with pytest.raises(InputError, match="cannot create the lock file"):
        with OutputLock(readonly_dir / "out.h5", "d"):
            pass


def test_two_concurrent_cli_runs_the_second_refused(tmp_path):
    """Two real processes on one output: the second is refused naming the first's PID."""
    slow = tmp_path / "slow.nml"
    slow.write_text(
        "&case name='s', type='normal', gap_a=1.0, gap_b=1.0, nx=200, ny=200, "
        "dx=0.05e-3, dy=0.05e-3, fn=1e4, method='gs' /\n"
    )
    out = tmp_path / "out.h5"
    first = subprocess.Popen(
        [sys.executable, "-m", "railvti.runner.cli", "run", str(slow), "-o", str(out), "-q", "--serial"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        for _ in range(300):
            if lock_path(out).exists() and lock_path(out).read_text().strip():
                break
            first.poll()
            assert first.returncode is None
            import time

            time.sleep(0.05)
        deck = write_deck(tmp_path, "a")
        r = subprocess.run(
            [sys.executable, "-m", "railvti.runner.cli", "run", str(deck), "-o", str(out), "-q", "--serial"],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert r.returncode == 2 and f"PID {first.pid}" in r.stderr and str(slow.resolve()) in r.stderr
        assert "Traceback" not in r.stderr
    finally:
        first.terminate()
        first.communicate(timeout=60)
    assert first.returncode in (0, 143) and not lock_path(out).exists()


# ---------------------------------------------------------------------------------------------
# Disk errors while the run writes: exit 3


class Disk:
    """The write calls of railvti.runner.guarded_io on a disk that fails at file number ``at``
    (1: the first file written through guarded_io) after ``after`` bytes, with ``code``."""

    def __init__(self, at: int, after: int = 0, code: int = errno.ENOSPC) -> None:
        self.at, self.after, self.code = at, after, code
        self.files: list[int] = []

    def _number(self, fd: int) -> int:
        name = os.readlink(f"/proc/self/fd/{fd}")  # temporary names are unique
        if name not in self.files:
            self.files.append(name)
        return self.files.index(name) + 1

    def pwrite(self, fd, data, pos):
        if self._number(fd) != self.at:
            return os.pwrite(fd, data, pos)
        if self.after <= 0:
            raise OSError(self.code, os.strerror(self.code))
        k = os.pwrite(fd, bytes(data[: min(len(data), self.after)]), pos)  # a short write
        self.after -= k
        return k


STAGES = {
    # name: (file number that fails, bytes it takes first, errno, cases kept)
    "first_case_enospc": (1, 0, errno.ENOSPC, 0),
    "first_case_after_4k": (1, 4096, errno.ENOSPC, 0),
    "second_case_enospc": (2, 0, errno.ENOSPC, 1),
    "second_case_short_write": (2, 777, errno.ENOSPC, 1),
    "third_case_enospc": (3, 1000, errno.ENOSPC, 2),
    "first_case_quota": (1, 0, errno.EDQUOT, 0),
    "second_case_eio": (2, 100, errno.EIO, 1),
    "second_case_efbig": (2, 0, errno.EFBIG, 1),
    "third_case_erofs": (3, 0, errno.EROFS, 2),
}


def _check_exit_3(
    rc: int,
    out: str,
    err: str,
    folder: Path,
    result: Path,
    kept: int | None,
    earlier: frozenset = frozenset(),
) -> None:
    """Exit 3, one line, no side file, the file holds exactly the cases reported ok (and
    ``kept`` of them when given)."""
    assert rc == 3, out + err
    assert len(err.splitlines()) == 1 and err.startswith("railvti: error: cannot write")
    assert "--resume" in err and len((out + err).splitlines()) < 20
    assert side_files(folder) == []
    reported = {
        f"{int(line.split()[1]):03d}_{line.split()[2][1:-2]}"
        for line in out.splitlines()
        if line.startswith("case ") and ("Fn =" in line or "streamed" in line)
    }
    assert reported | earlier == (set(groups(result)) if result.exists() else set())
    if kept is None:
        return
    if kept:
        assert len(groups(result)) == kept and set(groups(result).values()) == {"ok"}
        no_nan(result)
    else:
        assert not result.exists()


@pytest.mark.parametrize("stage", sorted(STAGES))
def test_write_error_exit_3(tmp_path, capfd, monkeypatch, stage):
    at, after, code, kept = STAGES[stage]
    disk = Disk(at, after, code)
    monkeypatch.setattr(guarded_io, "_pwrite", disk.pwrite)
    deck = write_deck(tmp_path, "a", "b", "c", "d")
    out = tmp_path / "out.h5"
    rc, text, err = run(capfd, str(deck), "-o", str(out))
    _check_exit_3(rc, text, err, tmp_path, out, kept)
    assert os.strerror(code) in err


OS_STAGES = ["fsync_eio", "rename_exdev", "temp_create_enospc", "resume_copy_enospc", "truncate_enospc"]


@pytest.mark.parametrize("stage", OS_STAGES)
def test_write_error_exit_3_os_calls(tmp_path, capfd, monkeypatch, stage):
    """The other system calls of a write: fsync, the rename, creating the temporary file,
    copying the file for --resume, setting its length."""
    deck = write_deck(tmp_path, "a", "b", "c")
    out = tmp_path / "out.h5"
    kept = None if stage == "truncate_enospc" else 1  # HDF5 truncates more than once
    calls = []

    def fail_second(real, code):
        def f(*a, **k):
            calls.append(1)
            if len(calls) >= 2:
                raise OSError(code, os.strerror(code))
            return real(*a, **k)

        return f

    if stage == "fsync_eio":
        monkeypatch.setattr(guarded_io, "_fsync", fail_second(os.fsync, errno.EIO))
    elif stage == "rename_exdev":
        monkeypatch.setattr(results.os, "replace", fail_second(os.replace, errno.EXDEV))
    elif stage == "temp_create_enospc":
        monkeypatch.setattr(results, "temp_path", fail_second(results.temp_path, errno.ENOSPC))
    elif stage == "truncate_enospc":
        # HDF5 sets the length of a file it writes on disk; a version built in memory is
        # written whole (railvti.runner.results.MEMORY_IMAGE_BYTES): all on disk here
        monkeypatch.setattr(results, "MEMORY_IMAGE_BYTES", 0)
        monkeypatch.setattr(guarded_io, "_ftruncate", fail_second(os.ftruncate, errno.ENOSPC))
    elif stage == "resume_copy_enospc":
        assert run(capfd, str(write_deck(tmp_path, "a")), "-o", str(out))[0] == 0
        deck = write_deck(tmp_path, "a", "b", "c")
        monkeypatch.setattr(results.shutil, "copyfile", fail_second(shutil.copyfile, errno.ENOSPC))
        calls.append(1)  # the first copy already fails
    args = [str(deck), "-o", str(out)] + (["--resume"] if stage == "resume_copy_enospc" else [])
    rc, text, err = run(capfd, *args)
    _check_exit_3(
        rc,
        text,
        err,
        tmp_path,
        out,
        kept,
        frozenset({"001_a"}) if stage == "resume_copy_enospc" else frozenset(),
    )


def test_a_file_that_takes_no_record_at_all_is_exit_3(tmp_path, capfd, monkeypatch):
    """A record HDF5 refuses, and then the same record without its results refused too:
    the file's fault, exit 3 (not a traceback, not a case error)."""
    real = results.write_case

    def refuse(f, rec, check=None):
        if rec.case.name == "b":
            raise TypeError("Object dtype dtype('O') has no native HDF5 equivalent")
        return real(f, rec, check)

    monkeypatch.setattr(results, "write_case", refuse)
    deck = write_deck(tmp_path, "a", "b", "c")
    out = tmp_path / "out.h5"
    rc, text, err = run(capfd, str(deck), "-o", str(out))
    _check_exit_3(rc, text, err, tmp_path, out, 1)
    assert "TypeError" in err and "case 2 'b'" in err


@pytest.fixture
def streamer(monkeypatch):
    """A case type that streams ``blocks`` blocks of 100 rows through railvti.runner.stream."""

    def run_streamer(params):
        stream = case_stream(1e9, store=("t", "q"))
        assert stream is not None
        t = np.arange(100.0)
        for b in range(int(params["blocks"])):
            stream.append({"t": t + 100 * b, "q": np.ones((100, 8)) * b})
        stream.close()
        return CaseOutput(
            summary="streamed", datasets={"t": (stream.streamed("t"), "s"), "q": (stream.streamed("q"), "m")}
        )

    monkeypatch.setitem(
        REGISTRY, "streamer", CaseType(name="streamer", defaults={"blocks": 5}, run=run_streamer)
    )
    monkeypatch.setenv(STREAM_ENV, "0")


STREAM_STAGES = {
    # the deck is a normal case (file 1), then the streamer (its stream file: 2, then the
    # results rewrite that copies it: 3)
    "stream_first_block": (2, 0),
    "stream_later_block": (2, 10_000),
    "stream_close": (2, 4 * 100 * 72 + 3000),
    "copy_of_the_stream": (3, 2000),
}


@pytest.mark.parametrize("stage", sorted(STREAM_STAGES))
def test_stream_write_error_exit_3(tmp_path, capfd, monkeypatch, streamer, stage):
    at, after = STREAM_STAGES[stage]
    monkeypatch.setattr(guarded_io, "_pwrite", Disk(at, after).pwrite)
    deck = tmp_path / "deck.nml"
    deck.write_text(
        deck_text("a")
        + "&case name='s', type='streamer', blocks=5 /\n"
        + deck_text("c").replace("'c'", "'c'")
    )
    out = tmp_path / "out.h5"
    rc, text, err = run(capfd, str(deck), "-o", str(out))
    _check_exit_3(rc, text, err, tmp_path, out, 1)
    assert groups(out) == {"001_a": "ok"}


def test_stream_without_failure_is_copied(tmp_path, capfd, streamer):
    deck = tmp_path / "deck.nml"
    deck.write_text("&case name='s', type='streamer', blocks=3 /\n")
    out = tmp_path / "out.h5"
    assert run(capfd, str(deck), "-o", str(out))[0] == 0
    with h5py.File(out, "r") as f:
        assert f["001_s/t"].shape == (300,) and f["001_s/q"][-1, 0] == 2.0
    assert side_files(tmp_path) == []


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EIO])
def test_api_write_error(tmp_path, monkeypatch, capfd, code):
    """save() and a HistoryStream on a failing disk: WriteFailed, the old file kept, HDF5
    quiet (no "Exception ignored"), the process sound (a later write works)."""
    from railvti.contact.normal import NormalResult  # noqa: F401 - a result class

    target = tmp_path / "r.h5"
    target.write_bytes(b"old")
    monkeypatch.setattr(guarded_io, "_pwrite", Disk(1, 500, code).pwrite)
    from dataclasses import dataclass

    @dataclass
    class R:
        x: np.ndarray

    with pytest.raises(WriteFailed) as exc:
        result_objects.save(R(np.arange(5000.0)), target)
    assert exc.value.errno == code and target.read_bytes() == b"old"
    monkeypatch.setattr(guarded_io, "_pwrite", Disk(1, 500, code).pwrite)
    s = HistoryStream(tmp_path / "s.h5")
    with pytest.raises(WriteFailed):  # in a block or at the close
        try:
            for _b in range(50):
                s.append({"t": np.arange(1000.0)})
        finally:
            s.close()
    s.close()  # a second close is quiet
    assert s.failed or s.rows < 50000
    monkeypatch.setattr(guarded_io, "_pwrite", os.pwrite)
    with h5py.File(tmp_path / "after.h5", "w") as f:  # HDF5 still sound
        f["x"] = np.arange(3)
    assert "Exception ignored" not in capfd.readouterr().err
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


class SignalInWrite:
    """os.pwrite raising KeyboardInterrupt (a signal handler) at its ``at``-th call, once."""

    def __init__(self, at: int) -> None:
        self.at, self.calls = at, 0

    def __call__(self, fd, data, pos):
        self.calls += 1
        if self.calls == self.at:
            raise KeyboardInterrupt
        return os.pwrite(fd, data, pos)


@pytest.mark.parametrize("at", [1, 3, 8])
def test_signal_inside_a_stream_write(tmp_path, monkeypatch, capfd, at):
    """Ctrl-C while HDF5 writes a streamed block: HDF5 never sees it, the block finishes,
    the interrupt is raised after it, the stream closes into a valid file of whole blocks."""
    monkeypatch.setattr(guarded_io, "_pwrite", SignalInWrite(at))
    s = HistoryStream(tmp_path / "s.h5", store=("t", "q"))
    blocks = 0
    with pytest.raises(KeyboardInterrupt):
        for b in range(200):
            s.append({"t": np.arange(4000.0) + 4000 * b, "q": np.ones((4000, 4)) * b})
            blocks += 1
    s.close()
    with h5py.File(tmp_path / "s.h5", "r") as f:
        t = f["history/t"][()]
        assert len(t) == 4000 * blocks and np.array_equal(t, np.arange(4000.0 * blocks))
        assert f["history"].attrs["rows"] == 4000 * blocks
    assert "Exception ignored" not in capfd.readouterr().err


def test_signal_inside_save(tmp_path, monkeypatch, capfd):
    from dataclasses import dataclass

    @dataclass
    class R:
        x: np.ndarray

    target = tmp_path / "r.h5"
    target.write_bytes(b"old")
    monkeypatch.setattr(guarded_io, "_pwrite", SignalInWrite(2))
    with pytest.raises(KeyboardInterrupt):
        result_objects.save(R(np.arange(5000.0)), target)
    assert target.read_bytes() == b"old" and side_files(tmp_path) == []
    monkeypatch.setattr(guarded_io, "_pwrite", os.pwrite)
    result_objects.save(R(np.arange(5.0)), target)  # HDF5 still sound
    assert "Exception ignored" not in capfd.readouterr().err


@pytest.mark.parametrize("out_given", [True, False], ids=["out", "temporary_out"])
def test_sweeps_run_raises_on_a_write_error(tmp_path, monkeypatch, out_given):
    """The API (railvti.runner.sweeps.run): a run stopped by its file raises WriteFailed naming it,
    it does not return a short list of records."""
    from railvti.runner import sweeps

    monkeypatch.setattr(guarded_io, "_pwrite", Disk(2, 0).pwrite)
    cases = parse_deck(deck_text("a", "b", "c"))
    with pytest.raises(WriteFailed, match="keeps the 1 case written before") as exc:
        sweeps.run(cases, out=tmp_path / "o.h5" if out_given else None)
    assert exc.value.errno == errno.ENOSPC
    assert side_files(tmp_path) == []


def test_sweeps_run_refused_by_a_live_lock(holder, tmp_path):
    from railvti.runner import sweeps

    out, proc = holder
    with pytest.raises(InputError, match=f"PID {proc.pid}"):
        sweeps.run(parse_deck(deck_text("a")), out=out)
    assert not out.exists()


# ---------------------------------------------------------------------------------------------
# GuardedFile itself: handled edge cases


@pytest.mark.parametrize(
    "kind", ["lost_writes_read_back", "overlapping_lost_writes", "read_past_the_end", "truncate_then_grow"]
)
def test_guarded_file(tmp_path, monkeypatch, kind):
    p = tmp_path / "g.bin"
    fh = GuardedFile(p, "w")
    fh.write(b"abcdef")
    if kind == "lost_writes_read_back":
        monkeypatch.setattr(guarded_io, "_pwrite", Disk(1, 0).pwrite)
        fh.seek(4)
        fh.write(b"XYZW")
        fh.seek(0)
        assert fh.read(8) == b"abcdXYZW" and fh.error.errno == errno.ENOSPC
        assert p.read_bytes() == b"abcdef"
        with pytest.raises(WriteFailed):
            fh.check()
    elif kind == "overlapping_lost_writes":
        monkeypatch.setattr(guarded_io, "_pwrite", Disk(1, 0).pwrite)
        fh.seek(1)
        fh.write(b"1111")
        fh.seek(2)
        fh.write(b"22")
        fh.seek(0)
        assert fh.read(6) == b"a1221f"
    elif kind == "read_past_the_end":
        fh.seek(4)
        assert fh.read(6) == b"ef\0\0\0\0" and fh.tell() == 10
    elif kind == "truncate_then_grow":
        fh.truncate(2)
        fh.seek(0, 2)
        fh.write(b"zz")
        fh.seek(0)
        assert fh.read() == b"abzz" and fh.error is None
    fh.close()


def test_hdf5_through_a_guarded_file_equals_a_plain_one(tmp_path):
    data = np.random.default_rng(1).normal(size=(300, 7))
    fh = GuardedFile(tmp_path / "g.h5", "w")
    with open_h5(fh, "w") as f:
        f.create_dataset("d", data=data, compression="gzip")
        f.attrs["a"] = "text"
    fh.close()
    with h5py.File(tmp_path / "g.h5", "r") as f:
        assert np.array_equal(f["d"][()], data) and f.attrs["a"] == "text"
