"""Byte identity of two codes' outputs: two draw_edits.py .npz files (every array equal, same dtype), or two output
trees (every file byte-identical; a JSON file that differs is compared leaf by leaf, NaN equal to NaN, and its
differing leaves are listed apart where they are timings or paths).

    python same_outputs.py A.npz B.npz
    python same_outputs.py TREE_A TREE_B
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

#: leaves whose last key holds one of these are timings or paths, expected to differ between two runs
VOLATILE = ("ms", "_s", "time", "seconds", "wall", "cpu", "output_dir", "dir", "path", "image", "input", "edits")


def leaves(a, b, path: str, out: list[tuple[str, bool]]) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            leaves(a.get(k), b.get(k), f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            leaves(x, y, f"{path}[{i}]", out)
    else:
        nan = isinstance(a, float) and isinstance(b, float) and a != a and b != b
        out.append((path, a == b or nan))


def volatile_key(path: str) -> str | None:
    """The first key of a JSON leaf's ``path`` that names a timing or a path (None: none does)."""
    keys = path.replace("[", "/").split("/")
    return next((k for k in keys if any(v in k.lower() for v in VOLATILE)), None)


def compare_npz(a: Path, b: Path) -> None:
    x, y = np.load(a), np.load(b)
    keys = sorted(set(x.files) | set(y.files))
    bad = [k for k in keys if k not in x.files or k not in y.files or x[k].dtype != y[k].dtype
           or not np.array_equal(x[k], y[k])]
    print(f"{len(keys)} arrays, {len(bad)} differ: {bad[:10]}")


def compare_trees(a: Path, b: Path) -> None:
    files = sorted({p.relative_to(a) for p in a.rglob("*") if p.is_file()}
                   | {p.relative_to(b) for p in b.rglob("*") if p.is_file()})
    same, differ = 0, []
    for rel in files:
        pa, pb = a / rel, b / rel
        if pa.is_file() and pb.is_file() and pa.read_bytes() == pb.read_bytes():
            same += 1
            continue
        differ.append(rel)
    print(f"{len(files)} files: {same} byte-identical, {len(differ)} differ")
    for rel in differ:
        pa, pb = a / rel, b / rel
        if rel.suffix != ".json" or not (pa.is_file() and pb.is_file()):
            print(f"  {rel}: DIFFERS (not JSON or missing on one side)")
            continue
        out: list[tuple[str, bool]] = []
        leaves(json.loads(pa.read_text()), json.loads(pb.read_text()), "", out)
        bad = [p for p, ok in out if not ok]
        volatile = [p for p in bad if volatile_key(p) is not None]
        real = [p for p in bad if p not in volatile]
        print(f"  {rel}: {len(out)} leaves, {len(real)} differ outside timings/paths {real[:6]}; "
              f"timings/paths differing ({len(volatile)}): {sorted({volatile_key(p) for p in volatile})[:8]}")


if __name__ == "__main__":
    a, b = Path(sys.argv[1]), Path(sys.argv[2])
    (compare_npz if a.suffix == ".npz" else compare_trees)(a, b)
