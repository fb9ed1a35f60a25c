# ruff: noqa: E501
"""probe.py TREE OUT_DIR [BIN] [SOURCE]: every turn pair of TREE's bin BIN (default "turn 180") drawn by the photo
appearance (fill rays, the bench's photo defaults) from SOURCE (oracle: ground-truth geometry; semantic: predicted,
the session 11 demo's branches) with this tree's code. Per pair: the squared error on the car's target pixels split
by (part, source code) of the drawn pixel, printed as linearised dB shares (each class's share of the pair's summed
squared error times the pair's PSNR loss against 40 dB is not used: plain SSE shares); and OUT_DIR/<key>.npz with
input, target, drawn picture, source codes and part map (for pictures)."""

from __future__ import annotations

import json
import os
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
import torch

from sdn3d.cli._config import compose_config
from sdn3d.cli.bench import _proposal_fit
from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Rotate
from sdn3d.editing.photo.settings import SOURCE_NAMES, PhotoSettings
from sdn3d.evaluation import counterfactual as cf
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.parts import Part

RUNS = "/tmp/s11data/demo/out/runs"


def ends_only(x_min: float) -> None:
    """Variant (env GLASS_ENDS=X): the greenhouse glass only where the template point lies beyond X of the length
    from the middle (canonical |x| > X: the end panels), not along the sides."""
    import torch.nn.functional as F

    from sdn3d.editing.photo import transfer
    from sdn3d.meshes.parts import Part, greenhouse_glass

    def patched(found, pix, r, bank, template, local):
        body = (found == int(Part.BODY)).nonzero().flatten()
        if not len(body):
            return found
        t, f = template[body], local[body]
        tri = bank.verts.cpu()[t[:, None], bank.faces.cpu()[t, f]].double()
        bary = r.frags.bary.view(-1, 3)[pix[body]].double()
        height = (bary * tri[..., 1]).sum(1)
        along = (bary * tri[..., 0]).sum(1)
        normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
        glass = greenhouse_glass(found[body], height, -normal[:, 1], transfer._bank_belts(bank)[t]) & (along.abs() > x_min)
        out = found.clone()
        out[body[glass]] = int(Part.GLASS)
        return out

    transfer._greenhouse_glass = patched


def main() -> None:
    tree, out = sys.argv[1], Path(sys.argv[2])
    want = sys.argv[3] if len(sys.argv) > 3 else "turn 180"
    source = sys.argv[4] if len(sys.argv) > 4 else "oracle"
    out.mkdir(parents=True, exist_ok=True)
    if os.environ.get("GLASS_ENDS"):
        ends_only(float(os.environ["GLASS_ENDS"]))
    torch.set_num_threads(1)
    cfg = compose_config([], "bench")
    models = None
    if source != "oracle":
        models = Models.from_checkpoints(f"{RUNS}/semantic/checkpoints/inference.pt",
                                         f"{RUNS}/geometric/checkpoints/inference.pt", None, map_location="cpu")
    settings = cf.CounterfactualSettings(sources=(source,), fills=("rays",), generator=False, baselines=(),
                                         photo=PhotoSettings.from_mapping({k: v for k, v in cfg.photo.items() if k != "fill"}),
                                         min_pixels=int(cfg.geometric.min_pixels), fit=_proposal_fit(cfg), kinds=("turn",))
    index = load_pairs(tree)
    records = index_records(read_frames(tree))
    size = index.image_size
    groups: dict = defaultdict(list)
    for p in index.pairs:
        if p.kind == "turn" and cf.pair_bin(p) == want:
            groups[p.target_key].append(p)
    total: dict = defaultdict(float)
    rows = []
    for (world, variation, frame, _), pairs in groups.items():
        record = records[(world, variation, frame)]
        image = load_frame(record, size, semantic=False, instances=False).image
        source_mask = torch.from_numpy(load_pair_mask(index.root, pairs[0], "source_mask"))
        scene = cf._source_scene(source, record, image, load_frame(record, size, semantic=False, instances=False).intrinsics,
                                 models, settings, size)
        iid, iou = cf._match(scene, pairs[0].instance_id, source_mask)
        if iid is None or iou < settings.match_iou:
            continue
        renderer = cf._renderers(("photo:rays",), settings, models)["photo:rays"]
        state = renderer.prepare(image, PixelFrame(size, size), scene)
        for pair in pairs:
            target = torch.from_numpy(load_pair_rgb(index.root, pair)).permute(2, 0, 1).float() / 255
            car = torch.from_numpy(load_pair_mask(index.root, pair, "target_mask")).bool()
            ops = [Rotate(iid, np.radians(float(pair.angle_deg)))]
            drawn = renderer.draw(state, apply_edits(scene, ops), ops)
            pic = drawn.image.float().clamp(0, 1)
            codes = drawn.photo.source.long()
            parts = drawn.photo.parts.long() if drawn.photo.parts is not None else torch.full_like(codes, -1)
            se = ((pic - target) ** 2).sum(0)
            sse = float(se[car].sum())
            mse = sse / (3 * int(car.sum()))
            psnr = 10 * np.log10(1 / max(mse, 1e-10))
            split = defaultdict(float)
            for c in codes[car].unique().tolist():
                for q in parts[car].unique().tolist():
                    m = car & (codes == c) & (parts == q)
                    if bool(m.any()):
                        name = f"{Part(q).name.lower() if q >= 0 else 'none'}/{SOURCE_NAMES[c]}"
                        split[name] += float(se[m].sum())
            for k, v in split.items():
                total[k] += v
            rows.append({"key": pair.key, "iid": iid, "angle": float(pair.angle_deg), "psnr": psnr, "pixels": int(car.sum()),
                         "split": {k: round(v / sse, 3) for k, v in sorted(split.items(), key=lambda kv: -kv[1])[:6]}})
            print(json.dumps(rows[-1]), flush=True)
            np.savez_compressed(out / f"{pair.key.replace('/', '_')}.npz", input=image.numpy(), target=target.numpy(),
                                drawn=pic.numpy(), codes=codes.numpy().astype(np.uint8), parts=parts.numpy().astype(np.int8),
                                car=car.numpy())
    s = sum(total.values())
    print("TOTAL", json.dumps({k: round(v / s, 3) for k, v in sorted(total.items(), key=lambda kv: -kv[1])}))
    print("MEAN PSNR", np.mean([r["psnr"] for r in rows]), len(rows))


if __name__ == "__main__":
    main()
