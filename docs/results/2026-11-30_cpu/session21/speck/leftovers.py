"""leftovers.py MAIN_DIR BRANCH_DIR [EDIT ...]: the real frame's edits (probe.py / redraw.py outputs NNNNN_EDIT.npz: the
edited picture and its source map) of main and the branch, per car and edit (default: deleted turned_90), measured on
what a person sees around the removal:

- region: the pixels each code filled (source ``fill``), and those the branch filled that main did not;
- leftover pixels: pixels the picture keeps from the input (source ``input``) within 6 pixels of the union U of the
  two codes' filled regions, or inside U but not filled by this code, in the rows of the car's box (README's box,
  the roof row down to its bottom row), whose colour lies farther than 15 (CIE Lab, Euclidean) from the road's colour
  around (road.road_colours of the input pixels 8 to 40 pixels from U). Both codes are counted on the same pixels
  but for their own fills: what main keeps where the branch fills counts against main. Not road is not always the
  car (white lane markings, the island's grass near the hole count too): the picture says which;
- the same count inside the mirror's box (the black car's: rows 216-224, columns 724-737, below the white lane line
  of row 215; the red car's: rows 226-246, columns 462-491);
- texture ratio (deletes): mean absolute luma Laplacian of the filled region over that of the road 8 to 40 pixels
  around it (session 14's real_measure.py; issue 41's goal: within 10 % of 1).

    cd CODE_TREE && PYTHONPATH=CODE_TREE/src python leftovers.py MAIN_DIR BRANCH_DIR
"""

from __future__ import annotations

import sys

import numpy as np
import torch

from sdn3d.editing.photo.road import _luma_laplacian, road_colours, road_lab
from sdn3d.editing.photo.settings import FILL, INPUT
from sdn3d.image_ops import dilate_square

#: per car: its box's rows (README's box) and its mirror's box (x0, y0, x1, y1): where the mirror was in the input.
CARS = {12001: ("red", (203, 333), (462, 226, 492, 247)), 12002: ("black", (194, 305), (724, 216, 738, 225))}


def texture_ratio(image: torch.Tensor, region: torch.Tensor, source: torch.Tensor) -> float:
    ring = dilate_square(region, 40) & ~dilate_square(region, 8) & (source == INPUT)
    road = road_colours(image, ring)
    lab = road_lab(image.permute(1, 2, 0).reshape(-1, 3)).view(*region.shape, 3)
    around = ring & ((lab[..., 1:] - road[1:]).norm(dim=-1) < 12)
    lap = _luma_laplacian(image)
    return float(lap[region].mean() / lap[around].mean())


def main() -> int:
    main_dir, branch_dir = sys.argv[1], sys.argv[2]
    edits = sys.argv[3:] or ["deleted", "turned_90"]
    print("| car | edit | filled px main / branch | branch only | leftover px main | leftover px branch | "
          "in the mirror's box main / branch | texture ratio main / branch |")
    print("|---|---|---|---|---|---|---|---|")
    for edit in edits:
        for iid, (name, (y0, y1), (mx0, my0, mx1, my1)) in CARS.items():
            runs = [np.load(f"{d}/{iid}_{edit}.npz") for d in (main_dir, branch_dir)]
            pics = [torch.from_numpy(z["edited"]).permute(2, 0, 1).float() / 255 for z in runs]
            sources = [torch.from_numpy(z["source"]) for z in runs]
            regions = [s == FILL for s in sources]
            union = regions[0] | regions[1]
            rows = torch.zeros_like(union)
            rows[y0:y1] = True
            ring = dilate_square(union, 40) & ~dilate_square(union, 8) & (sources[0] == INPUT)
            road = road_colours(pics[0], ring)
            zone = (dilate_square(union, 6) & rows)
            mirror = torch.zeros_like(union)
            mirror[my0:my1, mx0:mx1] = True
            counts, in_mirror = [], []
            for pic, source, region in zip(pics, sources, regions, strict=True):
                lab = road_lab(pic.permute(1, 2, 0).reshape(-1, 3)).view(*union.shape, 3)
                left = zone & ~region & (source == INPUT) & ((lab - road).norm(dim=-1) > 15)
                counts.append(int(left.sum()))
                in_mirror.append(int((left & mirror).sum()))
            tex = ([f"{texture_ratio(p, r, s):.3f}" for p, r, s in zip(pics, regions, sources, strict=True)]
                   if edit == "deleted" else ["-", "-"])
            print(f"| {name} {iid} | {edit} | {int(regions[0].sum())} / {int(regions[1].sum())} | "
                  f"{int((regions[1] & ~regions[0]).sum())} | {counts[0]} | {counts[1]} | "
                  f"{in_mirror[0]} / {in_mirror[1]} | {tex[0]} / {tex[1]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
