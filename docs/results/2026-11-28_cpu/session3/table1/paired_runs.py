import json, sys, numpy as np
a = json.load(open(sys.argv[1])); b = json.load(open(sys.argv[2]))
rng = np.random.default_rng(0)
for src in a["entries"]:
    ea = {e["key"] + str(e["index"]): e for e in a["entries"][src]}
    eb = {e["key"] + str(e["index"]): e for e in b["entries"][src]}
    for region in ("all", "objects"):
        d = []
        for k in ea:
            ma, mb = ea[k].get("metrics", {}).get("photo"), eb.get(k, {}).get("metrics", {}).get("photo")
            if not ma or not mb or "3d-sdn" not in ma or "3d-sdn" not in mb: continue
            if region not in ma["3d-sdn"] or region not in mb["3d-sdn"]: continue
            d.append(mb["3d-sdn"][region]["psnr"] - ma["3d-sdn"][region]["psnr"])
        d = np.array(d); d = d[np.isfinite(d)]
        if not len(d): continue
        bs = [rng.choice(d, len(d)).mean() for _ in range(4000)]
        print(f"{src:9s} PSNR({region}) new-old {d.mean():+.2f} [{np.percentile(bs,2.5):+.2f}, {np.percentile(bs,97.5):+.2f}] better/worse/tie {int((d>1e-6).sum())}/{int((d<-1e-6).sum())}/{int((abs(d)<=1e-6).sum())} n={len(d)}")
