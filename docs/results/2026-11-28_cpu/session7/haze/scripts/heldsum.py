# ruff: noqa: E402, E501, E701, E702
"""heldsum.py OUT.json: held-out Table 1 (seed 2083) photo rows, 3D-SDN's PSNR on the edit region, shards merged:
final - start and final - final(ray_haze=0) per source x kind x weather (paired per entry; 10k bootstrap 95%;
wins/losses), plus the mean PSNR of each code."""
import glob
import json
import sys

import numpy as np

D = "/tmp/s7data/haze/held"
rng = np.random.default_rng(0)


def load(tag, src):
    out = {}
    for f in sorted(glob.glob(f"{D}/t1_2083_{tag}_{src}_*/results.json")):
        r = json.load(open(f))
        for s, es in r["entries"].items():
            for i, e in enumerate(es):
                m = ((e.get("metrics") or {}).get("photo") or {}).get("3d-sdn")
                if m: out[(s, i)] = (e.get("edit_kind"), m["all"]["psnr"], e["key"].split()[0].split("/")[1])
    return out


def ci(x):
    x = np.asarray(x)
    if not len(x): return None
    bt = x[rng.integers(0, len(x), (10000, len(x)))].mean(1)
    return [round(float(x.mean()), 3), round(float(np.percentile(bt, 2.5)), 3), round(float(np.percentile(bt, 97.5)), 3), int((x > 1e-9).sum()), int((x < -1e-9).sum()), len(x)]


def fmt(c): return "n=0" if c is None else f"{c[0]:+.2f} [{c[1]:+.2f}, {c[2]:+.2f}] {c[3]}/{c[4]} (n={c[5]})"


res = {}
for src in ("semantic_derender", "gt_derender", "gt_oracle"):
    codes = {t: load(t, src) for t in ("start", "final", "final0")}
    if not all(codes.values()): print(src, "incomplete:", {t: len(v) for t, v in codes.items()}); continue
    keys = sorted(set(codes["start"]) & set(codes["final"]) & set(codes["final0"]))
    print(f"== {src}: n={len(keys)} (start {len(codes['start'])}, final {len(codes['final'])}, final0 {len(codes['final0'])}); mean PSNR start {np.mean([codes['start'][k][1] for k in keys]):.3f} final {np.mean([codes['final'][k][1] for k in keys]):.3f} ray_haze=0 {np.mean([codes['final0'][k][1] for k in keys]):.3f}")
    r = {}
    for name, b in (("final-start", "start"), ("final-ray_haze0", "final0")):
        d = {k: codes["final"][k][1] - codes[b][k][1] for k in keys}
        r[name] = {"all": ci(list(d.values()))}
        print(f"  {name}: all {fmt(r[name]['all'])}")
        for kind in sorted({codes['final'][k][0] for k in keys}):
            r[name][kind] = {"all": ci([d[k] for k in keys if codes['final'][k][0] == kind])}
            line = f"    {kind}: {fmt(r[name][kind]['all'])} |"
            for w in ("clone", "fog", "rain"):
                c = ci([d[k] for k in keys if codes['final'][k][0] == kind and codes['final'][k][2] == w])
                r[name][kind][w] = c; line += f" {w} {fmt(c)} |"
            print(line)
    res[src] = r
json.dump(res, open(sys.argv[1], "w"), indent=1)
