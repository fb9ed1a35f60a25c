"""Paired comparison of two pose-table runs (benchmarks/pose_table.py JSON, the same tree and objects) per object:
a fit setting against the default, on the row given. Yaw error (degrees), flips (yaw more than 90 degrees off),
template right, silhouette IoU; B minus A with a 10,000-resample paired bootstrap 95 % interval and wins/losses.

    python knob_compare.py A.json B.json [ROW]
"""

from __future__ import annotations

import json
import sys

import numpy as np

ROW = "fit, oracle: ground-truth masks + boxes"


def _interval(values: np.ndarray, rng: np.random.Generator) -> tuple[float, float]:
    means = values[rng.integers(0, len(values), size=(10_000, len(values)))].mean(1)
    return float(np.percentile(means, 2.5)), float(np.percentile(means, 97.5))


def main() -> None:
    a, b = (json.load(open(p)) for p in sys.argv[1:3])
    row = sys.argv[3] if len(sys.argv) > 3 else ROW
    key = lambda o: (o["frame"], o["id"])  # noqa: E731
    objs_a = {key(o): o for o in a["objects"][row]}
    objs_b = {key(o): o for o in b["objects"][row]}
    keys = sorted(set(objs_a) & set(objs_b))
    rng = np.random.default_rng(0)
    changed = {k: v for k, v in b["fit_settings"].items() if a["fit_settings"].get(k) != v}
    print(f"{row}: {len(keys)} objects; B's settings differ in {changed}; seconds A {a['seconds'][row]} "
          f"B {b['seconds'][row]}")
    for name, get, better in (("yaw error deg", lambda o: o["yaw_deg"], "lower"),
                              ("flip share", lambda o: float(o["yaw_deg"] > 90), "lower"),
                              ("template right", lambda o: float(o["template_ok"]), "higher"),
                              ("silhouette IoU", lambda o: o.get("sil_iou") or 0.0, "higher")):
        va = np.array([get(objs_a[k]) for k in keys])
        vb = np.array([get(objs_b[k]) for k in keys])
        d = vb - va
        lo, hi = _interval(d, rng)
        wins = int((d < 0).sum() if better == "lower" else (d > 0).sum())
        losses = int((d > 0).sum() if better == "lower" else (d < 0).sum())
        print(f"  {name}: A mean {va.mean():.4f} (median {np.median(va):.3f}), B {vb.mean():.4f} "
              f"(median {np.median(vb):.3f}); B - A {d.mean():+.4f} [{lo:+.4f}, {hi:+.4f}]; B better/worse "
              f"{wins}/{losses} ({better} is better)")


if __name__ == "__main__":
    main()
