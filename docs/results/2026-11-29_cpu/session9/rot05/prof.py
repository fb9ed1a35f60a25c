# ruff: noqa: E402, E501, E701, E702
"""prof.py DATA OUT [KIND...]: cProfile of the photo appearance (prepare + draw, fresh source state) per edit kind on
the edits of a sdn3d-synth tree at the input's size (photo_latency.py's cases), 1 thread; writes OUT_<kind>.txt."""
import cProfile
import io
import pstats
import sys
import time
from pathlib import Path

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
from sdn3d.evaluation.edit_benchmark import edit_kind


def cases(root, limit=40):
    root = Path(root)
    records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(root)}
    entries = [e for e in load_edit_benchmark(root / BENCHMARK_NAME) if e.operations][:limit]
    work = (624, 192)
    out = []
    for entry in entries:
        record = records[(entry.world, entry.variation, entry.source_frame)]
        scene = scene_from_frame(record, work)
        edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
        original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
        out.append((edit_kind(entry), scene, edited, original))
    size = tuple(int(x) for x in out[0][3].shape[2:0:-1])
    return out, PixelFrame(size, work)


if __name__ == "__main__":
    data, prefix = sys.argv[1], sys.argv[2]
    kinds = sys.argv[3:]
    cs, frame = cases(data)
    renderer = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
    renderer.draw(renderer.prepare(cs[0][3], frame, cs[0][1]), cs[0][2])
    by_kind = {}
    for kind, scene, edited, original in cs:
        if kinds and kind not in kinds: continue
        pr = by_kind.setdefault(kind, cProfile.Profile(time.process_time))  # CPU time: the load does not count
        c0 = time.process_time()
        pr.enable()
        renderer.draw(renderer.prepare(original, frame, scene), edited)
        pr.disable()
        print(kind, f"{1000 * (time.process_time() - c0):.0f} ms CPU", flush=True)
    for kind, pr in by_kind.items():
        s = io.StringIO()
        pstats.Stats(pr, stream=s).sort_stats("cumulative").print_stats(70)
        pstats.Stats(pr, stream=s).sort_stats("tottime").print_stats(40)
        Path(f"{prefix}_{kind}.txt").write_text(s.getvalue())
