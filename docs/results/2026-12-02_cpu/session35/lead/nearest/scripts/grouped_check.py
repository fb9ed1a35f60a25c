# ruff: noqa: B007, E401, E402, E501, E701, E702, F401, F541, I001
import sys, time, torch
from sdn3d.editing.photo import nearest
calls = torch.load(sys.argv[1], weights_only=False)
torch.set_num_threads(int(sys.argv[2]) if len(sys.argv) > 2 else 1)
block = 0

tf = tg = 0
for c in calls:
    q, e, k = c["q"], c["e"], c["k"]
    if len(q) < 1000: continue
    t1s, t2s = [], []
    for rep in range(7):
        t = time.perf_counter(); a = nearest.nearest_examples(q, e, k); t1s.append(time.perf_counter() - t)
        t = time.perf_counter(); b = nearest.nearest_examples(q, e, k, shared_from=3); t2s.append(time.perf_counter() - t)
    t1, t2 = min(t1s), min(t2s)
    tf += t1; tg += t2
    print(tuple(q.shape), tuple(e.shape), k, f"flat {t1*1000:.1f} grouped {t2*1000:.1f} ms", "equal" if torch.equal(a, b) else "DIFFERENT", torch.equal(a, c["out"]))
print(f"block {block}: flat {tf:.3f} grouped {tg:.3f} (min of 7, alternated)")
