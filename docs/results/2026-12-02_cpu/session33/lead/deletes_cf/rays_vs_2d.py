# ruff: noqa: E501
"""rays_vs_2d.py: 3D-SDN's delete (photo, the default fill rays, shadow and contact darkening removed with the car)
against the 2D paste's (the car's own pixels removed, the same rays fill, no shadow removal) on session 31's held-out
counterfactual deletes (2303, ground-truth geometry, 110 pairs of 22 cars), on the benchmark's region (vacated region
plus shadow band), paired and resampled by car. Reads session 31's counterfactual.json.gz; computes nothing new on
the tree. Run with PYTHONPATH=<main>/src."""
import gzip
import json
import math
import os

from sdn3d.evaluation.paired import paired_difference

HERE = os.path.dirname(os.path.abspath(__file__))
d = json.load(gzip.open(os.path.join(HERE, "../../../../2026-12-01_cpu/session31/lead/cfdel2303/counterfactual.json.gz")))
pairs = [p for p in d["pairs"] if p["kind"] == "delete" and p["source"] == "oracle"]
for ours in ("photo:rays", "photo:learnt"):
    for metric, hib in (("psnr", True), ("l1", False), ("darkening_error", False)):
        use = [p for p in pairs if all(math.isfinite(p["metrics"].get(m, {}).get("hole", {}).get(metric, math.nan)) for m in (ours, "2d"))]
        a = [p["metrics"][ours]["hole"][metric] for p in use]
        b = [p["metrics"]["2d"]["hole"][metric] for p in use]
        r = paired_difference(a, b, higher_is_better=hib, groups=[p["car"] for p in use])
        print(f"{ours} - 2d, {metric}: {r.mean:+.4f} [{r.low:+.4f}, {r.high:+.4f}] {r.wins}/{r.losses} over {r.n} pairs, {len(set(p['car'] for p in use))} cars; means {sum(a)/len(a):.4f} vs {sum(b)/len(b):.4f}")
