"""pictures.py LABEL TREE OUT.npz [TREE@]FRAME:ID... | pictures.py --join MAIN.npz BRANCH.npz OUT.png: before/after
pictures of cars on the semantic branch's proposals (session 21's demo weights, w0; 312x96, photo crops, the
proposals' fit). Session 26 (axis40): a car may name its own tree (TREE@FRAME:ID).

First form, run once per code (PYTHONPATH=CODE/src): for each car (a true instance id of a frame) the proposal that
overlaps its true visible mask most is de-rendered and fitted by the code on the path; the panel is the photo around
it with the proposal's outline (cyan), the fitted car's silhouette outline (yellow), an arrow from the fitted car's
centre to its front (orange) and one to the true front (green: the ground truth, an oracle, only to score), titled
with LABEL and the yaw error. --join lays the two codes' panels side by side, one row per car, into OUT.png."""
import math
import os
import sys

import matplotlib
import numpy as np
import torch

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RUNS = "/tmp/s21data/demo/out/runs"
SIZE = (312, 96)
#: Session 25: ORACLE=1 in the environment draws pose_table's gt_fit row (ground-truth masks + boxes, an oracle, as the
#: fit's input) instead of the semantic proposals; the joined picture's heading says which (ORACLE at --join too).
ORACLE = os.environ.get("ORACLE") == "1"


def front_arrow(intr, center: torch.Tensor, ry: float, length: float) -> tuple[tuple[float, float], ...]:
    """Image points (working size) of an object's centre and of its front end's centre."""
    front = center + torch.tensor([math.cos(ry), 0.0, -math.sin(ry)], dtype=center.dtype) * length / 2

    def uv(p: torch.Tensor) -> tuple[float, float]:
        return (intr.fx * float(p[0]) / float(p[2]) + intr.cx, intr.fy * float(p[1]) / float(p[2]) + intr.cy)

    return uv(center), uv(front)


def panels(label: str, tree: str, out: str, cars: list[list[str]]) -> None:
    from sdn3d.cli._config import synth_data_source
    from sdn3d.data.frames import load_frame
    from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
    from sdn3d.data.sources import load_split
    from sdn3d.derender import BoxPrompts, derender
    from sdn3d.geometric.fit import FitSettings
    from sdn3d.labels import INSTANCE_DIVISOR
    from sdn3d.math3d.transforms import bottom_to_center
    from sdn3d.meshes.bank import default_bank
    from sdn3d.models import Models, geometric_crop_settings
    from sdn3d.render import RasterSettings, rasterize_meshes
    from sdn3d.render.objects import pose_meshes

    geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
    crop = geometric_crop_settings(geo)
    models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                     **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    trees = {}
    torch.set_num_threads(1)
    saved = {}
    for n, car in enumerate(cars):
        # session 26: a car may name its own tree (TREE@FRAME:ID); else the command's TREE
        where, key = car[0].split("@") if "@" in car[0] else (tree, car[0])
        iid = car[1]
        if where not in trees:
            source = synth_data_source(where)
            trees[where] = {r.key: r for part in ("train", "val", "test") for r in load_split(source, part)}
        record = trees[where][key]
        frame = load_frame(record, SIZE, semantic=False, instances=False)
        photo, gt = frame_photo(record, SIZE), ground_truth(record, SIZE)
        truth = scene_from_frame(record, SIZE).objects
        t = truth.index_of(int(iid))
        mine = gt.instances == int(iid)
        if ORACLE:  # pose_table's gt_fit row: every vehicle's true mask and box, fitted (session 25)
            ids = [i for i in truth.instance_id.tolist() if i // INSTANCE_DIVISOR in (12, 13)
                   and i % INSTANCE_DIVISOR in gt.boxes and int(truth.mask[truth.index_of(i)].sum()) >= 64
                   and truth.template_id[truth.index_of(i)] >= 0]
            boxes = [[b[0], b[1], b[2] + 1, b[3] + 1] for b in (gt.boxes[i % INSTANCE_DIVISOR].tolist() for i in ids)]
            names = tuple("Car" if i // INSTANCE_DIVISOR == 12 else "Van" for i in ids)
            masks = torch.stack([truth.mask[truth.index_of(i)] for i in ids]).bool()
            prompts = BoxPrompts(torch.tensor(boxes), names, FitSettings(), masks=masks, refine_masks=False)
            scene = derender(frame.image, frame.intrinsics, models, "boxes", gt, boxes=prompts, photo=photo)
            r = int((scene.objects.mask & mine).flatten(1).sum(1).argmax())
        else:
            scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, photo=photo, fit=FitSettings())
            r = int(((scene.objects.mask & mine).flatten(1).sum(1)
                     / (scene.objects.mask | mine).flatten(1).sum(1)).argmax())
        o = scene.objects
        # the fitted car's hard silhouette (as branch's proposal_fit.fitted_silhouettes; main has none)
        verts, faces = pose_meshes(default_bank(), o.template_id[r:r + 1], o.dims[r:r + 1].float(),
                                   o.ry[r:r + 1].float(), bottom_to_center(o.location, o.dims[:, 1])[r:r + 1].float(),
                                   o.phi[r:r + 1].float())
        shape = rasterize_meshes(verts, faces, frame.intrinsics.matrix().float(),
                                 RasterSettings((SIZE[1], SIZE[0]))).mask[0]
        d = float(o.ry[r] - truth.ry[t])
        err = abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))
        fit_arrow = front_arrow(frame.intrinsics, o.center[r], float(o.ry[r]), float(o.dims[r, 0]))
        true_arrow = front_arrow(frame.intrinsics, truth.center[t], float(truth.ry[t]), float(truth.dims[t, 0]))
        saved[f"{n}_image"] = photo.image.permute(1, 2, 0).numpy()
        saved[f"{n}_mask"] = o.mask[r].numpy()
        saved[f"{n}_shape"] = shape.numpy()
        saved[f"{n}_arrows"] = np.array([fit_arrow, true_arrow])
        saved[f"{n}_title"] = np.array(f"{label}\n{key[8:]} car {iid}: yaw error {err:.0f} deg")
    np.savez_compressed(out, **saved)


def draw(ax, z: np.lib.npyio.NpzFile, n: int) -> None:
    image, mask, shape = z[f"{n}_image"], z[f"{n}_mask"], z[f"{n}_shape"]
    sy, sx = image.shape[0] / mask.shape[0], image.shape[1] / mask.shape[1]
    rows, cols = np.nonzero(mask | shape)
    pad = 6
    left, right = max(cols.min() - pad, 0), min(cols.max() + pad, mask.shape[1] - 1)
    top, bottom = max(rows.min() - pad, 0), min(rows.max() + pad, mask.shape[0] - 1)
    extent = (-0.5 / sx, (image.shape[1] - 0.5) / sx, (image.shape[0] - 0.5) / sy, -0.5 / sy)
    ax.imshow(image, extent=extent)
    ax.contour(mask.astype(float), levels=[0.5], colors="cyan", linewidths=1.0)
    ax.contour(shape.astype(float), levels=[0.5], colors="yellow", linewidths=1.0)
    for (start, end), colour in zip(z[f"{n}_arrows"], ("orange", "lime"), strict=True):
        ax.annotate("", xy=end, xytext=start, arrowprops={"arrowstyle": "->", "color": colour, "lw": 2})
    ax.set_xlim(left - 0.5, right + 0.5)
    ax.set_ylim(bottom + 0.5, top - 0.5)
    ax.set_title(str(z[f"{n}_title"]), fontsize=8)
    ax.axis("off")


def join(main: str, branch: str, out: str) -> None:
    a, b = np.load(main), np.load(branch)
    cars = len([k for k in a.files if k.endswith("_title")])
    fig, axes = plt.subplots(cars, 2, figsize=(7, 2.6 * cars), squeeze=False)
    for n in range(cars):
        draw(axes[n, 0], a, n)
        draw(axes[n, 1], b, n)
    fig.suptitle(("ground-truth masks + boxes (oracle input)" if ORACLE else "predicted proposals") +
                 " (w0): mask (cyan), fitted car (yellow), fitted front (orange arrow),\n"
                 "true front (green arrow; ground truth, an oracle, for scoring only)", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)


if __name__ == "__main__":
    if sys.argv[1] == "--join":
        join(*sys.argv[2:5])
    else:
        panels(sys.argv[1], sys.argv[2], sys.argv[3], [c.split(":") for c in sys.argv[4:]])
