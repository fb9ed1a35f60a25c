# ruff: noqa: E501, E701, E702
"""neighbours.py REPLAY.json [...]: would "parallel neighbours face alike" tell the end? For every car of replay.py's
cars (main's fits), its same-frame neighbours with usable red lamps (their end is right on every tuning car) whose
fitted axis is within 30 degrees of the car's: whether all of them travel the same way as the car's truth, all the
opposite way, or mixed (the truth an oracle, for scoring only); counted by the car's own reading and whether its fit
is flipped (> 90 degrees off)."""
import json
import math
import sys
from collections import Counter, defaultdict

count = Counter()
for f in sys.argv[1:]:
    frames = defaultdict(list)
    for c in json.load(open(f))["cars"]: frames[c["src"]].append(c)
    for cars in frames.values():
        for c in cars:
            ry = c["hyps"][c["winner"]]["ry"]
            near = [d for d in cars if d is not c and d["lamp"][0] and d["lamp"][1]
                    and abs(math.cos(d["hyps"][d["winner"]]["ry"] - ry)) > math.cos(math.radians(30))]
            if not near: continue
            same = [math.cos(d["true_ry"] - c["true_ry"]) > 0 for d in near]
            way = "same way" if all(same) else "opposite" if not any(same) else "mixed"
            own = "red present" if c["lamp"][0] and c["lamp"][1] else "other reading"
            count[(own, way, "flipped" if c["err"] > 90 else "not flipped")] += 1
for k, v in sorted(count.items()): print(*k, v, sep=" | ")
