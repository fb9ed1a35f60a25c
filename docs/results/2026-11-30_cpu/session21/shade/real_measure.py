# ruff: noqa: E501
"""real_measure.py MAIN_DIR BRANCH_DIR: the real frame's deletes (redraw.py outputs, 12001_deleted.npz and
12002_deleted.npz: the edited picture and its source map) of main and the branch, measured per car:

- the shadow left outside main's hole (the region where the shadow was, defined without the branch): pixels within
  12 px of main's filled region (source code fill), outside it, in the lower half of its rows, road-coloured (within 12
  Lab chroma of the road, scaled by their lightness as a shadow's chroma shrinks: road.shadowed_road's test) and
  darker in the input than 0.8 of the road ring's median luma on the nearest rows (all of it, then each 8-connected
  piece on its own row: not all of it is the deleted car's shadow); its residual darkening per code:
  1 - (mean luma of the code's output there) / (that median), pixel-weighted over rows (0: as light as the road
  around; the shadow left behind shows as a positive figure, the input's own as the first column);
- speck's measures on each code's filled region: texture ratio (mean absolute luma Laplacian of the region over that
  of the road ring; goal within 10 % of 1) and residual darkening over its lower half.

The road ring: pixels 8 to 40 px from the union of the two codes' filled regions, kept input in both, road-coloured.

    PYTHONPATH=src python real_measure.py /tmp/s21data/shade/real/main /tmp/s21data/shade/real/br1
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.light import luminance
from sdn3d.editing.photo.road import _luma_laplacian, road_colours, road_lab
from sdn3d.editing.photo.settings import FILL, INPUT
from sdn3d.image_ops import dilate_square

FRAME = Path(__file__).resolve().parents[5] / "tests" / "data" / "0006_30-deg-right_00043.png"


def load(path: Path) -> tuple[torch.Tensor, torch.Tensor]:
    z = np.load(path)
    return torch.from_numpy(z["edited"]).permute(2, 0, 1).float() / 255, torch.from_numpy(z["source"])


def luma_of(image: torch.Tensor) -> torch.Tensor:
    return luminance(image.permute(1, 2, 0).reshape(-1, 3)).view(image.shape[1:])


def darkening(luma: torch.Tensor, region: torch.Tensor, ref_luma: torch.Tensor, around: torch.Tensor) -> float:
    """Pixel-weighted over the rows of ``region``: 1 - its mean ``luma`` / the median ``ref_luma`` of ``around`` on
    the 3 nearest rows that have some."""
    ref_rows = around.any(1).nonzero().flatten()
    total, weight = 0.0, 0
    for r in region.any(1).nonzero().flatten().tolist():
        nearest = ref_rows[(ref_rows - r).abs().argsort()[:3]]
        ref = float(ref_luma[nearest][around[nearest]].median())
        px = region[r]
        total += (1 - float(luma[r][px].mean()) / ref) * int(px.sum())
        weight += int(px.sum())
    return total / max(weight, 1)


def measure(main_dir: Path, branch_dir: Path, iid: int) -> dict:
    frame = torch.from_numpy(np.array(Image.open(FRAME).convert("RGB"))).permute(2, 0, 1).float() / 255
    main_img, main_src = load(main_dir / f"{iid}_deleted.npz")
    br_img, br_src = load(branch_dir / f"{iid}_deleted.npz")
    union = (main_src == FILL) | (br_src == FILL)
    ring_px = dilate_square(union, 40) & ~dilate_square(union, 8) & (main_src == INPUT) & (br_src == INPUT)
    road = road_colours(frame, ring_px)
    lab = road_lab(frame.permute(1, 2, 0).reshape(-1, 3)).view(*union.shape, 3)
    scale = (lab[..., 0] / float(road[0])).clamp(0, 1)[..., None]
    road_coloured = (lab[..., 1:] - road[1:] * scale).norm(dim=-1) < 12
    around = ring_px & road_coloured & ((lab[..., 1:] - road[1:]).norm(dim=-1) < 12)
    in_luma = luma_of(frame)
    main_fill = main_src == FILL
    rows = main_fill.any(1).nonzero().flatten()
    lower_rows = torch.zeros_like(main_fill)
    lower_rows[int(rows[len(rows) // 2]):] = True
    near = dilate_square(main_fill, 12) & ~main_fill & lower_rows & road_coloured
    ref_rows = around.any(1).nonzero().flatten()
    dark_in = torch.zeros_like(near)
    for r in near.any(1).nonzero().flatten().tolist():
        nearest = ref_rows[(ref_rows - r).abs().argsort()[:3]]
        dark_in[r] = near[r] & (in_luma[r] < 0.8 * float(in_luma[nearest][around[nearest]].median()))
    import cv2

    count, labels = cv2.connectedComponents(dark_in.numpy().astype(np.uint8), connectivity=8)
    pieces = []
    for k in range(1, count):
        piece = torch.from_numpy(labels == k)
        ys, xs = piece.nonzero(as_tuple=True)
        pieces.append({"px": int(piece.sum()), "rows": (int(ys.min()), int(ys.max())),
                       "cols": (int(xs.min()), int(xs.max())),
                       **{name: darkening(luma_of(image), piece, in_luma, around)
                          for name, image in (("input", frame), ("main", main_img), ("branch", br_img))}})
    out = {"tip_px": int(dark_in.sum()), "tip_input": darkening(in_luma, dark_in, in_luma, around), "pieces": pieces}
    lap_in = _luma_laplacian(frame)
    for name, image, src in (("main", main_img, main_src), ("branch", br_img, br_src)):
        fill = src == FILL
        frows = fill.any(1).nonzero().flatten()
        lower = fill.clone()
        lower[: int(frows[len(frows) // 2])] = False
        luma = luma_of(image)
        out[f"tip_{name}"] = darkening(luma, dark_in, in_luma, around)
        out[f"px_{name}"] = int(fill.sum())
        out[f"ratio_{name}"] = float(_luma_laplacian(image)[fill].mean() / lap_in[around].mean())
        out[f"lower_{name}"] = darkening(luma, lower, in_luma, around)
    return out


def main() -> int:
    main_dir, branch_dir = Path(sys.argv[1]), Path(sys.argv[2])
    print("| car | shadow left outside main's hole: px | its darkening: input | main | branch | filled px main / branch "
          "| texture ratio main / branch | darkening of the filled region's lower half main / branch |")
    print("|---|---|---|---|---|---|---|---|")
    for iid, name in ((12001, "red"), (12002, "black")):
        m = measure(main_dir, branch_dir, iid)
        print(f"| {name} {iid} | {m['tip_px']} | {100 * m['tip_input']:+.1f} % | {100 * m['tip_main']:+.1f} % | "
              f"{100 * m['tip_branch']:+.1f} % | {m['px_main']} / {m['px_branch']} | {m['ratio_main']:.3f} / "
              f"{m['ratio_branch']:.3f} | {100 * m['lower_main']:+.2f} % / {100 * m['lower_branch']:+.2f} % |")
        for p in m["pieces"]:
            print(f"| {name} {iid}, piece rows {p['rows'][0]}-{p['rows'][1]}, columns {p['cols'][0]}-{p['cols'][1]} | "
                  f"{p['px']} | {100 * p['input']:+.1f} % | {100 * p['main']:+.1f} % | {100 * p['branch']:+.1f} % "
                  "| | | |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
