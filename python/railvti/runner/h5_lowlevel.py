"""Datasets and attributes written through h5py's low-level calls: the same HDF5 objects as
``group.create_dataset(name, data=...)`` and ``obj.attrs[name] = value`` make, for the common
values (numbers, booleans, text and arrays of them), without the high-level layer's
per-call cost. One difference, on purpose: a small dataset (at most
:data:`COMPACT_MAX_BYTES`) is stored in HDF5's compact layout, its values inside its object
header (one write instead of two; readers see no difference: the same type, shape, values,
no chunks, no filters).

Why: a case of CONTACT's A-2.2 deck writes some 70 datasets and 220 attributes; through
h5py's high-level calls that took 17-20 ms per case, as long as a third of the case's solve
(issue 33). HDF5's own cost is about 40 us per dataset and 20 us per attribute; the rest was
h5py's Python layer (argument checks, property lists made anew, the object registry) and,
through the results writer's ``fileobj`` driver (railvti.runner.guarded_io), a Python call
per write of each small dataset's values.

Anything else (compound or complex values, a name with '/', an existing attribute, h5py
configured to track creation order) goes through the high-level calls, so every value is
stored as h5py stores it. tests/test_h5_lowlevel.py compares the two object by object.
"""

from __future__ import annotations

from typing import Any

import h5py
import numpy as np

__all__ = ["COMPACT_MAX_BYTES", "stored_array", "set_attr", "new_dataset"]

#: The dtype of text (variable-length UTF-8), as h5py stores a Python str.
TEXT = h5py.string_dtype()

_TYPES: dict[tuple, Any] = {}  # HDF5 types by numpy dtype and its metadata, made once


def _htype(dtype: np.dtype) -> Any:
    """The HDF5 type h5py makes for ``dtype`` (h5t.py_create, logical)."""
    # text dtypes differ in their metadata only
    key = (dtype.str, None if dtype.metadata is None else repr(dtype.metadata))
    t = _TYPES.get(key)
    if t is None:
        t = _TYPES[key] = h5py.h5t.py_create(dtype, logical=True)
    return t


def _plain_dcpl() -> Any:
    """The creation property list h5py's create_dataset makes for an unchunked dataset
    (creation times not stored; attribute creation order not tracked)."""
    dcpl = h5py.h5p.create(h5py.h5p.DATASET_CREATE)
    dcpl.set_obj_track_times(False)
    dcpl.set_attr_creation_order(0)
    return dcpl


#: Largest dataset (bytes of its values) stored in the compact layout: HDF5's limit is 64 kB
#: for the whole object header.
COMPACT_MAX_BYTES = 4096

_DCPL = _plain_dcpl()
_DCPL_COMPACT = _plain_dcpl()
_DCPL_COMPACT.set_layout(h5py.h5d.COMPACT)


def stored_array(value: Any) -> np.ndarray | None:
    """``value`` as the C-ordered array h5py would store for it (a str as variable-length
    UTF-8), when it is numbers, booleans or text; None for anything else."""
    if isinstance(value, str):
        return np.array(value, dtype=TEXT)
    if isinstance(value, (bytes, h5py.Empty)):
        return None
    arr = np.asarray(value, order="C")
    kind = arr.dtype.kind
    if kind in "biuf" and arr.dtype.isnative:
        return arr
    if kind == "O" and h5py.check_string_dtype(arr.dtype) is not None:
        return arr
    return None


def _low(obj: Any) -> Any:
    """The low-level identifier of an h5py object (an identifier itself unchanged)."""
    return obj.id if isinstance(obj, (h5py.Group, h5py.Dataset)) else obj


def _high(obj: Any) -> Any:
    """The high-level object of an identifier (an h5py object itself unchanged)."""
    if isinstance(obj, h5py.h5d.DatasetID):
        return h5py.Dataset(obj)
    if isinstance(obj, h5py.h5g.GroupID):
        return h5py.Group(obj)
    return obj


_SPACES: dict[tuple, Any] = {}  # dataspaces by shape (immutable once made)


def _space(arr: np.ndarray) -> Any:
    """The dataspace of ``arr`` (scalar for 0-d), made once per shape."""
    space = _SPACES.get(arr.shape)
    if space is None:
        space = h5py.h5s.create(h5py.h5s.SCALAR) if arr.ndim == 0 else h5py.h5s.create_simple(arr.shape)
        if len(_SPACES) < 256:
            _SPACES[arr.shape] = space
    return space


def set_attr(obj: Any, name: str, value: Any) -> None:
    """``obj.attrs[name] = value`` (``obj``: an h5py Group or Dataset, or its identifier),
    through the low-level calls when the attribute is new and the value numbers, booleans
    or text."""
    arr = stored_array(value)
    if arr is not None and not h5py.get_config().track_order:
        oid = _low(obj)
        try:
            aid = h5py.h5a.create(oid, name.encode("utf-8"), _htype(arr.dtype), _space(arr))
        except (KeyError, ValueError, RuntimeError, OSError):  # it exists: replaced as h5py does
            pass
        else:
            aid.write(arr)
            return
    _high(obj).attrs[name] = value


def new_dataset(group: h5py.Group, name: str, value: Any, compress: bool = False) -> Any:
    """A new dataset ``name`` in ``group`` holding ``value`` (``compress``: chunked and gzip
    level 4, through h5py's create_dataset; else compact when at most
    :data:`COMPACT_MAX_BYTES`); returns its low-level identifier."""
    arr = None if compress or "/" in name else stored_array(value)
    if arr is None or h5py.get_config().track_order:
        opts = {"compression": "gzip", "compression_opts": 4} if compress else {}
        return group.create_dataset(name, data=value, **opts).id
    dcpl = _DCPL_COMPACT if arr.nbytes <= COMPACT_MAX_BYTES else _DCPL
    dsid = h5py.h5d.create(group.id, name.encode("utf-8"), _htype(arr.dtype), _space(arr), dcpl=dcpl)
    dsid.write(h5py.h5s.ALL, h5py.h5s.ALL, arr)
    return dsid
