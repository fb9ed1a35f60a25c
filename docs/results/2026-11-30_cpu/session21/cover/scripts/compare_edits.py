"""Compare two draw_edits.py outputs (main's first, the branch's second) edit by edit: how many pixels of the picture
differ, whether every one of them is a fill pixel in both (source code ``fill``: where the rays' fill shows), the
largest and mean difference there (0-255 levels), and whether the source and part maps are equal.

    python compare_edits.py MAIN.npz BRANCH.npz
"""

import sys

import numpy as np

from sdn3d.editing.photo.settings import SOURCE_NAMES

FILL = SOURCE_NAMES.index("fill")
main, branch = np.load(sys.argv[1]), np.load(sys.argv[2])
print("| edit | pixels differing | all in the fill (both) | max diff | mean diff there | fill pixels (main) | "
      "source map equal | parts equal |")
print("|---|---|---|---|---|---|---|---|")
edits = sorted(int(k[5:]) for k in main.files if k.startswith("image"))
for i in edits:
    a, b = main[f"image{i}"].astype(np.int32), branch[f"image{i}"].astype(np.int32)
    sa, sb = main[f"source{i}"], branch[f"source{i}"]
    diff = np.abs(a - b).max(0)
    where = diff > 0
    fill = (sa == FILL) & (sb == FILL)
    parts = f"parts{i}"
    same_parts = (parts in main.files) == (parts in branch.files) and (
        parts not in main.files or np.array_equal(main[parts], branch[parts]))
    print(f"| {i} | {int(where.sum())} | {bool((~where | fill).all())} | {int(diff.max())} | "
          f"{float(diff[where].mean()) if where.any() else 0.0:.2f} | {int((sa == FILL).sum())} | "
          f"{bool(np.array_equal(sa, sb))} | {same_parts} |")
