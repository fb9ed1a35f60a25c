# ruff: noqa: E501
"""Held-out deletes, session 6: per fill (Telea, PatchMatch, generator, rays before, rays after) PSNR on the vacated
region plus the shadow band of the counterfactual pairs, all / clear (clone) / fog, with paired differences
(sdn3d.evaluation.paired: mean, 95 % bootstrap interval, wins/losses/ties) of rays after against each fill and
against the best of today's fills (the one of Telea, PatchMatch and the generator with the highest mean PSNR over
all pairs); residual darkening of the shadow band.

usage: paired4.py AFTER/counterfactual.json BEFORE/counterfactual.json [JSON_OUT]
"""

import json
import sys

from sdn3d.evaluation.paired import paired_difference


def deletes(path):
    return {p["key"]: p for p in json.load(open(path))["pairs"] if p["kind"] == "delete" and p["metrics"]}


after, before = deletes(sys.argv[1]), deletes(sys.argv[2])
keys = sorted(set(after) & set(before))
fills = {"Telea": (after, "photo:telea"), "PatchMatch": (after, "photo:patchmatch"), "generator": (after, "generator"),
         "rays before": (before, "photo:rays"), "rays after": (after, "photo:rays")}
groups = {"all": keys, "clear (clone)": [k for k in keys if "/clone/" in k], "fog": [k for k in keys if "/fog/" in k]}


def hole(run, method, k):
    return run[k]["metrics"][method]["hole"]


def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


today = ("Telea", "PatchMatch", "generator")
best = max(today, key=lambda f: mean([hole(*fills[f], k)["psnr"] for k in keys]))
record = {"n": len(keys), "best_today": best, "groups": {}}
print(f"n = {len(keys)} deletes; best of today's fills by mean PSNR over all pairs: {best}\n")
for gname, ks in groups.items():
    if not ks:
        continue
    print(f"### {gname} (n = {len(ks)})\n")
    print("| fill | PSNR | darkening | rays after minus it: ΔPSNR dB [95 %] w/l/t |\n|---|---|---|---|")
    g = record["groups"][gname] = {"n": len(ks), "fills": {}}
    ref = [hole(*fills["rays after"], k)["psnr"] for k in ks]
    for f, (run, m) in fills.items():
        vals = [hole(run, m, k)["psnr"] for k in ks]
        dark = mean([hole(run, m, k)["darkening"] for k in ks])
        cell = "–"
        entry = {"psnr": mean(vals), "darkening": dark}
        if f != "rays after":
            d = paired_difference(ref, vals, higher_is_better=True)
            cell = f"{d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}/{d.ties}"
            entry["delta"] = {"mean": d.mean, "low": d.low, "high": d.high, "wins": d.wins, "losses": d.losses,
                              "ties": d.ties}
        g["fills"][f] = entry
        print(f"| {f}{' (best of today)' if f == best else ''} | {mean(vals):.2f} | {dark:.3f} | {cell} |")
    tgt = mean([after[k]["reference"]["target"] for k in ks])
    src = mean([after[k]["reference"]["source"] for k in ks])
    g["darkening_target"], g["darkening_input"] = tgt, src
    print(f"\ndarkening of the shadow band: target {tgt:.3f}, input {src:.3f}\n")
print("per pair PSNR (Telea, PatchMatch, generator, rays before, rays after):")
for k in keys:
    print("  " + k + " " + " ".join(f"{hole(*fills[f], k)['psnr']:.2f}" for f in fills))
if len(sys.argv) > 3:
    json.dump(record, open(sys.argv[3], "w"), indent=1)
