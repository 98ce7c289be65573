"""Saving and loading any railvti result object (SimulationResult, NormalResult,
RollingResult, ...: a dataclass) as an HDF5 file.

:func:`save` writes the object's fields as datasets, each with a ``units`` attribute (from the
class's numpydoc Attributes section and its ``FIELD_UNITS``), and records the class, so that
:func:`load` returns an equal object. The file is written atomically, as a run's results file
(:mod:`railvti.runner.results`): a temporary file beside it, renamed over it.
"""

from __future__ import annotations

import dataclasses
import importlib
import json
import os
import re
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .. import __version__
from ..errors import InputError
from .guarded_io import GuardedFile, failure, open_h5
from .results import LAYOUT, attr_value, temp_path

__all__ = ["save", "load"]


_UNIT_RE = re.compile(
    r",\s*((?:1/)?(?:N m|N/m|N s/m|m/s\^2|m/s|rad/s|W/m\^2|m\^2|Pa|N|m|s|W|J|Hz|rad|"
    r"kg|1/m|1))\b\s*(?:\(|\.|$|;)"
)


def _doc_units(cls: type) -> dict[str, str]:
    """Units from a numpydoc Attributes section: 'name : type' then a description whose
    first sentence ends in ', UNIT.'"""
    out: dict[str, str] = {}
    doc = cls.__doc__ or ""
    for m in re.finditer(r"^\s{4}([\w, ]+?) : [^\n]*\n((?:\s{8}[^\n]*\n?)+)", doc, re.M):
        desc = " ".join(m.group(2).split())
        u = _UNIT_RE.search(desc)
        if u:
            for name in m.group(1).split(","):
                out[name.strip()] = u.group(1)
    return out


def _units_of(cls: type) -> dict[str, Any]:
    units: dict[str, Any] = dict(_doc_units(cls))
    units.update(getattr(cls, "FIELD_UNITS", {}))  # the class's own (SimulationResult's)
    return units


def _save_value(g: h5py.Group, name: str, value: Any, unit: Any) -> None:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        _save_object(g.create_group(name), value)
    elif isinstance(value, dict):
        sub = g.create_group(name)
        sub.attrs["kind"] = "dict"
        units = unit if isinstance(unit, dict) else {}
        for i, (k, v) in enumerate(value.items()):
            plain = isinstance(k, str) and k and "/" not in k and k != "." and not k.startswith("item")
            item = k if plain else f"item{i}"
            _save_value(sub, item, v, units.get(k, "") if plain else "")
            sub[item].attrs["key"] = json.dumps(list(k) if isinstance(k, tuple) else k)
            sub[item].attrs["order"] = i
            sub[item].attrs["key_is_tuple"] = int(isinstance(k, tuple))
    elif value is None:
        d = g.create_dataset(name, data=h5py.Empty("f8"))
        d.attrs["kind"] = "none"
        d.attrs["units"] = "none (no value)"
    elif isinstance(value, str):
        d = g.create_dataset(name, data=value)
        d.attrs["kind"] = "str"
        d.attrs["units"] = "text"
    elif isinstance(value, (tuple, list)) and value and all(isinstance(v, str) for v in value):
        d = g.create_dataset(name, data=np.array(value, dtype=h5py.string_dtype()))
        d.attrs["kind"] = "tuple_str"
        d.attrs["units"] = "text"
    elif isinstance(value, (tuple, list)) and not all(np.isscalar(v) for v in value):
        sub = g.create_group(name)
        sub.attrs["kind"] = "tuple" if isinstance(value, tuple) else "list"
        for i, v in enumerate(value):
            _save_value(sub, f"item{i}", v, "")
    else:
        arr = np.asarray(value)
        d = g.create_dataset(name, data=arr, **({"compression": "gzip"} if arr.size > 64 else {}))
        kind = {bool: "bool", int: "int", float: "float"}.get(type(value), "array")
        if isinstance(value, tuple):
            kind = "tuple"
        elif isinstance(value, list):
            kind = "list"
        d.attrs["kind"] = kind
        d.attrs["units"] = (unit if isinstance(unit, str) else "") or (
            "text" if arr.dtype.kind in "OSU" else "1"
        )


def _save_object(g: h5py.Group, obj: Any) -> None:
    cls = type(obj)
    g.attrs["class"] = f"{cls.__module__}:{cls.__qualname__}"
    units = _units_of(cls)
    for f in dataclasses.fields(obj):
        if not f.init:
            continue
        _save_value(g, f.name, getattr(obj, f.name), units.get(f.name, ""))
    extra = getattr(obj, "_save_attrs", None)
    if callable(extra):
        for node, attrs in extra().items():
            for k, v in attrs.items():
                g[node].attrs[k] = attr_value(v)


def save(obj: Any, path: str | Path) -> Path:
    """Save a result object (any railvti result dataclass) to an HDF5 file, atomically.

    Arrays become datasets with a ``units`` attribute; the class is recorded so that
    :func:`load` returns an equal object.
    """
    if not dataclasses.is_dataclass(obj) or isinstance(obj, type):
        raise InputError(f"save() takes a railvti result object, got {type(obj).__name__}")
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path} is a directory")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = temp_path(path)
    fh = GuardedFile(tmp, "w")  # a full disk raises WriteFailed, HDF5 stays sound
    try:
        try:
            with open_h5(fh, "w") as f:
                f.attrs["railvti_version"] = __version__
                f.attrs["layout"] = LAYOUT
                _save_object(f.create_group("result"), obj)
        except Exception:
            fh.check()
            raise
        fh.sync()
        fh.close()
        try:
            os.replace(tmp, path)
        except OSError as exc:
            raise failure(path, exc) from None
    finally:
        fh.close()
        tmp.unlink(missing_ok=True)
    return path


def _load_value(node: Any) -> Any:
    if isinstance(node, h5py.Group):
        if "class" in node.attrs:
            return _load_object(node)
        kind = node.attrs.get("kind")
        items = list(node.keys())
        if kind != "dict":
            items.sort(key=lambda s: int(s[4:]))
        else:
            items.sort(key=lambda s: node[s].attrs.get("order", 0))
            out = {}
            for k in items:
                key = json.loads(node[k].attrs["key"])
                if int(node[k].attrs.get("key_is_tuple", 0)):
                    key = tuple(key)
                out[key] = _load_value(node[k])
            return out
        seq = [_load_value(node[k]) for k in items]
        return tuple(seq) if kind == "tuple" else seq
    kind = node.attrs.get("kind", "array")
    if kind == "none":
        return None
    if kind == "str":
        v = node[()]
        return v.decode() if isinstance(v, bytes) else str(v)
    if kind == "tuple_str":
        return tuple(s.decode() if isinstance(s, bytes) else str(s) for s in node[()])
    v = node[()]
    if kind == "bool":
        return bool(v)
    if kind == "int":
        return int(v)
    if kind == "float":
        return float(v)
    if kind == "tuple":
        return tuple(np.asarray(v).tolist())
    if kind == "list":
        return list(np.asarray(v).tolist())
    return np.asarray(v)


def _load_object(g: h5py.Group) -> Any:
    module, _, qualname = str(g.attrs["class"]).partition(":")
    if not module.startswith("railvti"):
        raise InputError(f"not a railvti result class: {module}:{qualname}")
    obj: Any = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    kwargs = {name: _load_value(g[name]) for name in g.keys()}
    return obj(**kwargs)


def load(path: str | Path) -> Any:
    """Load a result object saved by :func:`save` (or ``SimulationResult.save``)."""
    try:
        f = h5py.File(path, "r")
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot open results file {path}: {exc}") from None
    with f:
        if "result" not in f or "class" not in f["result"].attrs:
            raise InputError(
                f"{path} holds no saved result object (a 'railvti run' file? "
                "read it with h5py, or re-make a case with case_deck)"
            )
        return _load_object(f["result"])
