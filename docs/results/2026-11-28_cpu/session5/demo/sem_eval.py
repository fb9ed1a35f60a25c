# ruff: noqa: E402, E501
"""The semantic branch on a common tree, per variation (session 5, demo): mean IoU over the classes present (the
prediction at the demo's 312x96 brought back to 624x192, nearest) and the proposals' recall / precision of Car and
Van over 256 visible pixels at 624x192 (IoU >= 0.5; :mod:`sdn3d.evaluation.proposal_recall`), every frame, and
per frame the objects and how many were found (for a paired bootstrap over frames).

    python sem_eval.py SEMANTIC.ckpt DATA_ROOT OUT.json
"""
import json
import sys
import time
from pathlib import Path

import torch

REPO = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(REPO / "src"))

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.sources import load_split
from sdn3d.evaluation.proposal_recall import PAPER_MIN_PIXELS, RecallCounts, match_proposals
from sdn3d.semantic.predict import SemanticPredictor

ckpt, root, out = sys.argv[1:4]
torch.set_num_threads(1)
source = synth_data_source(Path(root))
pred = SemanticPredictor.from_checkpoint(ckpt, image_size=(312, 96))
things = list(pred.thing_classes)
n = len(source.class_list)
res: dict = {}
t = time.time()
for record in [r for part in ("train", "val", "test") for r in load_split(source, part)]:  # every frame but the split gaps
    var = record.key.split("/")[2]
    frame = load_frame(record, None)
    seg = pred(frame.image)
    r = res.setdefault(var, {"conf": torch.zeros(n, n, dtype=torch.long), "counts": RecallCounts(), "frames": 0})
    label, gt = seg.label[0].cpu().long(), frame.semantic.long()
    ok = (gt >= 0) & (gt < n)
    r["conf"] += torch.bincount(gt[ok] * n + label[ok].clamp(0, n - 1), minlength=n * n).view(n, n)
    counts = match_proposals(seg.instance.cpu(), frame.instances[None], things, PAPER_MIN_PIXELS)
    r["counts"] += counts
    r["frames"] += 1
    one = counts.summary()
    r.setdefault("per_frame", []).append({"key": record.key, "objects": one["objects"],
                                          "found": round(one["recall"] * one["objects"])})
summary = {}
for var, r in res.items():
    c = r["conf"].double()
    inter, union = c.diag(), c.sum(0) + c.sum(1) - c.diag()
    present = c.sum(1) > 0
    s = r["counts"].summary()
    summary[var] = {"frames": r["frames"], "miou": round(float((inter[present] / union[present]).mean()), 4),
                    "recall": round(s["recall"], 4), "precision": round(s["precision"], 4), "objects": s["objects"],
                    "proposals": s["proposals"], "per_frame": r["per_frame"]}
summary["_info"] = {"checkpoint": ckpt, "data": root, "work_size": [312, 96], "min_pixels": PAPER_MIN_PIXELS,
                    "wall_s": round(time.time() - t, 1)}
Path(out).write_text(json.dumps(summary, indent=1))
print(json.dumps(summary, indent=1))
