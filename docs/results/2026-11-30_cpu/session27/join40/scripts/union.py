"""union.py PAIRS.json OUT.json CACHE:TREE...: fit the union of each touching pair's masks as one car (session 27
join40, step 1's second cue) and record its silhouette IoU beside the two parts' own fits.

For every pair pairs.py listed (read back from its scenes in the de-render caches CACHE..., each with
its tree's seed TREE as pairs.py names it), the union of the two
masks becomes one object, started from the larger part's fitted pose (template, dims, yaw, place, FFD), and is fitted
by :func:`sdn3d.proposal_fit.fit_proposals` with the proposals' default FitSettings, the other objects' pixels
ignored where they are nearer and the band under the semantic branch's masks unsure (as the de-render does). No yaw
belief (the lamps are not read here): the IoU, not the facing, is what is compared. Adds to each pair ``union_iou``
and ``parts_iou`` (the parts' fit IoUs, pixel-weighted).

Run: PYTHONPATH=<code>/src OMP_NUM_THREADS=1 python union.py pairs.json union.json \
    /tmp/s26data/frag40/t1/cache31main:31 /tmp/s26data/frag40/t1/cache35main:35 ...
"""
import glob
import json
import sys

import torch

from sdn3d.geometric.fit import FitSettings
from sdn3d.labels import CLASS_LISTS, INSTANCE_DIVISOR
from sdn3d.proposal_fit import fit_proposals, unsure_below


def main() -> None:
    torch.set_num_threads(1)
    pairs = json.load(open(sys.argv[1]))
    scenes = {}
    for arg in sys.argv[3:]:
        cache, tree = arg.split(":")
        for p in glob.glob(f"{cache}/*.pt"):
            s = torch.load(p, weights_only=False)
            if s.meta.get("proposals") == "semantic":
                scenes[tree, s.meta["source"]] = s
    settings = FitSettings()
    names = {c.id: c.name for c in CLASS_LISTS["vkitti"]}
    for n, pr in enumerate(pairs):
        s = scenes[pr["tree"], pr["key"]]
        o = s.objects
        ids = o.instance_id.tolist()
        ka, kb = ids.index(pr["a"]), ids.index(pr["b"])
        keep = [k for k in range(len(ids)) if k not in (ka, kb)]
        big = ka if pr["area_a"] >= pr["area_b"] else kb
        union = o.mask[ka] | o.mask[kb]
        masks = torch.cat([o.mask[keep], union[None]])
        rows = torch.tensor([len(keep)])
        geo = tuple(torch.cat([g[keep], g[big:big + 1]]) for g in (o.template_id, o.dims, o.ry, o.location, o.phi))
        new_ids = torch.cat([o.instance_id[keep], o.instance_id[big:big + 1]])
        classes = [names.get(int(i) // INSTANCE_DIVISOR) for i in new_ids]
        _, rec, _ = fit_proposals(s.intrinsics, masks, new_ids, rows, geo, settings, None, unsure_below(masks), classes)
        pr["union_iou"] = rec[0].iou
        fa, fb = pr["fit_a"] or 0.0, pr["fit_b"] or 0.0
        pr["parts_iou"] = round((fa * pr["area_a"] + fb * pr["area_b"]) / (pr["area_a"] + pr["area_b"]), 4)
        if n % 50 == 0:
            print(n, pr["label"], pr["union_iou"], pr["parts_iou"], flush=True)
    json.dump(pairs, open(sys.argv[2], "w"), indent=0)


if __name__ == "__main__":
    main()
