"""changed.py ROW MAIN.json:BRANCH.json [...]: the cars whose yaw differs between two codes' pose tables
(benchmarks/pose_table.py --out), with their yaw errors (the truth an oracle, used only to score), whether the
ground truth marks them cut by the image border, and their 312x96 box. ROW: gt_fit, gt_branch or pred_fit."""
import json
import sys

ROWS = {"gt_branch": "branch, oracle: ground-truth masks", "gt_fit": "fit, oracle: ground-truth masks + boxes",
        "pred_fit": "fit, predicted proposals"}


def main() -> None:
    row = ROWS[sys.argv[1]]
    for pair in sys.argv[2:]:
        m, b = (json.load(open(p))["objects"][row] for p in pair.split(":"))
        mains = {(o["frame"], o["id"]): o for o in m if o.get("matched", True)}
        for o in b:
            key = (o["frame"], o["id"])
            if key in mains and o.get("matched", True) and abs(mains[key]["ry"] - o["ry"]) > 1e-4:
                mo = mains[key]
                print(f"{pair.split(':')[1].rsplit('/', 1)[-1][:-5]:12} {o['frame']:26} {o['id']} "
                      f"cut {int(o['truncated'])} box {[round(v) for v in o['box']]} "
                      f"err {mo['yaw_deg']:5.1f} -> {o['yaw_deg']:5.1f}")


if __name__ == "__main__":
    main()
