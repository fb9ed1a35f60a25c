"""wagon_probe.py OUT [DEGREES [INSTANCE]]: the real frame (tests/data, README's boxes, session 21's demo weights
w0) with one car turned (default: the red wagon 12001 by 180 degrees) through ``sdn3d-edit`` in this process, with
``_part_examples`` and ``_part_colors`` of the code on PYTHONPATH wrapped to keep each car's examples (and the input
pixel each came from, matched by its features) and the never-seen points they drew; then prints, per part and end,
what was drawn and, for the front's body and plate below the lamp band, where the 4 nearest examples lay: their
image rows and columns, mean colour, reach and share on the road the mask took in (``recolor.ground_in_mask``).

    cd CODE && PYTHONPATH=CODE/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python wagon_probe.py OUT 180 12001
"""

from __future__ import annotations

import sys
from pathlib import Path

import torch
import yaml

import sdn3d.editing.photo.transfer as T
from sdn3d.cli import edit
from sdn3d.meshes.parts import PART_NAMES

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
WIDTH = 1242
RECORD: dict = {"examples": {}, "colors": []}
_examples, _colors = T._part_examples, T._part_colors


def part_examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, road, settings, air=None):
    """``_part_examples``, keeping its examples and the input pixel of each (nearest by features)."""
    kept, seen = _examples(b, s_mesh, visible_px, before, src, parts_src, img_flat, road, settings, air)
    ex = visible_px[(src.frags.mesh_at(visible_px) == s_mesh) & (parts_src[visible_px] >= 0)]
    pix = torch.zeros(0, dtype=torch.long)
    if len(ex):
        _, vid, bary, normal = T._surface(src, ex)
        tri = src.verts[torch.full((len(ex),), s_mesh, dtype=torch.long)[:, None], vid]
        feature = T._part_features(before, b, T.sum3(bary[..., None] * tri, 1), normal)
        pix = ex[torch.cdist(kept.feature.float(), feature.float()).argmin(1)]
    RECORD["examples"][b] = {"ex": kept, "pix": pix, "road": road}
    return kept, seen


def part_colors(b, own, seen_colors, points, normals, parts, before, body, others=None, max_examples=1500, k=4,
                air=None):
    """``_part_colors``, keeping the points it drew and what it drew."""
    out = _colors(b, own, seen_colors, points, normals, parts, before, body, others, max_examples, k, air)
    RECORD["colors"].append({"b": b, "parts": parts, "out": out, "q": T._part_features(before, b, points, normals)})
    return out


def report() -> None:
    for call in RECORD["colors"]:
        kept = RECORD["examples"][call["b"]]
        ex, pix, road = kept["ex"], kept["pix"], kept["road"]
        on_road = torch.zeros(len(pix), dtype=torch.bool) if road is None else road[pix]
        print(f"car row {call['b']}: {len(ex.part)} examples, reach counts "
              f"{torch.bincount(ex.reach.long(), minlength=4).tolist()}")
        for p in ex.part.unique().tolist():
            m = ex.part == p
            print(f"  examples {PART_NAMES[p]}: {int(m.sum())}, on the road {float(on_road[m].double().mean()):.3f}")
        q, parts, albedo = call["q"], call["parts"], call["out"][0]
        x, y = q[:, 0] / T.PART_LENGTH_WEIGHT, q[:, 1]
        for name, where in (("front", x > T.LAMP_END), ("rear", x < -T.LAMP_END), ("middle", x.abs() <= T.LAMP_END)):
            for p in parts[where].unique().tolist():
                m = where & (parts == p)
                mean = albedo[m].mean(0).numpy().round(2)
                print(f"  drawn {name} {PART_NAMES[p]}: {int(m.sum())} points, mean {mean}")
        usable = (ex.reach != T.REACH_SIDES) & (ex.reach != T.REACH_LAMPS)
        for lo, hi in ((0.05, 0.2), (0.2, 0.35)):
            band = (x > T.LAMP_END) & (y > lo) & (y <= hi)
            for p in parts[band].unique().tolist():
                m = band & (parts == p)
                have = ((ex.part == p) & usable).nonzero().flatten()
                if not len(have):
                    continue
                used = have[T._nearest_examples(q[m], ex.feature[have], 4)].flatten()
                rows, cols = pix[used] // WIDTH, pix[used] % WIDTH
                print(f"  front height ({lo}, {hi}] {PART_NAMES[p]}: {int(m.sum())} points drawn "
                      f"{albedo[m].mean(0).numpy().round(2)} from examples at rows {int(rows.min())}-{int(rows.max())}"
                      f" cols {int(cols.min())}-{int(cols.max())}, mean {ex.color[used].mean(0).numpy().round(2)}, "
                      f"on the road {float(on_road[used].double().mean()):.2f}")


def main() -> int:
    out = Path(sys.argv[1])
    degrees = int(sys.argv[2]) if len(sys.argv) > 2 else 180
    iid = int(sys.argv[3]) if len(sys.argv) > 3 else 12001
    out.mkdir(parents=True, exist_ok=True)
    spec = out / "spec.yaml"
    spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": degrees, "id": iid}]}))
    T._part_examples, T._part_colors = part_examples, part_colors
    edit.main([f"input.image={FRAME}", "run=/tmp/s21data/demo/out", "proposals=boxes", f"edits={spec}",
               f"output_dir={out / 'edit'}"])
    report()
    return 0


if __name__ == "__main__":
    sys.exit(main())
