# ruff: noqa: E402, E501, E701, E702
"""causes.py SRC SEED...: base rotate entries losing more than 0.5 dB to the 2D paste (PSNR all), each given one
cause: 'haze' (the AIR_MIN fix, m16_, won back at least half the loss), else 'flip' (a turned car fitted end for
end), else 'fit' (a turned car's fit poor, IoU < 0.7, or its distance off by over 30 %), else 'other'."""
import json
import sys

src = sys.argv[1]; seeds = sys.argv[2:]
short = {"gt": "gt", "semantic": "sem"}[src]
counts = {}; rows = []
for s in seeds:
    diag = {r["index"]: r for r in json.load(open(f"/tmp/s9data/t1rotate/runs/b{s}_{short}.diag.json"))}
    new = {e["index"]: e for e in list(json.load(open(f"/tmp/s9data/t1rotate/runs/m16_{s}_{src}/results.json"))["entries"].values())[0]}
    for i, r in diag.items():
        if r["d_all"] >= -0.5: continue
        m = new[i]["metrics"]["photo"]; dn = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"]
        turned = [o for o in r["ops"] if abs(o["turn_deg"]) >= 15]
        if dn - r["d_all"] >= 0.5 * -r["d_all"]: c = "haze"
        elif any(o.get("flip") for o in turned): c = "flip"
        elif any((o.get("fit") or {}).get("poor_fit") or abs(o.get("z_err") or 0) > 0.3 for o in turned): c = "fit"
        else: c = "other"
        counts.setdefault(c, []).append(r["d_all"]); rows.append((s, i, r["key"], r["d_all"], round(dn, 2), c))
for row in sorted(rows, key=lambda x: x[3]): print(*row)
print(src, "seeds", *seeds, "losses < -0.5 dB:", sum(len(v) for v in counts.values()))
for c, v in sorted(counts.items()): print(f"  {c}: {len(v)} entries, sum of losses {sum(v):.1f} dB")
