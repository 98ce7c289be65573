"""No Fortran procedure over 150 lines (issue 32), unless its file says why in a line
``! long: <name>: <one-line reason>``.

A procedure runs from its ``subroutine``/``function`` statement to its ``end``; a contained
procedure is counted on its own and its lines are left out of its host's count. Run as a
script to print every procedure over the limit and the longest ones.
"""

from __future__ import annotations

import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
FORTRAN = ROOT / "fortran"
LIMIT = 150
pytestmark = pytest.mark.skipif(not FORTRAN.is_dir(), reason="needs the source tree")

_PREFIX = (
    r"(?:(?:pure|elemental|impure|recursive|module|real\([^)]*\)|integer(?:\([^)]*\))?|logical|"
    r"complex\([^)]*\)|character\([^)]*\)|type\([^)]*\))\s+)*"
)
_START = re.compile(rf"^\s*{_PREFIX}(subroutine|function)\s+([a-z_][a-z0-9_]*)", re.I)
_END = re.compile(r"^\s*end(\s*(subroutine|function)(\s+[a-z_][a-z0-9_]*)?)?\s*$", re.I)
_INTERFACE = re.compile(r"^\s*(abstract\s+)?interface\b", re.I)
_LONG = re.compile(r"^\s*!\s*long:\s*([a-z_][a-z0-9_]*)\s*:\s*\S", re.I | re.M)


def procedure_lengths(path: pathlib.Path) -> list[tuple[str, int, int]]:
    """(name, first line, own line count) of every procedure in one file, interface bodies left out."""
    out, stack, in_interface = [], [], 0
    for no, raw in enumerate(path.read_text().splitlines(), 1):
        line = raw.split("!", 1)[0]
        if _INTERFACE.match(line):
            in_interface += 1
            continue
        if in_interface:
            if re.match(r"^\s*end\s*interface\b", line, re.I):
                in_interface -= 1
            continue
        m = _START.match(line)
        if m and not re.match(r"^\s*end\b", line, re.I):
            stack.append([m.group(2).lower(), no, 0])  # name, first line, lines of contained procedures
            continue
        if stack and _END.match(line):
            name, first, inner = stack.pop()
            total = no - first + 1
            out.append((name, first, total - inner))
            if stack:
                stack[-1][2] += total
    return out


def long_procedures(limit: int = LIMIT) -> list[tuple[str, str, int, bool]]:
    """(file, procedure, lines, excused) for every procedure over ``limit`` lines, longest first."""
    rows = []
    for path in sorted(FORTRAN.rglob("*.f90")):
        excused = {n.lower() for n in _LONG.findall(path.read_text())}
        for name, _, n in procedure_lengths(path):
            if n > limit:
                rows.append((str(path.relative_to(ROOT)), name, n, name in excused))
    return sorted(rows, key=lambda r: -r[2])


def test_scanner_counts_contained_procedures_apart(tmp_path):
    src = tmp_path / "m.f90"
    src.write_text(
        "module m\ncontains\n  pure subroutine a(x)\n    real, intent(in) :: x\n"
        "  contains\n    pure real(dp) function b()\n      b = 1\n    end function b\n"
        "  end subroutine a\n  subroutine c()\n    interface\n      subroutine d()\n"
        "      end subroutine\n    end interface\n  end subroutine\nend module m\n"
    )
    assert procedure_lengths(src) == [("b", 6, 3), ("a", 3, 4), ("c", 10, 6)]


def test_every_fortran_file_is_scanned():
    names = [p for path in FORTRAN.rglob("*.f90") for p in procedure_lengths(path)]
    assert len(names) > 300


def test_no_fortran_procedure_over_the_limit_without_a_reason():
    bad = [f"{f}::{name} ({n} lines)" for f, name, n, excused in long_procedures() if not excused]
    assert not bad, (
        f"Fortran procedures over {LIMIT} lines: split them, or add a line "
        f"'! long: <name>: <reason>' to the file:\n  " + "\n  ".join(bad)
    )


if __name__ == "__main__":
    for f, name, n, excused in long_procedures():
        print(f"{n:5d}  {f}::{name}{'  (long: reason given)' if excused else ''}")
