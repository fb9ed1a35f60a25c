# ruff: noqa: E402, E501, E701, E702, B023
"""figures.py real OUT.png REALDIR | worst OUT.png WEIGHTS A.npz [B.npz ...]

real: the real frame's two deletes (real.sh's output dirs), cropped around each car: input, photo.fill=rays,
photo.fill=learnt. worst: the 6 tuning deletes where the rays' fill scores worst (fill step alone, vacated + shadow
band), cropped around the hole: input, rays, learnt, truth (the exact render without the car); the scored region
outlined in the input panel."""
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from sdn3d.visualize import titled_row

sys.path.insert(0, str(Path(__file__).resolve().parents[5] / "benchmarks"))


def real(out, root):
    root = Path(root)
    rows = []
    for iid, crop, name in ((12001, (420, 150, 720, 360), "red car 12001"), (12002, (660, 150, 960, 360), "black car 12002")):
        pics = [("input (" + name + ")", Image.open(root / f"{iid}_rays/out/input.png") if (root / f"{iid}_rays/out/input.png").exists() else Image.open(Path(__file__).resolve().parents[5] / "tests/data/0006_30-deg-right_00043.png"))]
        pics += [(f"deleted, photo.fill={f}", Image.open(root / f"{iid}_{f}/out/edited.png")) for f in ("rays", "learnt")]
        rows.append(titled_row([(t, np.asarray(p.convert("RGB").crop(crop).resize((420, 294), Image.LANCZOS))) for t, p in pics]))
    Image.fromarray(np.concatenate(rows, 0)).quantize(256).save(out, optimize=True)


def worst(out, weights, paths):
    from learnt_fill import load

    from sdn3d.editing.photo.learnt import learnt_fill, load_fill_net
    net = load_fill_net(weights)
    pairs = load([Path(p) for p in paths])
    def psnr(a, b, m): return 10 * np.log10(1 / max(float((a - b)[:, m].square().mean()), 1e-6))
    scored = sorted(pairs, key=lambda p: psnr(p["filled"], p["target"], p["scored"]))[:6]
    rows = []
    for p in scored:
        fixed = learnt_fill(p["filled"], p["hole"], net, p["keep_out"])
        ys, xs = p["scored"].nonzero(as_tuple=True)
        h, w = p["scored"].shape
        m = max(int(ys.max() - ys.min()), int(xs.max() - xs.min())) // 2 + 16
        y0, y1, x0, x1 = max(int(ys.min()) - m, 0), min(int(ys.max()) + m, h), max(int(xs.min()) - m, 0), min(int(xs.max()) + m, w)
        edge = p["scored"] & ~torch.nn.functional.max_pool2d(p["scored"][None, None].float().neg(), 3, 1, 1)[0, 0].neg().bool()
        data = np.load(paths[[Path(q).stem for q in paths].index(p["key"].split(":")[0])])
        data = {k: data[k] for k in ("keys", "before")}
        i = list(data["keys"]).index(p["key"].split(":", 1)[1])
        before = torch.from_numpy(data["before"][i]).permute(2, 0, 1).float() / 255
        before = torch.where(edge[None], torch.tensor([1.0, 0.0, 1.0])[:, None, None], before)
        def c(x):
            a = (x[:, y0:y1, x0:x1].clamp(0, 1).permute(1, 2, 0).numpy() * 255).astype(np.uint8)
            s = 200 / max(a.shape[:2])
            return np.asarray(Image.fromarray(a).resize((max(1, round(a.shape[1] * s)), max(1, round(a.shape[0] * s))), Image.NEAREST))
        rows.append(titled_row([(f"{p['key'].split(':')[1][:26]} input (scored region outlined)", c(before)),
                                (f"rays {psnr(p['filled'], p['target'], p['scored']):.1f} dB", c(p["filled"])),
                                (f"learnt {psnr(fixed, p['target'], p['scored']):.1f} dB", c(fixed)),
                                ("truth (render without the car)", c(p["target"]))], font_size=11))
    wmax = max(r.shape[1] for r in rows)
    rows = [np.concatenate([r, np.full((r.shape[0], wmax - r.shape[1], 3), 255, np.uint8)], 1) for r in rows]
    Image.fromarray(np.concatenate(rows, 0)).quantize(256).save(out, optimize=True)


if __name__ == "__main__":
    if sys.argv[1] == "real": real(sys.argv[2], sys.argv[3])
    else: worst(sys.argv[2], sys.argv[3], sys.argv[4:])
