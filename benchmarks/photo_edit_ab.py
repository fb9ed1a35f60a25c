"""One photo edit at 1242x375 with 5 cars, timed in two source trees side by side (issue 39: before and after a
change to the photo appearance); prints what it measured, the medians and their ratio.

    python benchmarks/photo_edit_ab.py --tree /path/to/old/checkout [--repeats 7] [--threads 1]

A synthetic frame (``sdn3d.data.synth``, 1242x375, a seed whose first frame has 5 cars with geometry) is written
once into a temporary folder; its ground-truth scene at the working size 624x192 is the oracle (no network runs).
The edit moves the first car 40 px to the right, turns the second by 30 degrees, deletes the third and repaints
the fourth red (``fill='telea'``, relighting and contact shadows on: every per-object step of the photo
appearance runs). Each tree (this one, ``--tree``) times it in a fresh interpreter (``PYTHONPATH=TREE/src:TREE``)
that draws it once untimed, then ``--calls`` times, each with a fresh source state (what one ``sdn3d-edit`` call
draws; wall and process CPU time, which a loaded machine inflates less); the trees alternate ``--repeats`` times
(A, B, A, B, ...), so the load of a shared machine falls on both.
Every child draws through :func:`sdn3d.editing.appearance.appearance_renderer` where the tree has it, else through
``render_photo`` (an older tree); both print the picture's digest, which must agree.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = r'''
import hashlib, json, sys, time
import numpy as np, torch
torch.set_num_threads(int(sys.argv[2]))
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.pick import projected_centers
from sdn3d.editing.ops import Delete, Move, Rotate, SetCode
from sdn3d.textural.code_bank import named_color
try:  # this tree
    from sdn3d.editing.frame import PixelFrame
    from sdn3d.editing.photo.settings import PhotoSettings
except ImportError:  # a tree before editing.frame and the editing.photo package
    from sdn3d.editing.spec import PixelFrame
    from sdn3d.editing.photo import PhotoSettings
record = sorted(read_frames(sys.argv[1]), key=lambda r: (r.world, r.variation, int(r.frame)))[0]
work = (624, 192)
scene = scene_from_frame(record, work)
original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
frame = PixelFrame((original.shape[2], original.shape[1]), work)
cars = [int(i) for i, g in zip(scene.objects.instance_id, scene.objects.has_geometry) if bool(g)]
row = scene.objects.index_of(cars[0])
centers, _ = projected_centers(scene)
to = (float(centers[row, 0]) + 20.0, float(centers[row, 1]))
code = tuple(float(c) for c in scene.objects.code[scene.objects.index_of(cars[3])])
ops = [Move(cars[0], to), Rotate(cars[1], 0.5236), Delete(cars[2]), SetCode(cars[3], code, named_color("red"))]
edited = apply_edits(scene, ops)
settings = PhotoSettings(fill="telea")
try:
    from sdn3d.editing.appearance import appearance_renderer
    renderer = appearance_renderer("photo", photo=settings)
    def draw():
        return renderer.draw(renderer.prepare(original, frame, scene), edited, ops).image
    how = "appearance_renderer(photo).prepare/draw"
except ImportError:  # a tree before editing.appearance
    from sdn3d.editing.photo import paints, render_photo
    def draw():
        return render_photo(original, frame, scene, edited, None, settings, paints(ops)).image
    how = "render_photo"
image = draw()
times, cpu = [], []
for _ in range(int(sys.argv[3])):
    t0, c0 = time.perf_counter(), time.process_time()
    draw()
    times.append(1000 * (time.perf_counter() - t0))
    cpu.append(1000 * (time.process_time() - c0))
print(json.dumps({"ms": times, "cpu_ms": cpu, "cars": len(cars), "how": how, "size": list(image.shape),
                  "digest": hashlib.sha256(image.contiguous().numpy().tobytes()).hexdigest()[:16]}))
'''


def _run(tree: Path, data: Path, threads: int, calls: int) -> dict:
    env = dict(os.environ, PYTHONPATH=f"{tree / 'src'}{os.pathsep}{tree}", OMP_NUM_THREADS=str(threads))
    out = subprocess.run([sys.executable, "-c", CHILD, str(data), str(threads), str(calls)], env=env, check=True,
                         capture_output=True, text=True, cwd=tree)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--tree", type=Path, required=True, help="the other source tree (e.g. the code before)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--calls", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--seed", type=int, default=None, help="synth seed (default: the first with 5 cars)")
    args = parser.parse_args()
    here = Path(__file__).resolve().parents[1]
    trees = {"this": here, "tree": args.tree.resolve()}
    from sdn3d.data.synth import SynthConfig, generate_dataset
    from sdn3d.data.vkitti1 import read_frames

    with tempfile.TemporaryDirectory() as tmp:
        data = None
        for seed in ([args.seed] if args.seed is not None else range(40)):
            root = Path(tmp) / f"s{seed}"
            generate_dataset(SynthConfig(output_dir=str(root), seed=seed, image_size=(1242, 375), worlds=("0001",),
                                         variations=("clone",), frames_per_sequence=1, edit_pairs=0,
                                         occluder_pairs=0, workers=1, cars_per_frame=(5, 5)))
            record = sorted(read_frames(root), key=lambda r: (r.world, r.variation, int(r.frame)))[0]
            from sdn3d.data.scene_gt import scene_from_frame

            scene = scene_from_frame(record, (624, 192))
            if int(scene.objects.has_geometry.sum()) == 5:
                data = root
                print(f"synthetic frame: seed {seed}, 1242x375, 5 cars with geometry", flush=True)
                break
        if data is None:
            raise SystemExit("no synthetic frame with 5 cars with geometry")
        runs: dict[str, list[float]] = {k: [] for k in trees}
        cpu: dict[str, list[float]] = {k: [] for k in trees}
        seen: dict[str, dict] = {}
        load = os.getloadavg()
        for rep in range(args.repeats):
            for name, tree in trees.items():
                t0 = time.perf_counter()
                got = _run(tree, data, args.threads, args.calls)
                runs[name] += got["ms"]
                cpu[name] += got["cpu_ms"]
                seen[name] = got
                print(f"repeat {rep} {name} ({tree}): {[round(t) for t in got['ms']]} ms per edit, CPU "
                      f"{[round(t) for t in got['cpu_ms']]} ms "
                      f"[{got['how']}, {got['cars']} cars, picture {got['digest']}; "
                      f"process {time.perf_counter() - t0:.1f} s]", flush=True)
        med = {k: statistics.median(v) for k, v in runs.items()}
        print(json.dumps({"what": "one photo edit (move, rotate, delete, recolor) of a 1242x375 frame with "
                                  f"{seen['this']['cars']} cars, fill=telea, {args.threads} thread(s), CPU",
                          "trees": {k: str(v) for k, v in trees.items()}, "n": {k: len(v) for k, v in runs.items()},
                          "median_ms": {k: round(v, 1) for k, v in med.items()},
                          "min_ms": {k: round(min(v), 1) for k, v in runs.items()},
                          "ratio_tree_over_this": round(med["tree"] / med["this"], 3),
                          "cpu_median_ms": {k: round(statistics.median(v), 1) for k, v in cpu.items()},
                          "cpu_ratio_tree_over_this": round(statistics.median(cpu["tree"])
                                                            / statistics.median(cpu["this"]), 3),
                          "same_picture": seen["this"]["digest"] == seen["tree"]["digest"],
                          "load_before_after": [load[0], os.getloadavg()[0]], "cpus": os.cpu_count()}, indent=1))


if __name__ == "__main__":
    main()
