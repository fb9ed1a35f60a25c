"""How the semantic branch's proposals sit on their cars: per ground-truth vehicle of each source frame in a dbench.py
dump (deduplicated by frame), the proposal that overlaps it most and the offsets of the proposal's box edges from the
car's (pixels at the working size; left / top negative = the proposal reaches past the car), by the car's width.

python spill.py DUMP_DIR..."""
import glob
import sys

import numpy as np


def box(m):
    ys, xs = np.nonzero(m)
    return np.array([xs.min(), ys.min(), xs.max(), ys.max()])


def main():
    rows, seen = [], set()
    for d in sys.argv[1:]:
        for f in sorted(glob.glob(f"{d}/*.npz")):
            z = np.load(f, allow_pickle=True)
            src = (d, str(z["key"]).split("->")[0])
            if src in seen:
                continue
            seen.add(src)
            inst, prop = z["src_inst"], z["proposals"]
            for g in np.unique(inst):
                if g <= 0 or g // 1000 not in (12, 13):  # Car 12xxx, Van 13xxx (vkitti1 classes at this size)
                    continue
                car = inst == g
                if car.sum() < 20:
                    continue
                ids, counts = np.unique(prop[car], return_counts=True)
                keep = ids > 0
                if not keep.any():
                    continue
                p = ids[keep][np.argmax(counts[keep])]
                pm = prop == p
                iou = (pm & car).sum() / (pm | car).sum()
                rows.append((*(box(pm) - box(car)), box(car)[2] - box(car)[0] + 1, box(car)[3] - box(car)[1] + 1, iou))
    a = np.array(rows, dtype=float)
    print(f"{len(a)} cars in {len(seen)} frames; median IoU {np.median(a[:, 6]):.2f}")
    for lo, hi in ((0, 15), (15, 30), (30, 60), (60, 400)):
        s = a[(a[:, 4] >= lo) & (a[:, 4] < hi)]
        if len(s):
            print(f"car width {lo:3d}-{hi:3d} px: n={len(s):3d} median edge offsets L {np.median(s[:, 0]):+.0f} "
                  f"T {np.median(s[:, 1]):+.0f} R {np.median(s[:, 2]):+.0f} B {np.median(s[:, 3]):+.0f}, "
                  f"IoU {np.median(s[:, 6]):.2f}")


if __name__ == "__main__":
    main()
