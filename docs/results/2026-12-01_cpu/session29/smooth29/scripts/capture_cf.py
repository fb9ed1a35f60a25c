"""capture_cf.py TREE OUT: sdn3d-bench's counterfactual turn pairs (ground-truth geometry (oracle), fill rays) on TREE,
in-process, saving for every turn pair the drawn picture, the target and the car's target mask as OUT/<key>_{picture,
target,mask}.png (a diagnosis of where held-out 2279's oracle losses come from; run after the verdict, decides
nothing). Run with the code under test on PYTHONPATH (cwd: its tree)."""
import os
import sys

import numpy as np
from PIL import Image

from sdn3d.cli import bench
from sdn3d.evaluation import counterfactual as cf

TREE, OUT = sys.argv[1:3]
os.makedirs(OUT, exist_ok=True)
orig_score, orig_psnr = cf._score_pair, cf._psnr_l1
current = {}


def png(t, path):
    a = t.detach().float().clamp(0, 1).cpu().numpy()
    a = (255 * (a.transpose(1, 2, 0) if a.ndim == 3 else a)).round().astype(np.uint8)
    Image.fromarray(a).save(path)


def score(result, pair, *args, **kwargs):
    current["key"] = pair.key.replace("/", "_").replace(" ", "_") if pair.kind == "turn" else None
    return orig_score(result, pair, *args, **kwargs)


def psnr(pred, target, mask):
    key = current.get("key")
    if key and mask is not None and not os.path.exists(f"{OUT}/{key}_mask.png"):
        png(pred, f"{OUT}/{key}_picture.png")
        png(target, f"{OUT}/{key}_target.png")
        png(mask.float(), f"{OUT}/{key}_mask.png")
    return orig_psnr(pred, target, mask)


cf._score_pair, cf._psnr_l1 = score, psnr
sys.exit(bench.main(["counterfactual=true", f"data.root={TREE}", f"output_dir={OUT}/bench", "examples=0", "threads=1",
                     "counterfactual_kinds=[turn]", "counterfactual_sources=[oracle]", "counterfactual_fills=[rays]"]))
