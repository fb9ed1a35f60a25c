"""Why a Table 1 tree got no occluder-removed pair: every candidate of every test frame, and why it was refused.

    cd /work/wt/occl && OMP_NUM_THREADS=1 PYTHONPATH=src nice -n 5 /work/main/.venv/bin/python \
        docs/results/2026-11-30_cpu/session24/occl/scripts/diagnose.py OUT.json SEED...

Rebuilds the worlds of gen_t1.py's config (worlds 0001/0002, 40 frames, 624x192, cars 6-14, heldout) and the
test part's frames (32..39; their geometry is shared by clone and rain), then walks sample_occluder_removal's
steps by hand: cars visible, cars that pass each test of a hidden car, occluders per hidden car and why each
was refused, and, for every accepted pair, the reveal gain once the occluder is deleted (the generator wants
>= 1.2x the hidden car's source pixels).
"""

from __future__ import annotations

import json
import sys
from collections import Counter

import numpy as np
import torch

from sdn3d.data.synth import SynthConfig
from sdn3d.data.synth.edits import _in_frame, _separated, project_full
from sdn3d.data.synth.generate import _world
from sdn3d.data.synth.layout import frame_objects
from sdn3d.data.synth.scene_render import render_geometry


def main() -> None:
    torch.set_num_threads(1)
    out, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
    report = {}
    for seed in seeds:
        cfg = SynthConfig(output_dir="unused", seed=seed, image_size=(624, 192), worlds=("0001", "0002"),
                          variations=("clone", "rain"), frames_per_sequence=40, cars_per_frame=(6, 14),
                          edit_pairs=25, occluder_pairs=5)
        intr = cfg.intrinsics
        min_pixels = max(20, int(0.001 * intr.width * intr.height))
        for name in cfg.worlds:
            world = _world(seed, name, cfg.frames_per_sequence, cfg.cars_per_frame, cfg.vehicles, None, 0.0)
            frames = []
            for f in range(cfg.first_test_frame, cfg.frames_per_sequence):
                objects = frame_objects(world, f, 0.0)
                pose = world.camera.pose(f, 0.0)
                stats = render_geometry(world, objects, pose, intr).stats
                uv = project_full(objects.center)
                vis = stats.visible > 0
                z = objects.center[:, 2]
                hidden_refused = Counter()
                hidden = []
                for j in np.flatnonzero(vis):
                    why = [w for w, bad in ((f"pixels<{min_pixels}", stats.visible[j] < min_pixels),
                                            ("visible_fraction>0.8", stats.visible_fraction[j] > 0.8),
                                            ("truncr>0.3", stats.truncr[j] > 0.3), ("z<=3", z[j] <= 3.0)) if bad]
                    if why:
                        hidden_refused[why[0] if len(why) == 1 else "+".join(why)] += 1
                    else:
                        hidden.append(int(j))
                box = stats.box
                occ_refused, pairs = Counter(), []
                for j in hidden:
                    overlap = ((box[:, 0] <= box[j, 2]) & (box[j, 0] <= box[:, 2]) & (box[:, 1] <= box[j, 3])
                               & (box[j, 1] <= box[:, 3]))
                    nearer = vis & (z < z[j])
                    nearer[j] = False
                    if not nearer.any():
                        occ_refused["no nearer visible car"] += 1
                    elif not (nearer & overlap).any():
                        occ_refused["no nearer car's box overlaps"] += 1
                    for i in np.flatnonzero(nearer & overlap):
                        why = [w for w, bad in (("not separated (12 px)", not _separated(uv, vis, int(i))),
                                                ("centre out of frame", not _in_frame(uv[i], 0.0)),
                                                ("occluder z<=3", z[i] <= 3.0)) if bad]
                        if why:
                            occ_refused["occluder " + "+".join(why)] += 1
                        else:
                            keep = np.arange(len(objects)) != i
                            edited = objects.subset(keep)
                            after = render_geometry(world, edited, pose, intr).stats
                            r = int(keep[:j].sum())
                            pairs.append({"occluder": int(i), "hidden": j,
                                          "gain": round(float(after.visible[r] / stats.visible[j]), 3)})
                frames.append({"frame": f, "visible_cars": int(vis.sum()), "hidden_ok": len(hidden),
                               "hidden_refused": dict(hidden_refused), "occluder_refused": dict(occ_refused),
                               "pairs": pairs})
                print(seed, name, frames[-1], flush=True)
            report[f"{seed}/{name}"] = frames
    with open(out, "w") as fh:
        json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()
