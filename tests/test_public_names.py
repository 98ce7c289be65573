"""Every public module of the package says what it exports (issue 32): a ``__all__`` whose
names all exist, without duplicates. Public: not a ``_``-prefixed module, not a package's
``__init__`` that only gathers names."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import railvti


def _public_modules() -> list[str]:
    names = []
    for info in pkgutil.walk_packages(railvti.__path__, "railvti."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts[1:]) or info.ispkg:
            continue
        names.append(info.name)
    return sorted(names)


MODULES = _public_modules()


def test_the_package_has_public_modules():
    assert len(MODULES) > 80


@pytest.mark.parametrize("name", MODULES)
def test_a_public_module_names_its_exports(name):
    module = importlib.import_module(name)
    exported = getattr(module, "__all__", None)
    assert exported is not None, f"{name} has no __all__"
    assert len(set(exported)) == len(exported), f"{name}.__all__ lists a name twice"
    missing = [n for n in exported if not hasattr(module, n)]
    assert not missing, f"{name}.__all__ lists names it does not define: {missing}"
