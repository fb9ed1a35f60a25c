"""paired.py JSON...: photo_latency.py runs with a `rays` column (ray_vanishing=telea, the default) and a `near` column
(ray_vanishing=near), edit by edit: per kind the median CPU ms of each and, over all edits, the geometric mean of the
per-edit CPU ratio rays / near with a 10,000-resample bootstrap 95 % interval (seed 0) and how many edits were
faster."""
import json
import math
import random
import statistics
import sys

pairs = []
for path in sys.argv[1:]:
    d = json.load(open(path))
    pairs += [(a[0], a[2], b[2]) for a, b in zip(d["rays"], d["near"], strict=True)]
for kind in ["all"] + sorted({p[0] for p in pairs}):
    sel = [p for p in pairs if kind == "all" or p[0] == kind]
    print(f"{kind:17s} n {len(sel):2d}  median CPU ms telea {statistics.median(p[1] for p in sel):6.0f}  "
          f"near {statistics.median(p[2] for p in sel):6.0f}")
logs = [math.log(p[1] / p[2]) for p in pairs]
rng = random.Random(0)
means = sorted(statistics.fmean(rng.choices(logs, k=len(logs))) for _ in range(10000))
print(f"CPU ratio telea / near, geometric mean over {len(logs)} edits: {math.exp(statistics.fmean(logs)):.3f} "
      f"[{math.exp(means[249]):.3f}, {math.exp(means[9749]):.3f}]; telea faster in {sum(v < 0 for v in logs)}")
