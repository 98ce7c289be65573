"""railvti's imports point one way (docs: STYLE.md, "three layers, one direction"):

    railvti/runner/      decks, sweeps, batch, HDF5 results, streams, Dask, CLI  <- batch users
    railvti/<area>/      the physics (contact, geometry, track, wheelset, vehicle), scenarios
    railvti/_*.py ...    the floor: status, checks, threads, interrupts, Dask clients, plotting

The test reads every module of the package with ``ast`` (nothing is imported) and builds the
graph of imports among railvti's modules, resolving relative imports. It fails on

* a circle among the module-level imports (``if TYPE_CHECKING:`` blocks count: a circle of
  type hints is still a circle of concepts);
* any import of the runner from outside it, at module or function level (the physics knows
  no runner: a simulation writes to a sink it is handed, railvti.casetypes.HistorySink);
* an import inside a function that is not of an optional or slow third-party dependency
  (:data:`HEAVY`) or one of the deliberate lazy imports listed in :data:`LAZY`. An import
  inside a function that dodges a circle hides the circle from readers and from this test.
"""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path

import pytest

#: Third-party packages a module may import inside the function that needs them: each costs
#: 0.1-0.6 s to import or is needed by one path only, and ``import railvti`` (and the
#: ``railvti`` command's start, which installs its signal handlers first) should not pay
#: for it. dask/distributed: only runs on a cluster (``--serial`` never imports them);
#: matplotlib: only plots; scipy: only the flexible bodies' and sections' linear algebra
#: beyond numpy and the interpolation of Kalker's table; triangle: only the rail-section
#: mesher; tqdm: only progress bars (the CLI imports it after its signal handlers);
#: threadpoolctl: only BLAS thread limits.
HEAVY = frozenset({"dask", "distributed", "matplotlib", "scipy", "triangle", "tqdm", "threadpoolctl"})

#: Deliberate lazy imports of railvti's own modules: (importing module, imported module).
#: The ``railvti`` command installs its signal handlers before it imports anything that
#: loads numpy, h5py or Fortran (railvti/runner/cli.py's docstring: a Ctrl-C in the first
#: instant exits with one line); railvti/__init__ loads Material and STEEL on first use
#: (PEP 562) for the same reason. The runner's cost estimate imports the vehicle's contact
#: models and its default modal step (simulate.default_modal_step) for a vehicle case only: a
#: CONTACT deck's run does not load the vehicle area (~0.1 s, issue 33).
LAZY = frozenset(
    {
        ("railvti", "railvti.material"),
        ("railvti.runner.cost", "railvti.vehicle.contact_models"),
        ("railvti.runner.cost", "railvti.vehicle.simulate"),
        ("railvti.runner.cli", "railvti.casetypes"),
        ("railvti.runner.cli", "railvti.resources"),
        ("railvti.runner.cli", "railvti.runner.batch"),
        ("railvti.runner.cli", "railvti.runner.cost"),
        ("railvti.runner.cli", "railvti.runner.deck"),
        ("railvti.runner.cli", "railvti.runner.deck_registry"),
        ("railvti.runner.cli", "railvti.runner.output_lock"),
        ("railvti.runner.cli", "railvti.runner.plots"),
        ("railvti.runner.cli", "railvti.runner.summary"),
        ("railvti.runner.cli", "railvti.runner.sweeps"),
    }
)

RUNNER = "railvti.runner"
#: The physics packages and modules (they, and the floor, never import the runner).
PHYSICS = (
    "railvti.contact",
    "railvti.geometry",
    "railvti.track",
    "railvti.wheelset",
    "railvti.vehicle",
    "railvti.profiles",
    "railvti.scenarios",
    "railvti.critical_search",
    "railvti.envelope_criteria",
)


def _package_dir() -> Path:
    spec = importlib.util.find_spec("railvti")  # finds, does not import
    assert spec is not None and spec.submodule_search_locations, "railvti is not importable"
    return Path(list(spec.submodule_search_locations)[0])


def _modules(root: Path) -> dict[str, tuple[Path, bool]]:
    """Module name -> (file, is a package's __init__)."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = list(path.relative_to(root.parent).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts = parts[:-1]
        out[".".join(parts)] = (path, is_pkg)
    return out


def _targets(node: ast.Import | ast.ImportFrom, module: str, is_pkg: bool, modules: dict) -> list[str]:
    """The modules an import statement names (railvti's resolved to the module itself,
    a name imported from a package to its submodule when it is one; others as written)."""
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
    else:
        if node.level:
            base = module.split(".") if is_pkg else module.split(".")[:-1]
            base = base[: len(base) - (node.level - 1)]
            pkg = ".".join(base + ([node.module] if node.module else []))
        else:
            pkg = node.module or ""
        names = [f"{pkg}.{a.name}" if f"{pkg}.{a.name}" in modules else pkg for a in node.names]
    out = []
    for name in names:
        if name == "railvti" or name.startswith("railvti."):
            while name not in modules and "." in name:
                name = name.rsplit(".", 1)[0]
        out.append(name)
    return out


class _Imports(ast.NodeVisitor):
    def __init__(self, module: str, is_pkg: bool, modules: dict) -> None:
        self.module, self.is_pkg, self.modules = module, is_pkg, modules
        self.top: list[tuple[int, str]] = []  # (line, imported module)
        self.local: list[tuple[int, str]] = []
        self.depth = 0

    def _function(self, node: ast.AST) -> None:
        self.depth += 1
        self.generic_visit(node)
        self.depth -= 1

    visit_FunctionDef = visit_AsyncFunctionDef = visit_Lambda = _function

    def _import(self, node: ast.Import | ast.ImportFrom) -> None:
        for target in _targets(node, self.module, self.is_pkg, self.modules):
            (self.local if self.depth else self.top).append((node.lineno, target))

    visit_Import = visit_ImportFrom = _import


def _graph() -> tuple[dict[str, set[str]], list[tuple[str, int, str]], list[tuple[str, int, str]]]:
    modules = _modules(_package_dir())
    edges: dict[str, set[str]] = {m: set() for m in modules}
    every, local = [], []
    for name, (path, is_pkg) in modules.items():
        v = _Imports(name, is_pkg, modules)
        v.visit(ast.parse(path.read_text(encoding="utf-8"), str(path)))
        for _line, target in v.top:
            if target in modules and target != name:
                edges[name].add(target)
        every += [(name, line, t) for line, t in v.top + v.local]
        local += [(name, line, t) for line, t in v.local]
    return edges, every, local


GRAPH, EVERY, LOCAL = _graph()


def _circles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def _in(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


def test_the_reader_sees_the_package():
    """The graph is the package's: its layers are there and it has its known arrows."""
    assert {
        "railvti.runner.cli",
        "railvti.casetypes",
        "railvti.vehicle.simulate",
        "railvti.scenarios",
    } <= set(GRAPH)
    assert "railvti.casetypes" in GRAPH["railvti.runner.batch"]
    assert "railvti.vehicle.simulate" in GRAPH["railvti.vehicle.running"]
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_circle_among_the_module_level_imports():
    circles = _circles(GRAPH)
    assert not circles, "import circles: " + "; ".join(" <-> ".join(c) for c in circles)


def test_nothing_outside_the_runner_imports_it():
    wrong = [f"{m}:{line} imports {t}" for m, line, t in EVERY if not _in(m, RUNNER) and _in(t, RUNNER)]
    assert not wrong, "imports of the runner from below it:\n" + "\n".join(wrong)
    physics = [m for m in GRAPH if any(_in(m, p) for p in PHYSICS)]
    assert len(physics) > 40  # the physics is in the graph the check walked


@pytest.mark.parametrize("module, line, target", LOCAL, ids=[f"{m}:{line}:{t}" for m, line, t in LOCAL])
def test_an_import_inside_a_function_is_of_a_heavy_dependency_or_listed(module, line, target):
    if target.split(".")[0] in HEAVY or (module, target) in LAZY:
        return
    pytest.fail(
        f"{module}:{line} imports {target} inside a function: import it at the top "
        "(a circle it dodged is to be broken, not hidden)"
    )


def test_every_listed_lazy_import_is_still_there():
    """The allowance list does not outlive the imports it allows."""
    present = {(m, t) for m, _, t in LOCAL}
    assert LAZY <= present, f"listed but gone: {sorted(LAZY - present)}"
