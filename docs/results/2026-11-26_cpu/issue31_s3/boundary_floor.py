"""What a one-pixel boundary error costs in mask IoU, on the objects the issue's mask goal counts.

    .venv/bin/python docs/results/2026-11-26_cpu/issue31_s3/boundary_floor.py DATA_ROOT [PART] [MAX_FRAMES]

For every unoccluded, untruncated Car / Van with at least 1,000 visible pixels of the part's frames (the working size,
624x192; evenly spaced MAX_FRAMES of them, as benchmarks/box_fit.py picks them), the IoU of its true visible mask with
the same mask shrunk by one pixel (3x3 erosion) and grown by one pixel (3x3 dilation): a segmentation whose outline is
one pixel off all round. Prints the means and the share of objects each would put below 0.95. Uses the ground truth
only; nothing is fitted or chosen.
"""

import sys

import cv2
import numpy as np

from sdn3d.cli._config import synth_data_source
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.labels import INSTANCE_DIVISOR


def main() -> None:
    source = synth_data_source(sys.argv[1])
    records = load_split(source, sys.argv[2] if len(sys.argv) > 2 else "test")
    limit = int(sys.argv[3]) if len(sys.argv) > 3 else 20
    if limit and len(records) > limit:
        records = [records[i] for i in np.linspace(0, len(records) - 1, limit).round().astype(int)]
    size = tuple(source.image_size)
    shrunk, grown, pixels = [], [], []
    for record in records:
        gt, truth = ground_truth(record, size), scene_from_frame(record, size)
        annotated = {o.track_id + 1: o for o in record.objects}
        for row, iid in enumerate(truth.objects.instance_id.tolist()):
            k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
            mask = truth.objects.mask[row].numpy()
            if cls not in (12, 13) or k not in gt.boxes or truth.objects.template_id[row] < 0 or mask.sum() < 1000:
                continue
            if annotated[k].occluded != 0 or annotated[k].truncr != 0:
                continue
            m = mask.astype(np.uint8)
            kernel = np.ones((3, 3), np.uint8)
            inner, outer = cv2.erode(m, kernel).astype(bool), cv2.dilate(m, kernel).astype(bool)
            shrunk.append(inner.sum() / mask.sum())
            grown.append(mask.sum() / outer.sum())
            pixels.append(int(mask.sum()))
    shrunk, grown = np.array(shrunk), np.array(grown)
    print(f"{len(shrunk)} unoccluded, untruncated cars and vans over 1,000 px in {len(records)} frames "
          f"(median {int(np.median(pixels))} px)")
    print(f"one pixel shrunk: mean IoU {shrunk.mean():.3f}, below 0.95: {(shrunk < 0.95).mean():.2f}")
    print(f"one pixel grown:  mean IoU {grown.mean():.3f}, below 0.95: {(grown < 0.95).mean():.2f}")


if __name__ == "__main__":
    main()
