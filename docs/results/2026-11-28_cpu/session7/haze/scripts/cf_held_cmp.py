# ruff: noqa: E402, E501, E701, E702
"""cf_held_cmp.py START.json FINAL.json OUT.json: held-out counterfactual deletes per weather, final - start and final -
final with ray_haze=0 (PSNR on vacated region + shadow band; paired 95% bootstrap, wins/losses/ties)."""
import json
import sys

from sdn3d.evaluation.paired import paired_difference

s = {r["key"]: r for r in json.load(open(sys.argv[1]))["rows"]}
f = {r["key"]: r for r in json.load(open(sys.argv[2]))["rows"]}
keys = sorted(set(s) & set(f))
out = {}
for w in ("clone", "fog", "rain", "all"):
    ks = [k for k in keys if w == "all" or f[k]["variation"] == w]
    if not ks: continue
    st = [s[k]["m"]["start"]["psnr"] for k in ks]; fi = [f[k]["m"]["final"]["psnr"] for k in ks]; f0 = [f[k]["m"]["final0"]["psnr"] for k in ks]
    res = {"n": len(ks), "psnr": {"start": sum(st) / len(ks), "final": sum(fi) / len(ks), "final_ray_haze_0": sum(f0) / len(ks)}}
    line = f"{w:5s} n={len(ks):3d} start {res['psnr']['start']:.2f} final {res['psnr']['final']:.2f} ray_haze=0 {res['psnr']['final_ray_haze_0']:.2f} |"
    for name, a, b in (("final-start", fi, st), ("final-ray_haze0", fi, f0)):
        d = paired_difference(a, b, higher_is_better=True)
        res[name] = [d.mean, d.low, d.high, d.wins, d.losses, d.ties]
        line += f" {name} {d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}/{d.ties} |"
    out[w] = res; print(line)
out["per_pair"] = {k: {"variation": f[k]["variation"], "start": round(s[k]["m"]["start"]["psnr"], 3), "final": round(f[k]["m"]["final"]["psnr"], 3), "final_ray_haze_0": round(f[k]["m"]["final0"]["psnr"], 3)} for k in keys}
json.dump(out, open(sys.argv[3], "w"), indent=1)
