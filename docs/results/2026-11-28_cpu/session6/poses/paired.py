# ruff: noqa: E501
"""Paired comparison of two pose tables' rows (issue 40, session 4): per object (frame, id) present in both, the flip
indicator (yaw > 90 deg off), the yaw error and the template; a 95 % paired bootstrap interval (objects resampled,
10,000 draws, seed 0) of the change in flip rate, median yaw error, 90th percentile and template accuracy, with the
objects fixed and broken.

    python docs/results/2026-11-28_cpu/session6/poses/paired.py BEFORE.json AFTER.json [--row fit|branch|...]

Session 6 copy of session 4's: every pose_table row, and the median distance (x1e-2) and scale (m) errors' changes.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

ROWS = {"fit": ("fit, oracle: ground-truth masks + boxes", "fit, GT masks + boxes (oracle)"),
        "branch": ("branch, oracle: ground-truth masks", "branch, GT masks (oracle)"),
        "boxes_fit": ("fit, oracle: ground-truth boxes",), "pred_fit": ("fit, predicted proposals",),
        "boxes_branch": ("branch, oracle: ground-truth boxes",), "pred_branch": ("branch, predicted proposals",)}


def _rows(path: str, row: str) -> dict:
    objects = json.load(open(path))["objects"]
    name = next(n for n in ROWS[row] if n in objects)
    return {(r["frame"], r["id"]): r for r in objects[name]}


def paired(before_path: str, after_path: str, row: str = "fit") -> dict:
    before, after = _rows(before_path, row), _rows(after_path, row)
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
    d_p90 = np.percentile(ya[idx], 90, axis=1) - np.percentile(yb[idx], 90, axis=1)
    db = np.array([before[k]["dist"] for k in keys]) * 100
    da = np.array([after[k]["dist"] for k in keys]) * 100
    sb = np.array([before[k]["scale"] for k in keys])
    sa = np.array([after[k]["scale"] for k in keys])
    d_dist = np.median(da[idx], 1) - np.median(db[idx], 1)
    d_scale = np.median(sa[idx], 1) - np.median(sb[idx], 1)
    ci = lambda v: [round(float(np.percentile(v, 2.5)), 2), round(float(np.percentile(v, 97.5)), 2)]  # noqa: E731
    return {
        "n": len(keys),
        "only_before": len(set(before) - set(after)),
        "only_after": len(set(after) - set(before)),
        "flips_before": int(fb.sum()),
        "flips_after": int(fa.sum()),
        "flips_before_pct": round(100 * fb.mean(), 1),
        "flips_after_pct": round(100 * fa.mean(), 1),
        "flip_change_pp": round(100 * (fa.mean() - fb.mean()), 2),
        "flip_change_ci95_pp": ci(d_flip),
        "fixed": int(((fb == 1) & (fa == 0)).sum()),
        "broken": int(((fb == 0) & (fa == 1)).sum()),
        "yaw_better_by_5deg": int((ya < yb - 5).sum()),
        "yaw_worse_by_5deg": int((ya > yb + 5).sum()),
        "median_before": round(float(np.median(yb)), 2),
        "median_after": round(float(np.median(ya)), 2),
        "median_change_ci95": ci(d_med),
        "p90_before": round(float(np.percentile(yb, 90)), 2),
        "p90_after": round(float(np.percentile(ya, 90)), 2),
        "p90_change_ci95": ci(d_p90),
        "template_before_pct": round(100 * tb.mean(), 1),
        "template_after_pct": round(100 * ta.mean(), 1),
        "template_change_ci95_pp": ci(d_tmpl),
        "template_won": int(((tb == 0) & (ta == 1)).sum()),
        "template_lost": int(((tb == 1) & (ta == 0)).sum()),
        "distance_x1e2_before": round(float(np.median(db)), 2),
        "distance_x1e2_after": round(float(np.median(da)), 2),
        "distance_change_ci95": ci(d_dist),
        "scale_m_before": round(float(np.median(sb)), 3),
        "scale_m_after": round(float(np.median(sa)), 3),
        "scale_change_ci95": [round(float(np.percentile(d_scale, 2.5)), 3), round(float(np.percentile(d_scale, 97.5)), 3)],
    }


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--row", default="fit", choices=tuple(ROWS))
    a = p.parse_args()
    print(json.dumps(paired(a.before, a.after, a.row), indent=1))
