# ruff: noqa
"""fitprof.py INPUTS THREADS [key=value settings...]: the fit on captured inputs, each _stage's rows/steps/CPU."""
import sys, time, torch
torch.set_num_threads(int(sys.argv[2]))
import sdn3d.geometric.fit as fit
a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
first = torch.where(torch.isfinite(a["start_ry"]), a["start_ry"], torch.full_like(a["start_ry"], -1.5708))
def belief(ry):
    return torch.cos(ry - first[:, None])
inner = fit._stage
def stage(bank, template, start, *args, **kw):
    t = time.thread_time()
    r = inner(bank, template, start, *args, **kw)
    size, steps = args[5], args[6]
    print(f"  stage M={len(template)} size={size} steps={steps} ffd={kw.get('with_ffd')} barred={int(start['barred'].sum()) if 'barred' in start else 0} thread_cpu={time.thread_time()-t:.3f}", flush=True)
    return r
fit._stage = stage
kw = {}
for s in sys.argv[3:]:
    k, v = s.split("="); kw[k] = type(getattr(fit.FitSettings(), k))(eval(v))
settings = fit.FitSettings(**kw)
for _ in range(2):
    t = time.process_time(); w = time.perf_counter()
    r = fit.fit_to_masks(masks, boxes, intr, settings=settings, yaw_belief=belief, **a)
    print("fit cpu", round(time.process_time() - t, 3), "wall", round(time.perf_counter() - w, 3), flush=True)
torch.save({k: getattr(r, k) for k in ("template", "dims", "ry", "location", "phi", "iou", "loss", "hypothesis")}, "/tmp/s12data/speed/fitout_" + "_".join(sys.argv[3:]) + ".pt")
