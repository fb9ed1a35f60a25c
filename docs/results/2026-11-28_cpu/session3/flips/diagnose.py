"""Diagnose the fit's flips (issue 40): per object of a pose table's fit row, what each cue said.

    python docs/results/2026-11-28_cpu/session3/flips/diagnose.py TABLE.json CKPT OUT.json [--crops DIR] [--all]

Re-runs ``derender(..., 'boxes', masks=GT)`` on the frames holding a flipped object (``--all``: every frame of the
table) with hooks that record, per object: the net's raw yaw (before the lamp cue), the lamp cue's reading
(red pixels present / usable, column offset), the MultiBin belief in the true yaw, the start yaw (after the lamp
cue), and the fine stage's hypotheses (yaw, loss, whether within the tie). Nothing here changes the pipeline.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
import torch

REPO = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(REPO / "src"))

import sdn3d.geometric.fit as fitmod  # noqa: E402
from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import ground_truth, scene_from_frame  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.derender import BoxPrompts, derender  # noqa: E402
from sdn3d.geometric.lamps import red_lamps  # noqa: E402
from sdn3d.geometric.model import ray_angle, yaw_distribution  # noqa: E402
from sdn3d.geometric.predict import GeometricPredictor  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402

ROW = "fit, GT masks + boxes (oracle)"


def wrapd(a: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a), math.cos(a))))


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("table")
    p.add_argument("ckpt")
    p.add_argument("out")
    p.add_argument("--crops", default=None)
    p.add_argument("--all", action="store_true")
    args = p.parse_args()
    torch.manual_seed(0)
    torch.set_num_threads(1)
    table = json.load(open(args.table))
    rows = table["objects"][ROW]
    frames = sorted({r["frame"] for r in rows if args.all or r["yaw_deg"] > 90})
    crop = geometric_crop_settings(args.ckpt)
    models = Models.from_checkpoints(geometric=args.ckpt, **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    source = synth_data_source(table["data_root"])
    records = {r.key: r for part in ("train", "val", "test") for r in load_split(source, part)}
    size = tuple(source.image_size)

    captured = {}
    orig_predict = GeometricPredictor.predict

    def predict(self, crop, mask, box, intrinsics, *a, **k):
        cue, self.lamp_cue = self.lamp_cue, None
        raw = orig_predict(self, crop, mask, box, intrinsics, *a, **k)
        self.lamp_cue = cue
        out = orig_predict(self, crop, mask, box, intrinsics, *a, **k)
        present, usable, offset = red_lamps(crop * mask, mask, cue)
        captured["predict"] = dict(
            raw_ry=raw["ry"],
            ry=out["ry"],
            ray=ray_angle(box, intrinsics),
            present=present,
            usable=usable,
            offset=offset,
            raw=out,
            crop=crop * mask,
            mask=mask,
        )
        return out

    GeometricPredictor.predict = predict
    orig_stage = fitmod._stage
    stages = []

    def stage(*a, **k):
        values, loss = orig_stage(*a, **k)
        stages.append((values, loss, a[1], a[4]))
        return values, loss

    fitmod._stage = stage
    orig_choose = fitmod._choose
    chosen = []

    def choose(loss, belief, reverse, settings):
        chosen.append((loss, belief, reverse))
        return orig_choose(loss, belief, reverse, settings)

    fitmod._choose = choose
    import sdn3d.box_objects as boxmod

    orig_belief, seen = boxmod._yaw_belief, {}

    def yaw_belief(appearance, rows, bins):
        seen["appearance"] = None if appearance is None else appearance.rows(rows)
        return orig_belief(appearance, rows, bins)

    boxmod._yaw_belief = yaw_belief
    out_rows = []
    for key in frames:
        record = records[key]
        frame = load_frame(record, size, semantic=False, instances=False)
        gt = ground_truth(record, size)
        truth = scene_from_frame(record, size)
        objs = [r for r in rows if r["frame"] == key]
        ids = [r["id"] for r in objs]
        t = truth.objects
        trow = [int((t.instance_id == i).nonzero()[0]) for i in ids]
        masks = torch.stack([t.mask[r] for r in trow])
        boxes = torch.tensor([r["box"] for r in objs])
        names = tuple("Car" if i // 1000 == 12 else "Van" for i in ids)
        stages.clear()
        chosen.clear()
        seen.clear()
        fit = BoxPrompts(boxes, names, fitmod.FitSettings(**table["fit_settings"]), masks=masks, refine_masks=False)
        derender(frame.image, frame.intrinsics, models, "boxes", gt, boxes=fit)
        pr = captured["predict"]
        fine_values, fine_loss, fine_template, fine_ry0 = stages[-1]
        hyps = fine_loss.numel() // len(ids)
        fry = fine_values["ry"].view(len(ids), hyps)
        floss = fine_loss.view(len(ids), hyps)
        ftemp = fine_template.view(len(ids), hyps)
        ry0 = fine_ry0.view(len(ids), hyps)[:, 0]
        _, cbelief, creverse = chosen[-1]
        true_ry = torch.tensor([float(t.ry[r]) for r in trow])
        belief_true = yaw_distribution(pr["raw"], true_ry[:, None])[:, 0]
        for j, r in enumerate(objs):
            best = float(floss[j].min())
            tie = float(table["fit_settings"]["tie"])
            hyp = [
                {
                    "ry_err": round(wrapd(float(fry[j, h]) - float(true_ry[j])), 1),
                    "ry": round(float(fry[j, h]), 5),
                    "loss": round(float(floss[j, h]), 5),
                    "equal": bool(floss[j, h] <= best * (1 + tie)),
                    "belief": round(float(cbelief[j, h]), 4),
                    "reverse": round(float(creverse[j, h]), 4),
                    "cos": round(math.cos(float(fry[j, h] - ry0[j])), 4),
                    "template_ok": int(ftemp[j, h]) == int(t.template_id[trow[j]]),
                }
                for h in range(hyps)
            ]
            rec = {
                **{
                    k: r[k]
                    for k in ("frame", "id", "pixels", "box", "truncated", "yaw_deg", "hypothesis", "template_ok")
                },
                "raw_err": round(wrapd(float(pr["raw_ry"][j]) - float(true_ry[j])), 1),
                "lamp_err": round(wrapd(float(pr["ry"][j]) - float(true_ry[j])), 1),
                "lamps_present": bool(pr["present"][j]),
                "lamps_usable": bool(pr["usable"][j]),
                "lamp_offset": round(float(pr["offset"][j]), 3),
                "alpha_true_deg": round(
                    math.degrees(
                        math.atan2(
                            math.sin(float(true_ry[j] - pr["ray"][j])), math.cos(float(true_ry[j] - pr["ray"][j]))
                        )
                    ),
                    1,
                ),
                "belief_true": round(float(belief_true[j]), 3),
                "fine": hyp,
                "start_err": round(wrapd(float(ry0[j]) - float(true_ry[j])), 1),
                "true_ry": float(true_ry[j]),
                "appearance": None
                if seen.get("appearance") is None
                else {k: v[j].tolist() for k, v in seen["appearance"].values.items()},
            }
            out_rows.append(rec)
            if args.crops and (r["yaw_deg"] > 90):
                from PIL import Image

                d = Path(args.crops)
                d.mkdir(parents=True, exist_ok=True)
                img = (pr["crop"][j].permute(1, 2, 0).numpy() * 255).astype(np.uint8)
                Image.fromarray(img).resize((192, 192), Image.NEAREST).save(
                    d / f"{key.replace('/', '_')}_{r['id']}.png"
                )
        print(key, len(objs), file=sys.stderr)
    json.dump(out_rows, open(args.out, "w"), indent=1)


if __name__ == "__main__":
    main()
