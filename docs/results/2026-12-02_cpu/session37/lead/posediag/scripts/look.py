# ruff: noqa: INP001, E501
"""look.py TREE OUT.png FRAME:ID...: for each car (frame key suffix 'world/variation/frame', ground-truth instance id),
a crop of the frame at 312x96 with three outlines: green the car's ground-truth mask, red the semantic branch's
proposal that overlaps it most, blue the fitted silhouette of that proposal (the predicted row's geometry); and
beside it, yellow the silhouette of the fit to the ground-truth mask (the oracle row's). Weights w37."""
import sys

import cv2
import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.derender import Models, derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.proposal_fit import fitted_silhouettes

torch.set_num_threads(1)
R = "/tmp/w37/outputs/demo/runs"
models = Models.from_checkpoints(geometric=f"{R}/geometric/checkpoints/inference.pt", semantic=f"{R}/semantic/checkpoints/inference.pt")
source = synth_data_source(sys.argv[1])
records = {r.key.split("/", 1)[1]: r for part in ("train", "val", "test") for r in load_split(source, part)}
size = (312, 96)
tiles = []
for spec in sys.argv[3:]:
    key, iid = spec.rsplit(":", 1)
    record = records[key]
    frame = load_frame(record, size, semantic=False, instances=False)
    gt = ground_truth(record, size)
    truth = scene_from_frame(record, size)
    t = int((truth.objects.instance_id == int(iid)).nonzero()[0])
    tmask = truth.objects.mask[t]
    out = {}
    for name, props in (("pred", "semantic"), ("gt", "gt")):
        scene = derender(frame.image, frame.intrinsics, models, props, gt, fit=FitSettings(), photo=frame_photo(record, size))
        o = scene.objects
        m = o.mask.flatten(1).float()
        iou = (m @ tmask.flatten().float()) / (m.sum(1) + tmask.sum() - m @ tmask.flatten().float()).clamp_min(1)
        r = int(iou.argmax())
        sil = fitted_silhouettes(frame.intrinsics, (o.template_id, o.dims, o.ry, o.location, o.phi), torch.tensor([r]))[0]
        out[name] = (o.mask[r], sil, float(iou[r]))
    img = (frame.image.permute(1, 2, 0).numpy()[:, :, ::-1] * 255).astype(np.uint8).copy()
    ys, xs = tmask.nonzero(as_tuple=True)
    y0, y1 = max(int(ys.min()) - 12, 0), min(int(ys.max()) + 12, size[1])
    x0, x1 = max(int(xs.min()) - 20, 0), min(int(xs.max()) + 20, size[0])
    panels = []
    for outlines in (((tmask, (0, 200, 0)), (out["pred"][0], (0, 0, 255)), (out["pred"][1], (255, 80, 0))),
                     ((tmask, (0, 200, 0)), (out["gt"][1], (0, 220, 255)))):
        p = img.copy()
        for mask, color in outlines:
            cs, _ = cv2.findContours(mask.numpy().astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
            cv2.drawContours(p, cs, -1, color, 1)
        p = cv2.resize(p[y0:y1, x0:x1], None, fx=3, fy=3, interpolation=cv2.INTER_NEAREST)
        panels.append(p)
    h = max(p.shape[0] for p in panels)
    row = np.concatenate([np.pad(p, ((0, h - p.shape[0]), (0, 6), (0, 0)), constant_values=255) for p in panels], 1)
    bar = np.full((16, row.shape[1], 3), 255, np.uint8)
    cv2.putText(bar, f"{key} car {iid}: green truth mask, red proposal (IoU {out['pred'][2]:.2f}), blue its fit | right: yellow fit to the truth mask",
                (3, 12), cv2.FONT_HERSHEY_SIMPLEX, 0.36, (0, 0, 0), 1, cv2.LINE_AA)
    tiles.append(np.concatenate([bar, row]))
w = max(t.shape[1] for t in tiles)
cv2.imwrite(sys.argv[2], np.concatenate([np.pad(t, ((0, 4), (0, w - t.shape[1]), (0, 0)), constant_values=255) for t in tiles]))
