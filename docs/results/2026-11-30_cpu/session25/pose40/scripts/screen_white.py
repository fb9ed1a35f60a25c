"""screen_white.py TREE PREFIX OUT.pt: the headlight test's pixels of every red-bodied car (the red cue unusable, its
red share over max_share) that a main diag run (diag.sh's PREFIX.json / PREFIX.diag.json) fitted, on its
ground-truth mask (an oracle) and on the semantic branch's proposal matched to it (IoU >= 0.5), with the car's true
end (front seen: sin(alpha) > 0; the truth an oracle, read only to score): the near-white lower-half pixels and the
red ones of the crop the lamp cue reads (look.py's read, main's white_lamps rule), saved for variants of the rule
(variants_white.py). Session 21's demo weights (w0), 312x96, photo crops. Run from the worktree with main's library:

    PYTHONPATH=/tmp/s25data/lead/base_9a6/src python screen_white.py /tmp/s21data/trees/t1_35 \\
        /tmp/s25data/pose40/main_35 /tmp/s25data/pose40/white_35.pt
"""
# ruff: noqa: E402
import json
import math
import sys
from collections import defaultdict
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).parent))
from look import RUNS, SIZE, read

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.sources import load_split
from sdn3d.derender import derender
from sdn3d.image_ops import mask_boxes, pixel_centre_boxes
from sdn3d.models import Models, geometric_crop_settings

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}


def red_bodied(prefix: str) -> dict[str, dict[int, float]]:
    """frame -> {car id: true alpha} of the cars read as red bodies on either row."""
    table, diag = json.load(open(prefix + ".json")), json.load(open(prefix + ".diag.json"))
    by = defaultdict(list)
    for d in diag:
        by[(d["row"], d["frame"], d["ry"])].append(d)
    cars: dict[str, dict[int, float]] = defaultdict(dict)
    for row, name in ROWS.items():
        for o in table["objects"][name]:
            hs = by.get((row, o["frame"], o["ry"]), [])
            if len(hs) == 1 and "app" in hs[0] and hs[0]["app"].get("front_usable"):
                cars[o["frame"]][o["id"]] = o["true_ry"] - hs[0]["app"]["ray"]
    return cars


def main() -> None:
    tree, prefix, out = sys.argv[1:4]
    geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
    crop = geometric_crop_settings(geo)
    models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                     **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    cue = models.geometric.lamp_cue
    records = {r.key: r for part in ("train", "val", "test") for r in load_split(synth_data_source(tree), part)}
    saved = []
    for key, cars in red_bodied(prefix).items():
        record = records[key]
        frame = load_frame(record, SIZE, semantic=False, instances=False)
        photo, gt = frame_photo(record, SIZE), ground_truth(record, SIZE)
        theirs = derender(frame.image, frame.intrinsics, models, "semantic", gt, photo=photo).objects.mask.bool()
        for iid, alpha in cars.items():
            truth = gt.instances == int(iid)
            front = math.sin(alpha) > 0
            l, t, r, b = gt.boxes[int(iid) % 1000].tolist()
            v = read(photo, truth, torch.tensor([l, t, r, b]), models, cue)
            saved.append({"frame": key, "id": iid, "mask": "oracle", "front": front, "white": v["white"],
                          "red": v["red"], "sure": v["sure"], "share_red": v["share_red"]})
            iou = (theirs & truth).flatten(1).sum(1) / (theirs | truth).flatten(1).sum(1).clamp_min(1)
            if not len(iou) or float(iou.max()) < 0.5:
                continue
            pred = theirs[int(iou.argmax())]
            v = read(photo, pred, pixel_centre_boxes(mask_boxes(pred[None]))[0], models, cue)
            saved.append({"frame": key, "id": iid, "mask": "proposal", "front": front, "white": v["white"],
                          "red": v["red"], "sure": v["sure"], "share_red": v["share_red"]})
        print(key, len(saved), file=sys.stderr)
    torch.save(saved, out)


if __name__ == "__main__":
    main()
