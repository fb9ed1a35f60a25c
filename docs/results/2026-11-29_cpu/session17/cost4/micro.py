# ruff: noqa: B023, E501
"""The rasterizations of the 14 latency edits (session14/cost/draw_edits.py, every ``transfer._rasterize`` call,
captured on a first pass) rasterized by main's ``rasterize_meshes`` (BASE_SRC's ``render/rasterize.py``, loaded
beside this branch's: the whole 1242x375 image) and by this branch's with ``crop=True``, alternating call by call, 5
times each, the least kept; the fragments are compared (the box's maps are the whole image's there, nothing outside
it). Paired over the calls: geometric mean of new/main, paired bootstrap 95 % interval (10k), wins / losses.

    python micro.py TREE BASE_SRC
"""

import importlib.util
import os
import runpy
import sys
import time
from pathlib import Path

import numpy as np
import torch

from sdn3d.editing.photo import transfer
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

tree, base_src = Path(sys.argv[1]), Path(sys.argv[2])
spec = importlib.util.spec_from_file_location("base_rasterize", base_src / "sdn3d/render/rasterize.py")
base = importlib.util.module_from_spec(spec)
sys.modules["base_rasterize"] = base
spec.loader.exec_module(base)
torch.set_num_threads(1)

calls = []
capture = transfer._rasterize


def record(rows, verts, faces, K, size):
    calls.append((verts.double(), faces, K, size, len(rows)))
    return capture(rows, verts, faces, K, size)


transfer._rasterize = record
draw = Path(__file__).resolve().parents[2] / "session14/cost/draw_edits.py"
sys.argv = [str(draw), str(tree), "/tmp/s17data/cost4/micro_capture"]
runpy.run_path(str(draw), run_name="__main__")
transfer._rasterize = capture

loads = [os.getloadavg()[0]]
times = {"new": [], "main": []}
same = True
for k, (verts, faces, K, size, g) in enumerate(calls):
    kw = {"mesh_to_image": torch.zeros(g, dtype=torch.long), "batch_size": 1}
    arms = {"new": lambda: rasterize_meshes(verts, faces, K, RasterSettings(image_size=size), **kw, crop=True),
            "main": lambda: base.rasterize_meshes(verts, faces, K, RasterSettings(image_size=size), **kw)}
    best = {arm: np.inf for arm in arms}
    out = {}
    for r in range(5):
        for arm in (("new", "main") if (r + k) % 2 == 0 else ("main", "new")):
            c0 = time.perf_counter()
            out[arm] = arms[arm]()
            best[arm] = min(best[arm], 1000 * (time.perf_counter() - c0))
    new, main = out["new"], out["main"]
    x0, y0, x1, y1 = new.box
    for field, empty in (("pix_to_face", -1), ("pix_to_mesh", -1), ("depth", float("inf")), ("bary", 0.0)):
        whole = getattr(main, field)
        same &= torch.equal(getattr(new, field), whole[:, y0:y1, x0:x1])
        same &= torch.equal(new.in_image(getattr(new, field), empty), whole)
    for arm in arms:
        times[arm].append(best[arm])
    print(f"call {k:2d}: {g} meshes, box {new.box} ({(x1 - x0) * (y1 - y0) / (size[0] * size[1]):.1%} of the image): "
          f"new {best['new']:.1f} ms, main {best['main']:.1f} ms", flush=True)
loads.append(os.getloadavg()[0])
new, main = np.array(times["new"]), np.array(times["main"])
ratio = new / main
rng = np.random.default_rng(0)
boot = np.exp(np.log(ratio)[rng.integers(0, len(ratio), (10000, len(ratio)))].mean(1))
print(f"{len(calls)} rasterizations (wall ms, least of 5 each, threads 1, load (1 min) {min(loads):.1f}-{max(loads):.1f}): "
      f"new/main {np.exp(np.log(ratio).mean()):.3f} [{np.quantile(boot, 0.025):.3f}, {np.quantile(boot, 0.975):.3f}], "
      f"wins {int((ratio < 1).sum())} / losses {int((ratio > 1).sum())}; mean new {new.mean():.1f} ms, main "
      f"{main.mean():.1f} ms")
print("cropped fragments equal the whole image's in their box, empty outside:", same)
