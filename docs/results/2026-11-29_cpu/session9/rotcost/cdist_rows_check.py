# ruff: noqa: E402, E501, E701, E702
"""cdist_rows_check.py: does torch.cdist (MKL's matrix product behind it) give the same distances when the query rows
are split into chunks? On the 82 cdist calls of _part_colors in lat3's rotate edits (capture_calls.py), for chunk sizes
of 1 to 1000 rows: how many calls differ in some distance, and how many in the 4 nearest examples' indices."""
import pickle

import torch

torch.set_num_threads(1)
rec = pickle.load(open("/tmp/s9data/rotcost/cap/rotate_calls.pkl", "rb"))
calls = [(a, b) for a, b in rec["cdist"] if a.dtype == torch.float64 and b.shape[1] == 6]
for n in (1, 7, 26, 64, 256, 1000):
    bad = 0; badi = 0
    for a, b in calls:
        full = torch.cdist(a, b)
        part = torch.cat([torch.cdist(x, b) for x in a.split(n)])
        bad += int(not torch.equal(full, part))
        badi += int(not torch.equal(full.topk(min(4, len(b)), largest=False).indices, part.topk(min(4, len(b)), largest=False).indices))
    print(n, "distance mismatch calls", bad, "index mismatch calls", badi)
