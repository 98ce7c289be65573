"""No Python module of the package over 800 lines and no function over 150 lines (issue 32),
unless the file says why: ``# long: <reason>`` in a module's first 5 lines, or on the line
just above a function's ``def`` (or its first decorator).

A function's length runs from its ``def`` to its last line, docstring included; a nested
function counts in its host too (it is part of what a reader holds in mind). Run as a script
to print every module and function over the limits.
"""

from __future__ import annotations

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "python" / "railvti"
MODULE_LIMIT = 800
FUNCTION_LIMIT = 150
pytestmark = pytest.mark.skipif(not PACKAGE.is_dir(), reason="needs the source tree")


def _excused(lines: list[str], lineno: int) -> bool:
    """A ``# long:`` reason on the line above line ``lineno`` (1-based)."""
    return lineno >= 2 and lines[lineno - 2].strip().startswith("# long:")


def long_functions(path: pathlib.Path, limit: int = FUNCTION_LIMIT) -> list[tuple[str, int, bool]]:
    """(name, lines, excused) of every function in ``path`` over ``limit`` lines."""
    text = path.read_text()
    lines = text.splitlines()
    out = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            n = node.end_lineno - node.lineno + 1
            if n > limit:
                first = min([node.lineno] + [d.lineno for d in node.decorator_list])
                out.append((node.name, n, _excused(lines, first)))
    return out


def long_modules(limit: int = MODULE_LIMIT) -> list[tuple[str, int, bool]]:
    """(file, lines, excused) of every package module over ``limit`` lines."""
    rows = []
    for path in sorted(PACKAGE.rglob("*.py")):
        lines = path.read_text().splitlines()
        if len(lines) > limit:
            excused = any(ln.strip().startswith("# long:") for ln in lines[:5])
            rows.append((str(path.relative_to(ROOT)), len(lines), excused))
    return rows


def test_the_scanner_counts_a_function_with_its_docstring(tmp_path):
    body = "\n".join(f"    x{i} = {i}" for i in range(150))
    src = tmp_path / "m.py"
    src.write_text(f'def f():\n    """doc."""\n{body}\n\n\n# long: a table\ndef g():\n{body}\n')
    assert long_functions(src) == [("f", 152, False), ("g", 151, True)]


def test_no_module_over_the_limit_without_a_reason():
    bad = [f"{f} ({n} lines)" for f, n, excused in long_modules() if not excused]
    assert not bad, (
        f"modules over {MODULE_LIMIT} lines: split them by meaning, or say why in a "
        f"'# long: <reason>' line among the first 5:\n  " + "\n  ".join(bad)
    )


def test_no_function_over_the_limit_without_a_reason():
    bad = [
        f"{path.relative_to(ROOT)}::{name} ({n} lines)"
        for path in sorted(PACKAGE.rglob("*.py"))
        for name, n, excused in long_functions(path)
        if not excused
    ]
    assert not bad, (
        f"functions over {FUNCTION_LIMIT} lines: split them into named steps, or say why in a "
        f"'# long: <reason>' line above the def:\n  " + "\n  ".join(bad)
    )


if __name__ == "__main__":
    for f, n, excused in long_modules():
        print(f"{n:5d}  {f}{'  (long: reason given)' if excused else ''}")
    for path in sorted(PACKAGE.rglob("*.py")):
        for name, n, excused in long_functions(path):
            print(f"{n:5d}  {path.relative_to(ROOT)}::{name}{'  (long: reason given)' if excused else ''}")
