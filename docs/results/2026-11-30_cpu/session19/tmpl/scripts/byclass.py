# ruff: noqa: E501, E702
"""byclass.py DIAG_DIR REF TAG: per row (semantic proposals, ground-truth masks (oracle)), the three tuning trees'
cars pooled (diag.py outputs DIAG_DIR/{semantic,gt}{35,37,31}_{REF,TAG}.json), per true template: cars, cars the
variant TAG gets right that REF gets wrong, and the reverse (the truth an oracle, for scoring only)."""
import json
import sys
from collections import Counter

from sdn3d.meshes.templates import TEMPLATE_NAMES

folder, ref, tag = sys.argv[1:4]
for row in ("semantic", "gt"):
    a = [c for s in ("35", "37", "31") for c in json.load(open(f"{folder}/{row}{s}_{ref}.json"))]
    b = [c for s in ("35", "37", "31") for c in json.load(open(f"{folder}/{row}{s}_{tag}.json"))]
    n, won, lost = Counter(), Counter(), Counter()
    for x, y in zip(a, b, strict=True):
        t = TEMPLATE_NAMES[x["truth_tpl"]]; n[t] += 1
        ra, rb = x["fit_tpl"] == x["truth_tpl"], y["fit_tpl"] == y["truth_tpl"]
        won[t] += rb and not ra; lost[t] += ra and not rb
    print(f"{row}: {tag} against {ref}, truth: cars +won/-lost: " + ", ".join(f"{t} {n[t]} +{won[t]}/-{lost[t]}" for t in TEMPLATE_NAMES if n[t]))
