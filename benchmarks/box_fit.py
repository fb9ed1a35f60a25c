"""Objects from boxes (issue 31): GrabCut masks and the 3D fit against the ground truth, on a synthetic part.

    python benchmarks/box_fit.py --geometric RUN/checkpoints/inference.pt --data-root DATA [--part test]
                                 [--max-frames 40] [--threads 2] [--out result.json] [--examples DIR]

On every frame of ``--part`` (default ``test``; evenly spaced ``--max-frames`` of them; nothing here selects or
tunes anything) the evaluated objects are the annotated Car and Van instances with at least ``--min-pixels``
visible pixels at the frame's size (624x192 for the synthetic data). The only input of the box rows is each
object's annotated 2D box (all of the frame's evaluated boxes at once, so they occlude each other as in use), the
image and the camera. Rows, per object, all on the same objects (paired):

- ``fit, box masks``: what ``sdn3d-edit`` does with ``objects: [{box: ...}]`` (:func:`sdn3d.derender.derender`,
  ``proposals='boxes'``): GrabCut masks nearest first, the geometric branch's prediction as the start, the fit on
  the road plane ``y = 1.65 m`` (:class:`sdn3d.geometric.fit.FitSettings` defaults);
- ``prediction, box masks``: the geometric branch on the same GrabCut masks, no fit;
- ``prediction, GT masks (oracle)``: the geometric branch on the ground-truth visible masks, no fit (the paper's
  protocol for Table 2, with the frame's annotated boxes);
- ``fit, GT masks (oracle)``: the fit on the ground-truth masks (isolates the masks' share of the error);
- ``fit, box masks, true camera height (oracle)``: the synthetic worlds put the camera 1.50-1.65 m up; this row
  gives the fit each frame's true road height (the median annotated ``y3d``).

Figures (Table 2's definitions, ``sdn3d.geometric.metrics``): orientation similarity ``(1 + cos dry) / 2``, distance
``|log |c~| - log |c||`` (x1e-2), scale ``||s~ - s||_2`` (m), reprojection: pixels of the square window around
the object's visible box (grown by 0.1) where the hard silhouette and the ground-truth visible mask disagree, nearer
objects' pixels ignored, over the frame's W x H (x1e-3); mask IoU with the true visible mask (also for the
unoccluded, untruncated objects over 1,000 pixels, the issue's goal) of the first GrabCut mask (``mask_iou``) and of
the mask the scene ends with, segmented again seeded by the fitted 3D shape (``mask_iou_refined``, with its paired
difference to the first); for those large objects, the same IoUs with the true outline's band ignored (the pixels within
one pixel of it on either side, as PASCAL VOC ignores a 5-px band) and, for scale, the IoU of the true mask shrunk by
one pixel (an outline one pixel off all round); and the fit's own silhouette IoU.
Beside the means: the paired difference of each fit row to ``prediction, GT masks`` with a 95 % t-interval over
objects (objects of one frame are not independent: the interval is indicative). Timing: GrabCut and fit per object.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np
import torch

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sdn3d.box_masks import grabcut_masks  # noqa: E402
from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import ground_truth, scene_from_frame  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.derender import BoxPrompts, GroundTruth, derender  # noqa: E402
from sdn3d.geometric.fit import FitSettings  # noqa: E402
from sdn3d.geometric.metrics import distance_error, orientation_similarity, scale_error  # noqa: E402
from sdn3d.image_ops import mask_boxes, pixel_centre_boxes, square_crop_window  # noqa: E402
from sdn3d.io import write_json_atomic  # noqa: E402
from sdn3d.labels import INSTANCE_DIVISOR  # noqa: E402
from sdn3d.math3d.rotations import roty  # noqa: E402
from sdn3d.meshes.bank import MeshBank  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402
from sdn3d.render import RasterSettings, rasterize_meshes  # noqa: E402
from sdn3d.render.objects import pose_meshes  # noqa: E402

ROWS = ("fit, box masks", "prediction, box masks", "prediction, GT masks (oracle)", "fit, GT masks (oracle)",
        "fit, box masks, true camera height (oracle)")
METRICS = ("orientation", "distance_x1e2", "scale_m", "reprojection_x1e3")
BIG_UNOCCLUDED = 1000


def reprojection(obj, gt_mask: torch.Tensor, nearer: torch.Tensor, intr, bank: MeshBank) -> float:
    """Disagreeing pixels of the hard silhouette and ``gt_mask`` in the square window around the visible box (grown
    by 0.1), ``nearer`` pixels ignored, over W x H."""
    height, width = gt_mask.shape
    box = pixel_centre_boxes(mask_boxes(gt_mask[None]))[0]
    left, top, side = square_crop_window(box, 0.1)
    verts, faces = pose_meshes(bank, torch.tensor([obj["template"]]), obj["dims"][None].float(),
                               obj["ry"][None].float(), obj["center"][None].float(), obj["phi"][None].float())
    sil = rasterize_meshes(verts, faces, intr.matrix().float(), RasterSettings((height, width))).mask[0]
    window = torch.zeros_like(gt_mask)
    window[max(0, top):max(0, top + side), max(0, left):max(0, left + side)] = True
    return float(((sil != gt_mask) & window & ~nearer).sum()) / (width * height)


def outline_band(mask: torch.Tensor) -> torch.Tensor:
    """``(H, W)`` bool: the pixels within one pixel of ``mask``'s outline, on either side (3x3 dilation minus 3x3
    erosion): the pixels a mask drawn from colours at this resolution may get either way (anti-aliased edges)."""
    grown = torch.nn.functional.max_pool2d(mask[None, None].float(), 3, 1, 1)[0, 0] > 0
    shrunk = -torch.nn.functional.max_pool2d(-mask[None, None].float(), 3, 1, 1)[0, 0] > 0
    return grown & ~shrunk


def objects_of(scene, ids: list[int]) -> list[dict]:
    """Per id, the object's geometry (template -1: absent from the scene, e.g. an empty mask, or no geometry)."""
    t = scene.objects
    out = []
    for iid in ids:
        hit = (t.instance_id == iid).nonzero().flatten()
        if not len(hit):
            out.append({"template": -1})
            continue
        r = int(hit[0])
        out.append({"template": int(t.template_id[r]), "dims": t.dims[r].double(), "ry": t.ry[r].double(),
                    "center": t.center[r].double(), "phi": t.phi[r].float()})
    return out


def row_of(scene, iid: int) -> int:
    return int((scene.objects.instance_id == iid).nonzero().flatten()[0])


def interval(diff: np.ndarray) -> list[float]:
    """Mean and 95 % t-interval (normal quantile for n > 30) of paired differences."""
    n = len(diff)
    if n < 2:
        return [float(diff.mean()) if n else float("nan"), float("nan"), float("nan")]
    from scipy import stats

    half = stats.t.ppf(0.975, n - 1) * diff.std(ddof=1) / math.sqrt(n)
    return [float(diff.mean()), float(diff.mean() - half), float(diff.mean() + half)]


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--geometric", required=True, help="geometric checkpoint or inference export (the fit's start)")
    p.add_argument("--data-root", required=True)
    p.add_argument("--part", default="test", choices=("train", "val", "test"))
    p.add_argument("--max-frames", type=int, default=40, help="evenly spaced frames of the part (0: all)")
    p.add_argument("--min-pixels", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--fit", nargs="*", default=[], metavar="KEY=VALUE",
                   help="FitSettings fields to change (choose them on --part val, never on test)")
    p.add_argument("--out", default=None)
    p.add_argument("--details", action="store_true",
                   help="also record every object's true and per-row size, yaw and template (result['details'])")
    args = p.parse_args(argv)
    torch.set_num_threads(args.threads)
    crop = geometric_crop_settings(args.geometric)
    models = Models.from_checkpoints(geometric=args.geometric, **({"crop_size": crop[0], "margin": crop[1]}
                                                                   if crop else {}))
    source = synth_data_source(args.data_root)
    records = load_split(source, args.part)
    if args.max_frames and len(records) > args.max_frames:
        records = [records[i] for i in np.linspace(0, len(records) - 1, args.max_frames).round().astype(int)]
    size = tuple(source.image_size)
    bank = MeshBank.templates()
    fit = FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in (a.split("=", 1) for a in args.fit)})
    per_row: dict[str, dict[str, list[float]]] = {r: {m: [] for m in METRICS} for r in ROWS}
    mask_iou, mask_iou_big, fit_iou, details = [], [], [], []
    refined_iou, refined_iou_big = [], []
    band_iou_big = {"first": [], "refined": []}  # the true outline's band ignored (module doc)
    one_px_off_big = []  # the true mask shrunk by one pixel: an outline one pixel off all round (module doc)
    times = {"grabcut_ms": [], "fit_ms": [], "objects": 0}
    t_start = time.perf_counter()
    for record in records:
        frame = load_frame(record, size, semantic=False, instances=False)
        image, intr = frame.image, frame.intrinsics
        gt = ground_truth(record, size)
        truth = scene_from_frame(record, size)
        annotated = {o.track_id + 1: o for o in record.objects}
        ids, boxes = [], []
        for iid in truth.objects.instance_id.tolist():
            k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
            r = row_of(truth, iid)
            pixels = int(truth.objects.mask[r].sum())
            if cls not in (12, 13) or k not in gt.boxes or pixels < args.min_pixels or truth.objects.template_id[r] < 0:
                continue
            ids.append(iid)
            l, t, rr, b = gt.boxes[k].tolist()
            boxes.append([l, t, rr + 1, b + 1])  # inclusive pixel centres -> half-open edges
        if not ids:
            continue
        names = ["Car" if i // INSTANCE_DIVISOR == 12 else "Van" for i in ids]
        box_t = torch.tensor(boxes)
        # Box rows (the timing: GrabCut alone, then the whole derender minus it is the fit and the branch).
        t0 = time.perf_counter()
        masks = grabcut_masks(image, box_t).masks
        t_grab = time.perf_counter() - t0
        t0 = time.perf_counter()
        fitted = derender(image, intr, models, "boxes", gt, boxes=BoxPrompts(box_t, tuple(names), fit))
        t_fit = time.perf_counter() - t0 - t_grab
        times["grabcut_ms"].append(1000 * t_grab / len(ids))
        times["fit_ms"].append(1000 * t_fit / len(ids))
        times["objects"] += len(ids)
        box_ids = [r.instance_id for r in fitted.meta["boxes"]]
        height = float(np.median([annotated[i % INSTANCE_DIVISOR].location[1] for i in ids]))
        oracle_h = derender(image, intr, models, "boxes", gt,
                            boxes=BoxPrompts(box_t, tuple(names), FitSettings(camera_height=height)))
        # Predictions on the GrabCut masks: the same frame with the GrabCut masks as its instance map.
        box_instances = torch.zeros_like(gt.instances)
        for m, iid in zip(masks, ids, strict=True):
            box_instances[m] = iid
        pred_box = derender(image, intr, models, "gt", GroundTruth(gt.key, gt.classes, gt.semantic, box_instances,
                                                                     gt.boxes))
        pred_gt = derender(image, intr, models, "gt", gt)
        # The fit on the true masks: the same starts and settings, GrabCut's step replaced.
        gt_masks = torch.stack([truth.objects.mask[row_of(truth, i)] for i in ids])
        fit_gt = derender(image, intr, models, "boxes", gt, boxes=BoxPrompts(box_t, tuple(names), fit,
                                                                               masks=gt_masks))
        true = objects_of(truth, ids)
        depth = torch.tensor([float(o["center"][2]) for o in true])
        sources = {
            ROWS[0]: objects_of(fitted, box_ids),
            ROWS[1]: objects_of(pred_box, ids),
            ROWS[2]: objects_of(pred_gt, ids),
            ROWS[3]: objects_of(fit_gt, [r.instance_id for r in fit_gt.meta["boxes"]]),
            ROWS[4]: objects_of(oracle_h, [r.instance_id for r in oracle_h.meta["boxes"]]),
        }
        for j, iid in enumerate(ids):
            m_true = gt_masks[j]
            nearer = torch.zeros_like(m_true)
            for k2 in range(len(ids)):
                if k2 != j and depth[k2] < depth[j]:
                    nearer |= gt_masks[k2]
            inter, union = float((masks[j] & m_true).sum()), float((masks[j] | m_true).sum())
            mask_iou.append(inter / max(union, 1))
            final = fitted.objects.mask[row_of(fitted, box_ids[j])]
            refined_iou.append(float((final & m_true).sum()) / max(float((final | m_true).sum()), 1))
            obj = annotated[iid % INSTANCE_DIVISOR]
            if obj.occluded == 0 and obj.truncr == 0 and int(m_true.sum()) >= BIG_UNOCCLUDED:
                mask_iou_big.append(inter / max(union, 1))
                refined_iou_big.append(refined_iou[-1])
                band = outline_band(m_true)
                one_px_off_big.append(float((m_true & ~band).sum()) / float(m_true.sum()))
                for name, m in (("first", masks[j]), ("refined", final)):
                    kept = ~band
                    band_iou_big[name].append(float((m & m_true & kept).sum()) / max(float(((m | m_true) & kept).sum()),
                                                                                       1))
            fit_iou.append(fitted.meta["boxes"][j].to_json()["fit_iou"] or 0.0)
            if args.details:
                details.append({"frame": record.key, "id": iid, "pixels": int(m_true.sum()), "mask_iou": mask_iou[-1],
                                "mask_iou_refined": refined_iou[-1], "fit_iou": fit_iou[-1],
                                "true": {"dims": true[j]["dims"].tolist(), "ry": float(true[j]["ry"]),
                                         "template": true[j]["template"], "z": float(true[j]["center"][2])},
                                **{name: ({"dims": objs[j]["dims"].tolist(), "ry": float(objs[j]["ry"]),
                                           "template": objs[j]["template"], "z": float(objs[j]["center"][2])}
                                          if objs[j]["template"] >= 0 else None) for name, objs in sources.items()}})
            for name, objs in sources.items():
                o, t = objs[j], true[j]
                if o["template"] < 0:  # no geometry: the worst figures (counted, not dropped)
                    o = {**t, "ry": t["ry"] + math.pi, "center": t["center"] * 2, "dims": t["dims"] * 2}
                per_row[name]["orientation"].append(float(orientation_similarity(roty(o["ry"][None]),
                                                                                 roty(t["ry"][None]))[0]))
                per_row[name]["distance_x1e2"].append(100 * float(distance_error(o["center"][None],
                                                                                 t["center"][None])[0]))
                per_row[name]["scale_m"].append(float(scale_error(o["dims"][None], t["dims"][None])[0]))
                per_row[name]["reprojection_x1e3"].append(1000 * reprojection(o, m_true, nearer, intr, bank))
        print(f"{record.key}: {len(ids)} objects, {time.perf_counter() - t_start:.0f} s", file=sys.stderr)
    base = ROWS[2]
    table = {name: {m: float(np.mean(v)) for m, v in values.items()} for name, values in per_row.items()}
    paired = {name: {m: interval(np.array(per_row[name][m]) - np.array(per_row[base][m])) for m in METRICS}
              for name in (ROWS[0], ROWS[3], ROWS[4])}
    result = {
        "geometric": str(Path(args.geometric).resolve()), "data_root": str(Path(args.data_root).resolve()),
        "part": args.part, "frames": len(records), "objects": times["objects"], "size_wh": list(size),
        "min_pixels": args.min_pixels, "fit_settings": fit.to_dict(), "table": table,
        "paired_to_prediction_gt_masks_mean_ci95": paired,
        "mask_iou": {"all": float(np.mean(mask_iou)), "n_all": len(mask_iou),
                     f"unoccluded_untruncated_over_{BIG_UNOCCLUDED}px": float(np.mean(mask_iou_big)) if mask_iou_big
                     else None, "n_big": len(mask_iou_big),
                     "big_below_0.95": int(sum(v < 0.95 for v in mask_iou_big))},
        "mask_iou_refined": {"all": float(np.mean(refined_iou)), f"unoccluded_untruncated_over_{BIG_UNOCCLUDED}px":
                             float(np.mean(refined_iou_big)) if refined_iou_big else None,
                             "big_below_0.95": int(sum(v < 0.95 for v in refined_iou_big)),
                             "minus_first_ci95": interval(np.array(refined_iou) - np.array(mask_iou)),
                             "minus_first_big_ci95": interval(np.array(refined_iou_big) - np.array(mask_iou_big))},
        "mask_iou_big_outline_band_ignored": {k: float(np.mean(v)) if v else None for k, v in band_iou_big.items()},
        "mask_iou_big_true_mask_one_px_off": float(np.mean(one_px_off_big)) if one_px_off_big else None,
        "fit_iou_mean": float(np.mean(fit_iou)),
        "ms_per_object": {"grabcut": float(np.mean(times["grabcut_ms"])), "fit_and_branch": float(np.mean(
            times["fit_ms"]))},
        "seconds": round(time.perf_counter() - t_start, 1),
        "machine": f"{platform.machine()} cpu, {args.threads} threads, torch {torch.__version__}",
        "how": __doc__.split("\n\n", 2)[2].strip(),
        **({"details": details} if args.details else {}),
    }
    print(json.dumps({k: v for k, v in result.items() if k not in ("how", "details")}, indent=2))
    if args.out:
        write_json_atomic(args.out, result)
    return result


if __name__ == "__main__":
    main()
