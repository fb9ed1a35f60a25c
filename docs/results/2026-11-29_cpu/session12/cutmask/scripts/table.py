# ruff: noqa: E501
"""Markdown pose table of main (before) and this branch (after) from pairs of pose-table JSONs, every row each pair
shares, with paired.py's changes (95 % bootstrap interval, objects won / lost) beside the after figures; a row of
BEFORE alone (the geometric branch without the fit, which this branch does not change) with main's figures only.

    python table.py BEFORE.json AFTER.json [BEFORE.json AFTER.json ...]
"""

from __future__ import annotations

import sys

from paired import compare, rows

FIELDS = (("yaw_median", "median yaw error (deg)"), ("yaw_p90", "p90 yaw error (deg)"), ("flips_pct", "flips > 90 deg (%)"),
          ("template_acc_pct", "template accuracy (%)"), ("length_median", "median length error (m)"),
          ("distance_x1e2_median", "median distance error (x1e-2)"), ("sil_iou_mean", "mean silhouette IoU"))


def main() -> None:
    args = sys.argv[1:]
    print("| row | n | floor (%) | " + " | ".join(label for _, label in FIELDS) + " |")
    print("|---|---|---|" + "---|" * len(FIELDS))
    for before_path, after_path in zip(args[::2], args[1::2], strict=True):
        before, after = rows(before_path), rows(after_path)
        for name in (r for r in before if r not in after):  # the branch alone: this branch's change cannot move it
            c = compare(before[name], before[name])
            cells_b = [f"{c[f]['before']}" if f in c else "-" for f, _ in FIELDS]
            print(f"| {name}: main (same code here) | {c['n']} | {c['template_majority_floor_pct']} | " + " | ".join(cells_b) + " |")
        for name in (r for r in after if r in before):
            c = compare(before[name], after[name])
            cells_b = [f"{c[f]['before']}" if f in c else "-" for f, _ in FIELDS]
            cells_a = [f"{c[f]['after']} ({c[f]['change']:+g} [{c[f]['ci95'][0]:+g}, {c[f]['ci95'][1]:+g}], {c[f]['won']}/{c[f]['lost']})"
                       if f in c else "-" for f, _ in FIELDS]
            print(f"| {name}: main | {c['n']} | {c['template_majority_floor_pct']} | " + " | ".join(cells_b) + " |")
            print(f"| {name}: this branch | {c['n']} | {c['template_majority_floor_pct']} | " + " | ".join(cells_a) + " |")


if __name__ == "__main__":
    main()
