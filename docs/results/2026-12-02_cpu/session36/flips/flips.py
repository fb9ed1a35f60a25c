# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""flips.py POSE_JSON...: rows gt_fit and pred_fit of benchmarks/pose_table.py outputs (one held-out tree each): per
tree and pooled, flips (yaw error over 90 degrees; on pred_fit an unmatched car counts as flipped, as the table counts
it) with a 95 % bootstrap interval resampling frames (4,000 resamples, seed 0), and the median yaw error."""
import gzip, json, random, sys, statistics as st
from collections import defaultdict
ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}

def load(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return json.load(f)

def interval(frames, reps=4000, seed=0):
    rng = random.Random(seed)
    fr = list(frames.values())
    boots = []
    for _ in range(reps):
        s = [fr[rng.randrange(len(fr))] for _ in fr]
        boots.append(sum(sum(v) for v in s) / max(1, sum(len(v) for v in s)))
    boots.sort()
    return 100 * boots[int(0.025 * reps)], 100 * boots[int(0.975 * reps)]

pooled = {k: defaultdict(list) for k in ROWS}
yaws = {k: [] for k in ROWS}
for path in sys.argv[1:]:
    data = load(path)
    tree = path.split("_")[-1].split(".")[0]
    for short, row in ROWS.items():
        objs = data["objects"][row]
        frames = defaultdict(list)
        for o in objs:
            frames[(tree, o["frame"])].append(o["yaw_deg"] > 90)
            pooled[short][(tree, o["frame"])].append(o["yaw_deg"] > 90)
            yaws[short].append(o["yaw_deg"])
        n = len(objs); f = sum(o["yaw_deg"] > 90 for o in objs)
        print(f"{tree} {short}: {f} of {n} cars flipped ({100 * f / n:.1f} %), median yaw error {st.median(o['yaw_deg'] for o in objs):.1f} deg, {len(frames)} frames")
for short in ROWS:
    fr = pooled[short]
    n = sum(len(v) for v in fr.values()); f = sum(sum(v) for v in fr.values())
    lo, hi = interval(fr)
    print(f"pooled {short}: {f} of {n} cars flipped ({100 * f / n:.1f} % [{lo:.1f}, {hi:.1f}], bootstrap over {len(fr)} frames), median yaw error {st.median(yaws[short]):.1f} deg")
