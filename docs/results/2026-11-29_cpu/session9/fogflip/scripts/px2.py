# ruff: noqa: E402, E501, E701, E702
import math
import sys

import torch

seen_keys = set()
for f in sys.argv[1:]:
    rows = torch.load(f, weights_only=False)
    for r in rows:
        m = r["lamps"][0] if r["lamps"].dim() == 3 else r["lamps"]
        px = r["seen"].float()[:, m].T
        if px.shape[0] < 150: continue
        alpha = r["true_ry"] - float(r["ray"]); back = math.sin(alpha) < 0
        med = px.median(0).values
        sig = (r["key"][1], back, tuple((med * 10).round().tolist()))
        if sig in seen_keys: continue
        seen_keys.add(sig)
        chroma = px[:, 0] - px[:, 1:].amax(1)
        idx = chroma.argsort(descending=True)[:5]
        dark = torch.quantile(px.amin(1), 0.05)
        print(f"{f[-5:-3]} {r['key'][1]:6s} {'BACK ' if back else 'front'} med {[round(v, 2) for v in med.tolist()]} dark {dark:.2f} top chroma px", [[round(v, 2) for v in px[i].tolist()] for i in idx[:3]])
