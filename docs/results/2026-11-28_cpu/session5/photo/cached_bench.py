"""sdn3d-bench with the de-rendered source scenes cached on disk (tuning only: the photo appearance changes, the
de-render does not). python cached_bench.py CACHE_DIR BENCH_ARGS..."""
import hashlib
import os
import sys

import torch

import sdn3d.evaluation.edit_benchmark as eb

cache = sys.argv[1]
os.makedirs(cache, exist_ok=True)
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
from sdn3d.cli.bench import main  # noqa: E402

sys.exit(main(sys.argv[2:]))
