# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import pickle, time, cProfile, pstats, torch
torch.set_num_threads(1)
import sdn3d.editing.photo.road as road
rec = pickle.load(open("/tmp/s9data/rot05/mw_calls.pkl", "rb"))
for a, k in rec:
    print(a[2].shape, road._matched_weight(*a, **k))
t = time.process_time()
pr = cProfile.Profile(time.process_time); pr.enable()
for a, k in rec: road._matched_weight(*a, **k)
pr.disable()
print(f"{1000*(time.process_time()-t)/len(rec):.1f} ms/call")
pstats.Stats(pr).sort_stats("tottime").print_stats(15)
