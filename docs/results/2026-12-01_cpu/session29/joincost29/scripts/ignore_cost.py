"""ignore_cost.py: CPU milliseconds of what every de-render now does in its first pass, join or not: the pixels each
of 10 proposals' fits ignores, of those it reads (proposal_fit.proposal_ignore with the fit's settings), at 312x96 and
624x192 (median of 50 calls, one thread; session 29 joincost29)."""
import statistics
import time

import torch

from sdn3d.geometric.fit import FitSettings
from sdn3d.proposal_fit import proposal_ignore, unsure_below

torch.set_num_threads(1)
gen = torch.Generator().manual_seed(0)
for w, h in ((312, 96), (624, 192)):
    masks = torch.zeros(10, h, w, dtype=torch.bool)
    for k in range(10):  # ten boxes across the road
        x, y = int(torch.randint(0, w - w // 6, (1,), generator=gen)), int(torch.randint(h // 3, h - h // 5, (1,),
                                                                                          generator=gen))
        masks[k, y:y + h // 6, x:x + w // 8] = True
    masks &= ~(masks.long().cumsum(0) > 1)  # an instance map's masks do not overlap
    geometry = (torch.zeros(10, dtype=torch.long), torch.ones(10, 3, dtype=torch.float64),
                torch.zeros(10, dtype=torch.float64), torch.rand(10, 3, generator=gen).double() * 30,
                torch.zeros(10, 64, 3))
    band = unsure_below(masks)
    times = []
    for _ in range(50):
        t = time.process_time()
        proposal_ignore(masks, geometry, band, FitSettings())
        times.append(time.process_time() - t)
    print(f"{w}x{h}: {1000 * statistics.median(times):.2f} ms (median of 50)")
