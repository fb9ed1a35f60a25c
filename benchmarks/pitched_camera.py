"""Box fits under a pitched, lower camera with and without its camera.json (issue 40).

    python benchmarks/pitched_camera.py [--out result.json] [--frames 6] [--worlds 0001 0002] [--threads 2]
                                        [--keep DIR] [--seed 11]

Two small synthetic parts are generated (``sdn3d-synth``, ``--seed`` (11), 624x192, clone, ``--frames`` frames per
world, no edit pairs): *level*, the default camera (no pitch, 1.50-1.65 m up, drawn per world) and *pitched*
(``camera_height: 1.2``, ``camera_pitch: 0.045``: a Cityscapes-like camera). On every frame the objects are the
annotated Car and Van with at least ``--min-pixels`` visible pixels and truncation under 0.3; each is given by its
true 2D box (motgt ``l t r b``), as ``objects: [{box: ...}]`` names it in ``sdn3d-edit``: GrabCut masks of all the
frame's boxes (:func:`sdn3d.box_masks.grabcut_masks`, default settings), then the fit on the road plane
(:func:`sdn3d.geometric.fit.fit_to_masks`, default :class:`~sdn3d.geometric.fit.FitSettings`; no geometric branch
start, so no checkpoint is needed: every template x 4 starting yaws), each object drawn towards the road's axis where
it stands with the settings' ``lane_reg``, as ``sdn3d-edit``'s box objects are (:func:`sdn3d.road_heading.road_axes`
in the row's level camera). The same masks serve both rows of a part:

- ``without camera.json``: what ``sdn3d-edit input.image=`` does with a Virtual-KITTI-shaped image and no camera:
  the Virtual KITTI intrinsics, the road 1.65 m below a level camera;
- ``with camera.json``: ``input.camera=`` the sequence's ``camera.json`` (the level part's is built from the
  generator's world, :func:`sdn3d.data.synth.generate.camera_json`, since a default tree holds none): its height as
  ``camera_height``, its pitch folded into ``cy`` (:meth:`sdn3d.math3d.camera.CameraPose.level_intrinsics`).

Figures per row, median over objects (and n): the fit's silhouette IoU with its mask (``FitResult.iou``); the
distance error ``| |c~| - |c| | / |c|`` (%) of the bottom-face centre ``c`` in the level camera frame (truth: motgt's
location rotated by the camera's tilt; the fit works in the level frame); the yaw error ``|wrap(ry~ - ry)|`` (deg)
and the axis error ``min(e, 180 - e)`` (a silhouette without the geometric branch's start does not tell a car's
front from its back); also the share of objects within 5 % distance, 30 deg yaw and 15 deg axis, 95 % bootstrap
intervals of the medians (over objects) and, per part, the paired change of the medians from the row without
camera.json to the row with it (the same objects and masks).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from sdn3d.box_masks import grabcut_masks  # noqa: E402
from sdn3d.data import vkitti1  # noqa: E402
from sdn3d.data.cityscapes import camera_pose  # noqa: E402
from sdn3d.data.synth import SynthConfig, generate_dataset  # noqa: E402
from sdn3d.data.synth.generate import _world, camera_json  # noqa: E402
from sdn3d.geometric.fit import FitSettings, fit_to_masks  # noqa: E402
from sdn3d.io import write_json_atomic  # noqa: E402
from sdn3d.math3d.camera import DEFAULT_CAMERA_HEIGHT, Intrinsics  # noqa: E402
from sdn3d.road_heading import road_axes  # noqa: E402

PARTS = {"level": {}, "pitched": {"camera_height": 1.2, "camera_pitch": 0.045}}
ROWS = ("without camera.json", "with camera.json")


def _generate(root: Path, part: str, worlds: tuple[str, ...], frames: int, seed: int = 11) -> SynthConfig:
    cfg = SynthConfig(output_dir=str(root / part), seed=seed, image_size=(624, 192), worlds=worlds,
                      variations=("clone",), frames_per_sequence=frames, cars_per_frame=(6, 10), edit_pairs=0,
                      occluder_pairs=0, overwrite=True, **PARTS[part])
    generate_dataset(cfg)
    return cfg


def _camera(cfg: SynthConfig, record) -> dict:
    """The sequence's camera.json: the file beside the frames, else (the level default) the generator's own."""
    path = Path(cfg.output_dir) / "vkitti_1.3.1_rgb" / record.world / record.variation / "camera.json"
    if path.is_file():
        return json.loads(path.read_text())
    world = _world(cfg.seed, record.world, cfg.frames_per_sequence, cfg.cars_per_frame, cfg.vehicles,
                   cfg.camera_height, cfg.camera_pitch)
    return camera_json(world, cfg.intrinsics, 0.0)


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _median_ci(values: np.ndarray, draws: int = 10000, seed: int = 0) -> list[float]:
    """95 % bootstrap interval of the median of ``values`` (objects resampled)."""
    rng = np.random.default_rng(seed)
    medians = np.median(values[rng.integers(0, len(values), (draws, len(values)))], 1)
    return [round(float(v), 4) for v in np.percentile(medians, [2.5, 97.5])]


def _paired(without: dict, with_: dict, draws: int = 10000, seed: int = 0) -> dict:
    """The change of the medians from ``without`` to ``with_`` (the same objects), with paired 95 % intervals."""
    rng = np.random.default_rng(seed)
    out = {}
    for key in ("fit_iou", "distance_pct"):
        a, b = np.array(without[key]), np.array(with_[key])
        idx = rng.integers(0, len(a), (draws, len(a)))
        change = np.median(b[idx], 1) - np.median(a[idx], 1)
        out[key] = {"median_change": round(float(np.median(b) - np.median(a)), 4),
                    "ci95": [round(float(v), 4) for v in np.percentile(change, [2.5, 97.5])],
                    "better": int((b > a).sum() if key == "fit_iou" else (b < a).sum()),
                    "worse": int((b < a).sum() if key == "fit_iou" else (b > a).sum())}
    return out


def measure(cfg: SynthConfig, min_pixels: int) -> dict:
    rows = {r: {"fit_iou": [], "distance_pct": [], "yaw_deg": [], "axis_deg": []} for r in ROWS}
    for record in vkitti1.read_frames(cfg.output_dir):
        camera = _camera(cfg, record)
        pose = camera_pose(camera["extrinsic"])
        intr = record.intrinsics
        ins = vkitti1.load_instances(record) % 1000
        objs = [o for o in record.objects if o.label in ("Car", "Van") and o.truncr < 0.3
                and int((ins == o.track_id + 1).sum()) >= min_pixels]
        if not objs:
            continue
        image = torch.from_numpy(np.ascontiguousarray(vkitti1.load_rgb(record))).permute(2, 0, 1).float() / 255
        boxes = torch.tensor([[o.box2d[0], o.box2d[1], o.box2d[2] + 1, o.box2d[3] + 1] for o in objs])
        masks = grabcut_masks(image, boxes).masks
        tilt = pose.tilt()
        truth = [tilt.T @ np.asarray(o.location) for o in objs]  # bottom-face centres, level camera frame
        settings = {
            ROWS[0]: (Intrinsics(intr.fx, intr.fy, intr.cx, intr.cy, intr.width, intr.height),
                      FitSettings(camera_height=DEFAULT_CAMERA_HEIGHT)),
            ROWS[1]: (pose.level_intrinsics(Intrinsics(camera["intrinsic"]["fx"], camera["intrinsic"]["fy"],
                                                       camera["intrinsic"]["u0"], camera["intrinsic"]["v0"],
                                                       intr.width, intr.height)),
                      FitSettings(camera_height=pose.height)),
        }
        for row, (k, fit) in settings.items():
            axes = road_axes(image, k.matrix(), masks) if fit.lane_reg else None
            result = fit_to_masks(masks, boxes, k, settings=fit, road_ry=axes)
            for j, o in enumerate(objs):
                c, t = result.location[j].double().numpy(), truth[j]
                rows[row]["fit_iou"].append(float(result.iou[j]))
                rows[row]["distance_pct"].append(100 * abs(np.linalg.norm(c) - np.linalg.norm(t)) / np.linalg.norm(t))
                yaw = abs(math.degrees(_wrap(float(result.ry[j]) - o.ry)))
                rows[row]["yaw_deg"].append(yaw)
                rows[row]["axis_deg"].append(min(yaw, 180.0 - yaw))
        print(f"{cfg.output_dir}: {record.key}: {len(objs)} objects", file=sys.stderr)
    out = {}
    for row, values in rows.items():
        d, y, a = (np.array(values[k]) for k in ("distance_pct", "yaw_deg", "axis_deg"))
        out[row] = {"n": len(d), "fit_iou_median": float(np.median(values["fit_iou"])),
                    "distance_error_pct_median": float(np.median(d)), "yaw_error_deg_median": float(np.median(y)),
                    "axis_error_deg_median": float(np.median(a)), "within_5pct_distance": float(np.mean(d < 5)),
                    "within_30deg_yaw": float(np.mean(y < 30)), "within_15deg_axis": float(np.mean(a < 15))}
        if len(d):
            out[row].update(fit_iou_median_ci95=_median_ci(np.array(values["fit_iou"])),
                            distance_error_pct_median_ci95=_median_ci(d))
    if rows[ROWS[0]]["fit_iou"]:
        out["with - without camera.json (paired)"] = _paired(rows[ROWS[0]], rows[ROWS[1]])
    return out


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--frames", type=int, default=6, help="frames per world")
    p.add_argument("--worlds", nargs="+", default=["0001", "0002"])
    p.add_argument("--min-pixels", type=int, default=300)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=11, help="the generator's seed (11: a tuning seed)")
    p.add_argument("--keep", default=None, help="generate the parts here (kept) instead of a temporary folder")
    p.add_argument("--out", default=None)
    args = p.parse_args(argv)
    torch.set_num_threads(args.threads)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(args.keep) if args.keep else Path(tmp)
        table = {}
        for part in PARTS:
            cfg = _generate(root, part, tuple(args.worlds), args.frames, args.seed)
            table[part] = measure(cfg, args.min_pixels)
    result = {"parts": {k: {"camera_height": v.get("camera_height", "1.50-1.65 (drawn per world)"),
                            "camera_pitch": v.get("camera_pitch", 0.0)} for k, v in PARTS.items()},
              "seed": args.seed, "worlds": args.worlds, "frames_per_world": args.frames, "min_pixels": args.min_pixels,
              "table": table,
              "seconds": round(time.perf_counter() - t0, 1),
              "machine": f"{platform.machine()} cpu, {args.threads} threads, torch {torch.__version__}",
              "how": __doc__.split("\n\n", 2)[2].strip()}
    print(json.dumps({k: v for k, v in result.items() if k != "how"}, indent=2))
    print(f"{'part':8} {'row':20} {'n':>3} {'fit IoU':>8} {'dist err %':>10} {'yaw err':>8} {'axis err':>8} "
          f"{'<5%':>5} {'<30deg':>6} {'axis<15':>7}")
    for part, rows in table.items():
        for row, r in rows.items():
            if row not in ROWS:
                continue
            print(f"{part:8} {row:20} {r['n']:3d} {r['fit_iou_median']:8.3f} {r['distance_error_pct_median']:10.1f} "
                  f"{r['yaw_error_deg_median']:8.1f} {r['axis_error_deg_median']:8.1f} "
                  f"{r['within_5pct_distance']:5.2f} {r['within_30deg_yaw']:6.2f} {r['within_15deg_axis']:7.2f}")
    if args.out:
        write_json_atomic(args.out, result)
    return result


if __name__ == "__main__":
    main()
