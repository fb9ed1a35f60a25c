"""Before/after strip of the photo appearance at 1242x375 with the demo's weights (issue 27's figure).

    .venv/bin/python docs/results/2026-11-26_cpu/issue27/make_strip.py RUN DATA OUT.png [FRAME_KEY|-] [FILL]

RUN: the demo's output (its geometric and textural checkpoints); DATA: a sdn3d-synth tree at 1242x375. The scene is
de-rendered by the demo's geometric branch on the frame's ground-truth masks (an oracle for the masks: the demo's
semantic branch finds no car); the largest car that lies wholly inside the frame is moved closer (zoom 1.6 on the
ground), turned by 45 degrees,
deleted and repainted red, each drawn with the photo appearance (sdn3d.editing.photo) at the frame's resolution.
"""

import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from sdn3d.data.frames import load_frame
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models
from sdn3d.editing.apply import Delete, Rotate, SetCode, Zoom
from sdn3d.editing.photo import PhotoSettings
from sdn3d.editing.render import edit_image
from sdn3d.editing.spec import PixelFrame
from sdn3d.runs import find_run_checkpoints
from sdn3d.textural.code_bank import named_color
from sdn3d.visualize import titled_row


def main() -> None:
    run, data, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    photo = PhotoSettings(fill=sys.argv[5]) if len(sys.argv) > 5 else PhotoSettings()
    torch.set_num_threads(2)
    chosen, _ = find_run_checkpoints(run)
    models = Models.from_checkpoints(None, chosen["geometric"]["path"], chosen["textural"]["path"])
    records = [r for r in read_frames(data) if r.objects]
    if len(sys.argv) > 4 and sys.argv[4] != "-":
        record = next(r for r in records if r.key.endswith(sys.argv[4]))
    else:  # the frame with the largest car lying wholly inside it (its box 20 px from every edge)
        def inside(o) -> bool:
            left, top, right, bottom = o.box2d
            return o.label in ("Car", "Van") and left > 20 and right < 1222 and bottom < 355 and o.location[2] > 5

        def area(o) -> float:
            return (o.box2d[2] - o.box2d[0]) * (o.box2d[3] - o.box2d[1])

        record = max(records, key=lambda r: max((area(o) for o in r.objects if inside(o)), default=0.0))
    work = (624, 192)
    frame = load_frame(record, work, semantic=True, instances=True)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    transform = PixelFrame((original.shape[2], original.shape[1]), work)
    gt = ground_truth(record, work)
    base = edit_image(frame.image, frame.intrinsics, [], models, "gt", gt, original=original, transform=transform)
    table = base.scene.objects
    visible = table.mask.flatten(1).sum(1).double()
    edge = torch.tensor([bool(table.mask[i][:, :3].any() or table.mask[i][:, -3:].any() or table.mask[i][-3:].any())
                         for i in range(len(table))])
    depth = torch.where(table.has_geometry & ~edge, -visible, torch.full_like(visible, 1e9))  # the largest inside
    car = int(table.instance_id[int(depth.argmin())])
    edits = {"closer (zoom 1.6)": [Zoom(car, 1.6, on_ground=True)], "turned 45 deg": [Rotate(car, np.deg2rad(45))],
             "deleted": [Delete(car)], "recoloured red": [SetCode(car, tuple(table.code[int(depth.argmin())].tolist()),
                                                                   named_color("red"))]}
    panels = [(f"source {record.key}, car {car}", original.permute(1, 2, 0).numpy())]
    for name, ops in edits.items():
        result = edit_image(frame.image, frame.intrinsics, ops, models, "gt", gt, original=original,
                            transform=transform, photo=photo)
        panels.append((f"{name} (photo appearance)", result.edited.permute(1, 2, 0).numpy()))
        print(name, result.photo.summary()["objects"].get(car), result.photo.warnings)
    rows = [titled_row(panels[:3], font_size=26), titled_row(panels[3:] + [("", np.full_like(panels[0][1], 255))],
                                                              font_size=26)]
    Image.fromarray(np.concatenate([rows[0], np.full((8, rows[0].shape[1], 3), 255, np.uint8), rows[1]])).save(out)
    print("wrote", out, record.key, car)


if __name__ == "__main__":
    main()
