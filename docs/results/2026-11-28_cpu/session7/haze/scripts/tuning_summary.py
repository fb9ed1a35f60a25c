# ruff: noqa: E402, E501, E701, E702
"""tuning_summary.py OUT.json: the tuning trees' Table 1 photo rows (3D-SDN PSNR on the edit region) and counterfactual
deletes (vacated region + shadow band) per source x kind x weather: gated (photo.ray_haze_airlight=0.25 with the
off-scale refusal) minus always-on (session start) and minus off (ray_haze=0), and always-on minus off. Gated numbers
are the per-entry on or off result chosen by the gate's logged decision on that entry's 3D-SDN fill calls (the real
gated run on t1_35 predicted proposals gave the same numbers)."""
import json
import sys

sys.path.insert(0, "/tmp/s7data/haze")
import sim


def plaus(c):
    f = c["fit"]; return all(-0.05 <= a + b <= 1.05 for a, b in zip(f["fog"], f["delta"], strict=False))


def gate(c): return c.get("fog_vs_hz", 9) <= 0.25 and plaus(c)


rows = sim.t1_rows() + sim.cf_rows()
groups = {}
for r in rows:
    ok = [gate(c) for c in r["calls"]]
    g = r["on"] if ok and all(ok) else r["off"]
    for key in ((r["set"], r["kind"], r["weather"]), (r["set"], r["kind"], "all")):
        groups.setdefault(key, []).append((g - r["on"], g - r["off"], r["on"] - r["off"]))
out = {}
for key in sorted(groups):
    v = sim.np.array(groups[key])
    out[" | ".join(key)] = {"n": len(v), **{name: sim.ci(v[:, i]) for i, name in enumerate(("gated-always", "gated-off", "always-off"))}}
    print(f"{key[0]:22s} {key[1]:16s} {key[2]:5s} gated-always {sim.ci(v[:, 0])} | gated-off {sim.ci(v[:, 1])} | always-off {sim.ci(v[:, 2])}")
json.dump({"trees": sorted({r['tree'] for r in rows}), "rows": out}, open(sys.argv[1], "w"), indent=1)
