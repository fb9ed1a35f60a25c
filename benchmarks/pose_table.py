"""Pose table (issue 40): the geometric branch alone and after the test-time fit, per source scene.

    python benchmarks/pose_table.py --geometric RUN/checkpoints/last.ckpt --data-root DATA [--part test|all]
                                    [--max-frames 40] [--threads 1] [--fit KEY=VALUE ...] [--out result.json]
                                    [--rows gt_branch gt_fit boxes_branch boxes_fit pred_branch pred_fit]
                                    [--semantic SEMANTIC.ckpt] [--crops photo|image]

On evenly spaced frames of ``--part`` (``all``: every frame of the tree, for a held-out tree no run trained on) the
evaluated objects are the annotated Car and Van instances with at least ``--min-pixels`` visible pixels at the
frame's working size and a template. Rows, on the same objects (paired):

- ``branch, oracle: ground-truth masks``: the geometric branch on the ground-truth visible masks and their boxes
  (:func:`sdn3d.derender.derender`, ``proposals='gt'``);
- ``fit, oracle: ground-truth masks + boxes``: what ``proposals=boxes`` does given the true boxes and the true masks
  (``BoxPrompts(masks=...)``): the branch's prediction starts :func:`sdn3d.geometric.fit.fit_to_masks`;
- ``branch, oracle: ground-truth boxes`` and ``fit, oracle: ground-truth boxes``: ``proposals=boxes`` given the true
  boxes alone (GrabCut's masks, as for a photo): the branch's prediction kept (the fit's ``min_mask_pixels`` set out
  of reach, so no object is fitted), and fitted;
- ``branch, predicted proposals`` and ``fit, predicted proposals``: the semantic branch's proposals
  (``proposals='semantic'``, ``--semantic``), as predicted and after the proposals' fit (``derender(fit=...)``).
  Each evaluated object is matched to the proposal whose mask overlaps its visible mask most (IoU at least
  ``--match-iou``); an object without a match (or whose match has no geometry) counts as the worst (180 degrees,
  wrong template): the figures are over every evaluated object, ``matched_pct`` says how many were found.

Figures per row and per source scene (world) and over all: yaw error ``|wrap(ry~ - ry)|`` in degrees (median, 90th
percentile), flips (share of objects whose yaw is more than 90 degrees off: end for end), template accuracy (the
template the object's mesh is or approximates) beside its majority floor (the share of the evaluated objects' most
common true template), distance error ``|log |c~| - log |c||`` (median, x1e-2), scale error ``||s~ - s||_2``
(median, m) and length error ``|l~ - l|`` (median and 90th percentile, m; an object without geometry: its length).
Each object's record also names the template chosen (``template``, -1: none), the signed distance error
(``dist_signed``, ``log |c~| - log |c|``: positive is too far) and both centres and sizes (``center``, ``dims``,
``true_center``, ``true_dims``; camera frame, metres; a level camera's ``true_center[1]`` is its height).
Nothing here selects or tunes anything.

``--crops photo`` (the default, as the edit path does for a user's image): the geometric branch's crops are read from
the frame as stored on disk (its own resolution, e.g. 624x192 for a working size of 312x96; ``derender(photo=...)``);
``--crops image``: from the working-size image (the measurement before session 6).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import torch

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.derender import BoxPrompts, derender  # noqa: E402
from sdn3d.geometric.fit import FitSettings  # noqa: E402
from sdn3d.io import write_json_atomic  # noqa: E402
from sdn3d.labels import INSTANCE_DIVISOR  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402

ROWS = {"gt_branch": "branch, oracle: ground-truth masks", "gt_fit": "fit, oracle: ground-truth masks + boxes",
        "boxes_branch": "branch, oracle: ground-truth boxes", "boxes_fit": "fit, oracle: ground-truth boxes",
        "pred_branch": "branch, predicted proposals", "pred_fit": "fit, predicted proposals"}


def row_of(scene, iid: int) -> int:
    hit = (scene.objects.instance_id == iid).nonzero().flatten()
    return int(hit[0]) if len(hit) else -1


def full_iou(scene, r: int, truth_mask: torch.Tensor, others: torch.Tensor) -> float | None:
    """Silhouette IoU of the object's fitted mesh, drawn in the whole image, with its true visible mask, the other
    objects' true pixels left out (they may hide it): the same yardstick whatever the fit's crop size."""
    from sdn3d.meshes.bank import default_bank
    from sdn3d.render import RasterSettings, rasterize_meshes
    from sdn3d.render.objects import pose_meshes

    o = scene.objects
    if r < 0 or int(o.template_id[r]) < 0:
        return None
    verts, faces = pose_meshes(default_bank(), o.template_id[r:r + 1], o.dims[r:r + 1].float(), o.ry[r:r + 1].float(),
                               o.center[r:r + 1].float(), o.phi[r:r + 1].float())
    drawn = rasterize_meshes(verts, faces, scene.intrinsics.matrix().float(),
                             RasterSettings(tuple(truth_mask.shape))).mask[0] & ~others
    target = truth_mask & ~others
    union = int((drawn | target).sum())
    return round(int((drawn & target).sum()) / union, 4) if union else None


def figures(rows: list[dict]) -> dict:
    """The table's figures of per-object rows (``yaw_deg``, ``template_ok``, ``true_template``, ``dist``, ``scale``,
    ``length``)."""
    if not rows:
        return {"n": 0}
    yaw = np.array([r["yaw_deg"] for r in rows])
    true_t = Counter(r["true_template"] for r in rows)
    return {
        "n": len(rows),
        "yaw_median_deg": round(float(np.median(yaw)), 2),
        "yaw_p90_deg": round(float(np.percentile(yaw, 90)), 2),
        "flips_over_90_pct": round(100 * float((yaw > 90).mean()), 1),
        "template_acc_pct": round(100 * float(np.mean([r["template_ok"] for r in rows])), 1),
        "template_majority_floor_pct": round(100 * max(true_t.values()) / len(rows), 1),
        "distance_median_x1e2": round(100 * float(np.median([r["dist"] for r in rows])), 2),
        "scale_median_m": round(float(np.median([r["scale"] for r in rows])), 3),
        "length_median_m": round(float(np.median([r["length"] for r in rows])), 3),
        "length_p90_m": round(float(np.percentile([r["length"] for r in rows], 90)), 3),
        "matched_pct": round(100 * float(np.mean([r.get("matched", True) for r in rows])), 1),
        "sil_iou_mean": (round(float(np.mean([r["sil_iou"] or 0.0 for r in rows])), 4)
                         if all("sil_iou" in r for r in rows) else None),
    }


def matched_rows(scene, masks: torch.Tensor, min_iou: float) -> list[int]:
    """Per evaluated object (``masks (K, H, W)`` its visible mask) the row of ``scene``'s object whose mask overlaps
    it most, -1 where none reaches ``min_iou``."""
    theirs = scene.objects.mask.bool()
    if not len(theirs):
        return [-1] * len(masks)
    inter = (masks[:, None] & theirs[None]).flatten(2).sum(2).float()
    union = (masks[:, None] | theirs[None]).flatten(2).sum(2).float().clamp_min(1)
    iou, best = (inter / union).max(1)
    return [int(b) if float(i) >= min_iou else -1 for i, b in zip(iou, best, strict=True)]


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--geometric", required=True, help="geometric checkpoint or inference export")
    p.add_argument("--data-root", required=True)
    p.add_argument("--part", default="test", choices=("train", "val", "test", "all"))
    p.add_argument("--max-frames", type=int, default=40, help="evenly spaced frames of the part (0: all)")
    p.add_argument("--min-pixels", type=int, default=256)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--no-fit", action="store_true", help="the branch's row only")
    p.add_argument("--fit", nargs="*", default=[], metavar="KEY=VALUE", help="FitSettings fields to change")
    p.add_argument("--no-lamps", action="store_true",
                   help="the branch's yaw as the net gives it (GeometricPredictor.lamp_cue=None: no red-lamp cue)")
    p.add_argument("--rows", nargs="*", default=["gt_branch", "gt_fit"], choices=tuple(ROWS),
                   help="the rows to measure (module doc)")
    p.add_argument("--semantic", default=None, help="semantic checkpoint (the predicted proposals' rows)")
    p.add_argument("--match-iou", type=float, default=0.5)
    p.add_argument("--image-size", type=int, nargs=2, default=None, metavar=("W", "H"),
                   help="working size (default: the tree's; the demo's branches work at 312 96)")
    p.add_argument("--crops", default="photo", choices=("image", "photo"),
                   help="the geometric branch's crops from the frame at its own resolution (the edit path's default) "
                        "or from the working-size image (before session 6)")
    p.add_argument("--out", default=None)
    args = p.parse_args(argv)
    if args.no_fit:
        args.rows = [r for r in args.rows if not r.endswith("_fit")]
    if any(r.startswith("pred_") for r in args.rows) and not args.semantic:
        p.error("the predicted proposals' rows need --semantic")
    torch.manual_seed(0)
    torch.set_num_threads(args.threads)
    crop = geometric_crop_settings(args.geometric)
    models = Models.from_checkpoints(geometric=args.geometric, semantic=args.semantic,
                                     **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    if args.no_lamps:
        models.geometric.lamp_cue = None
    source = synth_data_source(args.data_root)
    records = ([r for part in ("train", "val", "test") for r in load_split(source, part)] if args.part == "all"
               else load_split(source, args.part))
    records = sorted(records, key=lambda r: r.key)
    if args.max_frames and len(records) > args.max_frames:
        records = [records[i] for i in np.linspace(0, len(records) - 1, args.max_frames).round().astype(int)]
    size = tuple(args.image_size or source.image_size)

    def converted(v: str, default):
        if v.lower() in ("none", "null"):
            return None
        if isinstance(default, bool):
            return v.lower() in ("true", "1", "yes")
        return float(v) if default is None else type(default)(v)

    fit = FitSettings(**{k: converted(v, getattr(FitSettings(), k)) for k, v in (a.split("=", 1) for a in args.fit)})
    rows_asked = [ROWS[r] for r in args.rows]
    kept = FitSettings(**{**fit.to_dict(), "min_mask_pixels": 2**62, "coarse_steps": 0, "fine_steps": 0, "keep": 1,
                          "mirror": False})  # no object is fitted: the branch's predictions on the box masks
    per_object: dict[str, list[dict]] = {r: [] for r in rows_asked}
    t_start, seconds = time.perf_counter(), {r: 0.0 for r in rows_asked}
    for record in records:
        frame = load_frame(record, size, semantic=False, instances=False)
        image, intr = frame.image, frame.intrinsics
        photo = frame_photo(record, size) if args.crops == "photo" else None
        gt = ground_truth(record, size)
        truth = scene_from_frame(record, size)
        ids, boxes = [], []
        for iid in truth.objects.instance_id.tolist():
            k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
            r = row_of(truth, iid)
            if (cls not in (12, 13) or k not in gt.boxes or int(truth.objects.mask[r].sum()) < args.min_pixels
                    or truth.objects.template_id[r] < 0):
                continue
            ids.append(iid)
            left, top, right, bottom = gt.boxes[k].tolist()
            boxes.append([left, top, right + 1, bottom + 1])  # inclusive pixel centres -> half-open edges
        if not ids:
            continue
        names = tuple("Car" if i // INSTANCE_DIVISOR == 12 else "Van" for i in ids)
        gt_masks = torch.stack([truth.objects.mask[row_of(truth, i)] for i in ids]).bool()
        scenes = {}
        for key in args.rows:
            name = ROWS[key]
            t0 = time.perf_counter()
            if key == "gt_branch":
                scene = derender(image, intr, models, "gt", gt, photo=photo)
                found = [row_of(scene, i) for i in ids]
            elif key in ("gt_fit", "boxes_branch", "boxes_fit"):
                prompts = BoxPrompts(torch.tensor(boxes), names, kept if key == "boxes_branch" else fit,
                                     **({"masks": gt_masks, "refine_masks": False} if key == "gt_fit" else {}))
                scene = derender(image, intr, models, "boxes", gt, boxes=prompts, photo=photo)
                found = [row_of(scene, b.instance_id) for b in scene.meta["boxes"]]
            else:
                scene = derender(image, intr, models, "semantic", gt, fit=fit if key == "pred_fit" else None,
                                 photo=photo)
                found = matched_rows(scene, gt_masks, args.match_iou)
            seconds[name] += time.perf_counter() - t0
            scenes[name] = (scene, found)
        parts = record.key.split("/")  # "<dataset>/<world>/<variation>/<frame>"
        world = parts[1] if len(parts) > 2 else parts[0]
        for j, iid in enumerate(ids):
            t = truth.objects
            tr = row_of(truth, iid)
            box = boxes[j]
            cut = box[0] <= 0 or box[1] <= 0 or box[2] >= size[0] or box[3] >= size[1]  # touches the border
            for name, (scene, found) in scenes.items():
                o = scene.objects
                r = found[j]
                if r < 0 or int(o.template_id[r]) < 0:  # no geometry: counted as the worst
                    yaw, ok, dist, scale = 180.0, False, 1.0, float(t.dims[tr].norm())
                    length, dist_signed = float(t.dims[tr][0]), None
                else:
                    d = float(o.ry[r] - t.ry[tr])
                    yaw = abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))
                    ok = int(o.template_id[r]) == int(t.template_id[tr])
                    dist_signed = math.log(float(o.center[r].norm()) / float(t.center[tr].norm()))
                    dist = abs(dist_signed)
                    scale = float((o.dims[r] - t.dims[tr]).norm())
                    length = abs(float(o.dims[r][0] - t.dims[tr][0]))
                per_object[name].append({"world": world, "frame": record.key, "id": iid, "yaw_deg": yaw,
                                         "pixels": int(t.mask[tr].sum()), "true_ry": round(float(t.ry[tr]), 4),
                                         "true_xz": [round(float(t.center[tr][k]), 2) for k in (0, 2)],
                                         "template_ok": ok, "true_template": int(t.template_id[tr]), "dist": dist,
                                         "scale": scale, "length": length, "dist_signed": dist_signed,
                                         "true_center": [round(float(v), 3) for v in t.center[tr]],
                                         "true_dims": [round(float(v), 3) for v in t.dims[tr]],
                                         "center": None if r < 0 else [round(float(v), 3) for v in o.center[r]],
                                         "dims": None if r < 0 else [round(float(v), 3) for v in o.dims[r]],
                                         "template": -1 if r < 0 else int(o.template_id[r]),
                                         "box": [round(float(v), 1) for v in box],
                                         "truncated": bool(cut),
                                         "ry": None if r < 0 else round(float(o.ry[r]), 4),
                                         "matched": r >= 0,
                                         "hypothesis": (scene.meta["boxes"][j].hypothesis
                                                        if scene.meta.get("boxes") else None),
                                         "fit_iou": (scene.meta["boxes"][j].iou if scene.meta.get("boxes")
                                                     else None),
                                         "sil_iou": full_iou(scene, r, t.mask[tr], t.mask.any(0) & ~t.mask[tr])})
        print(f"{record.key}: {len(ids)} objects, {time.perf_counter() - t_start:.0f} s", file=sys.stderr)
    table = {}
    for name, rows in per_object.items():
        if not rows:
            continue
        worlds = sorted({r["world"] for r in rows})
        table[name] = {"all": figures(rows), **{w: figures([r for r in rows if r["world"] == w]) for w in worlds}}
        if not all(r["matched"] for r in rows):  # the poses of the objects found, apart from the finding
            table[name]["matched objects only"] = figures([r for r in rows if r["matched"]])
    result = {"geometric": str(Path(args.geometric).resolve()), "data_root": str(Path(args.data_root).resolve()),
              "part": args.part, "frames": len(records), "lamp_cue": not args.no_lamps, "min_pixels": args.min_pixels,
              "crops": args.crops, "image_size": list(size),
              "fit_settings": fit.to_dict(), "table": table,
              "seconds": {k: round(v, 1) for k, v in seconds.items()},
              "machine": f"{platform.machine()} cpu, {args.threads} threads, torch {torch.__version__}",
              "objects": per_object}
    print(json.dumps({k: v for k, v in result.items() if k != "objects"}, indent=1))
    if args.out:
        write_json_atomic(args.out, result)
    return result


if __name__ == "__main__":
    main()
