import json, sys, numpy as np
r = json.load(open(sys.argv[1])); rng = np.random.default_rng(0)
for src, ents in r["entries"].items():
    for region in ("all", "objects"):
        for metric in ("psnr", "l1"):
            d = np.array([e["metrics"]["photo"]["3d-sdn"][region][metric] - e["metrics"]["photo"]["2d"][region][metric]
                          for e in ents if e.get("metrics", {}).get("photo") and "3d-sdn" in e["metrics"]["photo"]
                          and region in e["metrics"]["photo"]["3d-sdn"] and region in e["metrics"]["photo"].get("2d", {})])
            d = d[np.isfinite(d)]
            bs = [rng.choice(d, len(d)).mean() for _ in range(4000)]
            better = (d > 0) if metric == "psnr" else (d < 0)
            print(f"{src:9s} {metric}({region}) 3D-2D {d.mean():+.4f} [{np.percentile(bs,2.5):+.4f}, {np.percentile(bs,97.5):+.4f}] 3D better {int(better.sum())}/{len(d)}")
