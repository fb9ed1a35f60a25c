# ruff: noqa: E402
"""misses.py CACHE OUT_JSON BENCH_ARGS...: per delete / occluder-removed entry of a Table 1 photo run (the same
de-render cache as dbench.py, the same sdn3d-bench arguments; ONLY= picks the entries), how much of the removed car's
true pixels (the tree's ground-truth instance mask of the source frame: an oracle used only to diagnose) lie outside
3D-SDN's hole, and how much of that the removed car's fitted silhouette covers (uncarved; and carved only by the
other objects' masks within BAND input pixels of the car's own mask, the change of this helper).

Captured from the code under PYTHONPATH (run with the code tree's src): render_photo's PhotoSource (outline_ids, the
fitted silhouettes; src_ids, the proposals' instance map; erode) and vacated_hole's arguments (the removed ids and the
pixels of the objects that stay). The hole is recomputed as main's render_photo builds it (masks' hole, then the
fitted silhouette carved by every mask's reach), before the leftovers and the shadow pieces. All at the photo's input
size. Writes OUT_JSON: one record per entry. BAND (env, default "4 8 12"): the bands measured.
Run: cd CODE && ONLY=... PYTHONPATH=CODE/src OMP_NUM_THREADS=1 python misses.py CACHE OUT data.root=TREE ..."""
import hashlib
import json
import os
import sys

import torch

import sdn3d.editing.photo.transfer as tr
import sdn3d.evaluation.edit_benchmark as eb
from sdn3d.image_ops import dilate_square, isin_ids

cache, out_json = sys.argv[1], sys.argv[2]
BANDS = [int(b) for b in os.environ.get("BAND", "4 8 12").split()]
ONLY = {int(i) for i in os.environ.get("ONLY", "").split(",") if i}
original = eb._source_scene
STATE: dict = {"source": None, "calls": []}
RECORDS: list[dict] = []


def cached(image, intrinsics, record, models, settings):
    key = f"{record.world}_{record.variation}_{record.frame}_{settings.scene}_{settings.proposals}_{settings.fit}"
    path = os.path.join(cache, hashlib.md5(key.encode()).hexdigest() + ".pt")
    if os.path.exists(path):
        return torch.load(path, weights_only=False)
    scene = original(image, intrinsics, record, models, settings)
    tmp = f"{path}.{os.getpid()}.tmp"
    torch.save(scene, tmp)
    os.replace(tmp, path)
    return scene


orig_check = tr.PhotoSource.check
orig_vacated = tr.vacated_hole


def check(self, *a, **k):
    STATE["source"] = self
    return orig_check(self, *a, **k)


def vacated(ids, gone, keep, settings):
    STATE["calls"].append((ids.clone(), gone.clone(), keep.clone(), settings))
    return orig_vacated(ids, gone, keep, settings)


orig_eval = eb.evaluate_entry


def evaluate_entry(index, entry, *a, **k):
    if ONLY and index not in ONLY:
        return eb.EntryResult(index, "skipped", 0, errors={"entry": "skipped (ONLY)"})
    STATE["calls"] = []
    r = orig_eval(index, entry, *a, **k)
    if not STATE["calls"] or STATE["source"] is None:
        return r
    source, target, settings = a[0], a[1], a[3]
    ids, gone, keep, photo = STATE["calls"][0]  # the 3D-SDN photo call (the first vacated_hole of the entry)
    ps = STATE["source"]
    h, w = ids.shape
    gt_ids = eb.edit_regions(entry, source, target, settings.image_size, settings.frame_size)[2]
    truth_map = eb._instances(source, (w, h))
    truth = isin_ids(truth_map, torch.as_tensor(gt_ids, dtype=torch.long)) & (truth_map != 0)
    covered = ids != 0
    background = ~dilate_square(covered, ps.erode)
    hole_masks = orig_vacated(ids, gone, keep, photo)
    fitted_all = isin_ids(ps.outline_ids, gone)
    fitted_main = fitted_all & ~background
    hole_main = hole_masks | (dilate_square(fitted_main, photo.hole_dilate_px) & ~keep)
    own = isin_ids(ids, gone) & covered
    others = covered & ~own
    miss = truth & ~hole_main
    rec = {"index": index, "kind": r.edit_kind, "key": r.key, "truth": int(truth.sum()),
           "miss_main": int(miss.sum()), "hole_main": int(hole_main.sum()),
           "hole_main_not_truth": int((hole_main & ~truth).sum()),
           "fit_uncarved_covers_miss": int((miss & dilate_square(fitted_all, photo.hole_dilate_px)).sum()),
           "fit_uncarved_px": int(fitted_all.sum()), "miss_in_other_masks": int((miss & others).sum()),
           "miss_in_keep": int((miss & keep).sum()), "miss_no_mask": int((miss & ~covered).sum()),
           "miss_no_mask_fit_covers": int((miss & ~covered & dilate_square(fitted_all, photo.hole_dilate_px)).sum()),
           "own_px": int(own.sum())}
    for band in BANDS:
        near = dilate_square(own, band) & ~dilate_square(others, ps.erode)
        fitted_band = fitted_all & (~background | near)
        hole_band = hole_masks | (dilate_square(fitted_band, photo.hole_dilate_px) & ~keep)
        rec[f"band{band}_covers_miss"] = int((miss & hole_band).sum())
        rec[f"band{band}_extra_not_truth"] = int((hole_band & ~hole_main & ~truth).sum())
    # The other proposals on the removed car's fitted silhouette: the share of each one's pixels inside it (grown
    # by hole_dilate_px) and on the true car (a fragment of the same car, or a neighbour spilt onto it).
    grown_fit = dilate_square(fitted_all, photo.hole_dilate_px)
    rec["others_on_fit"] = []
    for oid in torch.unique(ids[others & grown_fit]).tolist():
        mine = ids == oid
        n = int(mine.sum())
        rec["others_on_fit"].append({"id": oid, "px": n, "in_fit": round(int((mine & grown_fit).sum()) / n, 3),
                                     "on_truth": round(int((mine & truth).sum()) / n, 3),
                                     "truth_px": int((mine & truth).sum())})
    RECORDS.append(rec)
    print(json.dumps(rec), flush=True)
    return r


tr.PhotoSource.check = check
tr.vacated_hole = vacated
eb._source_scene = cached
eb.evaluate_entry = evaluate_entry
from sdn3d.cli.bench import main

try:
    main(sys.argv[3:])
finally:
    tmp = f"{out_json}.tmp"
    with open(tmp, "w") as f:
        json.dump(RECORDS, f, indent=1)
    os.replace(tmp, out_json)
