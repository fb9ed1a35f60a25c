# ruff: noqa: E401, E402, E501, E701, E702, E731, F401, I001, B023
"""Mean loss per Adam step of each fit stage on the seed-31 tuning frame's 10 boxes (captured fit inputs of session 4,
no yaw belief), ffd_step 1.0 (before) and 0.1 (after): loss_curves.png + loss_curves.json.

    PYTHONPATH=src python loss_curves.py /tmp/s4data/cost/dense31_args.pt OUT_DIR
"""
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import torch
torch.set_num_threads(1)
import sdn3d.geometric.fit as fm
a = dict(torch.load(sys.argv[1], weights_only=False)); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
out = {}
orig = fm.adam_fit
for step in (1.0, 0.1):
    H = []
    def rec(params, objective, steps, lr):
        h = orig(params, objective, steps, lr)
        with torch.no_grad(): H.append([float(x.mean()) for x in h] + [float(objective().mean())])
        return h
    fm.adam_fit = rec
    r = fm.fit_to_masks(masks, boxes, intr, settings=fm.FitSettings(ffd_step=step), **a)
    out[str(step)] = {"stages": H, "iou": [round(float(v), 3) for v in r.iou], "template": r.template.tolist()}
fm.adam_fit = orig
fig, ax = plt.subplots(1, 3, figsize=(11, 3.2))
for i, name in enumerate(("search: all 320 starts", "search: 80 survivors", "fine: 50 hypotheses (FFD on)")):
    for step, style in (("1.0", "r-o"), ("0.1", "b-s")):
        ax[i].plot(out[step]["stages"][i], style, ms=3, label=f"ffd_step {step}")
    ax[i].set_title(name); ax[i].set_xlabel("Adam step (last point: after the last step)"); ax[i].set_ylabel("mean loss")
    ax[i].legend()
fig.suptitle("seed-31 tuning frame, 10 boxes: the fit's mean loss per step, ffd_step 1.0 (before) vs 0.1 (after)", fontsize=9)
fig.tight_layout(); fig.savefig(f"{sys.argv[2]}/loss_curves.png", dpi=80)
json.dump(out, open(f"{sys.argv[2]}/loss_curves.json", "w"))
print(json.dumps({k: {"fine_last": round(v["stages"][2][-1], 4), "iou_mean": round(sum(v["iou"]) / len(v["iou"]), 3)} for k, v in out.items()}))
