"""kinds.py TREE [KIND...]: comma-separated indices of the Table 1 tree's entries whose edit_kind is one of KIND
(default delete and occluder_removed), for dbench.py's ONLY=. Run with PYTHONPATH=<code>/src."""
import os
import sys

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.evaluation.edit_benchmark import edit_kind

tree = sys.argv[1]
wanted = set(sys.argv[2:]) or {"delete", "occluder_removed"}
entries = load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))
print(",".join(str(i) for i, e in enumerate(entries) if e.operations and edit_kind(e) in wanted))
