# ruff: noqa: E501
"""Tuning numbers on cf33 (seed-33 counterfactual deletes, oracle geometry) from diag_deletes.py outputs: session
start's rays (= this branch with photo.ray_haze=0, run P0 of cf33_hz.json), this branch's rays (P), PatchMatch and
Telea (cf33_base.json, session start's code); PSNR on vacated region + shadow band, all / clear / fog, paired
differences of this branch's rays (sdn3d.evaluation.paired).   usage: tuning_cf33.py BASE.json HZ.json OUT.json"""
import json
import sys

from sdn3d.evaluation.paired import paired_difference

base, hz = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
rows = {r["key"]: {"PatchMatch": r["m"]["PM"], "Telea": r["m"]["TE"], "rays start": r["m"]["P"]} for r in base["rows"]}
for r in hz["rows"]:
    rows[r["key"]]["rays start (haze 0)"] = r["m"]["P0"]
    rows[r["key"]]["rays after"] = r["m"]["P"]
keys = sorted(rows)
out = {}
for g, ks in (("all", keys), ("clear", [k for k in keys if "/clone/" in k]), ("fog", [k for k in keys if "/fog/" in k])):
    ref = [rows[k]["rays after"]["psnr"] for k in ks]
    out[g] = {"n": len(ks)}
    print(f"{g} (n={len(ks)}): rays after {sum(ref) / len(ref):.2f} dB")
    for f in ("rays start", "PatchMatch", "Telea"):
        o = [rows[k][f]["psnr"] for k in ks]
        d = paired_difference(ref, o, higher_is_better=True)
        out[g][f] = {"psnr": sum(o) / len(o), "delta": [d.mean, d.low, d.high, d.wins, d.losses, d.ties]}
        print(f"  vs {f} ({sum(o) / len(o):.2f}): {d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}/{d.ties}")
    out[g]["darkening"] = {f: sum(rows[k][f]["dark"] for k in ks) / len(ks) for f in ("rays start", "rays after")}
out["same_with_haze_0"] = all(abs(rows[k]["rays start"]["psnr"] - rows[k]["rays start (haze 0)"]["psnr"]) < 1e-9 for k in keys)
out["per_pair"] = {k: {f: round(v["psnr"], 2) for f, v in rows[k].items()} for k in keys}
print("ray_haze=0 reproduces the session start:", out["same_with_haze_0"])
json.dump(out, open(sys.argv[3], "w"), indent=1)
