"""The floor plan of docs/ARCHITECTURE.md, checked on the code: no import cycle, the ground floor imports
nothing above it, the library never imports Lightning, and the inference path never reads a dataset."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"


def _modules() -> dict[str, Path]:
    out = {}
    for path in (SRC / "sdn3d").rglob("*.py"):
        parts = path.relative_to(SRC).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


MODULES = _modules()


def _imports(name: str) -> set[str]:
    """Every sdn3d module ``name`` imports, at the top or inside a function (a cycle hidden in a
    function-local import is still a cycle)."""
    found = set()
    for node in ast.walk(ast.parse(MODULES[name].read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            targets = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
            continue
        found.update(t for t in targets if t in MODULES and t != name)
    return found


def _cycles() -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    graph = {m: _imports(m) for m in MODULES}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_no_import_cycle():
    assert _cycles() == []


def test_the_cycle_check_finds_a_cycle(monkeypatch):
    graph_of = {"sdn3d.a": {"sdn3d.b"}, "sdn3d.b": {"sdn3d.a"}}
    monkeypatch.setattr(sys.modules[__name__], "MODULES", dict.fromkeys(graph_of, Path()))
    monkeypatch.setattr(sys.modules[__name__], "_imports", lambda name: graph_of[name])
    assert _cycles() == [["sdn3d.a", "sdn3d.b"]]


GROUND_FLOOR = ("sdn3d.errors", "sdn3d.labels", "sdn3d.math3d", "sdn3d.resources")


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith(GROUND_FLOOR)))
def test_ground_floor_imports_only_the_ground_floor(module):
    above = sorted(m for m in _imports(module) if not m.startswith(GROUND_FLOOR))
    assert above == [], f"{module} imports {above}"


def test_library_never_imports_training_orchestration():
    """Only the command-line entry points (sdn3d.cli) may start training runs."""
    for name in (m for m in MODULES if not m.startswith("sdn3d.cli")):
        tree = ast.parse(MODULES[name].read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                assert node.module.split(".")[0] not in ("lightning", "lightning_modules", "datamodules"), name
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    assert alias.name.split(".")[0] not in ("lightning", "lightning_modules", "datamodules"), name


INFERENCE = ("sdn3d.derender", "sdn3d.scene.maps", "sdn3d.scene.io", "sdn3d.editing.render", "sdn3d.editing.spec",
             "sdn3d.textural.renderer", "sdn3d.semantic.predict", "sdn3d.geometric.predict", "sdn3d.export")
ALLOWED_DATA = {"sdn3d.data", "sdn3d.data.edit_benchmark", "sdn3d.data.errors"}


def test_inference_path_reads_no_dataset():
    """Imported in a fresh interpreter: which sdn3d.data modules (readers, Datasets) come along."""
    code = ("import importlib, sys\n"
            f"for m in {INFERENCE!r}: importlib.import_module(m)\n"
            "print('\\n'.join(sorted(m for m in sys.modules if m.startswith('sdn3d.data') or m == 'lightning'\n"
            "                      or m.startswith(('lightning.', 'lightning_modules', 'datamodules')))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert set(out) <= ALLOWED_DATA, sorted(set(out) - ALLOWED_DATA)


def test_edit_command_starts_without_trimesh_or_scipy():
    """``sdn3d-edit`` start-up time (issue 19): the edit path builds the template bank from arrays and grows regions
    with torch; trimesh (glTF, with ``diagnostics=true``) and scipy (amodal fill, point matching) load when used."""
    code = ("import sys, sdn3d.cli.edit, sdn3d.editing.render, sdn3d.derender\n"
            "from sdn3d.meshes.bank import MeshBank\n"
            "MeshBank.templates()\n"
            "print(' '.join(sorted({m.split('.')[0] for m in sys.modules} & {'trimesh', 'scipy'})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert out == []
