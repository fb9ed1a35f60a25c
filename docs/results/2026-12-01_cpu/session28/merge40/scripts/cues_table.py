# ruff: noqa: E501
"""cues_table.py CUES.json... [TWO.json...]: (twofit.py's files joined to fit_cues.py's by frame and id) for each fit cue of fit_cues.py, how many merged proposals (oracle label) a single
threshold catches while catching no / at most 2 / at most 5 single proposals, and the cue's AUC (the chance a merge
scores above a single, ties half). Direction per cue: 'high' (a merge should score high) or 'low'. Markdown to
stdout. Session 28 merge40."""
import json
import os
import sys

import numpy as np

from sdn3d.meshes import TEMPLATE_DIMENSIONS

CUES = [("iou", "low"), ("unexpl", "high"), ("unexpl_cc", "high"), ("unexpl_cc_px", "high"), ("unexpl_open", "high"), ("unexpl_open_px", "high"), ("cols_out", "high"),
        ("wratio", "high"), ("l_ratio", "high"), ("w_ratio", "high"), ("area", "high"),
        ("union_iou_gain", "high"), ("iou2", "high"), ("len_m", "high"), ("foot_m2", "high"),
        ("two_gain", "high"), ("two_min_part_iou", "high"), ("two_feet_overlap", "low")]


def value(r, c):
    if c == "union_iou_gain":
        return r["union_iou"] - r["iou1_mask"] if "union_iou" in r else 0.0
    if c == "iou2":
        return r.get("iou2") or 0.0
    if c == "len_m":
        return r["l_ratio"] * TEMPLATE_DIMENSIONS[r["template"]][0]
    if c == "foot_m2":
        return r["l_ratio"] * TEMPLATE_DIMENSIONS[r["template"]][0] * r["w_ratio"] * TEMPLATE_DIMENSIONS[r["template"]][2]
    if c.startswith("two_"):  # twofit.py's: proposals under 128 px or not cut score as no second car
        t = r.get("two")
        if t is None:
            return {"two_gain": -1.0, "two_min_part_iou": 0.0, "two_feet_overlap": 1.0}[c]
        return {"two_gain": t["iou_two"] - t["iou_one"], "two_min_part_iou": min(x or 0.0 for x in t["part_ious"]),
                "two_feet_overlap": t["feet_overlap"]}[c]
    return r[c]


def auc_interval(mv, mk, sv, sk, n=1000, seed=0):
    """95 % bootstrap interval of the AUC, resampling frames (a frame's proposals together: the trees' frames 32-39
    repeat the same cars, so this is still optimistic)."""
    rng = np.random.default_rng(seed)
    keys = sorted(set(mk) | set(sk))
    idx = {k: i for i, k in enumerate(keys)}
    mv, sv = np.asarray(mv, float), np.asarray(sv, float)
    mi, si = np.array([idx[k] for k in mk]), np.array([idx[k] for k in sk])
    out = []
    for _ in range(n):
        w = np.bincount(rng.integers(0, len(keys), len(keys)), minlength=len(keys))
        wm, ws = w[mi], w[si]
        if wm.sum() == 0 or ws.sum() == 0:
            continue
        cmp = (mv[:, None] > sv[None]) + 0.5 * (mv[:, None] == sv[None])
        out.append(float(wm @ cmp @ ws) / float(wm.sum() * ws.sum()))
    return np.percentile(out, 2.5), np.percentile(out, 97.5)


def main() -> None:
    rows, two = [], {}
    for p in sys.argv[1:]:
        tree = "".join(ch for ch in os.path.basename(p) if ch.isdigit())  # cues<SEED>.json / two<SEED>.json
        for r in json.load(open(p)):
            r["key"] = f"{tree}:{r['key']}"  # the trees reuse frame names
            if "iou_two" in r:
                two[(r["key"], r["id"])] = r
            else:
                rows.append(r)
    for r in rows:
        r["two"] = two.get((r["key"], r["id"]))
    mer = [r for r in rows if r["label"] == "merge"]
    sin = [r for r in rows if r["label"] == "single"]
    if os.environ.get("COMPARABLE"):  # singles that are one car's proposal (>= 50 % of it on one true car), as big
        sin = [r for r in sin if r["main_share_px"] >= 0.5 and r["area"] >= min(m["area"] for m in mer)]
    big = [r for r in sin if r["area"] >= min(m["area"] for m in mer)] if mer else sin
    print(f"{len(rows)} fitted vehicle proposals: {len(mer)} merges, {len(sin)} single "
          f"({len(big)} single at least as large as the smallest merge)\n")
    print("| cue | merges high/low | AUC [95 % interval, frames resampled] | merges caught, 0 singles | <= 2 singles | <= 5 singles | "
          "merges caught at 10 % of singles |")
    print("|---|---|---|---|---|---|---|")
    for c, d in CUES:
        s = 1 if d == "high" else -1
        mv = sorted((s * value(r, c) for r in mer), reverse=True)
        sv = sorted((s * value(r, c) for r in sin), reverse=True)
        auc = sum((m > x) + 0.5 * (m == x) for m in mv for x in sv) / max(len(mv) * len(sv), 1)
        lo, hi = auc_interval([s * value(r, c) for r in mer], [r["key"] for r in mer],
                              [s * value(r, c) for r in sin], [r["key"] for r in sin])
        out = []
        for allowed in (0, 2, 5, int(0.1 * len(sv))):
            # the threshold just above the (allowed+1)-th highest single: merges strictly above it
            t = sv[allowed] if len(sv) > allowed else float("-inf")
            caught = sum(m > t for m in mv)
            out.append(f"{caught} (> {s * t:.3g})" if s > 0 else f"{caught} (< {s * t:.3g})")
        print(f"| {c} | {d} | {auc:.2f} [{lo:.2f}, {hi:.2f}] | " + " | ".join(out) + " |")


if __name__ == "__main__":
    main()
