"""docs/equations.md stays true: every file::procedure and test it names exists, every Kaiser
equation 1-29 has a row, and every Fortran file's header says which equations it implements."""

from __future__ import annotations

import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "equations.md"
pytestmark = pytest.mark.skipif(not DOC.exists(), reason="needs the source tree")


def _defined(path: pathlib.Path, name: str) -> bool:
    text = path.read_text()
    if path.suffix == ".f90":
        pat = (
            rf"^\s*(pure\s+|elemental\s+|recursive\s+|real\(dp\)\s+)*"
            rf"(subroutine|function)\s+{re.escape(name)}\b"
        )
        return re.search(pat, text, re.M | re.I) is not None
    return all(re.search(rf"^\s*(def|class)\s+{re.escape(p)}\b", text, re.M) for p in name.split("."))


def _rows() -> list[tuple[str, str]]:
    section, rows = "", []
    for line in DOC.read_text().splitlines():
        if line.startswith("## "):
            section = line
        elif line.startswith("| ") and "::" in line:
            rows.append((section, line))
    return rows


def test_every_named_procedure_and_test_exists():
    bad = []
    for _, line in _rows():
        for path, name in re.findall(r"`([^`\s]+?)::([A-Za-z_][A-Za-z_0-9.]*)`", line):
            p = ROOT / path
            if not p.exists() or not _defined(p, name):
                bad.append(f"{path}::{name}")
    assert not bad, f"docs/equations.md names what does not exist: {bad}"


def test_every_row_has_an_implementation_and_a_test_or_says_none():
    bad = []
    for section, line in _rows():
        if "Fortran files" in section:
            continue
        refs = re.findall(r"`([^`\s]+?)::", line)
        if not any(not r.startswith("tests/") for r in refs):
            bad.append(line[:60])
        if (
            not any(r.startswith("tests/") for r in refs)
            and "no test" not in line
            and "no pytest" not in line
        ):
            bad.append(line[:60])
    assert not bad, bad


def test_every_kaiser_equation_has_a_row():
    seen: set[int] = set()
    for line in DOC.read_text().splitlines():
        m = re.match(r"\| (\d+)(?:-(\d+))? \|", line)
        if m:
            seen.update(range(int(m.group(1)), int(m.group(2) or m.group(1)) + 1))
    assert set(range(1, 30)) <= seen, sorted(set(range(1, 30)) - seen)


def test_every_fortran_header_names_its_equations():
    bad = []
    for f in sorted((ROOT / "fortran").rglob("*.f90")):
        head = []
        for line in f.read_text().splitlines():
            if not line.startswith("!"):
                break
            head.append(line)
        if not any("Implements" in h for h in head):
            bad.append(str(f.relative_to(ROOT)))
    assert not bad, f"headers that do not say which equations they implement: {bad}"
