"""railvti.runner.h5_lowlevel against h5py's high-level calls: every value the results writer
stores makes the same HDF5 object (type, character set, shape, filters, creation properties,
values) through either path; a small dataset differs only in its layout (compact, on
purpose), a larger one not at all."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from railvti.runner.h5_lowlevel import COMPACT_MAX_BYTES, new_dataset, set_attr, stored_array

VALUES = {
    "float": 1.25,
    "int": -7,
    "bool": True,
    "text": "mm, N – ü",
    "empty_text": "",
    "np_float32": np.float32(2.5),
    "np_int8": np.int8(3),
    "np_uint16": np.uint16(65000),
    "np_bool": np.bool_(False),
    "vector": np.array([1.0, np.nan, -np.inf]),
    "matrix": np.arange(6.0).reshape(2, 3),
    "fortran": np.asfortranarray(np.arange(6.0).reshape(2, 3)),
    "strided": np.arange(10.0)[::3],
    "ints": np.array([[1, 2], [3, 4]], dtype=np.int32),
    "status": np.array([[0, 1], [2, 1]], dtype=np.int8),
    "bools": np.array([True, False]),
    "empty": np.zeros(0),
    "labels": np.array(["left", "right", "ü"], dtype=object).astype(h5py.string_dtype()),
    "list": [1.0, 2.0],
    "nested": [[1, 2], [3, 4]],
}


def _signature(obj, layout: bool = True) -> tuple:
    t = obj.id.get_type() if isinstance(obj, h5py.Dataset) else obj.get_type()
    cls = t.get_class()
    if cls == h5py.h5t.STRING:
        typ = (cls, t.is_variable_str(), t.get_cset(), None if t.is_variable_str() else t.get_size())
    else:
        typ = (cls, t.get_size(), t.get_order() if hasattr(t, "get_order") else None)
    if isinstance(obj, h5py.Dataset):
        plist = obj.id.get_create_plist()
        return typ + (
            obj.shape,
            obj.dtype,
            obj.chunks,
            obj.compression,
            obj.compression_opts,
            plist.get_layout() if layout else None,
            plist.get_obj_track_times(),
            plist.get_attr_creation_order(),
        )
    return typ + (obj.shape,)


def _same_values(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    return np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


@pytest.mark.parametrize("key", sorted(VALUES))
def test_dataset_as_h5py_makes_it(tmp_path, key):
    value = VALUES[key]
    with h5py.File(tmp_path / "f.h5", "w") as f:
        ref = f.create_dataset("ref", data=value)
        ours = h5py.Dataset(new_dataset(f, f"ours_{key}", value))
        assert _signature(ours, layout=False) == _signature(ref, layout=False)
        assert ours.id.get_create_plist().get_layout() == h5py.h5d.COMPACT
        assert _same_values(ours[()], ref[()])
    with h5py.File(tmp_path / "f.h5", "r") as f:  # read back from the file, not HDF5's cache
        assert _same_values(f[f"ours_{key}"][()], f["ref"][()])


def test_a_larger_dataset_is_as_h5py_makes_it(tmp_path):
    arr = np.arange(COMPACT_MAX_BYTES // 8 + 1, dtype=float)
    with h5py.File(tmp_path / "f.h5", "w") as f:
        ref = f.create_dataset("ref", data=arr)
        ours = h5py.Dataset(new_dataset(f, "ours", arr))
        assert _signature(ours) == _signature(ref)
        assert ours.id.get_create_plist().get_layout() == h5py.h5d.CONTIGUOUS
        assert _same_values(ours[()], arr)


@pytest.mark.parametrize("key", sorted(VALUES))
def test_attribute_as_h5py_makes_it(tmp_path, key):
    value = VALUES[key]
    with h5py.File(tmp_path / "f.h5", "w") as f:
        g, d = f.create_group("g"), f.create_dataset("d", data=1.0)
        f.attrs["ref"] = value
        set_attr(g, "a", value)
        set_attr(d.id, "a", value)  # a low-level identifier too
        for obj in (g, d):
            assert _signature(obj.attrs.get_id("a")) == _signature(f.attrs.get_id("ref"))
            assert _same_values(obj.attrs["a"], f.attrs["ref"])


def test_compressed_dataset_as_h5py_makes_it(tmp_path):
    arr = np.linspace(0.0, 1.0, 56 * 104).reshape(56, 104)
    with h5py.File(tmp_path / "f.h5", "w") as f:
        ref = f.create_dataset("ref", data=arr, compression="gzip", compression_opts=4)
        ours = h5py.Dataset(new_dataset(f, "ours", arr, compress=True))
        assert _signature(ours) == _signature(ref) and ours.compression == "gzip"
        assert _same_values(ours[()], arr)


def test_other_values_take_the_high_level_path(tmp_path):
    assert stored_array(1 + 2j) is None and stored_array(b"raw") is None
    assert stored_array(np.array(["a"])) is None  # numpy unicode: h5py's own conversion (refused)
    with h5py.File(tmp_path / "f.h5", "w") as f:
        g = f.create_group("g")
        set_attr(g, "z", 1 + 2j)
        assert g.attrs["z"] == 1 + 2j
        set_attr(g, "x", 1.0)
        set_attr(g, "x", "replaced")  # an existing attribute is replaced, as attrs[...] = does
        assert g.attrs["x"] == "replaced"
        new_dataset(f, "sub/deeper", 2.0)  # a path: h5py makes the groups
        assert f["sub/deeper"][()] == 2.0
        with pytest.raises((ValueError, RuntimeError, KeyError)):
            new_dataset(f, "sub/deeper", 3.0)  # an existing dataset is an error either way
        new_dataset(g, "x_ds", 1.0)
        with pytest.raises((ValueError, RuntimeError, KeyError)):
            new_dataset(g, "x_ds", 1.0)


def test_track_order_configured_takes_the_high_level_path(tmp_path):
    cfg = h5py.get_config()
    old = cfg.track_order
    cfg.track_order = True
    try:
        with h5py.File(tmp_path / "f.h5", "w") as f:
            ref = f.create_dataset("ref", data=1.0)
            ours = h5py.Dataset(new_dataset(f, "ours", 1.0))
            assert _signature(ours) == _signature(ref)
    finally:
        cfg.track_order = old
