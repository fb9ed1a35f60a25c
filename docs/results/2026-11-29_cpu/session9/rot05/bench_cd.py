# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import pickle, time
import torch
torch.set_num_threads(1)
rec = pickle.load(open("/tmp/s9data/rotcost/cap/rotate_calls.pkl", "rb"))
calls = [(a, b) for a, b in rec["cdist"] if a.dtype == torch.float64 and b.shape[1] == 6]
print(len(calls), sum(len(a)*len(b) for a,b in calls)/6/1e6, "M pairs/edit")
def sq32(x1, x2):
    a = x1.float(); b = x2.float()
    d = (a * a).sum(1, keepdim=True) - 2 * a @ b.T + (b * b).sum(1)[None]
    return d
def sq32b(x1, x2):
    a = x1.float(); b = x2.float()
    A = torch.cat([-2 * a, (a * a).sum(1, keepdim=True)], 1)
    B = torch.cat([b, torch.ones(len(b), 1)], 1)
    return torch.addmm((b*b).sum(1)[None], A, B.T) if False else A @ B.T + (b*b).sum(1)[None]
fs = dict(c64=lambda a,b: torch.cdist(a,b), c32=lambda a,b: torch.cdist(a.float(), b.float()), sq32=sq32)
same = {n: 0 for n in fs}
for a, b in calls:
    k = min(4, len(b))
    ref = torch.cdist(a, b).topk(k, largest=False).indices.sort(1).values
    for n, f in fs.items():
        same[n] += int(torch.equal(f(a, b).topk(k, largest=False).indices.sort(1).values, ref))
print("same neighbour sets", same, "of", len(calls))
for _rep in range(3):
    out = []
    for n, f in fs.items():
        t = time.process_time()
        for a, b in calls: f(a, b).topk(min(4, len(b)), largest=False)
        out.append(f"{n} {1000*(time.process_time()-t)/6:.1f}")
    print(" | ".join(out), "ms/edit")
