"""Each exact cut of this branch against the expression it replaced, on inputs the size of the latency edits'
(1242x375 input, 624x192 working size), in one process, threads 1: the least of 15 timings of each (the shared
machine's interference only adds), and whether the results are equal.

    python micro.py
"""

import math
import time

import numpy as np
import torch

from sdn3d.editing.frame import PixelFrame, upsample_ids
from sdn3d.editing.photo.road import _heading_votes, _masked_median
from sdn3d.image_ops import id_counts, isin_ids

torch.set_num_threads(1)
g = torch.Generator().manual_seed(0)


def best(fn, reps: int = 15) -> tuple[float, object]:
    out, times = None, []
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return 1000 * min(times), out


def same(a, b) -> bool:
    return torch.equal(a, b) if isinstance(a, torch.Tensor) else a == b


heading = torch.deg2rad(torch.arange(-70.0, 70.25, 0.5))
aim = torch.deg2rad(torch.randn(4000, generator=g) * 20)
spread = math.radians(1.0)
level = torch.rand(375, 1242, generator=g).square()
valid = torch.rand(375, 1242, generator=g) < 0.6
ids = torch.randint(0, 12, (375, 1242), generator=g) * 1000 + torch.randint(0, 4, (375, 1242), generator=g)
wanted = torch.tensor([1001, 3002, 5000, 7003, 9001, 11002, 2003, 4000])
work = torch.randint(0, 12, (192, 624), generator=g) * 1000
frame = PixelFrame((1242, 375), (624, 192))


def upsample_ids_before(values: torch.Tensor, transform: PixelFrame) -> torch.Tensor:
    """editing.frame.upsample_ids as it was (main)."""
    (sx, sy), (left, top) = transform.scale, transform.offset
    w_in, h_in = transform.input_size
    h, w = values.shape
    j = torch.floor((torch.arange(w_in, dtype=torch.float64) + 0.5) * sx - left).long()
    i = torch.floor((torch.arange(h_in, dtype=torch.float64) + 0.5) * sy - top).long()
    ok = ((i >= 0) & (i < h))[:, None] & ((j >= 0) & (j < w))[None, :]
    out = values.cpu()[i.clamp(0, h - 1)][:, j.clamp(0, w - 1)]
    return torch.where(ok, out, torch.zeros_like(out))


table = torch.zeros(int(ids.max()) + 1, dtype=torch.bool)
table[wanted] = True
mesh = torch.randint(-1, 9, (375 * 1242,), generator=g)
rows, instance = torch.arange(9), torch.randint(1000, 13000, (9,), generator=g)
outline = torch.cat([instance.new_zeros(1), instance[rows]])[mesh + 1]
own = torch.where(torch.rand(375 * 1242, generator=g) < 0.5, outline, 0)

cases = [
    ("vanishing-point votes (4000 edges x 281 headings)",
     lambda: torch.exp(-0.5 * ((heading[None] - aim[:, None]) / spread).square()),
     lambda: _heading_votes(heading, aim, spread)),
    ("grain scale: median of the valid pixels", lambda: float(level[valid].median()),
     lambda: _masked_median(level, valid)),
    ("seen pixels of 8 objects", lambda: torch.stack([(ids == i).sum() for i in wanted.tolist()]),
     lambda: id_counts(ids, wanted)),
    ("id table lookup over the picture (isin_ids)", lambda: table[ids.long()], lambda: isin_ids(ids, wanted)),
    ("upsample_ids 624x192 -> 1242x375", lambda: upsample_ids_before(work, frame),
     lambda: upsample_ids(work, frame)),
    ("parts' shows mask", lambda: (mesh >= 0) & (own != 0) & (own == torch.where(
        mesh >= 0, instance[rows[mesh.clamp(min=0)]], -1)), lambda: (mesh >= 0) & (own != 0) & (own == outline)),
]
print("| cut | before ms | after ms | equal |\n|---|---|---|---|")
total = [0.0, 0.0]
for name, old, new in cases:
    (t_old, a), (t_new, b) = best(old), best(new)
    total[0] += t_old
    total[1] += t_new
    print(f"| {name} | {t_old:.2f} | {t_new:.2f} | {same(a, b)} |")
print(f"| sum (each once) | {total[0]:.2f} | {total[1]:.2f} | |")
print(f"numpy {np.__version__}, torch {torch.__version__}, {torch.backends.cpu.get_cpu_capability()}")
