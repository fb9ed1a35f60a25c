# ruff: noqa: E501, E701, E702
"""why.py LABEL DIAG.json [DIAG.json ...]: why each fitted car's template wins (diag.py's records, pooled; the truth an
oracle, for scoring only): the winning hypothesis' kind (the prediction's four, carrying the branch's template, or the
search's), whether the truth's template reached the fine stage, the coarse search's rank of the truth's template, the
winner's loss against the best fine hypothesis of the truth's template (silhouette part and prior part), and the
template accuracy of re-choices among the recorded fine hypotheses (exact: no refit): main's rule; the lowest loss;
the lowest silhouette loss; the belief choosing the yaw axis only (the lowest loss among the fits within tie that
share the chosen fit's axis and end)."""
import json
import math
import sys
from collections import Counter

import numpy as np

from sdn3d.meshes.templates import TEMPLATE_NAMES

label, files = sys.argv[1], sys.argv[2:]
cars = [c for f in files for c in json.load(open(f))]
n = len(cars)
short = [t[:5] for t in TEMPLATE_NAMES]
truth = np.array([c["truth_tpl"] for c in cars])
fit = np.array([c["fit_tpl"] for c in cars])
floor_t, floor_n = Counter(truth.tolist()).most_common(1)[0]
print(f"== {label}: {n} cars; majority floor ({TEMPLATE_NAMES[floor_t]}) {floor_n / n:.3f}; main's fit right {np.mean(truth == fit):.3f}")
kind = Counter()
for c in cars:
    w = c["win"]; right = c["fit_tpl"] == c["truth_tpl"]
    k = "prediction's (0-3)" if w < 4 else "search's"
    kind[k, right] += 1
for k in ("prediction's (0-3)", "search's"):
    print(f"  winner {k}: {kind[k, True] + kind[k, False]} cars, right {kind[k, True]}")
p_wins = Counter((c["fit_tpl"], c["fit_tpl"] == c["truth_tpl"]) for c in cars if c["win"] < 4)
print("  the prediction's winners by template (right/all): " + ", ".join(
    f"{TEMPLATE_NAMES[t]} {p_wins[t, True]}/{p_wins[t, True] + p_wins[t, False]}" for t in range(len(TEMPLATE_NAMES))
    if p_wins[t, True] + p_wins[t, False]))
CLASS_RULE = {"Car": {"sedan", "hatchback", "wagon", "suv", "pickup", "van"}, "Van": {"van", "minibus", "bus"}}
barred = Counter((c["class"], TEMPLATE_NAMES[c["truth_tpl"]]) for c in cars
                 if TEMPLATE_NAMES[c["truth_tpl"]] not in CLASS_RULE.get(c["class"], set(TEMPLATE_NAMES)))
print(f"  truth's template barred by the class rule: {sum(barred.values())} (" + ", ".join(f"{k} {t}: {m}" for (k, t), m in barred.most_common()) + ")")
in_fine = [any(h["tpl"] == c["truth_tpl"] for h in c["hyps"]) for c in cars]
print(f"  truth's template among the fine hypotheses: {sum(in_fine)} of {n}")
ranks = []
for c in cars:
    co = {int(t): v for t, v in c["coarse"].items() if v is not None}
    order = sorted(co, key=co.get)
    ranks.append(order.index(c["truth_tpl"]) + 1 if c["truth_tpl"] in co else 0)
print("  coarse rank of the truth's template among the templates (0: barred by the class rule, or every start of it dropped at the search's first cut): " + ", ".join(f"{r}: {k}" for r, k in sorted(Counter(ranks).items())))
# wrong cars: how far the truth's best fine hypothesis is behind the winner, and why (silhouette vs prior)
rows = []
for c in cars:
    if c["fit_tpl"] == c["truth_tpl"]: continue
    tr = [h for h in c["hyps"] if h["tpl"] == c["truth_tpl"]]
    if not tr: continue
    w = c["hyps"][c["win"]]; b = min(tr, key=lambda h: h["loss"])
    rows.append((b["loss"] / w["loss"] - 1, b["sil"] - w["sil"], (b["loss"] - b["sil"]) - (w["loss"] - w["sil"]), b["belief"] - w["belief"]))
if rows:
    r = np.array(rows)
    print(f"  wrong cars whose truth template was fitted finely: {len(r)}; its loss over the winner's: median {np.median(r[:, 0]):+.3f}; "
          f"within tie 0.1: {int((r[:, 0] <= 0.1).sum())}, lower loss (lost on the belief): {int((r[:, 0] < 0).sum())}; "
          f"silhouette part higher in {int((r[:, 1] > 0).sum())}, prior part higher in {int((r[:, 2] > 0).sum())}")
conf = Counter((c["truth_tpl"], c["fit_tpl"], "P" if c["win"] < 4 else "S") for c in cars)
print("  truth -> fit (winner P: the prediction's, S: the search's), errors: " +
      "; ".join(f"{TEMPLATE_NAMES[a]}->{TEMPLATE_NAMES[b]} {k} {m}" for (a, b, k), m in conf.most_common() if a != b))


def axis_rule(c, tie=0.1):
    """The main rule's winner fixes the yaw (the belief's job); the lowest loss among the tied fits of that yaw wins."""
    hs = c["hyps"]; w = hs[c["win"]]
    best = min(h["loss"] for h in hs)
    same = [h for h in hs if h["loss"] <= best * (1 + tie) and math.cos(math.radians(h["yaw_err"] - w["yaw_err"])) > math.cos(math.radians(30))]
    return min(same, key=lambda h: h["loss"])["tpl"]


rules = {"main": lambda c: c["fit_tpl"], "lowest loss": lambda c: min(c["hyps"], key=lambda h: h["loss"])["tpl"],
         "lowest silhouette": lambda c: min(c["hyps"], key=lambda h: h["sil"])["tpl"], "belief picks the axis only": axis_rule}
base = truth == fit
for name, rule in rules.items():
    got = np.array([rule(c) for c in cars]) == truth
    d = got.astype(float) - base
    bt = d[np.random.default_rng(0).integers(0, n, (10000, n))].mean(1)
    print(f"  re-choice '{name}': template {got.mean():.3f}; minus main {d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 0).sum())}/{int((d < 0).sum())}")
