# ruff: noqa: E402, E501, E701, E702
"""pair.py A B...: per-entry 3D-SDN PSNR/L1 all (photo) of predicted rows: B - A paired, with bits-equal count."""
import json
import sys

sys.path.insert(0, "/work/main/src")
from sdn3d.evaluation.paired import paired_difference

tot = {"psnr": ([], []), "l1": ([], [])}
for a, b in zip(sys.argv[1::2], sys.argv[2::2], strict=False):
    ra, rb = (json.load(open(p + "/results.json")) for p in (a, b))
    ea, eb = ra["entries"]["semantic"], rb["entries"]["semantic"]
    same = 0; n = 0; chg = []
    for x, y in zip(ea, eb, strict=True):
        assert x["index"] == y["index"]
        mx = x["metrics"].get("photo", {}).get("3d-sdn", {}).get("all", {})
        my = y["metrics"].get("photo", {}).get("3d-sdn", {}).get("all", {})
        if "psnr" not in mx or "psnr" not in my: continue
        n += 1
        if mx["psnr"] == my["psnr"] and mx["l1"] == my["l1"]: same += 1
        else: chg.append((y["index"], x["edit_kind"], my["psnr"] - mx["psnr"]))
        for k in ("psnr", "l1"):
            tot[k][0].append(my[k]); tot[k][1].append(mx[k])
    print(a.split("/")[-1], "->", b.split("/")[-1], f"entries {n}, identical {same}, changed {len(chg)}:",
          ", ".join(f"#{i} {k} {d:+.3f}" for i, k, d in chg[:20]))
for k, hib in (("psnr", True), ("l1", False)):
    d = paired_difference(tot[k][0], tot[k][1], higher_is_better=hib)
    print(k, f"fix - base {d.mean:+.4f} [{d.low:+.4f}, {d.high:+.4f}] {d.wins}/{d.losses}/{d.ties} n={d.n}")
