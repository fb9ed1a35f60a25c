"""Reference files of the 3D-SDN paper, shipped with sdn3d as package data.

- ``vkitti_edit_benchmark.json``: the paper's Virtual KITTI editing benchmark (Table 1) as released
  with the authors' code: 184 entries, the 92 edited image pairs followed by 92 identity entries
  (format: :mod:`sdn3d.data.edit_benchmark`). ``sdn3d-bench benchmark=paper`` evaluates it.
- ``vkitti_edit_example.json``: the released example, five rotations of one car of Virtual KITTI
  frame ``0006/30-deg-right/00043``.
- ``LICENSE-3D-SDN.txt``: the licence of the authors' release (Yao, Hsu, Zhu and Wu, 2018), under
  whose BSD 3-Clause terms (its first section) the two JSON files are redistributed unchanged; the
  file also reproduces the licences of the third-party code that release bundled.

Read them through :func:`resource_path` (or :func:`paper_benchmark_path` /
:func:`paper_example_path`), which works for editable installs, wheels and zipped installs alike::

    >>> from sdn3d.data.edit_benchmark import load_edit_benchmark
    >>> len(load_edit_benchmark(paper_benchmark_path()))
    184
"""

from __future__ import annotations

import atexit
from contextlib import ExitStack
from importlib.resources import as_file, files
from pathlib import Path

__all__ = [
    "PAPER_BENCHMARK",
    "PAPER_EXAMPLE",
    "PAPER_LICENSE",
    "RESOURCES",
    "resource_path",
    "paper_benchmark_path",
    "paper_example_path",
]

PAPER_BENCHMARK = "vkitti_edit_benchmark.json"
PAPER_EXAMPLE = "vkitti_edit_example.json"
PAPER_LICENSE = "LICENSE-3D-SDN.txt"
#: Every file of this package's data.
RESOURCES = (PAPER_BENCHMARK, PAPER_EXAMPLE, PAPER_LICENSE)

# Files extracted from a zipped install stay on disk until the interpreter exits.
_extracted = ExitStack()
atexit.register(_extracted.close)


def resource_path(name: str) -> Path:
    """A file system path of the shipped file ``name`` (one of :data:`RESOURCES`).

    Raises ``ValueError`` for an unknown name and ``FileNotFoundError`` if the installation lacks
    the file (a build that dropped the package data).
    """
    if name not in RESOURCES:
        raise ValueError(f"unknown sdn3d resource {name!r}; shipped: {', '.join(RESOURCES)}")
    resource = files(__name__) / name
    if not resource.is_file():
        raise FileNotFoundError(f"sdn3d resource {name!r} is missing from the installation ({resource})")
    if isinstance(resource, Path):
        return resource
    return _extracted.enter_context(as_file(resource))


def paper_benchmark_path() -> Path:
    """Path of the paper's editing benchmark, ``vkitti_edit_benchmark.json``."""
    return resource_path(PAPER_BENCHMARK)


def paper_example_path() -> Path:
    """Path of the released editing example, ``vkitti_edit_example.json``."""
    return resource_path(PAPER_EXAMPLE)
