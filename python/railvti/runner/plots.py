"""PNG plots of HDF5 results (matplotlib, Agg backend)."""

from __future__ import annotations

import hashlib
import logging
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")

from .deck_registry import case_types  # noqa: E402
from ..errors import InputError  # noqa: E402
from .sweep_plots import MAX_POINT_PLOTS, plot_sweeps, sweep_points  # noqa: E402

log = logging.getLogger(__name__)


def plot_results(
    path: str | Path, outdir: str | Path | None = None, points: bool = False, notes: list[str] | None = None
) -> list[Path]:
    """Draw every successful case of a results file, what an interrupted case kept (its
    time history up to the signal), and a summary of each sweep
    (railvti.runner.sweep_plots.plot_sweeps); return the PNG paths.

    Parameters
    ----------
    path : path
        HDF5 file written by ``railvti run``.
    outdir : path, optional
        Folder for the PNGs (default: next to the file).
    points : bool
        Also draw each point of the sweeps larger than railvti.runner.sweep_plots.MAX_POINT_PLOTS.
    notes : list, optional
        Gets one line per case drawn partly or not at all, saying why (failed, interrupted
        before it kept anything, no plot for its type, a plot that failed).
    """
    notes = notes if notes is not None else []
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
            if not hasattr(group, "attrs"):
                continue
            status = str(group.attrs.get("status", ""))
            partial = status.startswith("interrupted")
            if status != "ok" and not partial:
                failed = status.startswith("error")
                notes.append(
                    f"{gname}: not plotted: "
                    + (
                        f"the case failed ({status[5:].lstrip(': ')})"
                        if failed
                        else f"status {status or 'unknown'}"
                    )
                )
                continue
            if not points and sizes.get(str(group.attrs.get("sweep", "")), 0) > MAX_POINT_PLOTS:
                continue  # a large sweep: its summary plot only
            if partial and all(k == "inputs" for k in group):
                notes.append(f"{gname}: not plotted: {status}, before it kept any result")
                continue
            ctype = types.get(str(group.attrs.get("type")))
            if ctype is None or ctype.plot is None:
                notes.append(f"{gname}: not plotted: case type {group.attrs.get('type')!s} has no plot")
                continue
            try:
                new = ctype.plot(group, outdir, _stem(path.stem, gname))
            except Exception as exc:  # noqa: BLE001 - one bad case must not stop the others
                (log.debug if partial else log.warning)(
                    "no plot for %s: %s: %s", gname, type(exc).__name__, exc
                )
                new = []
                why = (
                    f"it was {status} before it kept a result ({type(exc).__name__}: {exc})"
                    if partial
                    else f"its plot failed: {type(exc).__name__}: {exc}"
                )
                notes.append(f"{gname}: not plotted: {why}")
            else:
                if partial:
                    notes.append(
                        f"{gname}: {status}: plotted what it kept"
                        + (f" ({_text(group.attrs.get('summary'))})" if group.attrs.get("summary") else "")
                    )
            written.extend(new)
        written.extend(plot_sweeps(f, outdir, path.stem))
    return written


def _text(value: object) -> str:
    return value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)


def _stem(file_stem: str, gname: str) -> str:
    """'FILE_GROUP' for the PNG names, cut (with a digest) to stay a valid file name."""
    stem = f"{file_stem}_{gname}".replace("/", "_").replace("\x00", "_")
    if len(stem) > 150:
        stem = f"{stem[:139]}~{hashlib.sha1(stem.encode('utf-8', 'replace')).hexdigest()[:10]}"
    return stem


__all__ = ["plot_results"]
