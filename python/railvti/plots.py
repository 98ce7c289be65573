"""PNG plots of HDF5 results (matplotlib, Agg backend)."""
from __future__ import annotations

import hashlib
import logging
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")

from .deck_registry import case_types  # noqa: E402
from .errors import InputError  # noqa: E402

log = logging.getLogger(__name__)


def plot_results(path: str | Path, outdir: str | Path | None = None,
                 points: bool = False) -> list[Path]:
    """Draw every successful case of a results file, and a summary of each sweep
    (railvti.sweeps.plot_sweeps); return the PNG paths.

    Parameters
    ----------
    path : path
        HDF5 file written by ``railvti run``.
    outdir : path, optional
        Folder for the PNGs (default: next to the file).
    points : bool
        Also draw each point of the sweeps larger than railvti.sweeps.MAX_POINT_PLOTS.
    """
    from .sweeps import MAX_POINT_PLOTS, plot_sweeps, sweep_points
    path = Path(path)
    outdir = Path(outdir) if outdir is not None else path.parent
    if outdir.exists() and not outdir.is_dir():
        raise InputError(f"plot folder {outdir} is an existing file: give a folder with -o")
    try:
        outdir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the plot folder {outdir}: {exc.strerror}") from None
    types = case_types()
    written: list[Path] = []
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"cannot open results file {path}: {exc}") from None
    with f:
        sizes = {k: len(v) for k, v in sweep_points(f).items()}
        for gname, group in f.items():
            if group.attrs.get("status") != "ok":
                continue
            if not points and sizes.get(str(group.attrs.get("sweep", "")), 0) > MAX_POINT_PLOTS:
                continue                 # a large sweep: its summary plot only
            ctype = types.get(str(group.attrs.get("type")))
            if ctype is None or ctype.plot is None:
                log.info("no plot for %s", gname)
                continue
            try:
                written.extend(ctype.plot(group, outdir, _stem(path.stem, gname)))
            except Exception as exc:  # noqa: BLE001 - one bad case must not stop the others
                log.error("no plot for %s: %s: %s", gname, type(exc).__name__, exc)
        written.extend(plot_sweeps(f, outdir, path.stem))
    return written


def _stem(file_stem: str, gname: str) -> str:
    """'FILE_GROUP' for the PNG names, cut (with a digest) to stay a valid file name."""
    stem = f"{file_stem}_{gname}".replace("/", "_").replace("\x00", "_")
    if len(stem) > 150:
        stem = f"{stem[:139]}~{hashlib.sha1(stem.encode('utf-8', 'replace')).hexdigest()[:10]}"
    return stem
