"""PNG plots of HDF5 results (matplotlib, Agg backend)."""
from __future__ import annotations

import logging
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")

from .deck_registry import case_types  # noqa: E402
from .errors import InputError  # noqa: E402

log = logging.getLogger(__name__)


def plot_results(path: str | Path, outdir: str | Path | None = None) -> list[Path]:
    """Draw every successful case of a results file; return the PNG paths.

    Parameters
    ----------
    path : path
        HDF5 file written by ``railvti run``.
    outdir : path, optional
        Folder for the PNGs (default: next to the file).
    """
    path = Path(path)
    outdir = Path(outdir) if outdir is not None else path.parent
    outdir.mkdir(parents=True, exist_ok=True)
    types = case_types()
    written: list[Path] = []
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"cannot open results file {path}: {exc}") from None
    with f:
        for gname, group in f.items():
            if group.attrs.get("status") != "ok":
                continue
            ctype = types.get(str(group.attrs.get("type")))
            if ctype is None or ctype.plot is None:
                log.info("no plot for %s", gname)
                continue
            written.extend(ctype.plot(group, outdir, f"{path.stem}_{gname}"))
    return written
