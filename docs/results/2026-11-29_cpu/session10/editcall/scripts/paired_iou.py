# ruff: noqa: E501
"""Session 6's paired pose-table comparison (docs/results/2026-11-28_cpu/session6/poses/paired.py: flips, median and
p90 yaw error, template, distance, scale; 10,000 paired bootstrap draws over objects, seed 0) plus the fit row's
silhouette IoUs (``fit_iou``: the fitted shape's soft silhouette against the mask at the fine crop; ``sil_iou``: its
hard silhouette), their mean change with a 95 % interval and the objects better / worse.

    python paired_iou.py BEFORE.json AFTER.json
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

spec = importlib.util.spec_from_file_location("paired6", Path(__file__).resolve().parents[4] / "2026-11-28_cpu/session6/poses/paired.py")
paired6 = importlib.util.module_from_spec(spec)
spec.loader.exec_module(paired6)

before_path, after_path = sys.argv[1], sys.argv[2]
out = paired6.paired(before_path, after_path, "fit")
before, after = paired6._rows(before_path, "fit"), paired6._rows(after_path, "fit")
keys = sorted(set(before) & set(after))
rng = np.random.default_rng(0)
idx = rng.integers(0, len(keys), size=(10_000, len(keys)))
for field in ("fit_iou", "sil_iou"):
    b = np.array([before[k][field] for k in keys], dtype=float)
    a = np.array([after[k][field] for k in keys], dtype=float)
    d = (a[idx] - b[idx]).mean(1)
    out[f"{field}_mean_before"] = round(float(b.mean()), 4)
    out[f"{field}_mean_after"] = round(float(a.mean()), 4)
    out[f"{field}_change_ci95"] = [round(float(np.percentile(d, 2.5)), 4), round(float(np.percentile(d, 97.5)), 4)]
    out[f"{field}_better"] = int((a > b + 1e-4).sum())
    out[f"{field}_worse"] = int((a < b - 1e-4).sum())
print(json.dumps(out, indent=1))
