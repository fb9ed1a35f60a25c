"""Where the red wagon's dark turned side comes from: the real frame of tests/data (README's boxes, this session's
demo weights) through ``sdn3d-edit``'s de-render, car 12001 turned 90 degrees, with the branch's code
(``PYTHONPATH=src``); the red car's body examples (``transfer._part_examples``) are recorded and drawn:

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session21/side/cause.py RUN_DIR OUT_DIR

Writes OUT_DIR/cause.png, four panels over the input crop of the car: (1) the input; (2) its body examples off the
lamps' heights (``_lamp_band(..., corners=False)``: blue, the pixels main's paint decision reads) and at them
(yellow); (3) main's paint (body examples ``body_paint`` keeps with the reference off the band: green kept, magenta
dropped); (4) the branch's (the whole body decides where its paint reaches off the band, ``_paint_off_the_band``).
Prints the shares.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import torch
import yaml
from PIL import Image

import sdn3d.editing.photo.transfer as T
from sdn3d.cli.edit import main as edit
from sdn3d.editing.photo.recolor import body_paint, srgb_to_lab
from sdn3d.meshes.parts import Part

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
CROP = (436, 173, 696, 343)
SEEN: list[dict] = []
_part_examples = T._part_examples


def recording(b, s_mesh, visible_px, before, src, parts_src, img_flat, settings):
    """``transfer._part_examples``, recording which pixels are its body examples and where they lie."""
    ex = visible_px[(src.frags.mesh_at(visible_px) == s_mesh) & (parts_src[visible_px] >= 0)]
    if len(ex):
        _, vid, bary, normal = T._surface(src, ex)
        tri = src.verts[torch.full((len(ex),), s_mesh, dtype=torch.long)[:, None], vid]
        point = T.sum3(bary[..., None] * tri, 1)
        good = T._view_cos(point, normal) >= settings.min_view_cos
        body = good & (parts_src[ex] == int(Part.BODY))
        feature = T._part_features(before, b, point[body], normal[body])
        SEEN.append({"iid": int(before.instance_id[b]), "px": ex[body], "colors": img_flat[ex[body]].double(),
                     "band": T._lamp_band(before, b, feature, corners=False)})
    return _part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, settings)


def main() -> int:
    run, out = Path(sys.argv[1]), Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    spec = out / "spec.yaml"
    spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": 90, "id": 12001}]}))
    T._part_examples = recording
    edit([f"input.image={FRAME}", f"run={run}", "proposals=boxes", f"edits={spec}", f"output_dir={out / 'edit'}"])
    red = next(s for s in SEEN if s["iid"] == 12001)
    lab = srgb_to_lab(red["colors"].float())
    off = red["band"] < 0
    main_paint, main_coloured = body_paint(lab, reference=lab[off])
    branch_off = T._paint_off_the_band(lab, red["band"])
    branch_paint, branch_coloured = body_paint(lab, reference=lab if branch_off else lab[off])
    print(f"body examples {len(lab)}, off the lamps' heights {int(off.sum())}; of those, the whole body's paint: "
          f"{float(body_paint(lab[off], reference=lab)[0].double().mean()):.3f}")
    print(f"main: paint coloured {main_coloured}, kept {int(main_paint.sum())}; branch: paint off the band "
          f"{branch_off}, coloured {branch_coloured}, kept {int(branch_paint.sum())}")
    picture = np.asarray(Image.open(FRAME).convert("RGB"))
    height, width = picture.shape[:2]
    y, x = (red["px"] // width).numpy(), (red["px"] % width).numpy()

    def overlay(colours: np.ndarray) -> np.ndarray:
        canvas = (picture * 0.35).astype(np.uint8)
        canvas[y, x] = colours
        return canvas[CROP[1]:CROP[3], CROP[0]:CROP[2]]

    def paint_colours(keep: torch.Tensor) -> np.ndarray:
        return np.where(keep.numpy()[:, None], [[40, 220, 60]], [[230, 40, 220]]).astype(np.uint8)

    from sdn3d.visualize import titled_row

    panels = [("input (car 12001)", picture[CROP[1]:CROP[3], CROP[0]:CROP[2]]),
              ("body examples: blue off lamp heights, yellow at",
               overlay(np.where(off.numpy()[:, None], [[60, 120, 255]], [[250, 220, 40]]).astype(np.uint8))),
              ("main: paint kept (green) / dropped (magenta)", overlay(paint_colours(main_paint))),
              ("branch: paint kept (green) / dropped (magenta)", overlay(paint_colours(branch_paint)))]
    Image.fromarray(titled_row(panels)).save(out / "cause.png")
    print(out / "cause.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
