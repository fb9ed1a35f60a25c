# ruff: noqa: E402
"""The 14 latency edits (session14/cost/draw_edits.py's cases: fill rays, a fresh source per edit, threads 1) drawn
in ONE process by this branch's code with the source's PictureLab (as it runs) and without it (PhotoSource.lab
replaced by None: every road test converts its own pixels by road_lab, as main does), alternating edit by edit and
arm by arm (A B, then B A), ROUNDS rounds: both arms see the same load within a second. Per edit the least CPU ms of
each arm, the ratio with/without, its geometric mean with a paired bootstrap 95 % interval (10k resamples of the
edits), wins and losses; and whether the two arms' pictures are equal.

    PYTHONPATH=src python ab_same_process.py TREE [ROUNDS]
"""

import sys
import time

import numpy as np
import torch

torch.set_num_threads(1)
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import PhotoSource
from sdn3d.evaluation.edit_benchmark import edit_kind

tree = sys.argv[1]
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(tree)}
entries = [e for e in load_edit_benchmark(f"{tree}/{BENCHMARK_NAME}") if e.operations][:40]
work = (624, 192)
cases = []
for entry in entries:
    record = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    cases.append((scene, edited, original, edit_kind(entry)))
frame = PixelFrame((1242, 375), work)
renderer = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
with_lab = PhotoSource.lab


def without_lab(self):
    return None


def draw(case, arm: bool):
    PhotoSource.lab = with_lab if arm else without_lab
    scene, edited, original, _ = case
    t = time.process_time()
    image = renderer.draw(renderer.prepare(original, frame, scene), edited).image
    return 1000 * (time.process_time() - t), image


draw(cases[0], True)
draw(cases[0], False)  # warm-up
times = np.full((2, rounds, len(cases)), np.inf)
equal = [True] * len(cases)
t0 = time.strftime("%H:%M:%S")
for r in range(rounds):
    for i, case in enumerate(cases):
        order = (True, False) if (r + i) % 2 == 0 else (False, True)
        images = {}
        for arm in order:
            ms, images[arm] = draw(case, arm)
            times[0 if arm else 1, r, i] = ms
        equal[i] &= torch.equal(images[True], images[False])
a, b = times[0].min(0), times[1].min(0)
log = np.log(a / b)
boot = np.exp(np.random.default_rng(0).choice(log, (10000, len(log))).mean(1))
print(f"{len(cases)} edits x {rounds} rounds, {t0}-{time.strftime('%H:%M:%S')}; pictures equal: {all(equal)}")
print(f"CPU with/without the PictureLab: {np.exp(log.mean()):.3f} [95 % {np.percentile(boot, 2.5):.3f}, "
      f"{np.percentile(boot, 97.5):.3f}], wins {int((log < 0).sum())} losses {int((log > 0).sum())}; median ms "
      f"{np.median(a):.0f} vs {np.median(b):.0f}, mean {a.mean():.0f} vs {b.mean():.0f}")
for i, case in enumerate(cases):
    print(f"  edit {i} {case[3]}: {a[i]:.0f} vs {b[i]:.0f} ms")
