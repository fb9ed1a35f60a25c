# ruff: noqa: E402, E501, E701, E702
"""Markdown rows of pose tables (JSONs of benchmarks/pose_table.py): every row's \"all\" figures.

    python table.py LABEL=FILE.json ...
"""
import json
import sys

for a in sys.argv[1:]:
    lab,p=a.split('=',1); d=json.load(open(p))
    for row,f in d['table'].items():
        a_=f['all']; print(f"| {lab} | {row} | {a_['n']} | {a_['yaw_median_deg']:.2f} | {a_['yaw_p90_deg']:.1f} | {a_['flips_over_90_pct']:.1f} % | {a_['template_acc_pct']:.1f} % ({a_['template_majority_floor_pct']:.1f} %) | {a_['distance_median_x1e2']:.2f} | {a_['scale_median_m']:.3f} |")
