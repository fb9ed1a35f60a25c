"""The docstring examples (``>>>``) of the public entry points, run by the default test suite.

A fixed list of modules, not ``--doctest-modules`` over ``src/``: collecting every module would
import optional dependencies. Each listed docstring must keep at least one example, and every
example must pass.
"""

from __future__ import annotations

import doctest
import importlib
import types

import pytest

#: Module -> the objects in it whose docstrings must carry examples.
EXAMPLES = {
    "sdn3d.render.rasterize": ("rasterize_meshes",),
    "sdn3d.render.soft": ("soft_silhouette",),
    "sdn3d.render.maps": ("normal_map", "pose_map", "render_scene_maps"),
    "sdn3d.math3d.encodings": ("AttributeEncoding",),
    "sdn3d.scene.code": ("SceneCode",),
    "sdn3d.editing.apply": ("apply_edits",),
    "sdn3d.resources": ("",),  # the module docstring
    "sdn3d.labels": ("",),
    "sdn3d.image_ops": ("",),
    "sdn3d.editing.photo.nearest": ("",),
}
OPTIONS = doctest.NORMALIZE_WHITESPACE


def run_doctests(module: types.ModuleType) -> tuple[doctest.TestResults, set[str], str]:
    """Run the examples of ``module``'s docstrings: ``(results, names of docstrings with examples, report)``."""
    tests = doctest.DocTestFinder(exclude_empty=True).find(module)
    runner = doctest.DocTestRunner(optionflags=OPTIONS, verbose=False)
    report: list[str] = []
    for test in sorted(tests, key=lambda t: t.name):
        runner.run(test, out=report.append)
    results = doctest.TestResults(runner.failures, runner.tries)
    return results, {t.name for t in tests if t.examples}, "".join(report)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_docstring_examples_pass(name: str) -> None:
    module = importlib.import_module(name)
    results, documented, report = run_doctests(module)
    assert results.failed == 0, f"{results.failed} of {results.attempted} examples of {name} failed:\n{report}"
    assert results.attempted > 0
    expected = {f"{name}.{obj}".rstrip(".") for obj in EXAMPLES[name]}
    assert expected <= documented, f"docstrings without examples: {sorted(expected - documented)}"


def test_a_broken_example_fails() -> None:
    module = types.ModuleType("sdn3d_doctest_probe")
    exec('def f():\n    """\n    >>> 1 + 1\n    3\n    """\n', module.__dict__)
    results, documented, report = run_doctests(module)
    assert results == (1, 1) and documented == {"sdn3d_doctest_probe.f"}
    assert "Expected:\n    3\nGot:\n    2" in report
