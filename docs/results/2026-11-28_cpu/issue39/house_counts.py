"""Counts for issue 39's figures: largest modules/functions, functions over 80 lines, string mode comparisons."""
import ast, sys, re
from pathlib import Path
root = Path(sys.argv[1])
files = [p for d in ("src", "lightning_modules", "datamodules", "benchmarks") for p in (root / d).rglob("*.py")]
funcs, mods, cmp_count = [], [], 0
appearance_sites, proposals_sites = [], []
for p in files:
    text = p.read_text(); tree = ast.parse(text); rel = str(p.relative_to(root))
    mods.append((len(text.splitlines()), rel))
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            funcs.append((node.end_lineno - node.lineno + 1, f"{rel}:{node.name}"))
        if isinstance(node, ast.Compare) and any(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops):
            consts = [c for c in [node.left, *node.comparators] if isinstance(c, ast.Constant) and isinstance(c.value, str)]
            tuples = [c for c in node.comparators if isinstance(c, (ast.Tuple, ast.List, ast.Set)) and c.elts and all(isinstance(e, ast.Constant) and isinstance(e.value, str) for e in c.elts)]
            if consts or tuples:
                cmp_count += 1
                src = ast.get_source_segment(text, node) or ""
                if re.search(r"appearance|\"photo\"|'photo'|\"generator\"", src):
                    appearance_sites.append(f"{rel}:{node.lineno}: {src[:80]}")
                if re.search(r"proposals|\"boxes\"|\"gt\"|\"semantic\"", src):
                    proposals_sites.append(f"{rel}:{node.lineno}: {src[:80]}")
funcs.sort(reverse=True); mods.sort(reverse=True)
print("largest modules:", mods[:6]); print("largest functions:", funcs[:8])
print("functions over 80 lines:", sum(1 for n, _ in funcs if n > 80))
print("string comparisons (==, !=, in against str constants):", cmp_count)
print(f"appearance comparisons: {len(appearance_sites)}"); [print("  ", s) for s in appearance_sites]
print(f"proposals comparisons: {len(proposals_sites)}"); [print("  ", s) for s in proposals_sites]
