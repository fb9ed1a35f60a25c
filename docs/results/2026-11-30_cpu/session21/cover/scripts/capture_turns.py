"""Run sdn3d-bench (its arguments follow) keeping, for every counterfactual pair and drawing, its picture: the
whole picture's PSNR and L1 against the pair's target, the picture itself (uint8, rounded) and the pair's car,
vacated and shadow masks, written to the .npz file named by $CAPTURE at the end (then compared between two codes
by turns_table.py).

    CAPTURE=out.npz python capture_turns.py counterfactual=true data.root=TREE ...
"""

import atexit
import os
import runpy
import sys

import numpy as np
import torch

import sdn3d.evaluation.counterfactual as cf

out = os.environ["CAPTURE"]
score_pair, psnr_l1 = cf._score_pair, cf._psnr_l1
current: dict = {}
kept: dict[str, dict] = {}


def score(result, pair, scene, iid, centre, image, target, masks, *a, **k):
    current.clear()
    current.update(key=f"{pair.key}|{pair.angle_deg}", target=target, masks=masks, kind=pair.kind)
    return score_pair(result, pair, scene, iid, centre, image, target, masks, *a, **k)


def measured(pred, target, mask):
    key = current.get("key")
    if key is not None and key not in kept and current["kind"] == "turn":
        whole = psnr_l1(pred, target, torch.ones_like(mask))
        m = current["masks"]
        code = (m["target_mask"].numpy().astype(np.uint8) | 2 * m["vacated"].numpy().astype(np.uint8)
                | 4 * m["shadow"].numpy().astype(np.uint8))
        kept[key] = {"psnr": whole["psnr"], "l1": whole["l1"], "masks": code,
                     "picture": (pred.clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8).numpy()}
    return psnr_l1(pred, target, mask)


def save() -> None:
    keys = sorted(kept)
    np.savez_compressed(out, keys=np.array(keys), psnr=np.array([kept[k]["psnr"] for k in keys]),
                        l1=np.array([kept[k]["l1"] for k in keys]),
                        pictures=np.stack([kept[k]["picture"] for k in keys]) if keys else np.zeros(0),
                        masks=np.stack([kept[k]["masks"] for k in keys]) if keys else np.zeros(0))


atexit.register(save)
cf._score_pair, cf._psnr_l1 = score, measured
sys.argv = ["sdn3d-bench", *sys.argv[1:]]
runpy.run_module("sdn3d.cli.bench", run_name="__main__")
