# ruff: noqa: E401, E501, E701, E702, E731, F401, I001
# ruff: noqa
"""maskdiag.py TREE W: the semantic branch's proposal masks against the ground-truth masks of the cars they match."""
import sys, numpy as np, torch, torch.nn.functional as F
sys.path.insert(0, "/work/main/benchmarks")
from sdn3d.models import Models
from sdn3d.cli._config import synth_data_source
from sdn3d.data.sources import load_split
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, frame_photo
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.scene.maps import scene_maps
torch.set_num_threads(1)
tree, W = sys.argv[1], sys.argv[2]
models = Models.from_checkpoints(semantic=f"{W}/semantic/checkpoints/inference.pt", geometric=f"{W}/geometric/checkpoints/inference.pt")
src = synth_data_source(tree)
recs = sorted([r for p in ("train", "val", "test") for r in load_split(src, p)], key=lambda r: r.key)
recs = [recs[i] for i in np.linspace(0, len(recs) - 1, 40).round().astype(int)]
size = (312, 96)
def dil(m, r):
    return F.max_pool2d(m[None, None].float(), 2 * r + 1, 1, r)[0, 0] > 0
def ero(m, r):
    return ~dil(~m, r)
def iou(a, b):
    u = (a | b).sum(); return float((a & b).sum() / u) if u else 0.0
rows = []
for rec in recs:
    fr = load_frame(rec, size, semantic=False, instances=False)
    gt = ground_truth(rec, size); truth = scene_from_frame(rec, size)
    sc = derender(fr.image, fr.intrinsics, models, "semantic", gt, fit=FitSettings(), photo=frame_photo(rec, size))
    from dataclasses import replace as _rp
    inst = scene_maps(_rp(sc, objects=_rp(sc.objects, has_mask=~sc.objects.has_geometry.bool()))).instance
    gm = [(int(i), truth.objects.mask[r].bool()) for r, i in enumerate(truth.objects.instance_id.tolist()) if i // 1000 in (12, 13) and truth.objects.mask[r].sum() >= 64]
    pm = [(sc.objects.mask[r].bool(), inst == int(sc.objects.instance_id[r])) for r in range(len(sc.objects.instance_id)) if int(sc.objects.instance_id[r]) // 1000 in (12, 13)]
    for iid, g in gm:
        best = max(((iou(p, g), (p, sl)) for p, sl in pm), key=lambda t: t[0], default=(0.0, None))
        if best[0] < 0.3: rows.append((iid, g.sum().item(), best[0], None)); continue
        p, sl = best[1]
        others = sum(1 for jid, g2 in gm if jid != iid and (p & g2).sum() > 0.2 * g2.sum())
        rows.append((iid, int(g.sum()), best[0], dict(prec=float((p & g).sum() / p.sum()), rec=float((p & g).sum() / g.sum()),
            d1=iou(dil(p, 1), g), e1=iou(ero(p, 1), g), merge=others, px=int(p.sum()), sil=iou(sl, g), ps1=iou(p & dil(sl, 1), g), ps2=iou(p & dil(sl, 2), g), pus=iou(p | sl, g), has=bool(sl.any()))))
m = [r for r in rows if r[3]]
print("cars", len(rows), "matched(IoU>=0.3)", len(m), "IoU>=0.5", sum(r[2] >= .5 for r in rows))
a = lambda k: np.mean([r[3][k] for r in m])
print(f"mean IoU {np.mean([r[2] for r in m]):.3f} precision {a('prec'):.3f} recall {a('rec'):.3f} dilate1 IoU {a('d1'):.3f} erode1 IoU {a('e1'):.3f} merges {sum(r[3]['merge']>0 for r in m)}")
for lo, hi in ((64, 300), (300, 1000), (1000, 1e9)):
    s = [r for r in m if lo <= r[1] < hi]
    if s: print(f" gt px [{lo},{hi}) n={len(s)} IoU {np.mean([r[2] for r in s]):.3f} prec {np.mean([r[3]['prec'] for r in s]):.3f} rec {np.mean([r[3]['rec'] for r in s]):.3f} d1 {np.mean([r[3]['d1'] for r in s]):.3f} merges {sum(r[3]['merge']>0 for r in s)}")

print("silhouette IoU", round(a("sil"), 3), "P&dil(S,1)", round(a("ps1"), 3), "P&dil(S,2)", round(a("ps2"), 3), "P|S", round(a("pus"), 3), "with sil", sum(r[3]["has"] for r in m))
for lo, hi in ((64, 300), (300, 1000), (1000, 1e9)):
    s2 = [r for r in m if lo <= r[1] < hi]
    print(f" gt px [{lo},{hi}) P {np.mean([r[2] for r in s2]):.3f} S {np.mean([r[3]['sil'] for r in s2]):.3f} P&S1 {np.mean([r[3]['ps1'] for r in s2]):.3f} P&S2 {np.mean([r[3]['ps2'] for r in s2]):.3f}")
