# ruff: noqa: E402, E501, E701, E702
"""sim.py: offline gate simulation on tuning runs (Table 1: runs/<tree>_{on,off}_<src>; cf: <tree>_diag.json).
A gate is a predicate on a road_haze call's signals; an entry takes 'on' when every applied 3d-sdn call passes, else
'off' (mixed entries are counted)."""
import json
import os

import numpy as np

R = "/tmp/s7data/haze/runs"
rng = np.random.default_rng(0)


def ci(d):
    d = np.asarray(d)
    if not len(d): return "n=0"
    bt = d[rng.integers(0, len(d), (4000, len(d)))].mean(1)
    return f"{d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n={len(d)})"


def load(d):
    r = json.load(open(d + "/results.json")); out = {}
    for _src, es in r["entries"].items():
        for i, e in enumerate(es):
            m = ((e.get("metrics") or {}).get("photo") or {}).get("3d-sdn")
            if m: out[e.get("id", i)] = (e.get("edit_kind"), m["all"]["psnr"], e["key"].split()[0].split("/")[1])
    return out


def t1_rows():
    rows = []
    for f in sorted(os.listdir(R)):
        if not f.endswith("_on_semantic_derender") and not f.endswith("_on_gt_oracle"): continue
        offd = f.replace("_on_", "_off_")
        if not os.path.exists(f"{R}/{offd}/results.json") or not os.path.exists(f"{R}/{f}/results.json"): continue
        on, off = load(f"{R}/{f}"), load(f"{R}/{offd}")
        sig = dict(enumerate(json.load(open(f"{R}/{f}.sig.json"))))  # in the results' order (ids skip identity entries)
        tree, src = f.split("_on_")
        for k in on:
            if k not in off: continue
            calls = [c for c in sig.get(k, {}).get("calls", []) if c.get("phase") != "2d" and c.get("applied")]
            rows.append({"set": f"T1 {src}", "tree": tree, "kind": on[k][0], "weather": on[k][2], "on": on[k][1], "off": off[k][1], "calls": calls})
    return rows


def cf_rows():
    rows = []
    for t in ("cf33", "cf37", "cf39"):
        p = f"/tmp/s7data/haze/{t}_diag.json"
        if not os.path.exists(p): continue
        for r in json.load(open(p))["rows"]:
            calls = [c for c in r["sig"] if c.get("applied")]
            rows.append({"set": "cf delete", "tree": t, "kind": "cf_delete", "weather": r["variation"], "on": r["m"]["on"]["psnr"], "off": r["m"]["off"]["psnr"], "calls": calls})
    return rows


def report(rows, gate, name):
    print(f"== gate {name}")
    mixed = 0
    groups = {}
    for r in rows:
        ok = [gate(c) for c in r["calls"]]
        mixed += bool(ok) and any(ok) and not all(ok)
        g = r["on"] if ok and all(ok) else r["off"]
        groups.setdefault((r["set"], r["kind"], r["weather"]), []).append((g - r["on"], g - r["off"], r["on"] - r["off"]))
    for key in sorted(groups):
        v = np.array(groups[key])
        if np.abs(v).max() < 1e-9: continue
        print(f"  {key[0]:14s} {key[1]:16s} {key[2]:6s} gated-on {ci(v[:, 0])} | gated-off {ci(v[:, 1])} | on-off {ci(v[:, 2])}")
    print("  mixed entries:", mixed)


if __name__ == "__main__":
    rows = t1_rows() + cf_rows()
    report(rows, lambda c: True, "always")
