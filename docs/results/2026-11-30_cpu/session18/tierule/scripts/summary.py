# ruff: noqa: E501, E701, E702
"""summary.py LABEL REPLAY.json [REPLAY.json ...]: the cars of replay.py's outputs pooled (one car per capture, source
and id; a capture's replays are NAME.json and NAME_TAG.json: its fits under every variant its files replayed): the geometric branch's
template accuracy against the majority floor and its calibration (accuracy per band of its top probability), then per
replay variant (template_belief_reg, or FitSettings fields) the fit's template accuracy, flips (|yaw error| > 90 deg), cars 20-90 deg off, median |yaw error|,
lengths off (length ratio over distance ratio outside [0.87, 1.15]), and its paired difference from the first variant (main's fit)
in template accuracy: mean, 10k-draw bootstrap 95 % interval (seed 0), cars won/lost."""
import json
import os
import sys
from collections import Counter

import numpy as np

from sdn3d.meshes.templates import TEMPLATE_NAMES


def ci(d):
    d = np.asarray(d, dtype=float)
    bt = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 0).sum())}/{int((d < 0).sum())}"


label, files = sys.argv[1], sys.argv[2:]
def key(variant):  # a number is template_belief_reg, whatever its spelling; base: the defaults (reg 0)
    if variant == "base":
        return "reg 0.0"
    try:
        return f"reg {float(variant)}"
    except ValueError:
        return variant


merged = {}  # one car per (capture, source, id): replays of one capture (NAME.json, NAME_TAG.json) add their fits
for f in files:
    capture = os.path.basename(f).split(".")[0].split("_")[0]
    for c in json.load(open(f)):
        car = merged.setdefault((capture, c["src"], c["id"]), {**c, "fits": {}})
        car["fits"].update({key(k): v for k, v in c["fits"].items()})
cars = list(merged.values())
n = len(cars)
truth = np.array([c["truth_tpl"] for c in cars]); belief = np.array([c["belief"] for c in cars])
top, conf = belief.argmax(1), belief.max(1)
count = Counter(truth.tolist()); major, major_n = count.most_common(1)[0]
print(f"== {label}: {n} cars (proposal IoU >= 0.3 with a ground-truth car; truth an oracle, for scoring only)")
print("truth templates: " + ", ".join(f"{TEMPLATE_NAMES[t]} {k}" for t, k in count.most_common()))
print(f"majority floor ({TEMPLATE_NAMES[major]}): {major_n / n:.3f}")
print(f"branch argmax: {(top == truth).mean():.3f}; top-2: {np.mean([t in np.argsort(-b)[:2] for t, b in zip(truth, belief, strict=True)]):.3f}; "
      f"mean p(truth) {belief[np.arange(n), truth].mean():.3f}; mean top p {conf.mean():.3f}")
print("branch argmax per template: " + ", ".join(f"{TEMPLATE_NAMES[t]} {k}" for t, k in Counter(top.tolist()).most_common()))
print("calibration (band of the top probability: cars, accuracy, mean top p):")
for lo, hi in ((0, 0.3), (0.3, 0.4), (0.4, 0.5), (0.5, 0.7), (0.7, 1.01)):
    sel = (conf >= lo) & (conf < hi)
    if sel.any(): print(f"  [{lo:.1f}, {min(hi, 1):.1f}): {int(sel.sum()):4d} cars, accuracy {(top[sel] == truth[sel]).mean():.3f}, mean top p {conf[sel].mean():.3f}")
regs = [r for r in cars[0]["fits"] if all(r in c["fits"] for c in cars)]  # the variants every file replayed
base = np.array([c["fits"][regs[0]]["tpl"] == c["truth_tpl"] for c in cars], dtype=float)
print("fit per variant: template accuracy, flips, 20-90 off, median |yaw err|, lengths off, cars whose template changed; template accuracy minus " + regs[0])
for r in regs:
    f = [c["fits"][r] for c in cars]
    acc = np.array([x["tpl"] == c["truth_tpl"] for x, c in zip(f, cars, strict=True)], dtype=float)
    ye = np.abs([x["yaw_err"] for x in f]); lr = np.array([x["len_ratio"] / x["dist_ratio"] for x in f])
    changed = sum(x["tpl"] != c["fits"][regs[0]]["tpl"] for x, c in zip(f, cars, strict=True))
    print(f"  {r:>16}: template {acc.mean():.3f}, flips {int((ye > 90).sum())} ({(ye > 90).mean():.3f}), 20-90 {int(((ye > 20) & (ye <= 90)).sum())}, "
          f"median |yaw| {np.median(ye):.1f}, lengths off {int(((lr < 0.87) | (lr > 1.15)).sum())}, changed {changed}; "
          f"vs {regs[0]}: {ci(acc - base)}")
fit0 = np.array([c["fits"][regs[0]]["tpl"] for c in cars])
dis = fit0 != top
print(f"{regs[0]}'s fit and the branch disagree on {int(dis.sum())} cars: fit right {(fit0[dis] == truth[dis]).mean():.3f}, branch right {(top[dis] == truth[dis]).mean():.3f}")
