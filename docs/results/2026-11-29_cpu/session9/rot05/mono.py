# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import pickle, torch
torch.set_num_threads(1)
import sdn3d.editing.photo.road as road
rec = pickle.load(open("/tmp/s9data/rot05/mw_calls.pkl", "rb"))
orig = road._nearest_zero
def spy(excess, count):
    es = [excess(i) for i in range(count)]
    print(" ".join("None" if e is None else f"{e:+.4f}" for e in es))
    return orig(excess, count)
road._nearest_zero = spy
for a, k in rec: road._matched_weight(*a, **k)
