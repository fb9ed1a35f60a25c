# ruff: noqa
import sys, time, torch
import sdn3d.geometric.fit as fit
inner = fit.fit_to_masks
def wrapped(masks, boxes, intr, **kw):
    t = time.process_time(); w = time.perf_counter()
    r = inner(masks, boxes, intr, **kw)
    print("FIT n", masks.shape, "classes", kw.get("classes"), "belief", kw.get("yaw_belief") is not None, "cpu", round(time.process_time()-t,2), "wall", round(time.perf_counter()-w,2), file=sys.stderr)
    torch.save({"masks": masks, "boxes": boxes, "intr": intr, **{k: v for k, v in kw.items() if k not in ("bank", "settings", "yaw_belief")}}, sys.argv[1])
    return r
fit.fit_to_masks = wrapped
import sdn3d.cli.edit as edit
edit.main(sys.argv[2:])
