# ruff: noqa: B007, E401, E402, E501, E701, E702, F401, F541, I001
import sys, time, torch
import sdn3d.editing.photo.transfer as T
from sdn3d.cli.edit import main
calls = []
orig = T.nearest_examples
def wrapped(q, e, k):
    t = time.perf_counter(); out = orig(q, e, k); dt = time.perf_counter() - t
    calls.append({"q": q.float().clone(), "e": e.float().clone(), "k": k, "out": out.clone(), "dt": dt})
    return out
T.nearest_examples = wrapped
spec, run, out = sys.argv[1:4]
try:
    main([f"input.image=tests/data/0006_30-deg-right_00043.png", f"edits={spec}", f"run={run}", "proposals=boxes",
          "threads=1", f"output_dir={out}", "overwrite=true", "progress=false"])
except SystemExit:
    pass
torch.save(calls, out + "/nn_calls.pt")
for c in calls:
    print(tuple(c["q"].shape), tuple(c["e"].shape), c["k"], f"{c['dt']*1000:.1f} ms")
print("total", sum(c["dt"] for c in calls))
