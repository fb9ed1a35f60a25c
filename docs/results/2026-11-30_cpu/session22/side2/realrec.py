"""Session 22 side2: the real Virtual KITTI frame of tests/data (README's boxes), each car turned 90 degrees through
``sdn3d-edit`` with the code on PYTHONPATH; every car's body examples as the paint decision sees them
(``transfer._part_examples``: CIE Lab, :func:`transfer._part_features`, lamp part, pixel index) saved with
``torch.save`` to OUT_PT, keyed ``real|<car>``, the format of probe.py's records.

    PYTHONPATH=src OMP_NUM_THREADS=1 /work/main/.venv/bin/python realrec.py RUN_DIR WORK_DIR OUT_PT
"""

from __future__ import annotations

import sys
from pathlib import Path

import torch
import yaml

import sdn3d.editing.photo.transfer as T
from sdn3d.cli.edit import main as edit
from sdn3d.editing.photo.recolor import srgb_to_lab
from sdn3d.meshes.parts import Part

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
RECORDS: dict[str, dict] = {}
_part_examples = T._part_examples


def recording(b, s_mesh, visible_px, before, src, parts_src, img_flat, *rest):
    """``transfer._part_examples``, recording the body examples it decides the paint on."""
    name = f"real|{int(before.instance_id[b])}"
    settings = rest[-1]  # main's code passes (settings), the branch's (road, settings)
    ex = visible_px[(src.frags.mesh_at(visible_px) == s_mesh) & (parts_src[visible_px] >= 0)]
    if name not in RECORDS and len(ex):
        _, vid, bary, normal = T._surface(src, ex)
        tri = src.verts[torch.full((len(ex),), s_mesh, dtype=torch.long)[:, None], vid]
        point = T.sum3(bary[..., None] * tri, 1)
        good = T._view_cos(point, normal) >= settings.min_view_cos
        body = good & (parts_src[ex] == int(Part.BODY))
        feature = T._part_features(before, b, point[body], normal[body])
        RECORDS[name] = {"lab": srgb_to_lab(img_flat[ex[body]].double().float()), "feature": feature,
                         "band": T._lamp_band(before, b, feature, corners=False), "px": ex[body],
                         "template": int(before.template_id[b]), "visible": visible_px.clone(),
                         "image": (img_flat.clamp(0, 1) * 255 + 0.5).floor().to(torch.uint8)}
    return _part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, *rest)


def main() -> int:
    run, work, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    T._part_examples = recording
    for iid in (12001, 12002):
        spec = work / f"spec_{iid}.yaml"
        spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": 90, "id": iid}]}))
        edit([f"input.image={FRAME}", f"run={run}", "proposals=boxes", f"edits={spec}",
              f"output_dir={work / f'edit_{iid}'}"])
    torch.save(RECORDS, out)
    print(sorted(RECORDS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
