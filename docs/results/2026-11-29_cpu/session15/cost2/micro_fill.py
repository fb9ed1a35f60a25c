# ruff: noqa: E402
"""The removal's fill (transfer._remove_with_effects, fill rays) of the latency edits that remove something, timed in
one process with a fresh PictureLab of the source (with its 8-bit levels, as PhotoSource.lab makes it) and without
one (lab=None: every road test converts its own pixels, as main did), alternating, ROUNDS times each; the least CPU
ms of each per edit, and whether the two fills are equal.

    PYTHONPATH=src python micro_fill.py TREE [ROUNDS]
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
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.road import PictureLab
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.edit_benchmark import edit_kind
from sdn3d.image_ops import isin_ids

tree = sys.argv[1]
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
settings = PhotoSettings(fill="rays")
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(tree)}
entries = [e for e in load_edit_benchmark(f"{tree}/{BENCHMARK_NAME}") if e.operations][:40]
work = (624, 192)
print(f"{'edit':>4} {'kind':>16} {'with lab ms':>12} {'without ms':>11} {'ratio':>6} equal")
ratios = []
for i, entry in enumerate(entries):
    record = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    frame = PixelFrame((1242, 375), work)
    source = transfer.PhotoSource(original, frame, scene, settings=settings, max_fills=0)
    before, after = scene.objects, edited.objects
    gone = before.instance_id[~torch.isin(before.instance_id, after.instance_id)]
    gone_rows = [int(b) for b in torch.isin(before.instance_id, gone).nonzero().flatten().tolist()
                 if bool(before.has_geometry[b])]
    if not gone_rows:
        continue
    src_ids = source.src_ids
    hole = isin_ids(src_ids, gone) & (src_ids != 0)
    objects_px = (src_ids != 0) & ~hole
    times = {True: [], False: []}
    outs = {}
    for _ in range(rounds):
        for with_lab in (True, False):
            lab = PictureLab(source.image, original) if with_lab else None
            t = time.process_time()
            out = transfer._remove_with_effects(source.image, hole, objects_px, before, gone_rows, source.K, None,
                                                settings, None, lab)
            times[with_lab].append(1000 * (time.process_time() - t))
            outs[with_lab] = out
    a, b = min(times[True]), min(times[False])
    ratios.append(a / b)
    same = all(torch.equal(x, y) for x, y in zip(outs[True], outs[False], strict=True))
    print(f"{i:>4} {edit_kind(entry):>16} {a:12.1f} {b:11.1f} {a / b:6.3f} {same}")
log = np.log(ratios)
boot = np.exp(np.random.default_rng(0).choice(log, (10000, len(log))).mean(1))
print(f"geometric mean ratio {np.exp(log.mean()):.3f} [95 % {np.percentile(boot, 2.5):.3f}, "
      f"{np.percentile(boot, 97.5):.3f}], {int((log < 0).sum())} wins / {int((log > 0).sum())} losses of {len(log)}")
