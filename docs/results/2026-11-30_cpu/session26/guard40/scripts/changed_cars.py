"""changed_cars.py MAIN.json BRANCH.json: the cars whose fitted yaw differs between two codes' pose tables
(benchmarks/pose_table.py --out, as scripts/diag.sh writes them), rows gt_fit (ground-truth masks + boxes, an oracle)
and pred_fit (predicted proposals, the cars matched in both), largest change of yaw error first: frame, instance id,
true yaw, each code's yaw (its yaw error), branch - main yaw error, the mask's pixels and the branch's hypothesis."""
import json
import math
import sys

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}


def per_car(path: str, row: str) -> dict:
    objects = json.load(open(path))["objects"][ROWS[row]]
    return {(o["frame"], o["id"]): o for o in objects if o.get("matched", True) and o.get("yaw_deg") is not None}


def main() -> None:
    for row in ROWS:
        a, b = per_car(sys.argv[1], row), per_car(sys.argv[2], row)
        lines = []
        for key in a.keys() & b.keys():
            m, r = a[key], b[key]
            if abs(m["ry"] - r["ry"]) < 1e-4:
                continue
            d = r["yaw_deg"] - m["yaw_deg"]
            frame = key[0].removeprefix("vkitti1/")
            lines.append((abs(d), f"{row} {frame} {key[1]} true {math.degrees(m['true_ry']):+.0f} "
                                  f"main {math.degrees(m['ry']):+.0f} ({m['yaw_deg']:.1f}) "
                                  f"br {math.degrees(r['ry']):+.0f} ({r['yaw_deg']:.1f}) d={d:+.1f} "
                                  f"px {m['pixels']} {r.get('hypothesis')}"))
        for _, line in sorted(lines, reverse=True):
            print(line)


if __name__ == "__main__":
    main()
