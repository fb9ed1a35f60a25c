"""The reverted cut 35e25e7: Models.from_checkpoints of w0's three inference exports, six times in one process, with
every torch file read whole (main) or with its tensors mapped (mmap=True); prints the seconds of each and a checksum
of the geometric weights (the same both ways).

    OMP_NUM_THREADS=1 PYTHONPATH=src python mmap_load_bench.py full|mmap
"""

import sys
import time

import torch

import sdn3d.inference_export as ie
from sdn3d.models import Models

torch.set_num_threads(1)
R = "/tmp/s21data/demo/out/runs/{}/checkpoints/inference.pt"
mm = sys.argv[1] == "mmap"
orig = ie.load_torch_file


def lt(path, what="checkpoint", map_location="cpu", mmap=False):
    return orig(path, what, map_location, mmap=mmap or mm)


ie.load_torch_file = lt
ts = []
for _ in range(6):
    t = time.perf_counter()
    m = Models.from_checkpoints(semantic=R.format("semantic"), geometric=R.format("geometric"),
                                textural=R.format("textural"))
    ts.append(time.perf_counter() - t)
print(sys.argv[1], [round(x, 3) for x in ts])
sd = m.geometric.net.state_dict() if hasattr(m.geometric, "net") else None
if sd is not None:
    print(sum(float(v.double().sum()) for v in sd.values() if v.is_floating_point()))
