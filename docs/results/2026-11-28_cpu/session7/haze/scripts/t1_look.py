# ruff: noqa: E402, E501, E701, E702
"""t1_look.py ON_DIR OFF_DIR: per entry on-off PSNR (3D-SDN photo, all) with the 3d-sdn road_haze calls' signals."""
import json
import sys


def load(d):
    r = json.load(open(d + "/results.json")); out = {}
    for _src, es in r["entries"].items():
        for i, e in enumerate(es):
            m = ((e.get("metrics") or {}).get("photo") or {}).get("3d-sdn")
            if m: out[e.get("id", i)] = (e.get("edit_kind"), m["all"]["psnr"], e["key"])
    return out
on, off = load(sys.argv[1]), load(sys.argv[2])
sig = dict(enumerate(json.load(open(sys.argv[1] + ".sig.json"))))  # in the results' order
for k in sorted(on):
    d = on[k][1] - off[k][1]
    calls = [c for c in sig.get(k, {}).get("calls", []) if c.get("phase") != "2d"]
    if abs(d) < 0.02 and not any(c.get("applied") for c in calls): continue
    print(f"{k:4d} {on[k][0][:8]:8s} {on[k][2]:28s} {off[k][1]:6.2f} {d:+6.2f}")
    for s in calls:
        f = s.get("fit")
        if not f: print("      nofit"); continue
        print(f'      app={int(s["applied"])} k={f["k"]:4.0f} fog={[round(x,2) for x in f["fog"]]} del={[round(x,2) for x in f["delta"]]} r2={s["r2"]:.2f} rms={s["rms"]:.3f} span={s["span"]:+.3f} hzhp={s["hz_hp"]:.3f} hzstd={s["hz_std"]:.3f} fvh={s.get("fog_vs_hz",0):.2f} hole={s["hole_rows"]} hor={s["horizon"]:.1f} dr={[round(x) for x in s["depth_range"]]} n={s["nrows"]}')
