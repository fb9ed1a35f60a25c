# ruff: noqa: E402, E501, E701, E702
"""cf_cmp.py TREE... : counterfactual deletes per weather, gated (this branch) vs always-on (start) vs off (start),
paired 95% bootstrap (sdn3d.evaluation.paired) and wins/losses/ties, PSNR on vacated region + shadow band."""
import json
import sys

from sdn3d.evaluation.paired import paired_difference

rows = {}
for t in sys.argv[1:]:
    base = json.load(open(f"/tmp/s7data/haze/{t}_diag.json"))
    gate = {r["key"]: r for r in json.load(open(f"/tmp/s7data/haze/{t}_gated.json"))["rows"]}
    for r in base["rows"]:
        g = gate.get(r["key"])
        if g: rows[(t, r["key"])] = (r["variation"], r["m"]["off"]["psnr"], r["m"]["on"]["psnr"], g["m"]["gated"]["psnr"])
out = {}
for w in ("clone", "fog", "rain", "all"):
    ks = [k for k in rows if w == "all" or rows[k][0] == w]
    if not ks: continue
    off, on, ga = ([rows[k][i] for k in ks] for i in (1, 2, 3))
    res = {"n": len(ks), "psnr": {"off": sum(off) / len(ks), "always": sum(on) / len(ks), "gated": sum(ga) / len(ks)}}
    line = f"{w:5s} n={len(ks):3d} off {res['psnr']['off']:.2f} always {res['psnr']['always']:.2f} gated {res['psnr']['gated']:.2f} |"
    for name, a, b in (("gated-always", ga, on), ("gated-off", ga, off), ("always-off", on, off)):
        d = paired_difference(a, b, higher_is_better=True)
        res[name] = [d.mean, d.low, d.high, d.wins, d.losses, d.ties]
        line += f" {name} {d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}/{d.ties} |"
    out[w] = res
    print(line)
if len(sys.argv) > 1 and sys.argv[-1].endswith(".json"): pass
json.dump({"trees": sys.argv[1:], "per_weather": out, "per_pair": {f"{t}/{k}": v for (t, k), v in rows.items()}}, open("/tmp/s7data/haze/cf_cmp_" + "_".join(sys.argv[1:]) + ".json", "w"), indent=1)
