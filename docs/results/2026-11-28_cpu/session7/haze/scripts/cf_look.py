# ruff: noqa: E402, E501, E701, E702
import json
import sys

d = json.load(open(sys.argv[1]))
for r in d["rows"]:
    dd = r["m"]["on"]["psnr"] - r["m"]["off"]["psnr"]
    for s in r["sig"][:1]:
        f = s.get("fit")
        if not f: print(r["key"], round(dd, 2), "nofit"); continue
        print(f'{r["key"]:28s} {dd:+6.2f} app={int(s["applied"])} k={f["k"]:4.0f} fog={[round(x,2) for x in f["fog"]]} del={[round(x,2) for x in f["delta"]]} r2={s["r2"]:.2f} rms={s["rms"]:.3f} span={s["span"]:+.3f} hzhp={s["hz_hp"]:.3f} hzstd={s["hz_std"]:.3f} fvh={s.get("fog_vs_hz",0):.2f} hole={s["hole_rows"]} hor={s["horizon"]:.0f} dr={[round(x) for x in s["depth_range"]]} n={len(r["sig"])}')
