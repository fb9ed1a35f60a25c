"""misstab.py JSON...: sums of misses.py's records per row (file name <SEED>_<row>.json) and kind: the removed cars'
true pixels (ground-truth instance masks: an oracle, to diagnose), those outside 3D-SDN's hole on main, where they lie
(inside another object's mask; under no mask), how many the removed car's fitted silhouette covers (uncarved, grown by
hole_dilate_px), and what a band of BAND input pixels around the car's own mask adds to the hole (of the misses; of
pixels that are not the car). Prints a markdown table."""
import json
import os
import sys

rows: dict[tuple[str, str], dict[str, int]] = {}
for path in sys.argv[1:]:
    row = os.path.basename(path)[:-5].split("_")[1]
    row = "predicted" if row == "semantic" else "ground-truth masks (oracle)"
    for r in json.load(open(path)):
        acc = rows.setdefault((row, r["kind"]), {"n": 0, "n_miss": 0})
        acc["n"] += 1
        acc["n_miss"] += r["miss_main"] > 0
        for k, v in r.items():
            if isinstance(v, int) and k != "index":
                acc[k] = acc.get(k, 0) + v
bands = sorted({int(k[4:].split("_")[0]) for acc in rows.values() for k in acc if k.startswith("band")})
head = ["row", "kind", "n", "entries with misses", "true px", "missed px (share)", "in other masks", "under no mask",
        "fit covers (of missed)", "fit covers (no mask)"]
head += [f"band {b}: misses taken / other px added" for b in bands]
print("| " + " | ".join(head) + " |")
print("|" + "---|" * len(head))
for (row, kind), a in sorted(rows.items()):
    share = a["miss_main"] / max(a["truth"], 1)
    cells = [row, kind, a["n"], a["n_miss"], a["truth"], f"{a['miss_main']} ({share:.1%})",
             a["miss_in_other_masks"], a["miss_no_mask"], a["fit_uncarved_covers_miss"], a["miss_no_mask_fit_covers"]]
    cells += [f"{a[f'band{b}_covers_miss']} / {a[f'band{b}_extra_not_truth']}" for b in bands]
    print("| " + " | ".join(str(c) for c in cells) + " |")
