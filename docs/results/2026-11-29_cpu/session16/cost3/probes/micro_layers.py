# ruff: noqa: E401, E402, E501, E701, E702, B023, F401, F841, I001
"""A probe of one cost this helper looked at and did not cut (README section 4); run from the worktree with
PYTHONPATH=src, threads 1."""
import time, sys, torch, numpy as np
from pathlib import Path
torch.set_num_threads(1)
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.meshes.bank import default_bank
from sdn3d.scene import maps
tree = Path("/tmp/s14data/cost/vkitti")
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(tree)}
entries = [e for e in load_edit_benchmark(tree / BENCHMARK_NAME) if e.operations][:40]
bank = default_bank()
seen = set()
orig = maps.rasterize_meshes
info = {}
def spy(verts, faces, K, settings, mesh_to_image=None, batch_size=None):
    info["size"] = settings.image_size; info["g"] = batch_size
    return orig(verts, faces, K, settings, mesh_to_image, batch_size)
maps.rasterize_meshes = spy
for e in entries:
    key = (e.world, e.variation, e.source_frame)
    if key in seen: continue
    seen.add(key)
    scene = scene_from_frame(records[key], (624, 192))
    ts = []
    for _ in range(5):
        t0 = time.process_time(); ids = maps.compose_instances(scene, bank); ts.append(time.process_time() - t0)
    print(key, "objects", len(scene.objects), "raster g", info["g"], "crop", info["size"], "min ms", round(1000 * min(ts), 1))
import cProfile, pstats
maps.rasterize_meshes = orig
pr = cProfile.Profile(); pr.enable()
for _ in range(20):
    maps.compose_instances(scene, bank)
pr.disable()
pstats.Stats(pr).sort_stats("tottime").print_stats(18)
