"""Collect, per evaluated object of a pose table, what the front/back cues see (issue 40 flips; no fit is run).

    python docs/results/2026-11-28_cpu/session3/flips/collect_cues.py TABLE.json CKPT OUT.pt [--size 64]

For each object of the table's fit row (ground-truth masks and boxes: an oracle) the geometric branch runs as
``derender(..., 'boxes')`` runs it (the mask's box, the model's crop), and OUT.pt holds: the masked crop
``(N, 3, S, S)`` and mask at the model's crop size, the same at ``--size`` px from the image, the box, the ray
angle, the MultiBin outputs, the net's yaw before and after the lamp cue, the true yaw, pixels and truncation.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import torch

REPO = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(REPO / "src"))

from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import scene_from_frame  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.image_ops import crop_windows, mask_boxes, pixel_centre_boxes, square_crop_window  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402

ROW = "fit, GT masks + boxes (oracle)"


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("table")
    p.add_argument("ckpt")
    p.add_argument("out")
    p.add_argument("--size", type=int, default=96)
    args = p.parse_args()
    torch.set_num_threads(1)
    table = json.load(open(args.table))
    rows = table["objects"][ROW]
    crop = geometric_crop_settings(args.ckpt)
    models = Models.from_checkpoints(geometric=args.ckpt, **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    pred = models.geometric
    cue = pred.lamp_cue
    source = synth_data_source(table["data_root"])
    records = {r.key: r for part in ("train", "val", "test") for r in load_split(source, part)}
    size = tuple(source.image_size)
    acc: dict[str, list] = {}
    for key in sorted({r["frame"] for r in rows}):
        record = records[key]
        frame = load_frame(record, size, semantic=False, instances=False)
        truth = scene_from_frame(record, size)
        t = truth.objects
        objs = [r for r in rows if r["frame"] == key]
        trow = [int((t.instance_id == r["id"]).nonzero()[0]) for r in objs]
        masks = torch.stack([t.mask[r] for r in trow])
        boxes = pixel_centre_boxes(mask_boxes(masks))
        windows = torch.tensor([square_crop_window(b, models.margin) for b in boxes], dtype=torch.float32)
        crops = crop_windows(frame.image, windows, models.crop_size, "bilinear")
        cmask = crop_windows(masks[:, None].float(), windows, models.crop_size, "nearest")
        big = crop_windows(frame.image, windows, args.size, "bilinear")
        bmask = crop_windows(masks[:, None].float(), windows, args.size, "nearest")
        intr = frame.intrinsics
        iv = torch.tensor([intr.fx, intr.fy, intr.cx, intr.cy], dtype=torch.float32).expand(len(objs), 4)
        pred.lamp_cue = None
        raw = pred.predict(crops * cmask, cmask, boxes, iv)
        pred.lamp_cue = cue
        out = pred.predict(crops * cmask, cmask, boxes, iv)
        part = {
            "crop": crops * cmask,
            "mask": cmask,
            "big": big * bmask,
            "bmask": bmask,
            "box": boxes,
            "raw_ry": raw["ry"],
            "lamp_ry": out["ry"],
            "yaw_bins": out["yaw_bins"],
            "yaw_residual": out["yaw_residual"],
            "yaw_ray": out["yaw_ray"],
            "true_ry": torch.tensor([float(t.ry[r]) for r in trow]),
            "pixels": torch.tensor([r["pixels"] for r in objs]),
            "truncated": torch.tensor([r["truncated"] for r in objs]),
            "fit_err": torch.tensor([r["yaw_deg"] for r in objs]),
            "iv": iv,
            "image_size": torch.tensor([size] * len(objs)),
        }
        for k, v in part.items():
            acc.setdefault(k, []).append(v)
        acc.setdefault("key", []).extend(f"{key}#{r['id']}" for r in objs)
    torch.save({k: (torch.cat(v) if k != "key" else v) for k, v in acc.items()}, args.out)
    print(len(acc["key"]), "objects")


if __name__ == "__main__":
    main()
