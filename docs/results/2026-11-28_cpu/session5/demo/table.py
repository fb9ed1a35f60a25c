"""Markdown rows of pose tables (compact JSONs of benchmarks/pose_table.py): every row's "all" figures.

    python table.py LABEL=FILE.json ...
"""
# ruff: noqa: E501
import json
import sys

for arg in sys.argv[1:]:
    label, path = arg.split("=", 1)
    for row, figs in json.load(open(path))["table"].items():
        a = figs["all"]
        print(f"| {label} | {row} | {a['n']} | {a['yaw_median_deg']:.2f} | {a['yaw_p90_deg']:.1f} | "
              f"{a['flips_over_90_pct']:.1f} % | {a['template_acc_pct']:.1f} % ({a['template_majority_floor_pct']:.1f} %) | "
              f"{a['distance_median_x1e2']:.2f} | {a['scale_median_m']:.3f} |")
