# ruff: noqa: E402, E501, E701, E702
"""t1_one.py CACHE OUT.npz IDX[,IDX] BENCH_ARGS...: the benchmark on the chosen entries only (cached de-render), their
pictures (source, target, photo:3d-sdn) and edit regions saved to OUT.npz."""
import hashlib
import os
import sys

import numpy as np
import torch

import sdn3d.evaluation.edit_benchmark as eb

cache, out, pick = sys.argv[1], sys.argv[2], {int(x) for x in sys.argv[3].split(",")}
original = eb._source_scene


def cached(image, intrinsics, record, models, settings):
    key = f"{record.world}_{record.variation}_{record.frame}_{settings.scene}_{settings.proposals}_{settings.fit}"
    path = os.path.join(cache, hashlib.md5(key.encode()).hexdigest() + ".pt")
    if os.path.exists(path): return torch.load(path, weights_only=False)
    scene = original(image, intrinsics, record, models, settings); torch.save(scene, path); return scene


orig_eval = eb.evaluate_entry
SAVED = {}


def evaluate_entry(index, entry, source, target, models, settings, lpips_net=None, keep_images=False, baseline_textural=None):
    if index not in pick: raise ValueError("skipped (t1_one.py)")
    r = orig_eval(index, entry, source, target, models, settings, lpips_net, True, baseline_textural)
    SAVED[f"{index}_source"] = r.images["source"]; SAVED[f"{index}_target"] = r.images["target"]
    SAVED[f"{index}_photo"] = r.images["photo:3d-sdn"]; SAVED[f"{index}_region"] = r.regions
    SAVED[f"{index}_psnr"] = np.array(r.metrics["photo"]["3d-sdn"]["all"]["psnr"])
    return r


eb._source_scene = cached; eb.evaluate_entry = evaluate_entry
eb.baseline_photo = lambda source, *a, **k: source.clone()
from sdn3d.cli.bench import main

rc = main(sys.argv[4:])
np.savez_compressed(out, **SAVED)
sys.exit(rc)
