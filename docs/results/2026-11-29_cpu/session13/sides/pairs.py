# ruff: noqa: E501
"""pairs.py TREE OUT.png VARIANT_A,VARIANT_B PAIR [PAIR ...]: per counterfactual turn pair (PAIR =
``world/variation/frame_instance:angle``, e.g. ``0006/clone/00024_13005:180``), ground-truth geometry (oracle), photo
fill rays, one titled row: the input, the exact target (sdn3d-synth's render of the car turned), each variant's
drawing (variants as variants.py names them, its PSNR on the car's target pixels in the title), each variant's
absolute error (x4, grey) and where the last variant's error is smaller (green) or larger (red) than the first's on
the car's target pixels (difference x6). Cropped around the car, enlarged to about 160 pixels tall."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent))
import variants  # noqa: E402

from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import scene_from_frame  # noqa: E402
from sdn3d.data.vkitti1 import read_frames  # noqa: E402
from sdn3d.editing.appearance import Appearance, appearance_renderer  # noqa: E402
from sdn3d.editing.apply import apply_edits  # noqa: E402
from sdn3d.editing.frame import PixelFrame  # noqa: E402
from sdn3d.editing.ops import Rotate  # noqa: E402
from sdn3d.editing.photo import transfer  # noqa: E402
from sdn3d.editing.photo.settings import PhotoSettings  # noqa: E402
from sdn3d.evaluation.edit_benchmark import index_records  # noqa: E402
from sdn3d.scene.code import DEFAULT_CODE_DIM  # noqa: E402
from sdn3d.visualize import titled_row  # noqa: E402


def main() -> None:
    tree, out, names, wanted = sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4:]
    torch.set_num_threads(1)
    transfer._part_normals = variants.patched_part_normals
    transfer._part_examples = variants.patched_examples
    transfer.PhotoSource.registered_parts = variants.patched_registered
    index = load_pairs(tree)
    records = index_records(read_frames(tree))
    renderer = appearance_renderer(Appearance.PHOTO, photo=PhotoSettings(fill="rays"))
    size = index.image_size
    rows = []
    for spec in wanted:
        target_key, angle = spec.split(":")
        pair = next(p for p in index.pairs if p.kind == "turn" and f"{p.world}/{p.variation}/{p.frame:05d}_{p.instance_id}" == target_key
                    and int(p.angle_deg) == int(angle))
        record = records[(pair.world, pair.variation, pair.frame)]
        frame = load_frame(record, size, semantic=False, instances=False)
        scene = scene_from_frame(record, size, DEFAULT_CODE_DIM)
        target = load_pair_rgb(tree, pair).astype(np.float32) / 255
        car = load_pair_mask(tree, pair, "target_mask")
        src = load_pair_mask(tree, pair, "source_mask")
        ys, xs = np.nonzero(car | src)
        pad = 12
        y0, y1, x0, x1 = max(0, ys.min() - pad), min(size[1], ys.max() + pad), max(0, xs.min() - pad), min(size[0], xs.max() + pad)
        state = renderer.prepare(frame.image, PixelFrame(size, size), scene)
        ops = [Rotate(pair.instance_id, math.radians(float(pair.angle_deg)))]
        edited = apply_edits(scene, ops)

        scale = max(1, round(160 / (y1 - y0)))

        def crop(a: np.ndarray, y0: int = y0, y1: int = y1, x0: int = x0, x1: int = x1, scale: int = scale) -> np.ndarray:
            a = (np.clip(a, 0, 1) * 255).astype(np.uint8)[y0:y1, x0:x1]
            return np.asarray(Image.fromarray(a).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST))

        panels = [(f"{spec} input", crop(frame.image.permute(1, 2, 0).numpy())), ("exact target", crop(target))]
        errors, errs = [], []
        for name in names:
            variants.STATE["variant"] = name.removesuffix("+wheels")
            variants.STATE["wheels"] = name.endswith("+wheels")
            drawn = renderer.draw(state, edited, ops)
            picture = drawn.image.float().clamp(0, 1).permute(1, 2, 0).numpy()
            err = np.abs(picture - target).mean(-1)
            m = car.astype(bool)
            psnr = -10 * math.log10(max(float(((picture - target) ** 2)[m].mean()), 1e-10))
            panels.append((f"{name} {psnr:.2f} dB", crop(picture)))
            errors.append((f"|error| x4 {name}", crop(np.repeat(np.minimum(err * 4, 1)[..., None], 3, -1))))
            errs.append(np.where(m, err, 0.0))
        # where the second variant is nearer the target (green) or farther (red) than the first, on the car
        gain = np.clip((errs[0] - errs[-1]) * 6, -1, 1)
        diff = np.zeros((size[1], size[0], 3), np.float32)
        diff[..., 1] = np.maximum(gain, 0)
        diff[..., 0] = np.maximum(-gain, 0)
        rows.append(titled_row(panels + errors + [(f"{names[-1]} vs {names[0]}: green better, red worse", crop(diff))]))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).save(out)
    print(out)


if __name__ == "__main__":
    main()
