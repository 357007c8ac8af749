"""The package's layers, read from its source with ``ast``: no import cycle among its
modules, and each layer imports only from the layers below it.

Layers, lowest first: ``sph.schema`` (configuration schema machinery, no project imports),
``sph.engine`` (the numerical core), ``sph.bodies`` and ``sph.io``, ``sph.cases``,
``sph.driver``, ``sph.study``, ``sph.cli``.
"""

import ast
import functools
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "sph"

#: layer rank of each top-level part of the package; a module may import only from parts
#: of a lower rank, or from its own part
RANK = {"sph": 0, "sph.schema": 0, "sph.engine": 1, "sph.bodies": 2, "sph.io": 2,
        "sph.cases": 3, "sph.driver": 4, "sph.study": 5, "sph.cli": 6}


def _module_name(path: Path) -> str:
    rel = path.relative_to(ROOT.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Project modules imported by the file, anywhere in it (top level or in functions)."""
    return _imports_of(path.read_text(encoding="utf-8"), _module_name(path),
                       path.name == "__init__.py")


def _imports_of(source: str, name: str, is_package: bool) -> set[str]:
    tree = ast.parse(source)
    package = name if is_package else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.split(".")[0] == "sph")
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if mod.split(".")[0] != "sph":
                continue
            for a in node.names:  # ``from sph.study import sweeps`` imports sph.study.sweeps
                sub = f"{mod}.{a.name}"
                out.add(sub if _exists(sub) else mod)
    return out


def _exists(module: str) -> bool:
    rel = Path(*module.split("."))
    return (ROOT.parent / rel.with_suffix(".py")).is_file() or (
        ROOT.parent / rel / "__init__.py").is_file()


@functools.lru_cache(maxsize=1)
def _graph() -> dict[str, set[str]]:
    return {_module_name(p): _imports(p) for p in sorted(ROOT.rglob("*.py"))}


def _part(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2]) if len(parts) > 1 else parts[0]


def test_every_module_has_a_layer():
    missing = sorted({_part(m) for m in _graph()} - set(RANK))
    assert not missing, f"modules outside every layer: {missing}"


def test_no_import_cycle():
    graph = {m: {i for i in deps if i in _graph()} for m, deps in _graph().items()}
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(m):
        state[m] = 1
        path.append(m)
        for d in sorted(graph.get(m, ())):
            if d == m or d == "sph":
                continue
            if state.get(d) == 1:
                cycle = path[path.index(d):] + [d]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if d not in state:
                visit(d)
        path.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)


@pytest.mark.parametrize("module", sorted(_graph()))
def test_imports_only_from_lower_layers(module):
    own = _part(module)
    bad = sorted(i for i in _graph()[module]
                 if _part(i) != own and i != "sph" and RANK[_part(i)] >= RANK[own])
    assert not bad, f"{module} (layer {own}) imports from the same or a higher layer: {bad}"


def test_schema_imports_nothing_from_the_project():
    assert _imports(ROOT / "schema.py") == set()


def test_engine_imports_nothing_above_it():
    """The check the architecture rests on, stated on its own: ``sph.engine`` imports only
    ``sph.schema`` and itself."""
    for path in sorted((ROOT / "engine").rglob("*.py")):
        above = sorted(i for i in _imports(path)
                       if not (i.startswith("sph.engine") or i in ("sph.schema", "sph")))
        assert not above, f"{_module_name(path)} imports {above}"


def test_the_reader_sees_every_form_of_import():
    """Relative, absolute and function-level imports all count."""
    source = ("import sph.io.output\nfrom . import kernels\n"
              "def f():\n    from sph.cases import CASES\n    from ..study import sweeps\n")
    assert _imports_of(source, "sph.engine.probe", False) == {
        "sph.io.output", "sph.engine.kernels", "sph.cases", "sph.study.sweeps"}


def test_importing_the_engine_loads_no_layer_above_it():
    """At run time too: a fresh interpreter that imports every engine module has loaded no
    module of ``sph.bodies``, ``sph.io``, ``sph.cases``, ``sph.study``, ``sph.driver`` or
    ``sph.cli``."""
    engine = sorted(_module_name(p) for p in (ROOT / "engine").glob("*.py"))
    code = ("import importlib, sys\n"
            f"for m in {engine!r}:\n    importlib.import_module(m)\n"
            "print(' '.join(sorted(m for m in sys.modules if m.startswith('sph'))))\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT.parent))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, timeout=120, check=True).stdout.split()
    assert set(engine) <= set(out)
    above = [m for m in out if _part(m) not in ("sph", "sph.schema", "sph.engine")]
    assert not above, f"importing the engine loaded {above}"
