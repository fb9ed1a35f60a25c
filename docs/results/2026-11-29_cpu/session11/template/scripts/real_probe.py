# ruff: noqa: E501
"""The real Virtual KITTI frame of tests/data (a tuning picture here) de-rendered through its two car boxes as
sdn3d-edit does (working size 624x192, the photo's crops, GrabCut masks, the box fit with FitSettings' defaults or
KEY=VALUE overrides), printing each car's fine-stage hypotheses (template, yaw, loss, the appearance's belief) and
the winner: why a template won.

    python real_probe.py RUNS_DIR [KEY=VALUE ...]
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

import sdn3d.geometric.fit as fit_module
from sdn3d.derender import BoxPrompts, derender
from sdn3d.editing.inputs import camera_for_image, fit_image
from sdn3d.geometric.fit import FitSettings
from sdn3d.image_ops import to_image_tensor
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.models import Models, geometric_crop_settings

FRAME = Path(__file__).resolve().parents[6] / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [[466, 203, 666, 333], [704, 194, 917, 305]]


def main() -> None:
    runs = Path(sys.argv[1])
    overrides = dict(a.split("=", 1) for a in sys.argv[2:])
    settings = FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in overrides.items()})
    torch.set_num_threads(1)
    ckpt = runs / "geometric" / "checkpoints" / "inference.pt"
    crop = geometric_crop_settings(str(ckpt))
    models = Models.from_checkpoints(geometric=str(ckpt), **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    rgb = np.asarray(Image.open(FRAME).convert("RGB"))
    intr0, _ = camera_for_image(rgb.shape[1], rgb.shape[0])
    image, intr, frame = fit_image(rgb, intr0, (624, 192))
    photo = frame.photo(to_image_tensor(rgb))
    boxes = []
    for x0, y0, x1, y1 in BOXES:
        a, b = frame.to_working((x0 - 0.5, y0 - 0.5)), frame.to_working((x1 - 0.5, y1 - 0.5))
        boxes.append([a[0] + 0.5, a[1] + 0.5, b[0] + 0.5, b[1] + 0.5])
    seen: dict = {}
    stage, choose = fit_module._stage, fit_module._choose

    def recorded_stage(bank, template, start, *args, **kwargs):
        values, loss = stage(bank, template, start, *args, **kwargs)
        if kwargs.get("with_ffd"):
            seen["template"] = template.clone()
        return values, loss

    def recorded_choose(loss, belief, ry, s):
        seen.update(loss=loss.clone(), belief=belief.clone(), ry=ry.clone())
        return choose(loss, belief, ry, s)

    fit_module._stage, fit_module._choose = recorded_stage, recorded_choose
    scene = derender(image, intr, models, "boxes", boxes=BoxPrompts(torch.tensor(boxes), ("Car", "Car"), settings),
                     photo=photo, classes="vkitti")
    n = seen["loss"].shape[0]
    hyps = seen["loss"].shape[1]
    template = seen["template"].view(n, hyps)
    for i in range(n):
        print(f"car {i}: box {BOXES[i]}")
        for h in range(hyps):
            print(f"  hyp {h}: {TEMPLATE_NAMES[int(template[i, h])]:9s} yaw {math.degrees(float(seen['ry'][i, h])):7.1f} "
                  f"loss {float(seen['loss'][i, h]):.4f} belief {float(seen['belief'][i, h]):.3f}")
        o = scene.objects
        print(f"  -> {TEMPLATE_NAMES[int(o.template_id[i])]} yaw {math.degrees(float(o.ry[i])):.1f} dims "
              f"{[round(float(v), 2) for v in o.dims[i]]} hypothesis {scene.meta['boxes'][i].hypothesis} iou {scene.meta['boxes'][i].iou:.3f}")


if __name__ == "__main__":
    main()
