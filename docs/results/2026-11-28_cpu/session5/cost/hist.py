# ruff: noqa: E401, E402, E501, E701, E702, E731, F401, I001, B023
"""Per-row loss history of each fit stage (dense31 frame): how soon do rows plateau?"""
import sys, torch
torch.set_num_threads(1)
import sdn3d.geometric.fit as fm
a = dict(torch.load('/tmp/s4data/cost/dense31_args.pt', weights_only=False)); masks, boxes, intr = a.pop('masks'), a.pop('boxes'), a.pop('intr')
H = []
orig = fm.adam_fit
def rec(params, objective, steps, lr):
    h = orig(params, objective, steps, lr); H.append(torch.stack(h)); return h
fm.adam_fit = rec
fm.fit_to_masks(masks, boxes, intr, **a)
for h in H:
    rel = (h[:-1] - h[1:]) / h[:-1]  # relative improvement per step
    print(h.shape, "median rel impr per step:", [round(float(x), 4) for x in rel.median(1).values])
    print("  share of rows with rel impr < 0.5% at step:", [round(float((x < 0.005).float().mean()), 2) for x in rel])
    print("  mean loss per step:", [round(float(x), 4) for x in h.mean(1)])
