# ruff: noqa: E501
"""cf_vs_2d.py COUNTERFACTUAL_JSON: 3D-SDN's delete (photo:rays, the default) against the 2D paste's (2d) on every
source scene of a counterfactual benchmark's delete pairs, on the hole region (vacated region plus shadow band),
paired and resampled by car (paired_difference, 95 %, seed 0); the share of pairs scored beside. Run with
PYTHONPATH=<main>/src."""
import json
import math
import sys

from sdn3d.evaluation.paired import paired_difference

d = json.load(open(sys.argv[1]))
pairs = [p for p in d["pairs"] if p["kind"] == "delete"]
for source in sorted({p["source"] for p in pairs}):
    mine = [p for p in pairs if p["source"] == source]
    for metric, hib in (("psnr", True), ("l1", False), ("darkening_error", False)):
        use = [p for p in mine if all(math.isfinite((p.get("metrics") or {}).get(m, {}).get("hole", {}).get(metric, math.nan)) for m in ("photo:rays", "2d"))]
        if not use:
            print(source, metric, "no pairs scored")
            continue
        a = [p["metrics"]["photo:rays"]["hole"][metric] for p in use]
        b = [p["metrics"]["2d"]["hole"][metric] for p in use]
        r = paired_difference(a, b, higher_is_better=hib, groups=[p["car"] for p in use])
        cars = len({p["car"] for p in use})
        better = (r.low > 0) if hib else (r.high < 0)
        worse = (r.high < 0) if hib else (r.low > 0)
        verdict = "too few cars" if cars < 10 else "3D-SDN better" if better else "2D better" if worse else "no clear difference"
        print(f"{source} {metric}: 3D-SDN {sum(a) / len(a):.4f} 2D {sum(b) / len(b):.4f} diff {r.mean:+.4f} [{r.low:+.4f}, {r.high:+.4f}] {r.wins}/{r.losses}, {len(use)} of {len(mine)} pairs scored, {cars} cars: {verdict}")
