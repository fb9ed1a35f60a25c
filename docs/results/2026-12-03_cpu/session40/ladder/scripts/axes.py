# ruff: noqa: INP001, E501
"""axes.py LOG.json (swap_bench.py's LOG=): each distinct fitted vehicle's axis error (degrees, either end) beside
the error of the road's axis its fit was drawn towards (its record's road_axis_deg)."""
import json
import math
import statistics
import sys

rows, seen = [], set()
for r in json.load(open(sys.argv[1])):
    if (r["frame"], r["id"]) not in seen:
        seen.add((r["frame"], r["id"]))
        rows.append(r)


def axis_error(angle):
    d = abs(math.degrees(math.atan2(math.sin(angle), math.cos(angle))))
    return min(d, 180 - d)


def quantiles(v):
    v = sorted(v)
    return [round(x, 2) for x in (statistics.median(v), v[3 * len(v) // 4], v[9 * len(v) // 10])]


both = [(axis_error(r["ry"] - r["gt_ry"]), axis_error(math.radians(r["road"]) - r["gt_ry"]))
        for r in rows if r.get("road") is not None]
print(len(rows), "vehicles,", len(both), "with a road axis")
print("fit axis error median / p75 / p90:", quantiles([axis_error(r["ry"] - r["gt_ry"]) for r in rows]))
print("road axis error median / p75 / p90:", quantiles([b for _, b in both]))
print("road nearer by over 1 degree:", sum(b < f - 1 for f, b in both), "farther:", sum(b > f + 1 for f, b in both))
