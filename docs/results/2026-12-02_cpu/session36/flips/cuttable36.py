# ruff: noqa: E401, E501, E701, E702, I001
"""cuttable36.py CUT_JSON[.gz]...: of the cars (row gt_fit, cutcars36.py outputs of main) that the left or right border cuts
and whose absence of lamps (no red lamps on a usable crop, or no headlights on a red body) is replaced by the traffic
side's evidence: how often the side's rule and the bins (2p - 1 > 0 in the true end) name the true end, and the fit's
flips in each cell."""
import gzip, json, sys
from collections import Counter
cells, flips = Counter(), Counter()
for path in sys.argv[1:]:
    for r in json.load(gzip.open(path, "rt") if path.endswith(".gz") else open(path)):
        absent = (r["lamp_usable"] and not r["lamp_present"]) or (not r["lamp_usable"] and r["front_usable"] and not r["front_present"])
        if r["side"] == 0 or not absent: continue
        key = ("rule right" if r["lamps_true"] > 0 else "rule wrong", "bins right" if r["net_true"] > 0 else "bins wrong")
        cells[key] += 1; flips[key] += r["yaw_deg"] > 90
for k in sorted(cells): print(f"{k[0]}, {k[1]}: {cells[k]} cars, {flips[k]} flipped by the fit (main)")
print("all:", sum(cells.values()), "cars,", sum(flips.values()), "flipped")
