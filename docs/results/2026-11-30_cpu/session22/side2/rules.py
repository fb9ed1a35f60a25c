"""Session 22 side2: which cars a paint rule changes, offline, on probe.py / realrec.py records (argv: .pt files):
per car, main's paint decision (``recolor.body_paint`` with the body examples off the lamps' heights as the
reference) against the branch's (where that is grey: the same less the examples on the road the car's mask took in,
``recolor.ground_in_mask`` of the input over the car's visible pixels, in clear air with CLEAR_AIR_ONLY=1, as the
branch does); prints every car whose paint turns coloured (the branch then draws its sides from that paint), and a
count. Pictures not stored in a record are read from TREE_ROOT/<tree>/vkitti_1.3.1_rgb
(the record file's name says the tree: ``..._cf<label>_...``).

With ROAD_MAX_SHARE=0.5 (the branch's ``transfer.ROAD_MAX_SHARE``; default 1: none) a car whose body examples are
more than that share road is left as main's. ``rules_final.txt``: CLEAR_AIR_ONLY=1 ROAD_MAX_SHARE=0.5 (13440f4);
``rules_3e22d80.txt``: CLEAR_AIR_ONLY=1 alone.

    CLEAR_AIR_ONLY=1 ROAD_MAX_SHARE=0.5 PYTHONPATH=src /work/main/.venv/bin/python rules.py \\
        /tmp/s22data/side2/probe/*.pt
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.recolor import body_paint, ground_in_mask
from sdn3d.editing.photo.transfer import _clear_air

TREES = {"2199": "/tmp/s21side/trees/cf2199", "2201": "/tmp/s21side/trees/cf2201", "31": "/tmp/s21data/trees/cf31",
         "33": "/tmp/s21data/trees/cf33", "39": "/tmp/s21data/trees/cf39", "2207": "/tmp/s22data/side2/trees/cf2207"}


def picture(path: str, name: str, rec: dict) -> torch.Tensor:
    """``(3, H, W)`` the input in [0, 1]."""
    if "image" in rec:
        flat = rec["image"].double() / 255
        size = (375, 1242) if name.startswith("real") else (192, 624)
        return flat.view(*size, 3).permute(2, 0, 1)
    label = re.search(r"_cf(\d+)_", Path(path).name).group(1)
    world, variation, frame = name.split("|")[0].split("/")
    png = Path(TREES[label]) / "vkitti_1.3.1_rgb" / world / variation / f"{frame.split('_')[0]}.png"
    return torch.from_numpy(np.asarray(Image.open(png).convert("RGB"))).permute(2, 0, 1).double() / 255


def decide(lab: torch.Tensor, reference_mask: torch.Tensor) -> tuple[torch.Tensor, bool]:
    return body_paint(lab, reference=lab[reference_mask])


def main() -> int:
    changed = total = 0
    for path in sys.argv[1:]:
        for name, rec in sorted(torch.load(path, weights_only=False).items()):
            lab = rec["lab"]
            if len(lab) < 8 or rec["band"] is None:
                continue
            total += 1
            image = picture(path, name, rec)
            height, width = image.shape[1:]
            mask = torch.zeros(height * width, dtype=torch.bool)
            mask[rec["visible"]] = True
            road = ground_in_mask(image.float(), mask.view(height, width)).view(-1)[rec["px"]]
            clear = _clear_air(image.permute(1, 2, 0).reshape(-1, 3)[rec["visible"]].double())
            if os.environ.get("CLEAR_AIR_ONLY") and not clear:
                road = torch.zeros_like(road)
            off = rec["band"] < 0
            told = off if int(off.sum()) >= 8 else torch.ones_like(off)
            tell = told & ~road
            main_keep, main_col = decide(lab, told)
            new_keep, new_col = main_keep, main_col
            if (not main_col and 8 <= int(tell.sum()) < int(told.sum())  # the branch's rule (transfer._part_examples)
                    and float(road.double().mean()) <= float(os.environ.get("ROAD_MAX_SHARE", "1"))):
                new_keep, new_col = decide(lab, tell)
            if new_col != main_col:
                changed += 1
                print(f"{Path(path).stem} {name}: road examples {int(road.sum())}/{len(lab)} (off band "
                      f"{int((off & road).sum())}/{int(off.sum())}); coloured {main_col} -> {new_col}, kept "
                      f"{int(main_keep.sum())} -> {int(new_keep.sum())}; clear air {clear}")
    print(f"changed {changed} of {total} car records")
    return 0


if __name__ == "__main__":
    sys.exit(main())
