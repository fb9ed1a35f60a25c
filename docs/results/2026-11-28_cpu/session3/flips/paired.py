"""Paired comparison of two pose tables' fit rows (issue 40 flips): per object, the flip indicator (yaw > 90 deg off)
before and after, a 95 % paired bootstrap interval of the change in flip rate (objects resampled, 10,000 draws,
seed 0), the objects fixed and broken, and the same for the median yaw error and template accuracy.

    python docs/results/2026-11-28_cpu/session3/flips/paired.py BEFORE.json AFTER.json [--row fit|branch]
"""

from __future__ import annotations

import argparse
import json

import numpy as np

ROWS = {"fit": "fit, GT masks + boxes (oracle)", "branch": "branch, GT masks (oracle)"}


def paired(before_path: str, after_path: str, row: str = "fit") -> dict:
    name = ROWS[row]
    before = {(r["frame"], r["id"]): r for r in json.load(open(before_path))["objects"][name]}
    after = {(r["frame"], r["id"]): r for r in json.load(open(after_path))["objects"][name]}
    keys = sorted(set(before) & set(after))
    yb = np.array([before[k]["yaw_deg"] for k in keys])
    ya = np.array([after[k]["yaw_deg"] for k in keys])
    tb = np.array([before[k]["template_ok"] for k in keys], dtype=float)
    ta = np.array([after[k]["template_ok"] for k in keys], dtype=float)
    fb, fa = (yb > 90).astype(float), (ya > 90).astype(float)
    rng = np.random.default_rng(0)
    idx = rng.integers(0, len(keys), size=(10_000, len(keys)))
    d_flip = (fa[idx] - fb[idx]).mean(1) * 100
    d_tmpl = (ta[idx] - tb[idx]).mean(1) * 100
    d_med = np.median(ya[idx], 1) - np.median(yb[idx], 1)
    ci = lambda v: [round(float(np.percentile(v, 2.5)), 2), round(float(np.percentile(v, 97.5)), 2)]  # noqa: E731
    return {
        "n": len(keys),
        "only_before": len(set(before) - set(after)),
        "only_after": len(set(after) - set(before)),
        "flips_before_pct": round(100 * fb.mean(), 1),
        "flips_after_pct": round(100 * fa.mean(), 1),
        "flip_change_pp": round(100 * (fa.mean() - fb.mean()), 2),
        "flip_change_ci95_pp": ci(d_flip),
        "fixed": int(((fb == 1) & (fa == 0)).sum()),
        "broken": int(((fb == 0) & (fa == 1)).sum()),
        "median_before": round(float(np.median(yb)), 2),
        "median_after": round(float(np.median(ya)), 2),
        "median_change_ci95": ci(d_med),
        "template_before_pct": round(100 * tb.mean(), 1),
        "template_after_pct": round(100 * ta.mean(), 1),
        "template_change_ci95_pp": ci(d_tmpl),
        "template_won": int(((tb == 0) & (ta == 1)).sum()),
        "template_lost": int(((tb == 1) & (ta == 0)).sum()),
    }


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--row", default="fit", choices=tuple(ROWS))
    a = p.parse_args()
    print(json.dumps(paired(a.before, a.after, a.row), indent=1))
