# ruff: noqa: E401, E402, E501, E701, E702, I001, F401
"""probe_parts.py: wraps dbench.py (python probe_parts.py dbench.py CACHE DUMP BENCH_ARGS...); see the README's 'Tried' section."""
import runpy, sys
import torch
import sdn3d.editing.photo.transfer as tr
orig = tr._part_colors
def pc(b, own, seen_colors, points, normals, parts, before, body, others=None, max_examples=1500, k=4):
    for part in (0, 1):
        have = (own.part == part)
        q = parts == part
        if q.any() and have.any():
            near = tr._nearest_examples(tr._part_features(before, b, points, normals)[q], own.feature[have], k)
            used = near.flatten().unique()
            print(f"part {part}: {int(have.sum())} examples, mean colour {own.color[have].mean(0).mul(255).round().tolist()}, used {len(used)} mean {own.color[have][used].mean(0).mul(255).round().tolist()}; ex features mean {own.feature[have].mean(0).round(decimals=2).tolist()}; query feat mean {tr._part_features(before, b, points, normals)[q].mean(0).round(decimals=2).tolist()}; used feat {own.feature[have][used].mean(0).round(decimals=2).tolist()}", file=sys.stderr)
    return orig(b, own, seen_colors, points, normals, parts, before, body, others, max_examples, k)
tr._part_colors = pc
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
