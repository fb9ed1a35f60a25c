"""cached_bench plus a dump of every photo result's source map and objects (debug)."""
import os
import sys

import numpy as np
import torch

import sdn3d.editing.appearance as ap
from sdn3d.editing.photo.settings import source_picture

out_dir = os.environ["DUMP"]
os.makedirs(out_dir, exist_ok=True)
orig = ap.render_photo
count = [0]


def wrapped(*a, **k):
    r = orig(*a, **k)
    from PIL import Image
    Image.fromarray(np.asarray(source_picture(r.source))).save(f"{out_dir}/{count[0]:03d}_source.png")
    Image.fromarray((r.image.permute(1, 2, 0).numpy() * 255 if r.image.dtype != torch.uint8 else
                     r.image.permute(1, 2, 0).numpy()).astype(np.uint8)).save(f"{out_dir}/{count[0]:03d}_image.png")
    print("PHOTO", count[0], {k: {kk: vv for kk, vv in v.items() if kk != "_pixels"} for k, v in r.objects.items()},
          r.warnings)
    count[0] += 1
    return r


ap.render_photo = wrapped
sys.argv = sys.argv[:1] + sys.argv[1:]
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "cached_bench.py")).read())
