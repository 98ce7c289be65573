"""The assessment table: one row per quantity with its value, unit, limit, the limit's source
and the verdict; a one-screen text rendering and HDF5 storage with units."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..errors import InputError

__all__ = ["Row", "Assessment", "VERDICTS"]

#: Verdicts: 'pass' (value <= limit), 'FAIL' (value > limit), 'info' (no limit applies),
#: 'n/a' (not evaluated: the row's note says why).
VERDICTS = ("pass", "FAIL", "info", "n/a")


@dataclass(frozen=True)
class Row:
    """One assessed quantity.

    Attributes
    ----------
    key : str
        Short name (HDF5 dataset name), e.g. 'sum_y_2m'.
    quantity : str
        What it is, with its filter and statistic.
    value : float
        The value (NaN when not evaluated), in ``unit``.
    unit : str
        Unit of ``value`` and ``limit`` (SI).
    limit : float
        Upper limit (NaN: none).
    limit_source : str
        Where the limit comes from ('' for none).
    where : str
        The wheel, wheelset or point giving the value.
    note : str
        Why a row was not evaluated, or what qualifies it (indicative, ...).
    """

    #: Units for railvti.runner.result_objects.save (the generic result file): per row.
    FIELD_UNITS: ClassVar[dict[str, str]] = {
        "value": "per the row's unit field",
        "limit": "per the row's unit field",
    }

    key: str
    quantity: str
    value: float
    unit: str
    limit: float = math.nan
    limit_source: str = ""
    where: str = ""
    note: str = ""

    @property
    def verdict(self) -> str:
        """'pass', 'FAIL', 'info' or 'n/a' (:data:`VERDICTS`)."""
        if not math.isfinite(self.value):
            return "n/a"
        if not math.isfinite(self.limit):
            return "info"
        return "pass" if self.value <= self.limit else "FAIL"

    @property
    def passed(self) -> bool | None:
        """True / False against the limit; None without one."""
        v = self.verdict
        return None if v in ("info", "n/a") else v == "pass"


def _num(x: float, unit: str) -> str:
    """A value in the table's display unit (kN for N)."""
    if not math.isfinite(x):
        return "-"
    if unit == "N":
        return f"{x / 1e3:.2f}"
    return f"{x:.3g}" if abs(x) < 1e4 else f"{x:.4g}"


@dataclass(frozen=True)
class Assessment:
    """The assessment of one run.

    Attributes
    ----------
    rows : tuple of Row
    title : str
        The run it assesses.
    notes : tuple of str
        How the quantities were computed where the table cannot say it.
    """

    rows: tuple
    title: str = ""
    notes: tuple = field(default_factory=tuple)

    def __post_init__(self) -> None:
        keys = [r.key for r in self.rows]
        if len(set(keys)) != len(keys):
            raise InputError(f"assessment rows must have distinct keys, got {keys}")

    def row(self, key: str) -> Row:
        """The row named ``key``."""
        for r in self.rows:
            if r.key == key:
                return r
        raise InputError(f"no assessment row {key!r}; rows: {[r.key for r in self.rows]}")

    @property
    def passed(self) -> bool:
        """No row fails."""
        return not any(r.verdict == "FAIL" for r in self.rows)

    def table(self) -> str:
        """The one-screen text table (forces in kN; sources as footnotes)."""
        sources: list[str] = []
        lines = [self.title] if self.title else []
        head = f"{'quantity':<44} {'value':>9} {'limit':>9} {'unit':<6} {'verdict':<7} where"
        lines += [head, "-" * len(head)]
        for r in self.rows:
            ref = ""
            if r.limit_source:
                if r.limit_source not in sources:
                    sources.append(r.limit_source)
                ref = f"[{sources.index(r.limit_source) + 1}]"
            unit = "kN" if r.unit == "N" else r.unit
            lim = _num(r.limit, r.unit) + ref
            where = r.where + (f" ({r.note})" if r.note else "")
            lines.append(
                f"{r.quantity:<44.44} {_num(r.value, r.unit):>9} {lim:>9} {unit:<6} {r.verdict:<7} {where}"
            )
        lines.append(f"overall: {'pass' if self.passed else 'FAIL'}")
        lines += [f"[{i + 1}] {s}" for i, s in enumerate(sources)]
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.table()

    def case_data(self, prefix: str = "assess_") -> dict[str, tuple]:
        """The rows as a results file's datasets: name -> (value, unit, labels) with labels
        quantity, limit and limit_units (only for a row with a limit), limit_source, verdict,
        where, note."""
        out: dict[str, tuple] = {}
        for r in self.rows:
            lim = {"limit": float(r.limit), "limit_units": r.unit} if math.isfinite(r.limit) else {}
            labels = {"quantity": r.quantity, **lim, "limit_source": r.limit_source, "verdict": r.verdict}
            out[prefix + r.key] = (np.float64(r.value), r.unit, {**labels, "where": r.where, "note": r.note})
        return out

    def to_hdf5(self, group: Any, name: str = "assessment") -> Any:
        """Write the table into h5py ``group`` as subgroup ``name``: one scalar dataset per
        row (attributes units, order, quantity, limit and limit_units for a row with a limit,
        limit_source, verdict, where, note), the text table as dataset ``table`` and the
        overall verdict as an attribute. Returns the subgroup."""
        g = group.create_group(name)
        g.attrs["title"] = self.title
        g.attrs["passed"] = int(self.passed)
        g.attrs["notes"] = "\n".join(self.notes)
        for i, (key, (value, unit, labels)) in enumerate(self.case_data(prefix="").items()):
            d = g.create_dataset(key, data=value)
            d.attrs["units"] = unit
            d.attrs["order"] = i
            for k, v in labels.items():
                d.attrs[k] = v
        g.create_dataset("table", data=self.table())
        return g

    @classmethod
    def from_hdf5(cls, g: Any) -> "Assessment":
        """Read an assessment written by :meth:`to_hdf5` (group ``g``)."""

        def text(v: Any) -> str:
            return v.decode() if isinstance(v, bytes) else str(v)

        rows = []
        for key in g:
            if key == "table":
                continue
            d = g[key]
            a = d.attrs
            rows.append(
                Row(
                    key=key,
                    quantity=text(a["quantity"]),
                    value=float(d[()]),
                    unit=text(a["units"]),
                    limit=float(a.get("limit", math.nan)),
                    limit_source=text(a["limit_source"]),
                    where=text(a["where"]),
                    note=text(a["note"]),
                )
            )
        rows.sort(key=lambda r: int(g[r.key].attrs["order"]))  # h5py lists keys alphabetically
        notes = text(g.attrs.get("notes", ""))
        return cls(
            rows=tuple(rows),
            title=text(g.attrs.get("title", "")),
            notes=tuple(n for n in notes.split("\n") if n),
        )
