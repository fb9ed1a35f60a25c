# ruff: noqa: E501
"""pictures.py OUT.png N TREE:CACHE:CUES.json...: N (default 6) merged proposals (oracle label) of CUES.json
(fit_cues.py), one per pair of true cars, the most even pairs first (second car's share x sqrt(area)), next to single ones of similar size: per row the frame (312x96, cropped around the proposal), the
proposal's mask, the ground-truth cars it holds (ORACLE, coloured), the fitted car's silhouette over the mask
(green: both, red: mask only = unexplained, blue: silhouette only). Session 28 merge40."""
import glob
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.proposal_fit import fitted_silhouettes

out, n = sys.argv[1], int(sys.argv[2])
records, rows, scenes = {}, [], {}
for arg in sys.argv[3:]:
    tree, cache, cues = arg.split(":")
    t = tree.rstrip("/").split("_")[-1]  # the trees reuse frame names: keys are "<seed>:<frame key>"
    records.update({f"{t}:{r.key}": r for r in index_records(read_source(synth_data_source(tree))).values()})
    rows += [{**r, "key": f"{t}:{r['key']}"} for r in json.load(open(cues))]
    for p in glob.glob(f"{cache}/*.pt"):
        s = torch.load(p, weights_only=False)
        if s.meta.get("proposals") == "semantic":
            scenes[f"{t}:{s.meta['source']}"] = s
mer, seen = [], set()
for r in sorted((r for r in rows if r["label"] == "merge"), key=lambda r: -r["second_share_px"] * r["area"] ** 0.5):
    if (r["key"].split(":")[0], tuple(r["held"])) not in seen:  # one proposal per pair of true cars (frames 32-39 repeat the pairs)
        seen.add((r["key"].split(":")[0], tuple(r["held"])))
        mer.append(r)
mer = mer[:n]
sin = sorted((r for r in rows if r["label"] == "single" and 600 <= r["area"] <= 8000 and r["main_share_px"] >= 0.5), key=lambda r: -r["area"])[:max(1, n // 3)]
pick = [(r, "merge") for r in mer] + [(r, "single") for r in sin]
fig, ax = plt.subplots(len(pick), 4, figsize=(13, 1.9 * len(pick)))
for i, (r, lab) in enumerate(pick):
    s = scenes[r["key"]]
    o = s.objects
    k = int((o.instance_id == r["id"]).nonzero()[0])
    m = o.mask[k]
    geometry = (o.template_id, o.dims, o.ry, o.location, o.phi)
    S = fitted_silhouettes(s.intrinsics, geometry, torch.tensor([k]))[0]
    rec = records[r["key"]]
    img = load_frame(rec, (312, 96), semantic=False, instances=False).image.permute(1, 2, 0).numpy()
    gi = ground_truth(rec, (312, 96)).instances
    ys, xs = (m | S).nonzero(as_tuple=True)
    y0, y1 = max(int(ys.min()) - 6, 0), min(int(ys.max()) + 7, 96)
    x0, x1 = max(int(xs.min()) - 10, 0), min(int(xs.max()) + 11, 312)
    crop = (slice(y0, y1), slice(x0, x1))
    gt = np.zeros((96, 312, 3))
    for j, g in enumerate(r["held"] or []):
        gt[(gi == g).numpy()] = [(1, 0.6, 0), (0, 0.7, 1), (0.8, 0, 0.8)][j % 3]
    ov = np.zeros((96, 312, 3))
    ov[(m & S).numpy()] = (0, 0.8, 0)
    ov[(m & ~S).numpy()] = (1, 0, 0)
    ov[(~m & S).numpy()] = (0.2, 0.4, 1)
    for j, (pic, title) in enumerate([(img, f"{lab}: {r['key']} id {r['id']}"), (m.numpy(), f"proposal mask ({r['area']} px)"),
                                      (gt, "oracle: true cars held >= 25 %"),
                                      (ov, f"fit ({r['template']}) IoU {r['iou']:.2f}, unexplained {r['unexpl']:.2f}")]):
        ax[i, j].imshow(pic[crop], cmap="gray" if pic.ndim == 2 else None, interpolation="nearest")
        ax[i, j].set_title(title, fontsize=8)
        ax[i, j].axis("off")
fig.tight_layout()
fig.savefig(out, dpi=110)
print(out)
