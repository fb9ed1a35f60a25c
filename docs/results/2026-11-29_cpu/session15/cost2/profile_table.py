"""Per-function table of a draw_edits.py cProfile (session14/cost/draw_edits.py --profile): the functions of sdn3d and
torch's, NumPy's and OpenCV's builtins with the most total (tottime) or cumulative time, in ms per edit.

    python profile_table.py EDITS.prof [N_EDITS] [TOP]
"""

import pstats
import sys

stats = pstats.Stats(sys.argv[1]).stats
edits = int(sys.argv[2]) if len(sys.argv) > 2 else 14
top = int(sys.argv[3]) if len(sys.argv) > 3 else 30
rows = []
for (path, line, name), (_, calls, tottime, cumtime, _) in stats.items():
    where = f"{path.split('/src/')[-1]}:{line}({name})" if "sdn3d" in path else name
    rows.append((where, calls / edits, 1000 * tottime / edits, 1000 * cumtime / edits))
for title, key in (("cumulative", 3), ("own (tottime)", 2)):
    print(f"top {top} by {title} time, ms per edit (calls per edit)")
    for where, calls, own, cum in sorted(rows, key=lambda r: -r[key])[:top]:
        print(f"  {cum:8.1f} cum {own:7.1f} own {calls:7.1f} calls  {where}")
