"""fillcache.py TREE MAIN_CACHE BRANCH_CACHE: copy main's de-rendered source scenes (dbench.py's cache files, predicted
proposals) into the branch's cache for the frames where the branch joins nothing, so that its Table 1 run
de-renders only the frames it changes (session 27 join40; frag40's fillcache.py for the join).

The branch's de-render is main's up to the join (its first pass is main's code), so a frame whose scene
:func:`sdn3d.proposal_fit.footprint_joins` finds no group in (read on main's scene: its masks, fitted geometry and
fit records) comes out as main's; the copy takes the branch's cache name (dbench.py's md5 of the key with the
branch's FitSettings). Prints the frames with a join (the branch's run de-renders them, ~40 s each).
Run: PYTHONPATH=<branch>/src python fillcache.py /tmp/s21data/trees/t1_37 /tmp/s26data/frag40/t1/cache37main OUT
"""
import hashlib
import os
import shutil
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import Scene, index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.proposal_fit import ProposalFit, footprint_joins
from sdn3d.proposals import Proposals


def name(record, fit: str) -> str:
    key = f"{record.world}_{record.variation}_{record.frame}_{Scene.DERENDER}_{Proposals.SEMANTIC}_{fit}"
    return hashlib.md5(key.encode()).hexdigest() + ".pt"


def groups_in(scene) -> list:
    o = scene.objects
    records = [ProposalFit(f["id"], f["fit_iou"], f["poor_fit"], f["hypothesis"]) for f in scene.meta["fits"]]
    geometry = (o.template_id, o.dims, o.ry, o.location, o.phi)
    return footprint_joins(o.mask, o.instance_id, geometry, records, FitSettings().join_overlap)


def main() -> None:
    tree, main_cache, branch_cache = sys.argv[1:4]
    branch_fit = repr(FitSettings())
    main_fit = branch_fit.replace(f", join_overlap={FitSettings().join_overlap}", "")
    assert main_fit != branch_fit
    entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
    records = index_records(read_source(synth_data_source(tree)))
    os.makedirs(branch_cache, exist_ok=True)
    joined, copied = [], 0
    for k in sorted({(e.world, e.variation, e.source_frame) for e in entries}):
        rec = records[k]
        src = os.path.join(main_cache, name(rec, main_fit))
        if not os.path.exists(src):
            print("no main scene for", rec.key)
            continue
        scene = torch.load(src, weights_only=False)
        groups = groups_in(scene)
        if groups:
            ids = scene.objects.instance_id
            joined.append((rec.key, [ids[g].tolist() for g in groups]))
            continue
        dst = os.path.join(branch_cache, name(rec, branch_fit))
        if not os.path.exists(dst):
            shutil.copyfile(src, f"{dst}.copy")
            os.replace(f"{dst}.copy", dst)
            copied += 1
    print(f"{tree}: {len(joined)} frames with a join {joined}; {copied} scenes copied from main")


if __name__ == "__main__":
    main()
