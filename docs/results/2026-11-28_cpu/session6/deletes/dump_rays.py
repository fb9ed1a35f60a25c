# ruff: noqa: E401, I001, B023, E402, E501, E701, E702
"""diag_t1.py with every ray_fill call's arguments saved (OUTDIR/rays_IDX_K.pt)."""
import os, sys, torch
import sdn3d.editing.photo.road as R
import sdn3d.evaluation.edit_benchmark as eb
outdir = sys.argv[2]; os.makedirs(outdir, exist_ok=True)
CUR = {"i": -1, "k": 0}
orig_rf = R.ray_fill
def rf(image, hole, vp, keep_out=None, *a, **k):
    torch.save(dict(image=image, hole=hole, vp=vp, keep_out=keep_out, a=a, k=k), f"{outdir}/rays_{CUR['i']}_{CUR['k']}.pt"); CUR["k"] += 1
    return orig_rf(image, hole, vp, keep_out, *a, **k)
R.ray_fill = rf
orig_ev = eb.evaluate_entry
def ev(index, *a, **k):
    CUR["i"], CUR["k"] = index, 0
    return orig_ev(index, *a, **k)
eb.evaluate_entry = ev
exec(open("/tmp/s6data/deletes/diag_t1.py").read())
