"""frag3d.py SEED...: would the fitted 3D boxes tell a removed car's fragments (other proposals of the same car) from
its neighbours? For each predicted delete / occluder-removed entry of the main runs (/tmp/s26data/del41/t1/
main<SEED>_semantic, dumps and de-render caches), each other proposal on the removed car's true pixels (ground-truth
instance mask: an oracle, to diagnose; share of the proposal's own pixels on it >= 0.7: a fragment, < 0.3: a
neighbour): the ground distance (x, z) between its fitted centre and the picked car's, in units of the picked car's
half length. Prints one line per proposal and, per threshold on that distance, the fragments' and neighbours' pixels
on the car and the neighbours' pixels off it. Run with PYTHONPATH=<code>/src."""
import glob
import json
import sys

import numpy as np
import torch

rows = []
for seed in sys.argv[1:]:
    run = f"/tmp/s26data/del41/t1/main{seed}_semantic"
    scenes = {}
    for path in glob.glob(f"/tmp/s26data/del41/t1/cache{seed}/*.pt"):
        scene = torch.load(path, weights_only=False)
        if scene.meta.get("proposals") == "semantic":
            src = scene.meta["source"].split("/")
            scenes["/".join(src[1:3]) + " " + src[3]] = scene
    for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
        if e["edit_kind"] not in ("delete", "occluder_removed") or not (e.get("metrics") or {}).get("photo"):
            continue
        d = np.load(f"{run}.dump/{e['index']:04d}.npz")
        scene = scenes.get(e["key"].split("->")[0])
        picks = d["picks"].tolist()
        if scene is None or not picks:
            continue
        ids = scene.objects.instance_id.tolist()
        truth = np.isin(d["src_inst"], d["gt_ids"]) & (d["src_inst"] != 0)
        props = d["proposals"]
        b = ids.index(picks[0])
        centre, half = scene.objects.location[b], float(scene.objects.dims[b, 0]) / 2
        for pid in np.unique(props[truth]).tolist():
            if pid == 0 or pid in picks or pid not in ids:
                continue
            mine = props == pid
            on, share = int((mine & truth).sum()), float((mine & truth).sum() / mine.sum())
            loc = scene.objects.location[ids.index(pid)]
            dist = float(torch.hypot(loc[0] - centre[0], loc[2] - centre[2])) / half
            rows.append((share, dist, on, int(mine.sum()) - on))
            print(f"{seed} #{e['index']} {e['edit_kind']} proposal {pid}: share on car {share:.2f}, ground distance "
                  f"{dist:.2f} half lengths, {on} px on the car")
print("| distance under (half lengths) | fragments (>= 0.7) taken: px on car | in between: px on / off | "
      "neighbours (< 0.3) taken: px on / off |")
print("|---|---|---|---|")
for cut in (0.5, 1.0, 1.5, 2.0, 3.0):
    frag = [r for r in rows if r[0] >= 0.7 and r[1] < cut]
    mid = [r for r in rows if 0.3 <= r[0] < 0.7 and r[1] < cut]
    nb = [r for r in rows if r[0] < 0.3 and r[1] < cut]
    print(f"| {cut} | {sum(r[2] for r in frag)} of {sum(r[2] for r in rows if r[0] >= 0.7)} | "
          f"{sum(r[2] for r in mid)} / {sum(r[3] for r in mid)} | {sum(r[2] for r in nb)} / {sum(r[3] for r in nb)} |")
