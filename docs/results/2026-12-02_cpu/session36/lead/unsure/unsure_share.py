# ruff: noqa: E401, E402, E501, E701, E702, F401, I001, UP031
"""unsure_share.py TREE...: per proposal of 64 px or more (40 frames a tree, w36), the share of its mask whose vehicle
probability lies between 0.3 and 0.7 (what the fit leaves out), by weather."""
import sys, numpy as np, torch
sys.path.insert(0, "/work/main/benchmarks")
from sdn3d.models import Models
from sdn3d.cli._config import synth_data_source
from sdn3d.data.sources import load_split
from sdn3d.data.frames import load_frame
torch.set_num_threads(1)
W = "/tmp/w36/outputs/demo/runs"
m = Models.from_checkpoints(semantic=f"{W}/semantic/checkpoints/inference.pt")
for tree in sys.argv[1:]:
    recs = sorted([r for p in ("train", "val", "test") for r in load_split(synth_data_source(tree), p)], key=lambda r: r.key)
    recs = [recs[i] for i in np.linspace(0, len(recs) - 1, 40).round().astype(int)]
    share = {"clone": [], "rain": []}
    for rec in recs:
        fr = load_frame(rec, (312, 96), semantic=False, instances=False)
        seg = m.semantic(fr.image)
        p = seg.probability[0, [12, 13]].sum(0)
        uns = (p > 0.3) & (p < 0.7)
        inst = seg.instance[0]
        for i in inst.unique().tolist():
            if i < 1000: continue
            mk = inst == i
            if mk.sum() < 64: continue
            share["rain" if "/rain/" in rec.key else "clone"].append(float((uns & mk).sum() / mk.sum()))
    for k, v in share.items():
        v = np.array(v); print(tree, k, "proposals", len(v), "unsure share of the mask: median %.3f p90 %.3f max %.3f" % (np.median(v), np.percentile(v, 90), v.max()))
