# ruff: noqa: E501, E701, E702
"""cues.py LABEL REPLAY.json [...]: how often each appearance cue names the right end, per reading (replay.py's cars;
the truth an oracle, for scoring only): at the true local orientation alpha, the sign of the lamps' evidence
(lamps.evidence_of of the recorded reading) and of the net's bins (at the fine hypothesis nearest the truth, when
within 30 degrees). A cue is right where its sign is positive (it favours the true end over its reverse); 0: abstains.
Cars seen nearly side on (|sin alpha| < 0.3) are counted apart: the lamps' side term decides there."""
import json
import math
import sys
from collections import defaultdict

import torch

from sdn3d.geometric.lamps import LampCue, evidence_of

label, files = sys.argv[1], sys.argv[2:]
cars = [c for f in files for c in json.load(open(f))["cars"]]
cue = LampCue()
tab = defaultdict(lambda: [0, 0, 0])  # right, wrong, abstain
for c in cars:
    a = torch.tensor([[c["true_alpha"]]], dtype=torch.float64)
    p, u, o = c["lamp"]
    front = None if c["front"] is None else (torch.tensor([c["front"][0]]), torch.tensor([c["front"][1]]), torch.tensor([float(c["front"][2])], dtype=torch.float64))
    ev = float(evidence_of(torch.tensor([p]), torch.tensor([u]), torch.tensor([o], dtype=torch.float64), a, cue, front=front))
    if u: kind = "red present" if p else "red absent"
    elif c["front"] and c["front"][1]: kind = "red body, white present" if c["front"][0] else "red body, white absent"
    else: kind = "no reading (red present, unusable)" if p else "no reading (small)"
    view = "side" if abs(math.sin(c["true_alpha"])) < 0.3 else ("back" if math.sin(c["true_alpha"]) < 0 else "front")
    near = [h for h in c["hyps"] if h["err"] <= 30]
    net = min(near, key=lambda h: h["err"])["net"] if near else None
    for k in (f"lamps | {kind} | {view}", f"lamps | {kind}", "lamps | all"):
        tab[k][0 if ev > 1e-6 else 1 if ev < -1e-6 else 2] += 1
    if net is not None:
        for k in (f"net | {kind}", "net | all", f"net | {view}"):
            tab[k][0 if net > 0 else 1 if net < 0 else 2] += 1
    if net is not None:
        b = ev + c["net_weight"] * net
        tab["belief (lamps + w net) | all"][0 if b > 0 else 1 if b < 0 else 2] += 1
print(f"== {label}: {len(cars)} cars; right / wrong / abstains at the truth's end")
for k in sorted(tab):
    r, w, z = tab[k]; print(f"  {k:60} {r:4d} {w:4d} {z:4d}   right {r / max(r + w, 1):.2f}")
