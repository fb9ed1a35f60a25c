# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""tables.py A.json B.json ...: flips (> 90 degrees) and median yaw error of row gt_fit per cutcars.py output, and
the paired change between runs that share a tree (by car), with a bootstrap interval over frames."""
import json, sys, random, statistics as st
from collections import defaultdict

def load(p):
    return {(r["frame"], r["id"]): r for r in json.load(open(p))}

def summary(rows):
    rows = list(rows.values())
    fl = sum(r["yaw_deg"] > 90 for r in rows)
    cut = [r for r in rows if r["side"] != 0]
    return f"n {len(rows)} flips {fl} ({100 * fl / len(rows):.1f} %) median {st.median(r['yaw_deg'] for r in rows):.1f} deg; cut {len(cut)} flipped {sum(r['yaw_deg'] > 90 for r in cut)}; net right {sum(r['net_true'] > r['net_rev'] for r in rows)}/{len(rows)} (cut {sum(r['net_true'] > r['net_rev'] for r in cut)}/{len(cut)})"

def paired(a, b, reps=4000, seed=0):
    keys = sorted(set(a) & set(b))
    frames = defaultdict(list)
    for k in keys:
        frames[k[0]].append((a[k]["yaw_deg"] > 90) - (b[k]["yaw_deg"] > 90))
    fr = list(frames.values())
    tot = sum(sum(v) for v in fr)
    rng = random.Random(seed)
    boots = []
    for _ in range(reps):
        s = [fr[rng.randrange(len(fr))] for _ in fr]
        boots.append(sum(sum(v) for v in s) / max(1, sum(len(v) for v in s)))
    boots.sort()
    fixed = sum(1 for k in keys if a[k]["yaw_deg"] > 90 and b[k]["yaw_deg"] <= 90)
    broke = sum(1 for k in keys if a[k]["yaw_deg"] <= 90 and b[k]["yaw_deg"] > 90)
    return f"flip rate A-B {100 * tot / len(keys):+.1f} pts [{100 * boots[int(0.025 * reps)]:+.1f}, {100 * boots[int(0.975 * reps)]:+.1f}] over {len(fr)} frames; B fixes {fixed}, breaks {broke}"

if __name__ == "__main__":
    for p in sys.argv[1:]:
        print(p, summary(load(p)))
