"""fragfit.py JSON...: from misses.py's records (predicted rows; ``others_on_fit``), would a rule "another proposal
goes with the removed car when at least X of its pixels lie inside the car's fitted silhouette (grown by
hole_dilate_px)" take the car's fragments and leave its neighbours? Per X: the proposals it takes, their pixels on
the removed car (ground-truth instance mask: an oracle, to diagnose) and their pixels off it (what it would wrongly
remove), against all other proposals' pixels on the removed cars. Prints markdown."""
import json
import sys

records = [r for path in sys.argv[1:] for r in json.load(open(path))]
others = [o for r in records for o in r.get("others_on_fit", [])]
in_other_masks = sum(r["miss_in_other_masks"] for r in records)
print(f"entries {len(records)}; missed true px inside other masks {in_other_masks}; proposals on a removed car's "
      f"fitted silhouette {len(others)}")
print("| X (share inside the fit) | proposals taken | their px on the removed car | their px off it |")
print("|---|---|---|---|")
for x in (0.5, 0.6, 0.7, 0.8, 0.9, 0.95):
    taken = [o for o in others if o["in_fit"] >= x]
    on = sum(o["truth_px"] for o in taken)
    off = sum(o["px"] - o["truth_px"] for o in taken)
    print(f"| {x} | {len(taken)} | {on} | {off} |")
