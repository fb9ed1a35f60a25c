# ruff: noqa: E401, I001, B023, E402, E501, E701, E702
"""Table 1 entries of chosen indices with pictures: cached_bench (cache dir) + only those indices evaluated,
their images saved as npz under OUTDIR.   python diag_t1.py CACHE OUTDIR IDX,IDX,... BENCH_ARGS..."""
import os, sys, hashlib
import numpy as np, torch
import sdn3d.evaluation.edit_benchmark as eb
cache, outdir, wanted = sys.argv[1], sys.argv[2], {int(x) for x in sys.argv[3].split(",")}
os.makedirs(outdir, exist_ok=True)
original = eb._source_scene
def cached(image, intrinsics, record, models, settings):
    key = f"{record.world}_{record.variation}_{record.frame}_{settings.scene}_{settings.proposals}_{settings.fit}"
    path = os.path.join(cache, hashlib.md5(key.encode()).hexdigest() + ".pt")
    if os.path.exists(path):
        return torch.load(path, weights_only=False)
    scene = original(image, intrinsics, record, models, settings)
    torch.save(scene, path)
    return scene
eb._source_scene = cached
orig_eval = eb.evaluate_entry if not hasattr(eb, "_w") else eb._w
def ev(index, entry, source, target, models, settings, lpips_net=None, keep_images=False, baseline_textural=None):
    if index not in wanted:
        raise ValueError("skipped")
    r = orig_eval(index, entry, source, target, models, settings, lpips_net, True, baseline_textural)
    np.savez_compressed(os.path.join(outdir, f"{index}_{settings.proposals}_{settings.scene}.npz"), regions=r.regions, **r.images)
    return r
eb.evaluate_entry = ev
from sdn3d.cli.bench import main
sys.exit(main(sys.argv[4:]))
