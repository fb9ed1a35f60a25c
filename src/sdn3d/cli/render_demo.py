"""``sdn3d-render-demo``: the renderer and data without trained networks (runs in about 15 s).

1. generate a small synthetic street-scene dataset in the Virtual KITTI 1.3.1 format;
2. read one frame back with the Virtual KITTI reader;
3. render its ground-truth 3D objects (templates named in motgt) with the hard rasterizer
   into instance, depth, normal and pose maps, and compare with the dataset's instance map;
4. refine one car's pose from a perturbed start by fitting its soft silhouette to its
   visible mask (the reprojection loss of the geometric branch, ignoring closer objects);
5. edit the scene in 3D (the car moved closer and rotated, another car deleted) and
   re-render the maps;
6. write ``outputs/demo/``: pictures, ``summary.json`` and ``report.md``.

Later stages of the project (training the three branches, the editing benchmark) extend it.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import hydra
import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from sdn3d.cli._config import CONFIG_DIR

console = Console(stderr=True)


def _meshes_for_objects(objects, bank, device: torch.device):
    from sdn3d.math3d.transforms import bottom_to_center
    from sdn3d.meshes import TEMPLATE_NAMES

    fallback = {"Car": "sedan", "Van": "van"}
    ids = [
        TEMPLATE_NAMES.index(o.model)
        if o.model in TEMPLATE_NAMES
        else TEMPLATE_NAMES.index(fallback.get(o.orig_label or o.label, "sedan"))
        for o in objects
    ]
    template_ids = torch.tensor(ids, dtype=torch.long, device=device)
    dims = torch.tensor([o.dims for o in objects], dtype=torch.float32, device=device).reshape(-1, 3)
    ry = torch.tensor([o.ry for o in objects], dtype=torch.float32, device=device)
    loc = torch.tensor([o.location for o in objects], dtype=torch.float32, device=device).reshape(-1, 3)
    center = bottom_to_center(loc, dims[:, 1])
    return template_ids, dims, ry, center


def _render_maps(bank, template_ids, dims, ry, center, K, size, labels):
    from sdn3d.math3d.rotations import observation_angle
    from sdn3d.render import RasterSettings, rasterize_meshes
    from sdn3d.render.maps import normal_map, pose_map
    from sdn3d.render.objects import pose_meshes

    verts, faces = pose_meshes(bank, template_ids, dims, ry, center)
    n = verts.shape[0]
    frags = rasterize_meshes(
        verts, faces, K, RasterSettings(image_size=size), torch.zeros(n, dtype=torch.long), batch_size=1
    )
    instance = torch.where(frags.pix_to_mesh >= 0, labels[frags.pix_to_mesh.clamp(min=0)], 0)[0]
    alpha = observation_angle(ry, center[:, 0], center[:, 2])
    normals = normal_map(frags, verts, faces)[0]
    pose = pose_map(frags, alpha)[0]
    return instance, frags.depth[0], normals, pose


def _fit_pose(bank, tid, dims, ry0, center0, target, ignore, K_crop, steps, lr, sigma):
    """Recover yaw and position of one object from its visible mask with the soft silhouette."""
    from sdn3d.render import SoftSilhouetteSettings, soft_silhouette
    from sdn3d.render.objects import pose_meshes

    settings = SoftSilhouetteSettings(image_size=tuple(target.shape), sigma=sigma)
    d_ry = torch.zeros(1, requires_grad=True)
    d_xz = torch.zeros(2, requires_grad=True)
    opt = torch.optim.Adam([d_ry, d_xz], lr=lr)
    keep = (~ignore).float()

    def current():
        # the car stays on the ground: only x, z and yaw move
        c = center0 + torch.stack([d_xz[0], torch.zeros(()), d_xz[1]])
        return ry0 + d_ry, c

    def silhouette():
        r, c = current()
        verts, faces = pose_meshes(bank, tid, dims, r, c.unsqueeze(0) if c.dim() == 1 else c)
        return soft_silhouette(verts, faces, K_crop, settings)[0]

    def iou(sil):
        hard = (sil > 0.5) & ~ignore
        t = target & ~ignore
        return float((hard & t).sum()) / max(float((hard | t).sum()), 1.0)

    with torch.no_grad():
        start_iou = iou(silhouette())
    losses = []
    for _ in range(steps):
        opt.zero_grad()
        sil = silhouette()
        loss = ((sil - target.float()).abs() * keep).mean()
        loss.backward()
        opt.step()
        losses.append(float(loss.detach()))
    with torch.no_grad():
        final = silhouette()
    r, c = current()
    return {
        "start_iou": start_iou,
        "final_iou": iou(final),
        "loss_first": losses[0],
        "loss_last": losses[-1],
        "ry": float(r),
        "center": [float(v) for v in c.reshape(-1)],
        "silhouette": final.detach(),
    }


def run_demo(cfg: DictConfig) -> dict:
    from sdn3d.data import vkitti1
    from sdn3d.data.synth.generate import SynthConfig, generate_dataset
    from sdn3d.io import write_json_atomic, write_png_atomic, write_text_atomic
    from sdn3d.meshes import MeshBank
    from sdn3d.visualize import (
        colorize_depth,
        colorize_ids,
        hstack_panels,
        normals_to_rgb,
        overlay_mask,
        pose_to_rgb,
    )

    torch.manual_seed(int(cfg.seed))
    torch.set_num_threads(int(cfg.threads))
    out = Path(cfg.output_dir)
    data_root = Path(cfg.data_dir)
    summary: dict = {"seed": int(cfg.seed), "device": "cpu", "threads": torch.get_num_threads(), "stages": {}}
    t_all = time.perf_counter()

    with Progress(
        TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(), console=console, transient=False,
    ) as progress:
        task = progress.add_task("sdn3d demo", total=5)

        # 1. data
        progress.update(task, description="1/5 synthetic data")
        t0 = time.perf_counter()
        synth = SynthConfig(
            output_dir=str(data_root), seed=int(cfg.seed), image_size=tuple(cfg.synth.image_size),
            worlds=tuple(cfg.synth.worlds), variations=tuple(cfg.synth.variations),
            frames_per_sequence=int(cfg.synth.frames_per_sequence), edit_pairs=int(cfg.synth.edit_pairs),
            overwrite=True,
        )
        generate_dataset(synth)
        summary["stages"]["synth_s"] = time.perf_counter() - t0
        progress.advance(task)

        # 2. read a frame back
        progress.update(task, description="2/5 read frame")
        frames = vkitti1.read_frames(data_root, worlds=[cfg.synth.worlds[0]], variations=[cfg.synth.variations[0]])
        frame = frames[int(cfg.frame)]
        rgb = vkitti1.load_rgb(frame)
        gt_instance = torch.from_numpy(vkitti1.load_instances(frame))
        objects = [o for o in frame.objects if (o.orig_label or o.label) in ("Car", "Van")]
        if not objects:
            raise RuntimeError(f"demo frame {frame.key} has no vehicles; choose another frame= or seed=")
        intr = frame.intrinsics
        K = intr.matrix()
        size = intr.size
        class_id = {"Car": 12, "Van": 13}
        labels = torch.tensor(
            [class_id.get(o.orig_label or o.label, 12) * 1000 + o.track_id + 1 for o in objects], dtype=torch.long
        )
        progress.advance(task)

        # 3. render ground-truth maps
        progress.update(task, description="3/5 render maps")
        bank = MeshBank.templates()
        tids, dims, ry, center = _meshes_for_objects(objects, bank, torch.device("cpu"))
        t0 = time.perf_counter()
        instance, depth, normals, pose = _render_maps(bank, tids, dims, ry, center, K, size, labels)
        summary["stages"]["render_ms"] = 1000 * (time.perf_counter() - t0)
        vehicle_gt = gt_instance >= 12000
        vehicle_ours = instance > 0
        inter = (vehicle_gt & vehicle_ours).sum().item()
        union = max((vehicle_gt | vehicle_ours).sum().item(), 1)
        summary["template_render_vehicle_iou"] = inter / union
        write_png_atomic(out / "frame_rgb.png", rgb)
        write_png_atomic(
            out / "maps.png",
            np.concatenate([
                hstack_panels([rgb, colorize_ids(gt_instance)]),
                np.full((4, 2 * rgb.shape[1] + 4, 3), 255, np.uint8),
                hstack_panels([colorize_ids(instance), colorize_depth(depth)]),
                np.full((4, 2 * rgb.shape[1] + 4, 3), 255, np.uint8),
                hstack_panels([normals_to_rgb(normals), pose_to_rgb(pose)]),
            ], 0),
        )
        progress.advance(task)

        # 4. fit one object's pose by its soft silhouette
        progress.update(task, description="4/5 silhouette fit")
        visible = torch.stack([(gt_instance == int(lab)).sum() for lab in labels])
        k = int(visible.argmax())
        obj = objects[k]
        left, top, right, bottom = obj.box2d
        margin = 0.15 * max(right - left, bottom - top)
        crop = int(cfg.fit.crop_size)
        x0, y0 = left - margin, top - margin
        side = max(right - left, bottom - top) + 2 * margin
        scale = crop / side
        # exact crop-resize intrinsics: u' + 0.5 = (u - x0 + 0.5) * scale
        K_crop = torch.tensor(
            [[intr.fx * scale, 0, (intr.cx - x0 + 0.5) * scale - 0.5],
             [0, intr.fy * scale, (intr.cy - y0 + 0.5) * scale - 0.5],
             [0, 0, 1.0]]
        )
        vs = (torch.arange(crop, dtype=torch.float32) + 0.5) / scale - 0.5 + y0
        us = (torch.arange(crop, dtype=torch.float32) + 0.5) / scale - 0.5 + x0
        rows = vs.round().long().clamp(0, size[0] - 1)
        cols = us.round().long().clamp(0, size[1] - 1)
        inside = ((vs >= -0.5) & (vs < size[0] - 0.5))[:, None] & ((us >= -0.5) & (us < size[1] - 0.5))[None]
        crop_ids = gt_instance[rows][:, cols]
        target = (crop_ids == int(labels[k])) & inside
        crop_depth = torch.from_numpy(vkitti1.load_depth(frame))[rows][:, cols]
        own_depth = float(center[k, 2])
        ignore = ((crop_ids >= 12000) & (crop_ids != int(labels[k])) & (crop_depth < own_depth)) | ~inside
        # a fixed, documented perturbation (config fit.*_noise) so runs are comparable
        ry0 = ry[k : k + 1] + float(cfg.fit.yaw_noise)
        c0 = center[k].clone()
        c0[0] += float(cfg.fit.offset_noise)
        c0[2] *= 1 + float(cfg.fit.distance_noise)
        t0 = time.perf_counter()
        fit = _fit_pose(
            bank, tids[k : k + 1], dims[k : k + 1], ry0, c0.unsqueeze(0), target, ignore, K_crop,
            int(cfg.fit.steps), float(cfg.fit.lr), float(cfg.fit.sigma),
        )
        summary["stages"]["fit_s"] = time.perf_counter() - t0
        true_c = center[k]
        summary["silhouette_fit"] = {
            "object_track_id": obj.track_id,
            "iou_start": fit["start_iou"],
            "iou_final": fit["final_iou"],
            "yaw_error_start_deg": math.degrees(abs(float(ry0 - ry[k]))),
            "yaw_error_final_deg": math.degrees(abs(math.remainder(fit["ry"] - float(ry[k]), 2 * math.pi))),
            "position_error_start_m": float((c0 - true_c).norm()),
            "position_error_final_m": float((torch.tensor(fit["center"]) - true_c).norm()),
            "steps": int(cfg.fit.steps),
        }
        crop_rgb = rgb[rows.numpy()][:, cols.numpy()]
        write_png_atomic(
            out / "silhouette_fit.png",
            hstack_panels([
                crop_rgb,
                overlay_mask(crop_rgb, target.numpy(), (0, 255, 0), 0.6),
                overlay_mask(crop_rgb, fit["silhouette"].clamp(0, 1).numpy(), (255, 0, 0), 0.6),
            ]),
        )
        progress.advance(task)

        # 5. a 3D edit: the fitted car comes closer and turns; the farthest other car is deleted
        progress.update(task, description="5/5 3D edit")
        keep = torch.ones(len(objects), dtype=torch.bool)
        if len(objects) > 1:
            others = torch.tensor([i for i in range(len(objects)) if i != k])
            keep[others[center[others, 2].argmax()]] = False
        e_center, e_ry = center.clone(), ry.clone()
        zoom = float(cfg.edit.zoom)
        bottom_y = e_center[k, 1] + dims[k, 1] / 2  # stay on the ground: move along the ground ray
        e_center[k, 0] /= zoom
        e_center[k, 2] /= zoom
        e_center[k, 1] = bottom_y - dims[k, 1] / 2
        e_ry[k] += float(cfg.edit.ry)
        e_inst, e_depth, e_normals, e_pose = _render_maps(
            bank, tids[keep], dims[keep], e_ry[keep], e_center[keep], K, size, labels[keep]
        )
        write_png_atomic(
            out / "edit_maps.png",
            np.concatenate([
                hstack_panels([colorize_ids(instance), colorize_ids(e_inst)]),
                np.full((4, 2 * rgb.shape[1] + 4, 3), 255, np.uint8),
                hstack_panels([normals_to_rgb(normals), normals_to_rgb(e_normals)]),
            ], 0),
        )
        summary["edit"] = {"zoom": zoom, "ry_added": float(cfg.edit.ry), "deleted": int((~keep).sum())}
        progress.advance(task)

    summary["wall_s"] = time.perf_counter() - t_all
    summary["frame"] = frame.key
    write_json_atomic(out / "summary.json", summary)
    fit_s = summary["silhouette_fit"]
    report = f"""# sdn3d demo report

Short CPU run ({summary['threads']} threads, seed {summary['seed']}); every number below was
measured by this run. No network was trained yet: this demo exercises the data, 3D core and
renderer (the branches come in later stages of the project).

| stage | result |
|---|---|
| synthetic data | {len(frames)} frames of {cfg.synth.worlds[0]}/{cfg.synth.variations[0]} at \
{size[1]}x{size[0]} in {summary['stages']['synth_s']:.1f} s (`{data_root}`) |
| hard render of frame {frame.key} | {len(objects)} vehicles in {summary['stages']['render_ms']:.0f} ms; \
vehicle-pixel IoU of undeformed templates vs the dataset's instance map: \
{summary['template_render_vehicle_iou']:.3f} |
| soft-silhouette pose fit (track {fit_s['object_track_id']}) | IoU {fit_s['iou_start']:.3f} -> \
{fit_s['iou_final']:.3f}; yaw error {fit_s['yaw_error_start_deg']:.1f} -> {fit_s['yaw_error_final_deg']:.1f} deg; \
position error {fit_s['position_error_start_m']:.2f} -> {fit_s['position_error_final_m']:.2f} m \
({fit_s['steps']} Adam steps, {summary['stages']['fit_s']:.1f} s; the dataset's cars are FFD-deformed and the \
fit uses the undeformed template, so its optimum sits off the true pose by that shape mismatch) |
| 3D edit | zoom {zoom}, yaw +{cfg.edit.ry} rad, {summary['edit']['deleted']} car deleted |

Pictures: `maps.png` (rgb | dataset instances / rendered instances | depth / normals | pose),
`silhouette_fit.png` (crop | target mask | fitted soft silhouette), `edit_maps.png`
(before | after). Total wall time {summary['wall_s']:.1f} s.
"""
    write_text_atomic(out / "report.md", report)
    console.print(report)
    return summary


@hydra.main(config_path=CONFIG_DIR, config_name="render_demo", version_base="1.3")
def main(cfg: DictConfig) -> None:
    console.print(OmegaConf.to_yaml(cfg))
    run_demo(cfg)


if __name__ == "__main__":
    main()
