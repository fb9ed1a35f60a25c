"""white_cost.py: CPU time of one white_lamps call on 20 crops of 64x64 (about the edit call's objects, each read up
to twice: the predictor and the re-reading), of the library on the path; run once per code, one thread:

    PYTHONPATH=/tmp/s25data/lead/base_9a6/src OMP_NUM_THREADS=1 python white_cost.py
    PYTHONPATH=/work/wt/pose40/src OMP_NUM_THREADS=1 python white_cost.py
"""
import time

import torch

from sdn3d.geometric.lamps import LampCue, white_lamps

torch.set_num_threads(1)
torch.manual_seed(0)
crop, mask = torch.rand(20, 3, 64, 64), (torch.rand(20, 1, 64, 64) > 0.3).float()
crop[:, 0] += 0.5  # red bodies: the test is usable
cue = LampCue()
for _ in range(20):
    white_lamps(crop, mask, cue)
runs = []
for _ in range(7):
    t = time.process_time()
    for _ in range(200):
        white_lamps(crop, mask, cue)
    runs.append((time.process_time() - t) / 200 * 1e3)
print(f"white_lamps, 20 crops of 64x64: {sorted(runs)[3]:.3f} ms CPU per call (median of 7 x 200)")
