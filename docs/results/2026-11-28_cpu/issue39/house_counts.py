"""Issue 39's counts of a source tree: the largest modules and functions, the functions over 80 lines, and the
comparisons against string constants (``==``, ``!=``, ``in``), with those that name an appearance or proposals.

    .venv/bin/python docs/results/2026-11-28_cpu/issue39/house_counts.py TREE
"""

import ast
import re
import sys
from pathlib import Path

APPEARANCE = re.compile(r"appearance|\"photo\"|'photo'|\"generator\"")
PROPOSALS = re.compile(r"proposals|\"boxes\"|\"gt\"|\"semantic\"")


def is_string_comparison(node: ast.Compare) -> bool:
    if not any(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops):
        return False
    sides = [node.left, *node.comparators]
    if any(isinstance(c, ast.Constant) and isinstance(c.value, str) for c in sides):
        return True
    return any(isinstance(c, (ast.Tuple, ast.List, ast.Set)) and c.elts
               and all(isinstance(e, ast.Constant) and isinstance(e.value, str) for e in c.elts)
               for c in node.comparators)


def main(root: Path) -> None:
    files = [p for d in ("src", "lightning_modules", "datamodules", "benchmarks") for p in (root / d).rglob("*.py")]
    funcs, mods, count, appearance, proposals = [], [], 0, [], []
    for path in files:
        text = path.read_text()
        rel = str(path.relative_to(root))
        mods.append((len(text.splitlines()), rel))
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                funcs.append((node.end_lineno - node.lineno + 1, f"{rel}:{node.name}"))
            if isinstance(node, ast.Compare) and is_string_comparison(node):
                count += 1
                src = ast.get_source_segment(text, node) or ""
                if APPEARANCE.search(src):
                    appearance.append(f"{rel}:{node.lineno}: {src[:80]}")
                if PROPOSALS.search(src):
                    proposals.append(f"{rel}:{node.lineno}: {src[:80]}")
    funcs.sort(reverse=True)
    mods.sort(reverse=True)
    print("largest modules:", mods[:6])
    print("largest functions:", funcs[:8])
    print("functions over 80 lines:", sum(1 for n, _ in funcs if n > 80))
    print("string comparisons (==, !=, in against str constants):", count)
    for name, sites in (("appearance", appearance), ("proposals", proposals)):
        print(f"{name} comparisons: {len(sites)}")
        for site in sites:
            print("  ", site)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
