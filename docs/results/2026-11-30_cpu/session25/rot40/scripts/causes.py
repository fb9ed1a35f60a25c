"""Count the causes (diag_pose.py) of the predicted rotates / zooms that lose to the 2D paste but win with ground-truth
masks (oracle), per tree, as a markdown table.

python causes.py LABEL=POSE.json [...]"""
import json
import sys

ORDER = ("wrong pick / proposal off the car", "class (car / van)", "flip", "yaw", "distance/size",
         "mask spill (IoU < 0.6)", "other", "no pose")


def main():
    print("| tree | rotates+zooms | lose (predicted) | of them win (oracle) | " + " | ".join(ORDER) + " |")
    print("|---|" + "---|" * (3 + len(ORDER)))
    for arg in sys.argv[1:]:
        label, path = arg.split("=")
        rows = json.load(open(path))
        lose = [r for r in rows if r["pred"] < 0 and r.get("oracle", -1) > 0]
        counts = [sum(r.get("cause") == c for r in lose) for c in ORDER]
        print(f"| {label} | {len(rows)} | {sum(r['pred'] < 0 for r in rows)} | {len(lose)} | "
              + " | ".join(map(str, counts)) + " |")


if __name__ == "__main__":
    main()
