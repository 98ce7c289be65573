"""HDF5 results of a deck run (h5py).

Layout: one group per case, ``/NNN_name``, with attributes ``type``, ``name``,
``status`` ('ok' or the error) and ``summary``; a subgroup ``inputs`` whose
attributes are the case's parameters; arrays and scalar results as datasets,
each with a ``units`` attribute. The file is written to a temporary name and
renamed when complete, so a failed run never leaves a half-written file.
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from . import __version__
from .casetypes import CaseOutput
from .deck import Case


@dataclass
class CaseRecord:
    """A case with its output, or the error that stopped it."""

    case: Case
    output: CaseOutput | None = None
    error: str | None = None


def _attr(value: Any) -> Any:
    if value is None:
        return "none"
    if isinstance(value, (list, tuple)):
        return np.asarray(value)
    return value


def write_results(path: str | Path, records: list[CaseRecord], deck_text: str = "") -> Path:
    """Write the records of a run to ``path`` atomically and return it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["railvti_version"] = __version__
            f.attrs["deck"] = deck_text
            for rec in records:
                c = rec.case
                g = f.create_group(f"{c.index:03d}_{c.name}")
                g.attrs["type"] = c.case_type.name
                g.attrs["name"] = c.name
                g.attrs["status"] = "ok" if rec.error is None else f"error: {rec.error}"
                gi = g.create_group("inputs")
                for key, value in c.params.items():
                    gi.attrs[key] = _attr(value)
                if rec.output is None:
                    continue
                g.attrs["summary"] = rec.output.summary
                for name, (arr, units) in rec.output.datasets.items():
                    d = g.create_dataset(name, data=np.asarray(arr), compression="gzip", compression_opts=4)
                    d.attrs["units"] = units
                for name, (value, units) in rec.output.scalars.items():
                    d = g.create_dataset(name, data=value)
                    d.attrs["units"] = units
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
