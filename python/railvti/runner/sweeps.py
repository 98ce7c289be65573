"""Sweeps: one deck case (or a Python call) run over lists or ranges of its keys, each point
a task, run serially or on a dask.distributed cluster.

A sweep in a deck (docs/sweeps.md)::

    &case
        name = 'hunt', type = 'vehicle', scenario = 'hunting', duration = 2.0
        sweep = 'product'                          ! or 'zip' (default 'product')
        sweep_range_speed_kmh = 300, 460, 20       ! start, stop (included), step
        sweep_y0 = 0.006, 0.0005                   ! a list of values
    /

``sweep_KEY = v1, v2, ...`` lists the values of the case key ``KEY`` (an alias such as
``speed_kmh`` is converted as a fixed key is), ``sweep_range_KEY = start, stop, step`` gives
them as a range with ``stop`` included. ``sweep = 'product'`` runs every combination (the
first key varies slowest), ``'zip'`` takes the i-th value of every key together (the lists must
be equally long). Each point is a case named ``NAME.KEY_VALUE[.KEY_VALUE]`` (or ``NAME.pNNNN``
when that name would be too long or not unique), checked with the rest of the deck before any
case runs, and written to its own HDF5 group with the attributes ``sweep`` (the base name) and
``sweep_point`` (its values, JSON).

Running: :func:`run_on_client` sends every case (deck cases and sweep points alike) as a task to
a dask.distributed client and writes each finished one at once through the batch runner's
writer (railvti.runner.batch: only this process writes the file; the workers return their records).
``railvti run`` does this on a ``LocalCluster`` by default; ``--serial`` runs in-process
without importing dask. Dask is imported only inside the functions that use it: ``import
railvti`` and the serial path do not import it.
"""

from __future__ import annotations

import contextlib
import itertools
import json
import logging
import math
import sys
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterable, Sequence

from .._cluster import (
    ADDRESS_FORM,
    CONNECT_TIMEOUT,
    SCHEDULER_TIMEOUT,
    WORKER_ENV,
    check_client,
    client_from,
    default_workers,
    local_client,
    remote_client,
    scheduler_address,
)
from ..casetypes import MAX_NAME, REGISTRY, REQUIRED, Case, CaseType, name_problem
from ..errors import InputError
from .batch import run_cases, run_on_client, run_task
from .deck_registry import case_types
from .guarded_io import WriteFailed
from .results import group_name

log = logging.getLogger("railvti")

#: The key that names the combination rule, and the prefixes of the swept keys.
MODE_KEY = "sweep"
VALUES_PREFIX = "sweep_"
RANGE_PREFIX = "sweep_range_"
MODES = ("product", "zip")
#: Most points of one sweep (the results file is rewritten after each: keep it moderate).
MAX_POINTS = 2000


@dataclass(frozen=True)
class SweepPoint(Case):
    """A case made by a sweep: ``sweep`` is the base case's name, ``point`` the swept keys
    and values as written in the deck (``(('speed_kmh', 300.0), ...)``)."""

    sweep: str = ""
    point: tuple = ()

    @property
    def point_json(self) -> str:
        """The swept values as JSON (the group's ``sweep_point`` attribute)."""
        return json.dumps(dict(self.point))


@dataclass(frozen=True)
class SweepSpec:
    """A sweep declared in a deck group: the combination rule and (key, values) per axis."""

    mode: str
    axes: tuple[tuple[str, tuple], ...]


def _as_list(value: Any) -> list:
    return list(value) if isinstance(value, (list, tuple)) else [value]


def _range(key: str, value: Any) -> tuple[list[float], str | None]:
    """The values of ``sweep_range_KEY = start, stop, step`` (stop included)."""
    v = _as_list(value)
    if len(v) != 3 or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v):
        return [], (f"key '{RANGE_PREFIX}{key}' must be three numbers: start, stop, step; got {value!r}")
    start, stop, step = (float(x) for x in v)
    if not all(math.isfinite(x) for x in (start, stop, step)) or step == 0.0 or (stop - start) / step < -1e-9:
        return [], (
            f"key '{RANGE_PREFIX}{key}' = {start:g}, {stop:g}, {step:g}: the step must be "
            "non-zero and go from start towards stop"
        )
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    if n > MAX_POINTS:
        return [], f"key '{RANGE_PREFIX}{key}' gives {n} values; at most {MAX_POINTS}"
    return [float(f"{start + i * step:.12g}") for i in range(n)], None


def split_sweep(group: dict[str, Any]) -> tuple[dict[str, Any], SweepSpec | None, list[str]]:
    """Take the sweep keys out of a deck group.

    Returns
    -------
    group : dict
        The group without ``sweep``, ``sweep_KEY`` and ``sweep_range_KEY``.
    spec : SweepSpec or None
        None when the group declares no sweep.
    problems : list of str
        Bad sweep keys (without the case label).
    """
    rest: dict[str, Any] = {}
    axes: list[tuple[str, tuple]] = []
    problems: list[str] = []
    mode: Any = None
    for key, value in group.items():
        k = str(key)
        if k == MODE_KEY:
            mode = value
        elif k.startswith(RANGE_PREFIX):
            values, msg = _range(k[len(RANGE_PREFIX) :], value)
            if msg:
                problems.append(msg)
            axes.append((k[len(RANGE_PREFIX) :], tuple(values)))
        elif k.startswith(VALUES_PREFIX):
            values = _as_list(value)
            if not values or any(x is None for x in values):
                problems.append(f"key '{k}' needs one or more values")
            axes.append((k[len(VALUES_PREFIX) :], tuple(values)))
        else:
            rest[key] = value
    if mode is None and not axes:
        return rest, None, problems
    if mode is None:
        mode = "product"
    if not isinstance(mode, str) or mode.strip().lower() not in MODES:
        problems.append(f"key '{MODE_KEY}' = {mode!r} must be one of {', '.join(map(repr, MODES))}")
        mode = "product"
    mode = mode.strip().lower()
    if not axes:
        problems.append(
            f"key '{MODE_KEY}' without swept keys: add sweep_KEY = values or "
            "sweep_range_KEY = start, stop, step"
        )
    names = [k for k, _ in axes]
    for k in sorted({k for k in names if names.count(k) > 1}):
        problems.append(f"key '{k}' is swept twice (sweep_{k} and sweep_range_{k}): give it once")
    if mode == "zip" and len({len(v) for _, v in axes}) > 1:
        problems.append(
            "sweep = 'zip' needs lists of equal length: " + ", ".join(f"{k} has {len(v)}" for k, v in axes)
        )
    return rest, SweepSpec(mode, tuple(axes)), problems


def _value_text(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.12g}"
    return str(value)


def _point_names(base: str, points: list[tuple]) -> list[str]:
    """``base.KEY_VALUE...`` per point, or ``base.pNNNN`` when those are too long, unsafe or
    not unique."""
    names = [".".join([base] + [f"{k}_{_value_text(v)}" for k, v in p]) for p in points]
    if len(set(names)) == len(names) and all(name_problem(n) is None for n in names):
        return names
    width = max(4, len(str(len(points))))
    return [f"{base[: MAX_NAME - width - 2]}.p{i:0{width}d}" for i in range(len(points))]


def _combine(spec: SweepSpec) -> list[tuple]:
    """The points of a sweep: tuples of (key, value), in order."""
    keys = [k for k, _ in spec.axes]
    if spec.mode == "zip":
        combos = zip(*(v for _, v in spec.axes))
    else:
        combos = itertools.product(*(v for _, v in spec.axes))
    return [tuple(zip(keys, c)) for c in combos]


def _resolve(ctype: CaseType, key: str, value: Any) -> tuple[str, Any, str | None]:
    """(case key, value in its unit, problem) of a swept key given in the deck."""
    if key in ctype.defaults:
        spec = ctype.keys.get(key)
        if spec is not None and spec.choices and isinstance(value, str):
            value = spec.choice(value) or value
        return key, value, None
    alias = ctype.aliases.get(key)
    if alias is None:
        return key, value, f"unknown key '{key}' for type '{ctype.name}' in the sweep"
    if alias.converts:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return alias.key, value, f"swept key '{key}' must be a number, got {value!r}"
        value = alias.to_key(value)
    return alias.key, value, None


def expand(case: Case, spec: SweepSpec, given: Iterable[str] = ()) -> tuple[list[Case], list[str]]:
    """The points of a sweep over ``case`` (its index and name are the base's), and the
    problems of the sweep's keys (without the case label; each point's values are checked by
    the caller with the case type's checks, as any case).

    Parameters
    ----------
    given : iterable of str
        Keys given fixed in the same deck group (a key may not be both fixed and swept).
    """
    ctype = case.case_type
    problems = []
    given = set(given)
    for key, _ in spec.axes:
        target = ctype.aliases[key].key if key in ctype.aliases else key
        clash = sorted(
            k
            for k in given
            if k == key or k == target or (k in ctype.aliases and ctype.aliases[k].key == target)
        )
        if clash:
            problems.append(f"key '{clash[0]}' is both given and swept: give it once")
    points = _combine(spec)
    if len(points) > MAX_POINTS:
        problems.append(f"the sweep has {len(points)} points; at most {MAX_POINTS}")
    if problems:
        return [], problems
    seen_problems: set[str] = set()
    out: list[Case] = []
    first: dict[str, int] = {}  # a point's resolved values -> its number, from 1
    for i, (name, point) in enumerate(zip(_point_names(case.name, points), points), 1):
        params = dict(case.params)
        for key, value in point:
            target, v, msg = _resolve(ctype, key, value)
            if msg and msg not in seen_problems:
                seen_problems.add(msg)
                problems.append(msg)
            params[target] = v
        # the same case twice is the same run twice, and two groups of one name in the file
        same = repr([(k, params[ctype.aliases[k].key if k in ctype.aliases else k]) for k, _ in point])
        if same in first:
            problems.append(
                f"the sweep has the same point twice: points {first[same]} and {i} are "
                + ", ".join(f"{k} = {_value_text(v)}" for k, v in point)
                + ": give each point once"
            )
        first.setdefault(same, i)
        out.append(
            SweepPoint(
                index=case.index,
                name=name,
                case_type=ctype,
                params=params,
                sweep=case.name,
                point=tuple(point),
            )
        )
    return ([] if problems else out), problems


def sweep(
    case_type: str,
    params: dict[str, Any],
    axes: dict[str, Sequence[Any]],
    *,
    mode: str = "product",
    name: str = "sweep",
) -> list[Case]:
    """Declare a sweep in Python: the cases of ``case_type`` over ``axes``.

    Parameters
    ----------
    case_type : str
        A registered case type ('vehicle', 'normal', ...; ``railvti cases``).
    params : dict
        The fixed keys (the type's defaults for the others).
    axes : dict
        Key -> sequence of values (deck key names and units, aliases such as ``speed_kmh``
        allowed).
    mode : {'product', 'zip'}
    name : str
        The base name of the points.

    Returns
    -------
    list of Case
        Checked, numbered from 1, ready for :func:`run`.

    Raises
    ------
    InputError
        Every problem of the sweep and of its points, at once.
    """
    ctype = case_types().get(case_type)
    if ctype is None:
        raise InputError(f"unknown case type {case_type!r}; known: {', '.join(sorted(REGISTRY))}")
    given, problems = ctype.resolve_aliases(dict(params))
    unknown = sorted(k for k in given if k not in ctype.defaults)
    problems += [f"unknown key '{k}' for type '{case_type}'" for k in unknown]
    if problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems))
    base_params = {k: v for k, v in ctype.defaults.items() if not _required(v)}
    base_params.update(given)  # each point is checked below, as a whole
    group = {f"{VALUES_PREFIX}{k}": list(v) for k, v in axes.items()}
    group[MODE_KEY] = mode
    _, spec, problems = split_sweep(group)
    if spec is None or problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems or ["no swept keys"]))
    base = Case(index=1, name=name, case_type=ctype, params=base_params)
    cases, problems = expand(base, spec, given=[k for k in params if k in axes])
    for c in cases:
        problems += [f"{c.name}: {p}" for p in ctype.problems(c.params)]
    if problems:
        raise InputError(f"sweep '{name}': " + "; ".join(problems))
    return [replace(c, index=i + 1) for i, c in enumerate(cases)]


def _required(value: Any) -> bool:
    return value is REQUIRED


# ---------------------------------------------------------------------------------------------
# Running a list of cases (serially or on dask.distributed: railvti._cluster, railvti.runner.batch)


def run(
    cases: list[Case],
    client: Any = None,
    *,
    out: str | Path | None = None,
    resume: bool = False,
    workers: int | None = None,
    deck_text: str = "",
    progress: bool = False,
) -> list[Any]:
    """Run cases (deck cases, sweep points) serially or on a Dask cluster.

    Parameters
    ----------
    cases : list of Case
        From :func:`railvti.runner.deck.read_deck` or :func:`sweep`.
    client : None, 'local', str or distributed.Client
        None: in this process, one after another (dask is not imported). 'local': a new
        LocalCluster of ``workers`` processes (default: the cores). Another text: the address
        of a running scheduler (``tcp://host:8786``). A Client: used as it is (not closed).
    out : path, optional
        Write the results file (one writer, this process; each case as it finishes). Without
        it, a temporary file is used and removed.
    resume : bool
        With ``out``: keep its complete cases and run the others.
    workers : int, optional
        Workers of the 'local' cluster.
    progress : bool
        A progress bar (tasks, failures, time left).

    Returns
    -------
    list of CaseRecord
        In the order of ``cases``; the cases kept by ``resume`` are absent.
    """
    records: dict[int, Any] = {}
    tmpdir = None
    if out is None:
        tmpdir = tempfile.TemporaryDirectory(prefix="railvti-sweep-")
        out = Path(tmpdir.name) / "sweep.h5"
    try:
        with contextlib.ExitStack() as stack:
            c = None if client is None else stack.enter_context(client_from(client, workers))
            bar = stack.enter_context(task_bar(len(cases), disable=not progress))
            report = run_cases(
                cases,
                Path(out),
                deck_text,
                resume=resume,
                write=log.info,
                client=c,
                bar=bar,
                on_record=lambda r: records.__setitem__(group_name(r.case), r),
            )
            if report.error:  # the file could not be written: the run stopped
                raise WriteFailed(report.failure.errno, report.error, str(out))
    finally:
        if tmpdir is not None:
            tmpdir.cleanup()
    return [records[group_name(c)] for c in cases if group_name(c) in records]


@contextlib.contextmanager
def task_bar(total: int, disable: bool = False) -> Any:
    """A tqdm bar on stderr counting finished tasks (postfix: failures; tqdm's estimate of
    the time left)."""
    from tqdm import tqdm

    bar = tqdm(total=total, desc="tasks", unit="task", disable=disable, file=sys.stderr, dynamic_ncols=True)
    try:
        yield bar
    finally:
        bar.close()


# the Dask clients (railvti._cluster) and the batch's task functions are this module's names too
__all__ = [
    "MODES",
    "SweepPoint",
    "SweepSpec",
    "check_client",
    "client_from",
    "expand",
    "local_client",
    "remote_client",
    "run",
    "run_cases",
    "run_on_client",
    "run_task",
    "split_sweep",
    "sweep",
    "task_bar",
    "ADDRESS_FORM",
    "CONNECT_TIMEOUT",
    "SCHEDULER_TIMEOUT",
    "WORKER_ENV",
    "default_workers",
    "scheduler_address",
]
