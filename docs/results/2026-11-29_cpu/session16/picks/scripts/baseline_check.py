# ruff: noqa: E501, E701, E702
"""baseline_check.py BASE_RUN:NEW_RUN [...]: how many entries' 2D paste (PSNR all, L1 all) differ between two runs of
the same tree (main's code and the branch's): the 2D paste picks by the scene's centres (editing.apply.projected_centers:
a mask's centroid without geometry, its projected 3D centre with), so geometry given to small masks moves its picks.
Prints per pair the count of entries whose 2D PSNR all changed, their summed change, and entries 3D-SDN failed."""
import json
import sys


def load(run):
    r = json.load(open(f"{run}/results.json"))
    return {e["index"]: e for e in list(r["entries"].values())[0]}


for pair in sys.argv[1:]:
    b, n = pair.split(":")
    a, c = load(b), load(n)
    changed, failed = [], {"base": 0, "new": 0}
    for i in sorted(set(a) & set(c)):
        ma, mc = (a[i].get("metrics") or {}).get("photo") or {}, (c[i].get("metrics") or {}).get("photo") or {}
        failed["base"] += "3d-sdn" not in ma and bool(a[i].get("operations")); failed["new"] += "3d-sdn" not in mc and bool(c[i].get("operations"))
        if "2d" in ma and "2d" in mc and abs(mc["2d"]["all"]["psnr"] - ma["2d"]["all"]["psnr"]) > 1e-6:
            changed.append((i, mc["2d"]["all"]["psnr"] - ma["2d"]["all"]["psnr"]))
    print(f"{n} vs {b}: 2D paste changed on {len(changed)} entries, PSNR all sum {sum(d for _, d in changed):+.2f} dB "
          f"({', '.join(f'{i}:{d:+.2f}' for i, d in changed)}); entries without a 3D-SDN result: base {failed['base']}, new {failed['new']}")
