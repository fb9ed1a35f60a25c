# ruff: noqa: E501
"""Paired comparison of two pose tables (benchmarks/pose_table.py JSON with per-object records) row by row: template
accuracy (with its majority floor), yaw error (median, p90), flips (> 90 degrees), length error (median), distance
error (median), silhouette IoU (mean): before, after, the change with a 95 % paired bootstrap interval (10,000 draws
over objects, seed 0) and the objects won / lost; plus each row's template confusion (true -> chosen) after.

    python paired.py BEFORE.json AFTER.json [ROW ...]   (ROW: a row's name as the table prints it; default: all shared)
"""

from __future__ import annotations

import json
import sys
from collections import Counter

import numpy as np

NAMES = ("sedan", "hatchback", "wagon", "suv", "pickup", "van", "minibus", "bus")


def rows(path: str) -> dict[str, dict[tuple[str, int], dict]]:
    objects = json.load(open(path))["objects"]
    return {name: {(o["frame"], o["id"]): o for o in objs} for name, objs in objects.items()}


def stat(name: str, values: np.ndarray) -> float:
    if name.endswith("median"):
        return float(np.median(values))
    if name.endswith("p90"):
        return float(np.percentile(values, 90))
    return float(values.mean())


def compare(before: dict, after: dict) -> dict:
    keys = sorted(set(before) & set(after))
    rng = np.random.default_rng(0)
    idx = rng.integers(0, len(keys), size=(10_000, len(keys)))
    fields = {"template_acc_pct": lambda o: 100.0 * o["template_ok"], "yaw_median": lambda o: o["yaw_deg"],
              "yaw_p90": lambda o: o["yaw_deg"], "flips_pct": lambda o: 100.0 * (o["yaw_deg"] > 90),
              "length_median": lambda o: o["length"], "length_mean": lambda o: o["length"],
              "distance_x1e2_median": lambda o: 100 * o["dist"], "sil_iou_mean": lambda o: o["sil_iou"] or 0.0}
    better_high = {"template_acc_pct", "sil_iou_mean"}
    true_t = Counter(before[k]["true_template"] for k in keys)
    out = {"n": len(keys), "template_majority_floor_pct": round(100 * max(true_t.values()) / len(keys), 1)}
    for name, f in fields.items():
        if name.startswith("length") and not all("length" in before[k] and "length" in after[k] for k in keys):
            continue  # a table without length records
        b = np.array([f(before[k]) for k in keys], dtype=float)
        a = np.array([f(after[k]) for k in keys], dtype=float)
        draws = np.array([stat(name, a[i]) - stat(name, b[i]) for i in idx])
        if name in ("template_acc_pct", "flips_pct"):
            won = int(((a > b) if name in better_high else (a < b)).sum())
            lost = int(((a < b) if name in better_high else (a > b)).sum())
        else:
            tol = 1e-3 if name != "sil_iou_mean" else 1e-4
            won = int(((a > b + tol) if name in better_high else (a < b - tol)).sum())
            lost = int(((a < b - tol) if name in better_high else (a > b + tol)).sum())
        out[name] = {"before": round(stat(name, b), 3), "after": round(stat(name, a), 3),
                     "change": round(stat(name, a) - stat(name, b), 3),
                     "ci95": [round(float(np.percentile(draws, 2.5)), 3), round(float(np.percentile(draws, 97.5)), 3)],
                     "won": won, "lost": lost}
    if all("template" in after[k] for k in keys):
        conf = Counter((NAMES[after[k]["true_template"]], NAMES[after[k]["template"]] if after[k]["template"] >= 0 else "none") for k in keys)
        out["confusion_after"] = {f"{t} -> {c}": v for (t, c), v in sorted(conf.items())}
    return out


def main() -> None:
    before, after = rows(sys.argv[1]), rows(sys.argv[2])
    wanted = sys.argv[3:] or [r for r in before if r in after]
    print(json.dumps({r: compare(before[r], after[r]) for r in wanted}, indent=1))


if __name__ == "__main__":
    main()
