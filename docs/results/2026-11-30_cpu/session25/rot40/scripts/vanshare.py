"""How surely the semantic branch tells a car from a van: per ground-truth car or van of each source frame of a
dbench.py dump (deduplicated), the proposal that overlaps it most, its class, and the van share of its pixels'
vehicle probability (mean over the mask of P(Van) / (P(Car) + P(Van)) of the branch's softmax).

python vanshare.py SEMANTIC_CKPT DUMP_DIR...   (run with PYTHONPATH=src of the code tree)"""
import glob
import sys

import numpy as np
import torch

from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.models import Models

CAR, VAN = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Van"]


def main():
    torch.set_num_threads(1)
    models = Models.from_checkpoints(semantic=sys.argv[1])
    rows, seen = [], set()
    for d in sys.argv[2:]:
        for f in sorted(glob.glob(f"{d}/*.npz")):
            z = np.load(f, allow_pickle=True)
            src = (d, str(z["key"]).split("->")[0])
            if src in seen:
                continue
            seen.add(src)
            image = torch.from_numpy(z["source"]).permute(2, 0, 1).float() / 255
            with torch.no_grad():
                seg = models.semantic(image)
            prob = seg.probability[0]
            share = prob[VAN] / (prob[CAR] + prob[VAN]).clamp_min(1e-6)
            inst, prop = z["src_inst"], seg.instance[0].numpy()
            for g in np.unique(inst):
                if g <= 0 or g // 1000 not in (CAR, VAN) or (inst == g).sum() < 20:
                    continue
                ids, counts = np.unique(prop[inst == g], return_counts=True)
                keep = ids > 0
                if not keep.any():
                    continue
                p = ids[keep][np.argmax(counts[keep])]
                m = torch.from_numpy(prop == p)
                rows.append((int(g // 1000), int(p // 1000), float(share[m].mean())))
    a = np.array(rows)
    print(f"{len(a)} matched cars and vans")
    for lo, hi in ((0, 0.2), (0.2, 0.35), (0.35, 0.5), (0.5, 0.65), (0.65, 0.8), (0.8, 1.01)):
        s = a[(a[:, 2] >= lo) & (a[:, 2] < hi)]
        print(f"van share {lo:.2f}-{hi:.2f}: n={len(s):3d} truly vans {int((s[:, 0] == VAN).sum()):3d}, "
              f"called vans {int((s[:, 1] == VAN).sum()):3d}, class wrong {int((s[:, 0] != s[:, 1]).sum()):3d}")


if __name__ == "__main__":
    main()
