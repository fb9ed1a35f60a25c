"""look.py TREE OUT.png FRAME:ID...: what the lamp cue reads of a car on its ground-truth mask (an oracle) and on the
semantic branch's proposal matched to it (session 21's demo weights, w0; 312x96, photo crops), side by side.

Per car, one row of panels: the crop (the geometric branch's window for each mask) with the mask's outline, the
pixels the lamp cue reads (derender.SURE_MASK), and in them the near-white lower-half pixels (white_lamps: green) and
the saturated red ones (red: red), each panel titled. Run with a code tree's library on the path (PYTHONPATH=TREE/src)
from the worktree."""
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
from sdn3d.geometric.lamps import LampCue, _red, through_the_air  # noqa: E402
from sdn3d.image_ops import crop_windows, mask_boxes, pixel_centre_boxes, square_crop_window  # noqa: E402
from sdn3d.models import Models, geometric_crop_settings  # noqa: E402

RUNS = "/tmp/s21data/demo/out/runs"
SIZE = (312, 96)


def read(photo, mask: torch.Tensor, box: torch.Tensor, models, cue: LampCue) -> dict:
    window = torch.tensor([square_crop_window(box, models.margin)], dtype=torch.float32)
    s = models.crop_size
    crop = photo.crops(window, s)
    sure = crop_windows(mask[None, None].float(), window, s, "bilinear")[0, 0] >= SURE_MASK
    near = crop_windows(mask[None, None].float(), window, s, "nearest")[0, 0] > 0.5
    seen = through_the_air(crop * sure, sure[None], cue.clear_dark)
    rows = torch.arange(s)[:, None].expand(s, s)
    top, bottom = rows[sure].min(), rows[sure].max()
    lower = rows * 2 > top + bottom
    hi, lo = seen[0].amax(0), seen[0].amin(0)
    white = sure & lower & (lo > cue.white_min) & (hi - lo < cue.white_spread)
    red = _red(seen, sure[None], cue)[0]
    return {"crop": crop[0].permute(1, 2, 0).clamp(0, 1), "sure": sure, "near": near, "white": white, "red": red,
            "share_red": float(red.sum()) / max(int(sure.sum()), 1), "n_white": int(white.sum()),
            "n_sure": int(sure.sum())}


def main() -> None:
    tree, out, cars = sys.argv[1], sys.argv[2], [c.split(":") for c in sys.argv[3:]]
    geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
    crop = geometric_crop_settings(geo)
    models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                     **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
    cue = models.geometric.lamp_cue
    source = synth_data_source(tree)
    records = {r.key: r for part in ("train", "val", "test") for r in load_split(source, part)}
    fig, axes = plt.subplots(len(cars), 4, figsize=(12, 3.1 * len(cars)), squeeze=False)
    for row, (key, iid) in enumerate(cars):
        record = records[key]
        frame = load_frame(record, SIZE, semantic=False, instances=False)
        photo, gt = frame_photo(record, SIZE), ground_truth(record, SIZE)
        truth = gt.instances == int(iid)
        scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, photo=photo)
        theirs = scene.objects.mask.bool()
        iou = (theirs & truth).flatten(1).sum(1) / (theirs | truth).flatten(1).sum(1)
        pred = theirs[int(iou.argmax())]
        l, t, r, b = gt.boxes[int(iid) % 1000].tolist()
        readings = {"ground-truth mask (oracle)": read(photo, truth, torch.tensor([l, t, r, b]), models, cue),
                    f"predicted proposal (IoU {float(iou.max()):.2f})":
                        read(photo, pred, pixel_centre_boxes(mask_boxes(pred[None]))[0], models, cue)}
        for k, (name, v) in enumerate(readings.items()):
            ax = axes[row, 2 * k]
            ax.imshow(v["crop"])
            ax.contour(v["near"].float(), levels=[0.5], colors="cyan", linewidths=0.8)
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
