# ruff: noqa: E501
"""flipped.py: the cars row gt_fit turned end for end (yaw error > 90 degrees) against the others, from
pose_2339.json.gz and pose_2341.json.gz (beside this script): visible pixels, cut by the image border (`truncated`), the
true observation angle |alpha| (alpha = ry - atan2(x, z), degrees; about 90: seen end on) and true template."""
import gzip
import json
import math
import os
import statistics as st

HERE = os.path.dirname(os.path.abspath(__file__))


def alpha(x):
    a = x["true_ry"] - math.atan2(x["true_xz"][0], x["true_xz"][1])
    return abs(math.degrees(math.atan2(math.sin(a), math.cos(a))))


for seed in ("2339", "2341"):
    rows = json.load(gzip.open(os.path.join(HERE, f"pose_{seed}.json.gz")))["objects"]["fit, oracle: ground-truth masks + boxes"]
    flipped, kept = [x for x in rows if x["yaw_deg"] > 90], [x for x in rows if x["yaw_deg"] <= 90]
    print(f"{seed}: {len(flipped)} flipped of {len(rows)}; cut by the border {sum(x['truncated'] for x in flipped)} of "
          f"{len(flipped)} against {sum(x['truncated'] for x in kept)} of {len(kept)}; median pixels {st.median([x['pixels'] for x in flipped]):.0f} "
          f"against {st.median([x['pixels'] for x in kept]):.0f}; |alpha| flipped {sorted(round(alpha(x)) for x in flipped)}, "
          f"the others' quartiles {[round(q) for q in st.quantiles([alpha(x) for x in kept], n=4)]}")
