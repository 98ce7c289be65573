"""Every relative link and image in README.md, CHANGELOG.md and docs/*.md points to a file that
exists (a page moved or a chart renamed breaks no link unnoticed). Reads the source tree only."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FILES = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md"))]
pytestmark = pytest.mark.skipif(not (ROOT / "docs").is_dir(), reason="needs the source tree")

_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
_FENCE = re.compile(r"^```.*?^```", re.S | re.M)


def _targets(path: Path) -> list[str]:
    text = _FENCE.sub("", path.read_text())  # code blocks hold no links
    return [t for t in _LINK.findall(text) if "://" not in t and not t.startswith(("#", "mailto:"))]


def test_the_documents_are_found():
    assert all(f.exists() for f in FILES[:2]) and len(FILES) >= 10


@pytest.mark.parametrize("path", [f for f in FILES if f.exists()], ids=lambda f: f.name)
def test_every_relative_link_resolves(path):
    broken = [t for t in _targets(path) if not (path.parent / t.split("#")[0]).exists()]
    assert not broken, f"{path.name}: {broken}"
