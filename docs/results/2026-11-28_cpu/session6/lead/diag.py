# ruff: noqa: E402, E501, E701, E702
"""Where the turned cars' error is (issue 41, turns): each turn pair of a counterfactual tree drawn by the photo
appearance (oracle geometry, ``photo:auto``, the benchmark's own path), its squared error on the car's target pixels
split by source-map class, by part and into edge pixels (within 2 px of the target silhouette).

    python diagnose.py TREE OUT [--limit N] [--png K] [photo.key=value ...]

Writes OUT/diagnose.json (per pair: pixels, summed squared error and the dB a perfect class would give, per class and
part) and OUT/diagnose.md (pooled per bin); with --png K, side-by-side PNGs (input, target, ours, |error|, source
map) of the first K target cars.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from PIL import Image

from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.appearance import Appearance, appearance_renderer
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Rotate
from sdn3d.editing.photo.settings import SOURCE_NAMES, PhotoSettings, part_picture, source_picture
from sdn3d.evaluation.counterfactual import _match
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.parts import PART_NAMES
from sdn3d.scene.code import DEFAULT_CODE_DIM


def _value(text: str):
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text


def classes(source: np.ndarray, parts: np.ndarray, car: np.ndarray) -> dict[str, np.ndarray]:
    edge = car & ~(F.max_pool2d(torch.from_numpy(~car).float()[None, None], 5, 1, 2)[0, 0].numpy() == 0)
    out = {"edge": edge}
    inner = car & ~edge
    for code, name in enumerate(SOURCE_NAMES):
        m = inner & (source == code)
        if m.any():
            out[f"src:{name}"] = m
    for p, name in enumerate(PART_NAMES):
        m = car & (parts == p)
        if m.any():
            out[f"part:{name}"] = m
    out["part:none"] = car & (parts < 0)
    for p, name in enumerate(PART_NAMES):  # the unseen pixels per part (source part/default/fallback), inner
        m = inner & (parts == p) & np.isin(source, [3, 7, 8])
        if m.any():
            out[f"unseen:{name}"] = m
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("tree")
    ap.add_argument("out")
    ap.add_argument("--limit", type=int, default=None)
    ap.add_argument("--png", type=int, default=0)
    ap.add_argument("--only", default=None)
    ap.add_argument("settings", nargs="*")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    pairs_kv = [s.split("=", 1) for s in args.settings]
    import sdn3d.editing.photo.transfer as transfer  # T.NAME=value: a module constant, for experiments

    for k, v in pairs_kv:
        if k.startswith("T."):
            setattr(transfer, k[2:], _value(v))
    photo = PhotoSettings(**{k: _value(v) for k, v in pairs_kv if not k.startswith("T.")})
    index = load_pairs(args.tree)
    records = index_records(read_frames(Path(args.tree)))
    size = index.image_size
    identity = PixelFrame(size, size)
    groups: dict = {}
    for p in index.pairs:
        if p.kind == "turn":
            groups.setdefault(p.target_key, []).append(p)
    chosen = list(groups.items())[: args.limit] if args.limit else list(groups.items())
    if args.only:
        chosen = [kv for kv in chosen if any(o in kv[1][0].key for o in args.only.split(","))]
    rows = []
    renderer = appearance_renderer(Appearance.PHOTO, photo=photo)
    for n, ((world, variation, frame_no, _), pairs) in enumerate(chosen):
        record = records[(world, variation, frame_no)]
        frame = load_frame(record, size, semantic=False, instances=False)
        image = frame.image
        scene = scene_from_frame(record, size, DEFAULT_CODE_DIM)
        source_mask = torch.from_numpy(load_pair_mask(index.root, pairs[0], "source_mask"))
        iid, _ = _match(scene, pairs[0].instance_id, source_mask)
        state = renderer.prepare(image, identity, scene)
        panels = []
        for pair in pairs:
            target = load_pair_rgb(index.root, pair).astype(np.float32) / 255
            car = load_pair_mask(index.root, pair, "target_mask")
            ops = [Rotate(iid, math.radians(float(pair.angle_deg)))]
            drawn = renderer.draw(state, apply_edits(scene, ops), ops)
            pic = drawn.image.float().clamp(0, 1).permute(1, 2, 0).numpy()
            src = drawn.photo.source.numpy()
            parts = drawn.photo.parts.numpy().astype(np.int64)
            se = ((pic - target) ** 2).sum(-1)  # per pixel, summed over channels
            total = float(se[car].sum())
            npx = int(car.sum())
            mse = total / (3 * npx)
            row = {
                "key": pair.key,
                "bin": f"turn {pair.angle_deg:g}",
                "pixels": npx,
                "se": total,
                "psnr": 10 * math.log10(1 / max(mse, 1e-6)),
                "classes": {},
            }
            for name, m in classes(src, parts, car).items():
                se_c = float(se[m].sum())
                rest = max(total - se_c, 1e-6 * 3 * npx)
                row["classes"][name] = {
                    "pixels": int(m.sum()),
                    "se": se_c,
                    "gain_db": 10 * math.log10(total / rest) if total > 0 else 0.0,
                    "signed": (pic[m] - target[m]).mean(0).round(4).tolist() if m.any() else None,
                }
            rows.append(row)
            dm = (src == 8) & car
            print(pair.key, "other-car px", int(((src == 11) & car).sum()), "default px", int(dm.sum()), "of", npx, "parts:", np.bincount(parts[dm] + 1, minlength=8).tolist(), "psnr {:.2f}".format(row["psnr"]))
            if n < args.png:
                err = np.abs(pic - target).mean(-1, keepdims=True).repeat(3, -1) * 3
                panels.append(
                    np.concatenate(
                        [
                            image.permute(1, 2, 0).numpy(),
                            target,
                            pic,
                            err.clip(0, 1),
                            source_picture(drawn.photo.source) / 255,
                            part_picture(drawn.photo.parts) / 255,
                        ],
                        1,
                    )
                )
        if panels:
            ys, xs = np.nonzero(source_mask.numpy() | car)
            y0, y1 = max(0, ys.min() - 20), min(size[1], ys.max() + 20)
            x0, x1 = max(0, xs.min() - 40), min(size[0], xs.max() + 40)
            w = size[0]
            crops = [np.concatenate([p[y0:y1, k * w + x0 : k * w + x1] for k in range(6)], 1) for p in panels]
            grid = (np.concatenate(crops, 0) * 255).round().astype(np.uint8)
            Image.fromarray(grid).save(out / f"pair_{n:02d}_{world}_{variation}_{frame_no}.png")
        print(f"[{n + 1}/{len(chosen)}] {pairs[0].key.split()[0]}", flush=True)
    (out / "diagnose.json").write_text(json.dumps({"settings": photo.to_dict(), "rows": rows}))
    lines = []
    for b in sorted({r["bin"] for r in rows}, key=lambda s: float(s.split()[1])):
        mine = [r for r in rows if r["bin"] == b]
        tot_px = sum(r["pixels"] for r in mine)
        tot_se = sum(r["se"] for r in mine)
        lines += [
            f"## {b} (n={len(mine)}, mean PSNR {np.mean([r['psnr'] for r in mine]):.2f} dB)",
            "",
            "| class | pixel share % | SE share % | RMSE | mean gain if perfect (dB) | mean signed err (RGB) |",
            "|---|---|---|---|---|---|",
        ]
        names = sorted({c for r in mine for c in r["classes"]}, key=lambda c: (c.split(":")[0], c))
        for c in names:
            px = sum(r["classes"].get(c, {}).get("pixels", 0) for r in mine)
            se = sum(r["classes"].get(c, {}).get("se", 0.0) for r in mine)
            gain = np.mean([r["classes"].get(c, {}).get("gain_db", 0.0) for r in mine])
            signed = [
                np.array(r["classes"][c]["signed"]) * r["classes"][c]["pixels"]
                for r in mine
                if c in r["classes"] and r["classes"][c]["signed"] is not None
            ]
            sg = (np.sum(signed, 0) / max(px, 1)).round(3).tolist() if signed else None
            lines.append(
                f"| {c} | {100 * px / tot_px:.1f} | {100 * se / max(tot_se, 1e-12):.1f} | "
                f"{math.sqrt(se / max(3 * px, 1)):.3f} | {gain:.2f} | {sg} |"
            )
        lines.append("")
    (out / "diagnose.md").write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
