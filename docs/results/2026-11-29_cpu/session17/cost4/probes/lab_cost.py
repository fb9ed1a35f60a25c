# ruff: noqa: B007, E401, E501, E702, E731, B023, I001
"""Probe (README section 4): the Lab conversion of a 150x600 box of a latency picture: its parts and its unique
colours (the synthetic tree has few; a photo has many: not a cut for photos)."""
import time, numpy as np, torch
from sdn3d.data.vkitti1 import read_frames
from sdn3d.data.records import load_rgb
from sdn3d.editing.photo.road import _lab_of_linear, _LINEAR_LEVELS
from pathlib import Path
torch.set_num_threads(1)
rec = read_frames(Path("/tmp/s14data/cost/vkitti"))[0]
img = np.ascontiguousarray(load_rgb(rec)).transpose(2, 0, 1)  # (3, H, W) uint8
box = np.ascontiguousarray(img[:, 150:300, 300:900]).reshape(3, -1)
print(box.shape)
def t(f, n=7):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter(); f(); ts.append(1e3 * (time.perf_counter() - t0))
    return round(min(ts), 2)
print("full conversion", t(lambda: _lab_of_linear(np.take(_LINEAR_LEVELS, box))))
lin = np.take(_LINEAR_LEVELS, box)
print("take", t(lambda: np.take(_LINEAR_LEVELS, box)))
print("lab_of_linear", t(lambda: _lab_of_linear(lin)))
xyz = np.random.rand(3, box.shape[1]).astype(np.float32)
print("cbrt 3xP", t(lambda: np.cbrt(xyz)))
key = (box[0].astype(np.int32) << 16) | (box[1].astype(np.int32) << 8) | box[2]
print("unique", t(lambda: np.unique(key, return_inverse=True)), "uniques", len(np.unique(key)), "of", len(key))
