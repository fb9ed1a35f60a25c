# ruff: noqa: E402, E501, E701, E702
"""sdn3d-bench with the de-rendered source scenes cached on disk (cbench.py of session9/t1rotate) and, per entry, an
npz of the pictures for diagnosis: source, target, 3D-SDN and 2D (photo), the 'all' region, 3D-SDN's PhotoResult.source
codes, parts and objects (working size) and the source scene's composed instance map (the proposals). ONLY=i,j,...
evaluates those entries alone (the others are recorded as skipped).
python dbench.py CACHE_DIR DUMP_DIR BENCH_ARGS..."""
import hashlib
import os
import sys

import numpy as np
import torch

import sdn3d.editing.appearance as ap
import sdn3d.evaluation.edit_benchmark as eb
from sdn3d.scene.maps import compose_instances

cache, dump = sys.argv[1], sys.argv[2]
os.makedirs(cache, exist_ok=True); os.makedirs(dump, exist_ok=True)
original = eb._source_scene
STATE = {"entry": None, "source": None, "scene": None}


def cached(image, intrinsics, record, models, settings):
    key = f"{record.world}_{record.variation}_{record.frame}_{settings.scene}_{settings.proposals}_{settings.fit}"
    path = os.path.join(cache, hashlib.md5(key.encode()).hexdigest() + ".pt")
    scene = None
    if os.path.exists(path):
        try:
            scene = torch.load(path, weights_only=False)
        except (RuntimeError, EOFError, OSError):
            scene = None
    if scene is None:
        scene = original(image, intrinsics, record, models, settings)
        tmp = f"{path}.{os.getpid()}.tmp"
        torch.save(scene, tmp)
        os.replace(tmp, path)
    STATE["scene"] = scene
    return scene


orig_rp = ap.render_photo


def render_photo(*a, **k):
    r = orig_rp(*a, **k)
    STATE["source"] = r.source.numpy().copy()
    STATE["parts"] = r.parts.numpy().copy()
    STATE["objects"] = repr({k: {kk: v for kk, v in o.items() if not kk.startswith("_")} for k, o in r.objects.items()})
    return r


orig_eval = eb.evaluate_entry


ONLY = {int(i) for i in os.environ.get("ONLY", "").split(",") if i}


def evaluate_entry(index, entry, *a, **k):
    if ONLY and index not in ONLY:
        return eb.EntryResult(index, "skipped", 0, errors={"entry": "skipped (ONLY)"})
    STATE["entry"] = index; STATE["source"] = None; STATE["parts"] = None; STATE["objects"] = ""
    k["keep_images"] = True
    r = orig_eval(index, entry, *a, **k)
    im = r.images or {}
    source, target, settings = a[0], a[1], a[3]
    size = settings.image_size
    gt_ids = eb.edit_regions(entry, source, target, size, settings.frame_size)[2]
    try:
        picks = [op.instance_id for op in eb.ops_from_benchmark(entry, STATE["scene"], settings.frame_size, settings.strict, settings.pick_radius, settings.modify_anchor)]
    except (ValueError, AttributeError):
        picks = []
    if "photo:3d-sdn" in im and "photo:2d" in im:
        np.savez_compressed(os.path.join(dump, f"{index:04d}.npz"), source=im["source"], target=im["target"],
                            sdn=im["photo:3d-sdn"], d2=im["photo:2d"], region=r.regions,
                            code=STATE["source"] if STATE["source"] is not None else np.zeros(0),
                            proposals=compose_instances(STATE["scene"]).cpu().numpy(),
                            src_inst=eb._instances(source, size).numpy(), tgt_inst=eb._instances(target, size).numpy(),
                            gt_ids=np.asarray(gt_ids), picks=np.asarray(picks),
                            kind=r.edit_kind, key=r.key, parts=STATE["parts"] if STATE["parts"] is not None else np.zeros(0),
                            objects=STATE["objects"])
    r.images = None; r.regions = None
    return r


ap.render_photo = render_photo
eb._source_scene = cached
eb.evaluate_entry = evaluate_entry
from sdn3d.cli.bench import main

sys.exit(main(sys.argv[3:]))
