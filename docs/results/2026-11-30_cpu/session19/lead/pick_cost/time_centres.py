"""Time projected_centers at 1242x375 (a synthetic frame's ground-truth scene, its objects made mask-only or not),
this tree's against the session start's formula (the grid-weighted centroid), same process, alternating."""
import sys
import tempfile
import time

import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import SynthConfig, generate_dataset
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.pick import projected_centers
from sdn3d.math3d.camera import project_points

torch.set_num_threads(1)
cfg = SynthConfig(output_dir=tempfile.mkdtemp() + "/data", seed=3, image_size=(1242, 375), frames_per_sequence=1,
                  cars_per_frame=(10, 10), edit_pairs=0)
scene = scene_from_frame(read_frames(generate_dataset(cfg))[0])


def old(scene):
    obj = scene.objects
    center = obj.center
    valid_3d = obj.has_geometry & (center[:, 2] > 0)
    safe = torch.where(valid_3d[:, None], center, center.new_tensor([0.0, 0.0, 1.0]))
    uv = project_points(safe, scene.intrinsics.matrix(torch.float64))
    height, width = scene.intrinsics.size
    grid = torch.stack(torch.meshgrid(torch.arange(height, dtype=torch.float64),
                                      torch.arange(width, dtype=torch.float64), indexing="ij"), -1)
    area = obj.mask.flatten(1).sum(1).double()
    centroid = torch.einsum("nhw,hwc->nc", obj.mask.double(), grid).flip(-1) / area.clamp(min=1)[:, None]
    use_mask = ~obj.has_geometry & (area > 0)
    return torch.where(use_mask[:, None], centroid, uv), valid_3d | use_mask


template = scene.objects.template_id.clone()
template[::3] = -1
half = scene.replace(objects=scene.objects.replace(template_id=template))
print(f"{len(scene.objects)} objects, mask dtype {scene.objects.mask.dtype}, size {scene.image_size}")
for name, s in (("all with geometry", scene), ("a third mask-only", half)):
    for f in (old, projected_centers):
        a, b = f(s), old(s)
        assert torch.equal(a[0], b[0]) and torch.equal(a[1], b[1])
    times = {old: [], projected_centers: []}
    for _ in range(int(sys.argv[1]) if len(sys.argv) > 1 else 7):
        for f in (old, projected_centers):
            t = time.perf_counter()
            f(s)
            times[f].append(time.perf_counter() - t)
    med = {f.__name__: sorted(v)[len(v) // 2] * 1000 for f, v in times.items()}
    print(f"{name}: median ms: session start {med['old']:.1f}, now {med['projected_centers']:.2f} (identical)")
