"""look.py TREE OUT.png FRAME:ID...: what the lamp cue reads of a car on its ground-truth mask (an oracle) and on the
semantic branch's proposal matched to it (session 21's demo weights, w0; 312x96, photo crops), side by side.

Per car, one row of panels: the crop (the geometric branch's window for each mask) with the mask's outline, the
pixels the lamp cue reads (derender.SURE_MASK), and in them the near-white lower-half pixels (white_lamps: green)
and the saturated red ones (red: red), each panel titled; and, with FIT=1 in the environment, the proposal after the
proposals' fit of the code on the path: its mask cut to the fitted shape (the fitted outline in yellow), the pixels
this branch's re-reading reads; LABEL in the environment names the code in the titles. Run with a code tree's
library on the path (PYTHONPATH=TREE/src) from the worktree."""
import os
import sys

import matplotlib
import torch

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from sdn3d.cli._config import synth_data_source  # noqa: E402
from sdn3d.data.frames import load_frame  # noqa: E402
from sdn3d.data.scene_gt import frame_photo, ground_truth  # noqa: E402
from sdn3d.data.sources import load_split  # noqa: E402
from sdn3d.derender import SURE_MASK, derender  # noqa: E402
from sdn3d.geometric.fit import FitSettings  # noqa: E402
from sdn3d.geometric.lamps import LampCue, _red, through_the_air  # noqa: E402
from sdn3d.image_ops import crop_windows, mask_boxes, pixel_centre_boxes, square_crop_window  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402
from sdn3d.proposal_fit import fitted_silhouettes  # noqa: E402

RUNS = "/tmp/s21data/demo/out/runs"
SIZE = (312, 96)


def read(photo, mask: torch.Tensor, box: torch.Tensor, models, cue: LampCue, shape: torch.Tensor | None = None
         ) -> dict:
    window = torch.tensor([square_crop_window(box, models.margin)], dtype=torch.float32)
    s = models.crop_size
    crop = photo.crops(window, s)
    near = crop_windows(mask[None, None].float(), window, s, "nearest")[0, 0] > 0.5
    fitted = None if shape is None else crop_windows(shape[None, None].float(), window, s, "nearest")[0, 0] > 0.5
    mask = mask if shape is None else mask & shape
    sure = crop_windows(mask[None, None].float(), window, s, "bilinear")[0, 0] >= SURE_MASK
    seen = through_the_air(crop * sure, sure[None], cue.clear_dark)
    rows = torch.arange(s)[:, None].expand(s, s)
    top, bottom = rows[sure].min(), rows[sure].max()
    lower = rows * 2 > top + bottom
    hi, lo = seen[0].amax(0), seen[0].amin(0)
    white = sure & lower & (lo > cue.white_min) & (hi - lo < cue.white_spread)
    red = _red(seen, sure[None], cue)[0]
    return {"crop": crop[0].permute(1, 2, 0).clamp(0, 1), "sure": sure, "near": near, "fitted": fitted, "white": white,
            "red": red,
            "share_red": float(red.sum()) / max(int(sure.sum()), 1), "n_white": int(white.sum()),
            "n_sure": int(sure.sum())}


def scene_truth_ry(record, iid: str) -> float:
    from sdn3d.data.scene_gt import scene_from_frame

    truth = scene_from_frame(record, SIZE).objects
    return float(truth.ry[truth.index_of(int(iid))])


def main() -> None:
    tree, out, cars = sys.argv[1], sys.argv[2], [c.split(":") for c in sys.argv[3:]]
    geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
    crop = geometric_crop_settings(geo)
    models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                     **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    cue = models.geometric.lamp_cue
    source = synth_data_source(tree)
    records = {r.key: r for part in ("train", "val", "test") for r in load_split(source, part)}
    fit = os.environ.get("FIT") == "1"
    cols = 6 if fit else 4
    fig, axes = plt.subplots(len(cars), cols, figsize=(3 * cols, 3.1 * len(cars)), squeeze=False)
    for row, (key, iid) in enumerate(cars):
        record = records[key]
        frame = load_frame(record, SIZE, semantic=False, instances=False)
        photo, gt = frame_photo(record, SIZE), ground_truth(record, SIZE)
        truth = gt.instances == int(iid)
        scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, photo=photo,
                         fit=FitSettings() if fit else None)
        theirs = scene.objects.mask.bool()
        iou = (theirs & truth).flatten(1).sum(1) / (theirs | truth).flatten(1).sum(1)
        best = int(iou.argmax())
        pred = theirs[best]
        pbox = pixel_centre_boxes(mask_boxes(pred[None]))[0]
        l, t, r, b = gt.boxes[int(iid) % 1000].tolist()
        readings = {"ground-truth mask (oracle)": read(photo, truth, torch.tensor([l, t, r, b]), models, cue),
                    f"predicted proposal (IoU {float(iou.max()):.2f})":
                        read(photo, pred, pbox, models, cue)}
        if fit:
            o = scene.objects
            shape = fitted_silhouettes(frame.intrinsics, (o.template_id, o.dims, o.ry, o.location, o.phi),
                                       torch.tensor([best]))[0]
            d = float(o.ry[best]) - float(scene_truth_ry(record, iid))
            err = abs(torch.rad2deg(torch.atan2(torch.sin(torch.tensor(d)), torch.cos(torch.tensor(d))))).item()
            label = os.environ.get("LABEL", "this code")
            readings[f"{label}: proposal cut to its fitted shape\n(fit's yaw error {err:.0f} deg)"] = read(
                photo, pred, pbox, models, cue, shape)
        for k, (name, v) in enumerate(readings.items()):
            ax = axes[row, 2 * k]
            ax.imshow(v["crop"])
            ax.contour(v["near"].float(), levels=[0.5], colors="cyan", linewidths=0.8)
            if v["fitted"] is not None:
                ax.contour(v["fitted"].float(), levels=[0.5], colors="yellow", linewidths=0.8)
            ax.set_title(f"{key[8:]} {iid}\n{name}: crop, mask outline", fontsize=7)
            ax = axes[row, 2 * k + 1]
            shown = v["crop"] * v["sure"][..., None] * 0.5
            shown[v["white"]] = torch.tensor([0.0, 1.0, 0.0])
            shown[v["red"]] = torch.tensor([1.0, 0.0, 0.0])
            ax.imshow(shown)
            ax.set_title(f"{name}: pixels read;\nwhite (green) {v['n_white']}, red share {v['share_red']:.2f}",
                         fontsize=7)
        for ax in axes[row]:
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=80)


if __name__ == "__main__":
    main()
