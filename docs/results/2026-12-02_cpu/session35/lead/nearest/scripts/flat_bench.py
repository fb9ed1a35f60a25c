# ruff: noqa: B007, E401, E402, E501, E701, E702, F401, F541, I001
import sys, time, torch
from sdn3d.editing.photo import nearest
calls = torch.load('/tmp/s35_t1/nn_calls.pt', weights_only=False)
torch.set_num_threads(1)
for i in (6, 7):
    c = calls[i]; q, e, k = c["q"], c["e"], c["k"]
    ts, tg = [], []
    for _ in range(15):
        t = time.perf_counter(); a = nearest.nearest_examples(q, e, k); ts.append(time.perf_counter() - t)
        t = time.perf_counter(); b = nearest.nearest_examples(q, e, k, shared_from=3); tg.append(time.perf_counter() - t)
    print(i, k, f"flat min {min(ts)*1e3:.1f} med {sorted(ts)[7]*1e3:.1f}; grouped min {min(tg)*1e3:.1f} med {sorted(tg)[7]*1e3:.1f}", torch.equal(a, c["out"]), torch.equal(b, a))
