# ruff: noqa: E501
"""kindcount.py TREE...: per Table 1 tree, how many entries of each edit kind (entries with operations; the bench
skips the others) and how many without operations. Run with PYTHONPATH=<plain tree>/src."""
import collections
import os
import sys

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.evaluation.edit_benchmark import edit_kind

for tree in sys.argv[1:]:
    entries = load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))
    c = collections.Counter(edit_kind(e) if e.operations else "(no operations)" for e in entries)
    print(os.path.basename(tree), len(entries), dict(sorted(c.items())))
