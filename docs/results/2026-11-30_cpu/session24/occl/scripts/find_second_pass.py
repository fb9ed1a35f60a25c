"""Small trees whose occluder-removed pair 0 the first pass (one drawn pair per test frame, main's only pass) misses
and the second pass (every other pair) finds: candidates for a test that fails on main.

    cd /work/wt/occl && OMP_NUM_THREADS=1 PYTHONPATH=src nice -n 5 /work/main/.venv/bin/python \
        docs/results/2026-11-30_cpu/session24/occl/scripts/find_second_pass.py WORLD FRAMES SEED...

Config as tests/test_occluder_removed.py's fixture (312x96, clone, cars 10-16) with FRAMES frames per sequence.
Prints per seed: pairs per test frame, the first pass's outcome and the pairs that reveal >= 20 % more.
"""

from __future__ import annotations

import sys

import numpy as np
import torch

from sdn3d.data.synth import SynthConfig
from sdn3d.data.synth.edits import occluder_candidates, remove_occluder
from sdn3d.data.synth.generate import _REVEAL_GAIN, _world
from sdn3d.data.synth.layout import frame_objects, rng_for
from sdn3d.data.synth.scene_render import render_geometry


def main() -> None:
    torch.set_num_threads(1)
    world_name, frames = sys.argv[1], int(sys.argv[2])
    for seed in (int(s) for s in sys.argv[3:]):
        cfg = SynthConfig(output_dir="unused", seed=seed, image_size=(312, 96), worlds=(world_name,),
                          variations=("clone",), frames_per_sequence=frames, cars_per_frame=(10, 16),
                          edit_pairs=1, occluder_pairs=1)
        world = _world(seed, world_name, frames, cfg.cars_per_frame, cfg.vehicles, None, 0.0)
        good, cands, rendered = {}, {}, {}
        for f in range(cfg.first_test_frame, frames):
            objects, pose = frame_objects(world, f, 0.0), world.camera.pose(f, 0.0)
            stats = render_geometry(world, objects, pose, cfg.intrinsics).stats
            rendered[f] = (objects, stats)
            cands[f] = occluder_candidates(objects, stats, cfg.intrinsics).pairs
            for pair in cands[f]:
                edited, _, hidden, revealed = remove_occluder(objects, *pair)
                after = render_geometry(world, edited, pose, cfg.intrinsics).stats
                good[(f, pair)] = bool(after.visible[revealed] >= (1 + _REVEAL_GAIN) * stats.visible[hidden])
        rng = rng_for(seed, world_name, "clone", "occluder", 0)
        first = None
        for f in (int(x) for x in rng.permutation(np.arange(cfg.first_test_frame, frames))):
            if cands[f]:
                pair = cands[f][int(rng.integers(len(cands[f])))]
                if good[(f, pair)]:
                    first = (f, pair)
                    break
        print(seed, {f: len(p) for f, p in cands.items()}, "first pass:", first,
              "good:", [k for k, v in good.items() if v], flush=True)


if __name__ == "__main__":
    main()
