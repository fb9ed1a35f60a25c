# ruff: noqa: E501
"""losers.py OUTDIR [N]: the predicted row's (semantic proposals) deletes and occluder removals of the three held-out
trees, each entry described from dbench.py's dump (source, target, 3D-SDN and 2D photos, the 'all' region, the
source scene's composed instance map = the proposals after main's join, the ground-truth instance maps (oracle,
used only to describe), the edited true ids and 3D-SDN's picked proposal ids). Writes OUTDIR/losers.jsonl (every
entry of those kinds, worst first per kind) and OUTDIR/losers.md (the N worst per kind, default 5), and
OUTDIR/../pictures/losers.png (the N worst per kind: source, target, 3D-SDN, 2D, and the proposals against the
true car; cropped around the edited car, x3).

Per entry: dPSNR = 3D-SDN - 2D on PSNR 'all' (the bench's value), the true car's pixels (M = the edited true ids in
the source), the picked proposal P: its cover of M (|P & M| / |M|), its precision (|P & M| / |P|), the other true
instances P holds >= 25 % of (merged neighbours), the other proposals holding >= 10 % of M (fragments), the share
of M each method changed (|out - source| > 8/255 in any channel: what it removed; unchanged = a ghost of the car
left standing) and each method's mean absolute error on the region split into the pixels it changed and the
pixels it left. Session 30 t1big30."""
import json
import os
import sys

import numpy as np
from PIL import Image, ImageDraw

T1 = "/tmp/s30/t1big30/t1"
SEEDS = ("2285", "2287", "2289")
KINDS = ("delete", "occluder_removed")
outdir = sys.argv[1]
N = int(sys.argv[2]) if len(sys.argv) > 2 else 5


rows = []
for seed in SEEDS:
    res = json.load(open(f"{T1}/{seed}_semantic/results.json"))
    (recs,) = res["entries"].values()
    metr = {e["index"]: e for e in recs}
    dump = f"{T1}/{seed}_semantic.dump"
    floor = {f["index"]: f["metrics"] for f in json.load(open(f"/tmp/s30/t1big30/floor/{seed}.json"))}
    for name in sorted(os.listdir(dump)):
        z = np.load(os.path.join(dump, name), allow_pickle=True)
        kind = str(z["kind"])
        if kind not in KINDS:
            continue
        index = int(name.split(".")[0])
        m = metr[index]["metrics"]["photo"]
        src, tgt, sdn, d2 = (z[k].astype(np.float64) / 255 for k in ("source", "target", "sdn", "d2"))
        region = z["region"].astype(bool)
        prop, sinst = z["proposals"], z["src_inst"]
        gt_ids, picks = [int(i) for i in z["gt_ids"]], [int(i) for i in z["picks"]]
        M = np.isin(sinst, gt_ids)
        P = np.isin(prop, picks) & (prop != 0) if picks else np.zeros_like(M)
        inter = int((P & M).sum())
        merged = {}
        for j in np.unique(sinst[P]):
            if j == 0 or int(j) in gt_ids:
                continue
            share = float((P & (sinst == j)).sum() / (sinst == j).sum())
            if share >= 0.25:
                merged[int(j)] = round(share, 2)
        frags = {}
        for q in np.unique(prop[M]):
            if q == 0 or int(q) in picks:
                continue
            share = float(((prop == q) & M).sum() / M.sum())
            if share >= 0.10:
                frags[int(q)] = round(share, 2)
        desc = {"seed": seed, "index": index, "key": str(z["key"]), "kind": kind,
                "dpsnr_all": m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"],
                "dl1_all": m["3d-sdn"]["all"]["l1"] - m["2d"]["all"]["l1"],
                "psnr_3d": m["3d-sdn"]["all"]["psnr"], "psnr_2d": m["2d"]["all"]["psnr"],
                "psnr_source": floor[index]["all"]["psnr"], "car_px": int(M.sum()), "region_px": int(region.sum()),
                "picked": picks, "proposal_px": int(P.sum()),
                "cover": inter / max(int(M.sum()), 1), "precision": inter / max(int(P.sum()), 1),
                "merged_neighbours": merged, "fragments": frags, "true_ids": gt_ids}
        for meth, out in (("3d", sdn), ("2d", d2)):
            changed = (np.abs(out - src) > 8 / 255).any(-1)
            err = np.abs(out - tgt).mean(-1)
            desc[f"changed_{meth}"] = float(changed[M].mean()) if M.any() else float("nan")
            desc[f"l1_changed_{meth}"] = float(err[region & changed].mean()) if (region & changed).any() else None
            desc[f"l1_left_{meth}"] = float(err[region & ~changed].mean()) if (region & ~changed).any() else None
            desc[f"left_px_{meth}"] = int((region & ~changed).sum())
        # where 3D-SDN loses: its error minus 2D's, summed over the region, split by who changed the pixel
        e3, e2 = np.abs(sdn - tgt).mean(-1), np.abs(d2 - tgt).mean(-1)
        c3, c2 = (np.abs(sdn - src) > 8 / 255).any(-1), (np.abs(d2 - src) > 8 / 255).any(-1)
        for tag, sel in (("both", c3 & c2), ("3d_only", c3 & ~c2), ("2d_only", ~c3 & c2), ("neither", ~c3 & ~c2)):
            desc[f"excess_{tag}"] = float((e3 - e2)[region & sel].sum())
        desc["_file"] = os.path.join(dump, name)
        rows.append(desc)

rows.sort(key=lambda r: (r["kind"], r["dpsnr_all"]))
os.makedirs(outdir, exist_ok=True)
with open(os.path.join(outdir, "losers.jsonl"), "w") as f:
    for r in rows:
        f.write(json.dumps({k: v for k, v in r.items() if k != "_file"}) + "\n")

lines = ["| kind | tree | entry | key | 3D-SDN - 2D PSNR all | 3D / 2D / source PSNR | car px | proposal: px, cover, "
         "precision | merged neighbours (share) | fragments (share of car) | car changed 3D / 2D | "
         "3D's excess error (sum over region): both changed / 3D only / 2D only / neither |", "|" + "---|" * 12]
worst = []
for kind in KINDS:
    sel = [r for r in rows if r["kind"] == kind][:N]
    worst += sel
    for r in sel:
        lines.append(f"| {kind} | {r['seed']} | {r['index']} | {r['key']} | {r['dpsnr_all']:+.2f} | "
                     f"{r['psnr_3d']:.2f} / {r['psnr_2d']:.2f} / {r['psnr_source']:.2f} | {r['car_px']} | "
                     f"{r['proposal_px']}, {r['cover']:.2f}, {r['precision']:.2f} | {r['merged_neighbours'] or '-'} | "
                     f"{r['fragments'] or '-'} | {r['changed_3d']:.2f} / {r['changed_2d']:.2f} | "
                     f"{r['excess_both']:+.1f} / {r['excess_3d_only']:+.1f} / {r['excess_2d_only']:+.1f} / "
                     f"{r['excess_neither']:+.1f} |")
open(os.path.join(outdir, "losers.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))

# the picture
S, PAD = 3, 4
panels = []
for r in worst:
    z = np.load(r["_file"], allow_pickle=True)
    M = np.isin(z["src_inst"], r["true_ids"])
    region = z["region"].astype(bool)
    P = np.isin(z["proposals"], r["picked"]) & (z["proposals"] != 0)
    ys, xs = np.nonzero(region | P)
    h, w = region.shape
    y0, y1 = max(ys.min() - 12, 0), min(ys.max() + 13, h)
    x0, x1 = max(xs.min() - 24, 0), min(xs.max() + 25, w)
    if x1 - x0 < 60:
        x0, x1 = max(0, (x0 + x1) // 2 - 30), min(w, (x0 + x1) // 2 + 30)
    over = z["source"].copy().astype(np.float64)
    other = (z["proposals"] != 0) & ~P
    over[other] = 0.5 * over[other] + 0.5 * np.array([0, 120, 255])
    over[P & ~M] = 0.4 * over[P & ~M] + 0.6 * np.array([255, 0, 0])
    over[P & M] = 0.4 * over[P & M] + 0.6 * np.array([0, 230, 0])
    over[M & ~P] = 0.4 * over[M & ~P] + 0.6 * np.array([255, 230, 0])
    edge = region & ~(np.roll(region, 1, 0) & np.roll(region, -1, 0) & np.roll(region, 1, 1) & np.roll(region, -1, 1))
    ims = []
    for name, img in (("source", z["source"]), ("target", z["target"]), ("3D-SDN", z["sdn"]), ("2D paste", z["d2"]),
                      ("proposals vs true car", over.astype(np.uint8))):
        im = img.copy()
        if name != "proposals vs true car":
            im[edge] = (255, 0, 255)
        ims.append((name, Image.fromarray(im[y0:y1, x0:x1].astype(np.uint8)).resize(((x1 - x0) * S, (y1 - y0) * S),
                                                                                     Image.NEAREST)))
    panels.append((r, ims))
cw = max(im.width for _, ims in panels for _, im in ims)
rh = [max(im.height for _, im in ims) + 30 for _, ims in panels]
canvas = Image.new("RGB", (5 * (cw + PAD) + PAD, sum(rh) + 40), "white")
d = ImageDraw.Draw(canvas)
d.text((PAD, 4), "Predicted row (semantic proposals), main 26c3e568, w30: the 5 worst deletes and occluder removals by "
       "3D-SDN - 2D PSNR 'all'. Magenta: the bench's 'all' region. Last panel: green = picked proposal on the true car, "
       "red = picked proposal off it, yellow = true car the proposal missed, blue = other proposals.", fill="black")
d.text((PAD, 18), "Crops around the region, x3 nearest.", fill="black")
y = 40
for (r, ims), hh in zip(panels, rh, strict=True):
    for c, (name, im) in enumerate(ims):
        x = PAD + c * (cw + PAD)
        title = name if c else (f"source: {r['kind']} {r['seed']}#{r['index']}, 3D-2D {r['dpsnr_all']:+.2f} dB")
        if name == "3D-SDN":
            title += f" {r['psnr_3d']:.1f} dB"
        if name == "2D paste":
            title += f" {r['psnr_2d']:.1f} dB"
        if name == "target":
            title += f" (source as edit {r['psnr_source']:.1f} dB)"
        d.text((x, y + 2), title, fill="black")
        canvas.paste(im, (x, y + 16))
    y += hh
canvas.save(os.path.join(outdir, "..", "pictures", "losers.png"))
