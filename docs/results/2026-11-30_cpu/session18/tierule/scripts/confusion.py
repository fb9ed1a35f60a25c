# ruff: noqa: E501, E701, E702
"""confusion.py LABEL REPLAY.json [REPLAY.json ...]: the fit's templates (the first variant of each replay.py output,
main's fit) against the truth's (an oracle, for scoring only): rows truth, columns fit, counts of cars."""
import json
import sys
from collections import Counter

from sdn3d.meshes.templates import TEMPLATE_NAMES

label, files = sys.argv[1], sys.argv[2:]
pairs = Counter()
for f in files:
    for c in json.load(open(f)):
        pairs[c["truth_tpl"], next(iter(c["fits"].values()))["tpl"]] += 1
short = [n[:5] for n in TEMPLATE_NAMES]
print(f"== {label}: {sum(pairs.values())} cars; rows: truth, columns: main's fit")
print("truth \\ fit " + " ".join(f"{n:>6}" for n in short) + "  right")
for t, name in enumerate(TEMPLATE_NAMES):
    row = [pairs[t, f] for f in range(len(TEMPLATE_NAMES))]
    if sum(row): print(f"{name:11s} " + " ".join(f"{v:6d}" for v in row) + f"  {row[t] / sum(row):.2f}")
