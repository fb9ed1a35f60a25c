"""merge_kinds.py CUES.json...: the merged proposals (oracle label, fit_cues.py) by the second true car's share of
the proposal's pixels, with the fit's figures (medians) against the single proposals', and how many distinct pairs
of true cars (tree, world, the two track ids) the merges are (frames 32-39 of a sequence repeat a pair). Session 28
merge40."""
import collections
import json
import statistics
import sys

from sdn3d.meshes import TEMPLATE_DIMENSIONS


def med(xs):
    return statistics.median(xs) if xs else float("nan")


rows = []
for p in sys.argv[1:]:
    for r in json.load(open(p)):
        r["tree"] = p.split("cues")[-1].split(".")[0]
        rows.append(r)
mer = [r for r in rows if r["label"] == "merge"]
sin = [r for r in rows if r["label"] == "single" and r["main_share_px"] >= 0.5]
pairs = {(r["tree"], r["key"].split("/")[1], tuple(sorted(r["held"]))) for r in mer}
print(f"{len(mer)} merged proposals = {len(pairs)} distinct pairs of true cars (tree, world, ids); "
      f"{len(sin)} single proposals lying >= 50 % on one true car\n")
print("| proposals | n | pairs | median px | median fit IoU | median unexplained | median fitted length m | "
      "templates |")
print("|---|---|---|---|---|---|---|---|")
bins = [("merge, second car < 10 % of the proposal", 0, 0.1), ("merge, 10-20 %", 0.1, 0.2),
        ("merge, 20-30 %", 0.2, 0.3), ("merge, >= 30 %", 0.3, 1.1)]
groups = [(n, [r for r in mer if lo <= r["second_share_px"] < hi]) for n, lo, hi in bins]
groups.append(("single (one car's)", sin))
for name, g in groups:
    pr = {(r["tree"], r["key"].split("/")[1], tuple(sorted(r["held"]))) for r in g} if "merge" in name else set()
    tpl = collections.Counter(r["template"] for r in g).most_common(3)
    print(f"| {name} | {len(g)} | {len(pr) if pr else '-'} | {med([r['area'] for r in g]):.0f} | "
          f"{med([r['iou'] for r in g]):.2f} | {med([r['unexpl'] for r in g]):.2f} | "
          f"{med([r['l_ratio'] * TEMPLATE_DIMENSIONS[r['template']][0] for r in g]):.2f} | "
          + ", ".join(f"{t} {c}" for t, c in tpl) + " |")
