"""A results file built in memory (railvti.runner.results.ResultsWriter: each version made in
HDF5's core driver from the last one and written with one write) holds what the same run
writes on disk (the file copied, then extended through the guarded ``fileobj`` driver):
every group, dataset (values, type, shape, chunks, filters) and attribute, case by case."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from railvti.runner import results
from railvti.runner.cli import main

DECK = Path(__file__).resolve().parent / "regression" / "decks" / "mbench_a22_small_left.inp"
#: Attributes that differ between two runs of the same deck.
RUN_ATTRS = {"wall_time", "deck_path"}


def _attrs(obj) -> dict:
    return {k: obj.attrs[k] for k in obj.attrs if k not in RUN_ATTRS}


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def _walk(obj, out: dict, name: str = "/") -> dict:
    """name -> (attributes, values, storage) of every object; the storage of a dataset is
    its type, shape, chunks and filters, and of every object its header's version (the
    file's format: HDF5 2.0's default for a file made without h5py.File is 1.8's, superblock
    v2 and object headers v2), of the file its superblock's."""
    header = h5py.h5o.get_info(obj.id).hdr.version
    if isinstance(obj, h5py.Dataset):
        plist = obj.id.get_create_plist()
        storage = (
            obj.dtype,
            obj.shape,
            obj.chunks,
            obj.compression,
            obj.compression_opts,
            plist.get_nfilters(),
        )
        out[name] = (_attrs(obj), obj[()], storage + (header,))
        return out
    if isinstance(obj, h5py.File):
        header = (header, obj.id.get_create_plist().get_version())
    out[name] = (_attrs(obj), None, header)
    for k in obj:
        _walk(obj[k], out, f"{name}{k}/")
    return out


def _run(tmp_path: Path, monkeypatch, limit: int) -> dict:
    monkeypatch.setattr(results, "MEMORY_IMAGE_BYTES", limit)
    out = tmp_path / f"a22_{limit}.h5"
    assert main(["run", str(DECK), "-o", str(out), "-q", "--serial"]) == 0
    with h5py.File(out, "r") as f:
        assert len(f) == 5
        return _walk(f, {})


def test_a_file_built_in_memory_holds_what_the_disk_path_writes(tmp_path, monkeypatch):
    memory = _run(tmp_path, monkeypatch, results.MEMORY_IMAGE_BYTES)
    disk = _run(tmp_path, monkeypatch, 0)  # every version on disk
    assert memory.keys() == disk.keys() and len(memory) > 5 * 60
    for name, (attrs, values, storage) in memory.items():
        d_attrs, d_values, d_storage = disk[name]
        assert attrs.keys() == d_attrs.keys(), name
        assert all(_same(attrs[k], d_attrs[k]) for k in attrs), name
        assert storage == d_storage, name
        assert values is None or _same(values, d_values), name


@pytest.mark.parametrize("limit", [0, 10**9])
def test_a_version_too_large_for_memory_goes_on_disk(tmp_path, monkeypatch, limit):
    """With a limit of 0 bytes every version is built on disk (the file copied): the writer
    keeps no image; with a large one it keeps the last version's bytes, byte for byte the
    file on disk."""
    monkeypatch.setattr(results, "MEMORY_IMAGE_BYTES", limit)
    from railvti.casetypes import CaseOutput
    from railvti.runner.deck import parse_deck
    from railvti.runner.results import CaseRecord, ResultsWriter

    text = (
        "&case name = '{}', type = 'normal', gap_a = 1.0, gap_b = 1.0, nx = 8, ny = 8, dx = 1e-3, dy = 1e-3, "
    )
    text += "fn = 1e3 /\n"
    cases = parse_deck("".join(text.format(n) for n in "ab"))
    out = tmp_path / "out.h5"
    w = ResultsWriter(out, "deck", cases=cases)
    for c in cases:
        w.write([CaseRecord(c, output=CaseOutput(summary=c.name, scalars={"x": (1.0, "m")}), wall_time=0.1)])
        assert (w._image is None) == (limit == 0)
        assert w._image is None or w._image == out.read_bytes()
    with h5py.File(out, "r") as f:
        assert sorted(f) == ["001_a", "002_b"] and f["002_b/x"][()] == 1.0 and f.attrs["deck"] == "deck"


def test_no_case_is_lost_when_the_file_outgrows_the_memory_limit(tmp_path, monkeypatch):
    """A version larger than the limit is not kept as the next one's base: the next version
    is built from the file on disk, not from an older image (which would drop the cases
    written since; a 24-case bifurcation deck lost two that way)."""
    from railvti.casetypes import CaseOutput
    from railvti.runner.deck import parse_deck
    from railvti.runner.results import CaseRecord, ResultsWriter

    text = "&case name = 'c{}', type = 'normal', gap_a = 1.0, gap_b = 1.0, nx = 8, ny = 8, "
    cases = parse_deck("".join((text + "dx = 1e-3, dy = 1e-3, fn = 1e3 /\n").format(n) for n in range(6)))

    def run(limit: int) -> list[int]:
        monkeypatch.setattr(results, "MEMORY_IMAGE_BYTES", limit)
        out = tmp_path / f"out_{limit}.h5"
        w = ResultsWriter(out, "deck", cases=cases)
        sizes = []
        for c in cases:
            out_c = CaseOutput(summary=c.name, scalars={"x": (1.0, "m")})
            w.write([CaseRecord(c, output=out_c, wall_time=0.1)])
            sizes.append(out.stat().st_size)
        with h5py.File(out, "r") as f:
            assert sorted(f) == [f"{i + 1:03d}_c{i}" for i in range(6)], limit
        return sizes

    sizes = run(10**9)
    for limit in (sizes[1], sizes[3]):  # outgrown after the 3rd and after the 5th case
        run(limit)
